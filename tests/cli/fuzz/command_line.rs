//! Fuzzing command-line arguments: every numeric option of the commands that finish in
//! seconds when given sane values, given one of the hostile values (non-finite, negative,
//! zero, absurd magnitudes, integer limits, text). The command must accept it or refuse it
//! naming the option — an absurd count or duration is refused with its range rather than
//! run for hours (which the 60 s limit reports as a hang).

use super::mutate::HOSTILE;
use super::{Case, config, run, s};
use crate::repo;
use proptest::prelude::*;

/// (arguments before the value, the option, arguments after). `OUT` is replaced by an
/// output directory, `REPO/` by the repository.
const TEMPLATES: &[(&[&str], &str, &[&str])] = &[
    (&["characterize"], "--length", &[]),
    (&["characterize"], "--base-diameter", &[]),
    (&["characterize"], "--tip-diameter", &[]),
    (&["characterize"], "--youngs-modulus", &[]),
    (&["characterize"], "--density", &[]),
    (&["characterize"], "--damping-ratio", &[]),
    (&["characterize"], "--segments", &[]),
    (&["characterize"], "--follicle-stiffness", &[]),
    (&["characterize"], "--force", &[]),
    (&["characterize"], "--at", &[]),
    (&["soak", "--objects", "box"], "--duration", &[]),
    (
        &["soak", "--objects", "box", "--duration", "0.05"],
        "--substeps",
        &[],
    ),
    (
        &["soak", "--objects", "box", "--duration", "0.05"],
        "--nudges",
        &[],
    ),
    (&["soak", "--duration", "0.05"], "--objects", &[]),
    (
        &[
            "maze-slam",
            "REPO/scenarios/maze_kinematic.toml",
            "--out",
            "OUT",
        ],
        "--seeds",
        &[],
    ),
    (
        &[
            "maze-slam",
            "REPO/scenarios/maze_kinematic.toml",
            "--out",
            "OUT",
        ],
        "--match-threshold",
        &[],
    ),
    (
        &[
            "maze-slam",
            "REPO/scenarios/maze_kinematic.toml",
            "--out",
            "OUT",
        ],
        "--inject-energy",
        &[],
    ),
    (
        &[
            "object-slam",
            "--objects",
            "mug",
            "--out",
            "OUT",
            "--no-rrd",
        ],
        "--seed",
        &[],
    ),
    (
        &["object-slam", "--out", "OUT", "--no-rrd"],
        "--objects",
        &[],
    ),
    (
        &["run", "REPO/scenarios/arm_tour.toml", "--out", "OUT"],
        "--seed",
        &[],
    ),
    (
        &["run", "REPO/scenarios/arm_tour.toml", "--out", "OUT"],
        "--set",
        &[],
    ),
    (
        &["run", "REPO/scenarios/quickstart.toml", "--out", "OUT"],
        "--set",
        &[],
    ),
    (
        &[
            "dataset",
            "REPO/scenarios/maze_kinematic.toml",
            "--out",
            "OUT",
        ],
        "--seed",
        &[],
    ),
    (
        &["urdf", "fk", "REPO/assets/urdf/ur5_whisker_array.urdf"],
        "--joints",
        &[],
    ),
    (
        &[
            "radial",
            "eval",
            "--data",
            "REPO/assets/radial/validation.csv",
            "--models",
            "REPO/assets/models",
        ],
        "--max-fraction",
        &[],
    ),
];

/// Fields of `--set` (with `run`): numbers with a physical range.
const SET_FIELDS: &[&str] = &[
    "seed",
    "arm.joint_speed_limit_rad_s",
    "output.sample_period_s",
    "kinematic.noise",
    "kinematic.point_noise_fraction",
    "kinematic.detection_probability",
    "explore.max_iterations",
    "explore.stop_ic",
    "explore.standoff_m",
    "explore.sphere_radius_m",
    "explore.segment_m",
    "explore.mesh_faces",
    "explore.placement.min_contacts",
    "explore.placement.cone_deg",
    "array.substeps",
    "array.segments",
    "maze.deformities.count",
    "maze.deformities.size_m",
    "maze_slam.circuits",
    "explore.map_loops",
];

proptest! {
    #![proptest_config(config(300))]

    #[test]
    fn fuzz_command_lines(
        template in prop::sample::select(TEMPLATES),
        value in prop::sample::select(HOSTILE),
        field in prop::sample::select(SET_FIELDS),
        listed in prop::sample::select(&["{v}", "{v},{v}", "1,{v}", "{v},0,0,0,0,0"][..]),
    ) {
        let tmp = tempfile::tempdir().unwrap();
        let fill = |a: &str| {
            a.replace("OUT", &s(&tmp.path().join("out")))
                .replace("REPO/", &format!("{}/", repo("").display()))
        };
        let (before, option, after) = template;
        let option: &str = option;
        let value = match option {
            "--set" => format!("{field}={}", if value.is_empty() { "''" } else { value }),
            "--seeds" | "--objects" | "--joints" | "--match-threshold" => listed.replace("{v}", value),
            _ => value.to_string(),
        };
        let mut args: Vec<String> = before.iter().map(|a| fill(a)).collect();
        // `--option=value`: a value such as `-inf` is not read as options.
        args.push(format!("{option}={value}"));
        args.extend(after.iter().map(|a| fill(a)));
        // A `--set` refusal names the field or the table on its way that is wrong
        // (`explore`: missing field `task`).
        let names = if option == "--set" {
            let parts: Vec<&str> = field.split('.').collect();
            (1..=parts.len()).map(|k| format!("`{}`", parts[..k].join("."))).collect()
        } else {
            vec![option.trim_start_matches('-').to_string()]
        };
        run(&Case { args, cwd: tmp.path(), names, watch: vec![] })?;
    }
}
