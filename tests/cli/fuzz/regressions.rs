//! Cases the fuzzing found while it was being built, kept as named tests; each failed
//! before its fix (their proptest seeds are in `tests/proptest-regressions/fuzz/`).

use crate::{repo, stderr, whisker};

/// (arguments, what the refusal must say). Before #37: `--length 1e308` refused naming a
/// NaN first mode and no option; `--force 1e308` and `--follicle-stiffness 1e308` diverged
/// (exit 1), as did 1e-320 of either (a load that never settled, a
/// ring-down with nothing to measure); `--nudges 4294967295` ran for ever; `--match-threshold 1e308,1e308` failed
/// writing a file whose name held 309 digits (exit 1); `radial eval --max-fraction 1e-320`
/// named the data file but not the option.
#[test]
fn absurd_command_line_values_are_refused_with_their_range() {
    let maze = repo("scenarios/maze_kinematic.toml");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["characterize", "--length=1e308"],
            "--length: length must be a number from 0.001 to 2 m, got 1e308",
        ),
        (
            vec!["characterize", "--force=1e308"],
            "--force: expected a load of 1e-6 to 10 N (either sign), got 1e308",
        ),
        (
            vec!["characterize", "--force=1e-320"],
            "--force: expected a load of 1e-6 to 10 N (either sign), got 1e-320",
        ),
        (
            vec!["characterize", "--follicle-stiffness=1e-320"],
            "or a number from 0.001 to 1e6 N·m/rad, got 1e-320",
        ),
        (
            vec!["characterize", "--follicle-stiffness=1e308"],
            "--follicle-stiffness: expected 0 (a rigid clamp) or a number from 0.001 to 1e6 N·m/rad, got 1e308",
        ),
        (
            vec![
                "soak",
                "--objects=box",
                "--duration=0.05",
                "--nudges=4294967295",
            ],
            "--nudges 4294967295: expected 0 to 100",
        ),
        (
            vec!["soak", "--objects=box", "--duration=1e308"],
            "expected a positive number of seconds up to 3600",
        ),
        (
            vec![
                "maze-slam",
                maze.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--match-threshold=1e308,1e308",
            ],
            "local_view.match_threshold 1e308: expected at most 287.4",
        ),
    ];
    let (data, models) = (repo("assets/radial/validation.csv"), repo("assets/models"));
    let radial = [
        "radial",
        "eval",
        "--data",
        data.to_str().unwrap(),
        "--models",
        models.to_str().unwrap(),
        "--max-fraction=1e-320",
    ];
    let cases = [
        cases,
        vec![(
            radial.to_vec(),
            "≤ 1e-320 L (--max-fraction): expected a larger fraction",
        )],
    ]
    .concat();
    for (args, needle) in cases {
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

/// Scenario fields with a physical range, through `run --set` (an audit after the fuzzing:
/// before #37 a 1e-300 m FEH segment panicked with a capacity overflow, 4294967295 maze
/// deformities and a 1e-9 s sample period ran for ever).
#[test]
fn absurd_scenario_values_are_refused_with_their_range() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let cases = [
        (
            "recognise_box_feh.toml",
            "explore.segment_m=1e-300",
            "field `explore.segment_m`: expected a length of at least 0.001 m, got 1e-300",
        ),
        (
            "maze_kinematic.toml",
            "maze.deformities.count=4294967295",
            "field `maze.deformities.count`: expected 0 to 1000",
        ),
        (
            "recognise_box.toml",
            "explore.max_iterations=4294967295",
            "field `explore.max_iterations`: expected 1 to 100000",
        ),
        (
            "explore_map_box.toml",
            "explore.map_loops=4294967295",
            "field `explore.map_loops`: expected 1 to 100",
        ),
        // Named `array (whisker A1)`, not the field, before (a long fuzz run).
        (
            "quickstart.toml",
            "array.segments=0",
            "field `array.segments`: whisker A1: segments must be between 2 and 200, got 0",
        ),
        (
            "arm_tour.toml",
            "output.sample_period_s=1e-9",
            "field `output.sample_period_s`: expected a number from 5e-4 to 1 s",
        ),
    ];
    // 2,000 copies of the Kettle took over a minute to check.
    let kettles = tmp.path().join("kettles.toml");
    let text = std::fs::read_to_string(repo("scenarios/objects.toml")).unwrap();
    let object = &text[text.find("[[objects]]").unwrap()..text.find("[[trajectory").unwrap()];
    let assets = format!("\"{}/", repo("assets").display());
    let many = text
        .replacen(object, &object.repeat(300), 1)
        .replace("\"../assets/", &assets);
    std::fs::write(&kettles, many).unwrap();
    let o = whisker(&["check", kettles.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("field `objects`: 300 objects: expected at most 256"));
    for (scenario, set, needle) in cases {
        let path = repo(&format!("scenarios/{scenario}"));
        let args = [
            "run",
            path.to_str().unwrap(),
            "--set",
            set,
            "--out",
            out.to_str().unwrap(),
        ];
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

/// A maze dataset whose manifest holds an injection energy of 0 (allowed, as in a
/// scenario) replays; before (a fourth long fuzz run) `slam` refused it blaming the options
/// `--match-threshold / --inject-energy`, which were not given.
#[test]
fn a_manifest_parameter_is_not_blamed_on_options_not_given() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path().join("d");
    let maze = repo("scenarios/maze_kinematic.toml");
    let (maze, d_str) = (maze.to_str().unwrap(), d.to_str().unwrap());
    let o = whisker(&["dataset", maze, "--seed", "0", "--out", d_str]);
    assert!(o.status.success(), "{}", stderr(&o));
    let path = d.join("dataset.json");
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    m["maze"]["ratslam"]["local_view"]["inject_energy"] = 0.into();
    std::fs::write(&path, m.to_string()).unwrap();
    let o = whisker(&["slam", d_str]);
    assert!(o.status.success(), "{}", stderr(&o));
}
