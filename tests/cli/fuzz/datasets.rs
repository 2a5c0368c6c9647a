//! Fuzzing datasets (docs/dataset.md): the manifest by structured edits, every file it
//! lists by number replacements or byte edits — relisted with its new size and checksum
//! half of the time, as a converter that wrote a bad file would, so that the readers and not
//! only the checksum meet the defect — through `whisker slam`.

use super::mutate::*;
use super::{Case, config, run, s};
use crate::dataset::{copy_dir, files, rehash};
use crate::repo;
use proptest::prelude::*;
use std::path::PathBuf;
use std::sync::OnceLock;

/// The four kinds of dataset, written once per test process: a kinematic maze run, an
/// object-SLAM run (the Mug), a closed loop (the quickstart, with its object maps) and an
/// office run (one lap, short closed loops at its stops, one of them map building).
fn datasets() -> &'static [PathBuf; 4] {
    static DATASETS: OnceLock<[PathBuf; 4]> = OnceLock::new();
    DATASETS.get_or_init(|| {
        // Under cargo's scratch directory for tests, not the system's: a static is
        // never dropped, so the directory outlives the run.
        let tmp = tempfile::Builder::new()
            .prefix("fuzz-datasets")
            .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
            .unwrap()
            .keep();
        let d = [
            tmp.join("maze"),
            tmp.join("object"),
            tmp.join("loop"),
            tmp.join("office"),
        ];
        let maze = s(&repo("scenarios/maze_kinematic.toml"));
        let quick = s(&repo("scenarios/quickstart.toml"));
        let office = s(&repo("scenarios/office.toml"));
        let runs: [Vec<String>; 4] = [
            vec!["dataset".into(), maze],
            vec![
                "dataset".into(),
                "object-slam".into(),
                "--objects".into(),
                "mug".into(),
            ],
            vec!["dataset".into(), quick],
            ["dataset", &office, "--set", "navigate.laps=1"]
                .into_iter()
                .chain(["--set", "navigate.object.explore.max_iterations=40"])
                .chain(["--set", "navigate.object.map_whisks=40"])
                .map(String::from)
                .collect(),
        ];
        for (args, out) in runs.iter().zip(&d) {
            let o = std::process::Command::new(env!("CARGO_BIN_EXE_whisker"))
                .args(args)
                .args(["--seed", "0", "--out", &s(out)])
                .output()
                .unwrap();
            assert!(
                o.status.success(),
                "{args:?}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
        d
    })
}

proptest! {
    #![proptest_config(config(100))]

    #[test]
    fn fuzz_datasets(
        kind in prop::sample::select(&[0usize, 0, 1, 1, 2, 3, 3][..]),
        file in any::<usize>(),
        tree in tree_edits(),
        numbers in number_edits(),
        bytes in byte_edits(),
        how in 0..3u8,
        relisted in any::<bool>(),
    ) {
        let tmp = tempfile::tempdir().unwrap();
        let d = tmp.path().join("d");
        copy_dir(&datasets()[kind], &d);
        let all: Vec<String> = files(&d).into_keys().collect();
        let rel = all[file % all.len()].clone();
        let path = d.join(&rel);
        let original = std::fs::read(&path).unwrap();
        let edited = if rel == "dataset.json" || how == 0 && rel.ends_with(".json") {
            let v: serde_json::Value = serde_json::from_slice(&original).unwrap();
            apply_tree(&v, &tree).to_string().into_bytes()
        } else if how == 1 {
            apply_numbers(&String::from_utf8_lossy(&original), &numbers).into_bytes()
        } else {
            apply_bytes(&original, &bytes)
        };
        std::fs::write(&path, &edited).unwrap();
        if relisted && rel != "dataset.json" {
            rehash(&d, &rel);
        }
        let name = rel.rsplit('/').next().unwrap().to_string();
        run(&Case {
            args: vec!["slam".into(), s(&d), "--out".into(), s(&tmp.path().join("out"))],
            cwd: tmp.path(),
            names: vec![name, "dataset.json".into()],
            watch: vec![d.clone()],
        })?;
    }
}
