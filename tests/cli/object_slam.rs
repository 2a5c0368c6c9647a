//! `whisker object-slam` (thesis §5.2) end to end: object maps are written and load back,
//! identification picks the explored object on its mapping trajectory and stays low on
//! the unmapped Skull, results do not depend on the number of threads, and bad input
//! exits 2.

use super::{stderr, stdout};
use std::process::Command;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

fn object_slam(args: &[&str], threads: &str) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_whisker"))
        .arg("object-slam")
        .args(args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("whisker runs")
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
    // Same seed, same numbers on one thread.
    let one = object_slam(&args, "1");
    assert_eq!(stdout(&one), stdout(&o));
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
