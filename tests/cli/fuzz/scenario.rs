//! Fuzzing scenarios: structured edits of the TOML tree (values of every type where any
//! field is, fields removed, unknown fields, arrays where tables are, long arrays) and
//! byte edits of the text, of the repository's scenarios. `whisker check` must accept or
//! refuse; what it refuses, `whisker run` (or, with `[trials]`, `whisker trials`) must
//! refuse too, leaving
//! nothing behind.

use super::mutate::*;
use super::{Case, Outcome, absolute_assets, config, run, s};
use crate::repo;
use proptest::prelude::*;

/// The scenarios mutated: every section the format has appears in one of them.
const SCENARIOS: &[&str] = &[
    "quickstart.toml",
    "objects.toml",
    "maze_kinematic.toml",
    "recognise_box_physics.toml",
    "trials_spc.toml",
    "trials_maze.toml",
    "whisking.toml",
    "arm_tour.toml",
];

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn fuzz_scenarios(
        name in prop::sample::select(SCENARIOS),
        edits in tree_edits(),
        bytes in byte_edits(),
        structured in prop::bool::weighted(0.75),
    ) {
        let tmp = tempfile::tempdir().unwrap();
        // The scenarios beside it, for `base`.
        for e in std::fs::read_dir(repo("scenarios")).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "toml") {
                let t = absolute_assets(&std::fs::read_to_string(&p).unwrap());
                std::fs::write(tmp.path().join(p.file_name().unwrap()), t).unwrap();
            }
        }
        let text = absolute_assets(&std::fs::read_to_string(repo(&format!("scenarios/{name}"))).unwrap());
        let text = if structured {
            let table = toml::Value::Table(toml::from_str(&text).unwrap());
            match apply_tree(&table, &edits) {
                toml::Value::Table(t) => toml::to_string(&t).unwrap_or(text),
                _ => text,
            }
        } else {
            String::from_utf8_lossy(&apply_bytes(text.as_bytes(), &bytes)).into_owned()
        };
        let scenario = tmp.path().join("fuzzed.toml");
        std::fs::write(&scenario, &text).unwrap();
        let names: Vec<String> = ["fuzzed.toml", ".toml", ".urdf", ".obj", ".json"].map(String::from).to_vec();
        let case = |args: &[&str]| Case {
            args: args.iter().map(|a| a.to_string()).collect(),
            cwd: tmp.path(),
            names: names.clone(),
            watch: vec![],
        };
        let checked = run(&case(&["check", &s(&scenario)]))?;
        if checked == Outcome::Refused {
            // `run` ignores `[trials]` (scenarios/README.md); `trials` reads it.
            let outcome = if text.contains("[trials") {
                let out = tmp.path().join("batch");
                run(&case(&["trials", &s(&scenario), "--out", &s(&out)]))?
            } else {
                run(&case(&["run", &s(&scenario)]))?
            };
            prop_assert_eq!(outcome, Outcome::Refused, "`check` refused what another command accepted");
        }
    }
}
