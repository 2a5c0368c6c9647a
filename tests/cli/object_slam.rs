//! `whisker object-slam` (thesis §5.2) end to end: object maps are written and load back,
//! identification picks the explored object on its mapping trajectory and stays low on
//! the unmapped Skull, results do not depend on the number of threads, and bad input
//! exits 2.

use super::{keep_refusal, stderr, stdout};
use std::process::Command;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

fn object_slam(args: &[&str], threads: &str) -> std::process::Output {
    let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .arg("object-slam")
        .args(args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("whisker runs");
    keep_refusal(&[&["object-slam"], args].concat(), &o);
    o
}

#[test]
fn identification_picks_the_explored_object_and_not_the_unmapped_skull() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let args = ["--objects", "mug,kettle,skull", "--json"];
    let mut with_out = args.to_vec();
    with_out.extend(["--out", out.to_str().unwrap()]);
    let o = object_slam(&with_out, "2");
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let id = v["identification"].as_array().unwrap();
    let mean = |object: &str, traj: &str, of: &str| {
        id.iter()
            .find(|r| r["object"] == object && r["trajectory"] == traj)
            .unwrap()["mean_confidence"][of]
            .as_f64()
            .unwrap()
    };
    for (object, other) in [("mug", "kettle"), ("kettle", "mug")] {
        assert!(
            mean(object, "A", object) > 0.2
                && mean(object, "A", object) > 5.0 * mean(object, "A", other),
            "{object}: {id:?}"
        );
        // The Skull, never mapped, wins less belief than a mapped object on its own loop.
        assert!(mean("skull", "A", object) < 0.5 * mean(object, "A", object));
    }
    // Twelve parameter sets per object (Table 5.1).
    assert_eq!(v["localisation"].as_array().unwrap().len(), 36);
    // The best set's maps load back; the CSV files exist.
    let map = ObjectMap::load(&out.join("maps/mug.json")).unwrap();
    assert!(map.experiences.len() > 5 && !map.links.is_empty());
    assert!(out.join("localisation.csv").is_file() && out.join("identification.csv").is_file());
    // Each re-localisation's perceived-pose error is in localisation.csv; recounted from
    // there, the true revisits (within the thesis' step, 11 cm and 12°) match the JSON's,
    // and a lap-2 revisit of A, whose poses repeat lap 1's exactly, can be exact (0).
    let csv = std::fs::read_to_string(out.join("localisation.csv")).unwrap();
    let mut exact = 0;
    for row in v["localisation"].as_array().unwrap() {
        let (object, set) = (
            row["object"].as_str().unwrap(),
            row["parameters"].as_str().unwrap(),
        );
        assert_eq!(row["thesis_step_m"], 0.11);
        assert_eq!(row["thesis_step_deg"], 12.0);
        for traj in ["A", "B"] {
            let perceived: Vec<(f64, f64)> = csv
                .lines()
                .map(|l| l.split(',').collect::<Vec<_>>())
                .filter(|f| f[0] == object && f[1] == set && f[2] == traj)
                .map(|f| (f[6].parse().unwrap(), f[7].parse().unwrap()))
                .collect();
            assert_eq!(
                perceived.len() as u64,
                row[traj]["relocalisations"].as_u64().unwrap()
            );
            let within = perceived
                .iter()
                .filter(|(t, r)| *t <= 0.11 && *r <= 12.0)
                .count();
            exact += perceived.iter().filter(|(t, _)| *t < 1e-9).count();
            assert_eq!(
                within as u64,
                row[traj]["true_revisits"].as_u64().unwrap(),
                "{object} {set} {traj}"
            );
        }
    }
    assert!(exact > 0);
    // Same seed, same numbers on one thread.
    let one = object_slam(&args, "1");
    assert_eq!(stdout(&one), stdout(&o));
}

/// The placement moves every object but the Kettle (which the thesis put on its
/// trajectory's centre) off the centre: the Kettle's results are the same either way,
/// the Mug's are not.
#[test]
fn the_placement_moves_the_mug_but_not_the_kettle() {
    let run = |object: &str, placement: &str| {
        let args = ["--objects", object, "--placement", placement, "--json"];
        let o = object_slam(&args, "2");
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    assert_eq!(run("kettle", "thesis"), run("kettle", "centred"));
    assert_ne!(run("mug", "thesis"), run("mug", "centred"));
    let o = object_slam(&["--placement", "sideways"], "1");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--placement"), "{}", stderr(&o));
}

#[test]
fn an_unknown_object_is_refused_with_exit_code_2() {
    let o = object_slam(&["--objects", "mug,teapot"], "1");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("teapot") && stderr(&o).contains("kettle"),
        "{}",
        stderr(&o)
    );
}
