//! Malformed scenarios and command lines.

use super::*;

#[test]
fn malformed_scenarios_exit_2_naming_file_and_field_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cyclic = tmp.path().join("cyclic.urdf");
    std::fs::write(
        &cyclic,
        r#"<robot name="c"><link name="a"/><link name="b"/>
        <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
        <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint></robot>"#,
    )
    .unwrap();
    let cyclic_arm = format!(
        "[arm]\nurdf = {:?}\ninitial_joints_deg = []\n",
        cyclic.display().to_string()
    );
    let box_object = format!(
        "[[objects]]\nmesh = {:?}\nname = \"box\"\nposition_m = [0.55, 0, 0]\n",
        repo("assets/meshes/box.obj").display().to_string()
    );
    // A valid scenario for the `base` cases to build on.
    let good = with_urdf(&format!("{ARM}{WAYPOINT}[output]\ndir = \"out-good\"\n"));
    std::fs::write(tmp.path().join("good_base.toml"), good).unwrap();
    let cases: Vec<(&str, String, &str)> = vec![
        ("base_elsewhere", "base = \"../x.toml\"\n".into(), "base"),
        // "cannot read scenario: Is a directory", naming neither file nor field, before #37.
        ("base_dot", "base = \".\"\n".into(), "field `base`"),
        ("base_cycle", "base = \"base_cycle.toml\"\n".into(), "base"),
        (
            "base_missing",
            "base = \"nowhere.toml\"\n".into(),
            "nowhere.toml",
        ),
        (
            "base_merged_unknown",
            "base = \"good_base.toml\"\ncolour = 1\n".into(),
            "colour",
        ),
        // toml names no field for an enum or an untagged enum in a table (a scenario
        // merged over its base): "wanted exactly 1 element, found 0 elements" and "data
        // did not match any variant of untagged enum Seeds" before #37.
        (
            "base_merged_enum",
            "base = \"good_base.toml\"\nsensing = {}\n".into(),
            "field `sensing`",
        ),
        (
            "base_merged_seeds",
            "base = \"good_base.toml\"\n[trials]\nseeds = \"x\"\n".into(),
            "field `trials.seeds`: expected a list of seeds",
        ),
        (
            "base_merged_bad_value",
            "base = \"good_base.toml\"\n[maze_slam]\nimages = []\n".into(),
            "maze_slam.images",
        ),
        (
            "maze_slam_bad",
            format!(
                "{ARM}{WAYPOINT}{OUTPUT}[maze_slam.ratslam.local_view]\nmatch_threshold = -1.0\n"
            ),
            "local_view.match_threshold",
        ),
        (
            "unknown_field",
            format!("{ARM}colour = \"red\"\n{WAYPOINT}{OUTPUT}"),
            "colour",
        ),
        (
            "wrong_type",
            format!("seed = \"one\"\n{ARM}{WAYPOINT}{OUTPUT}"),
            "seed",
        ),
        // An array where a table is expected was read positionally (dir, sample_period_s,
        // recording) before #37.
        (
            "table_as_array",
            format!("output = [OUT, 0.01, false]\n{ARM}{WAYPOINT}"),
            "field `output`: expected a table",
        ),
        (
            "waypoint_as_array",
            format!(
                "{ARM}[trajectory]\nwaypoints = [[[0.3, 0, 0.3], [0, 0, 0], [0, -80, 80, -90, -90, 0], 1.0]]\n{OUTPUT}"
            ),
            "field `trajectory.waypoints[0]`: expected a table",
        ),
        (
            "base_merged_table_as_array",
            "base = \"good_base.toml\"\noutput = [OUT, 0.01, true]\n".into(),
            "field `output`: expected a table",
        ),
        ("missing_section", format!("{ARM}{OUTPUT}"), "trajectory"),
        (
            "missing_urdf_file",
            format!(
                "[arm]\nurdf = \"nowhere.urdf\"\ninitial_joints_deg = [0,0,0,0,0,0]\n{WAYPOINT}{OUTPUT}"
            ),
            "arm.urdf",
        ),
        // Positive but absurd: each ran (and wrote rows) for ever before #37.
        (
            "nanosecond_period",
            format!("{ARM}{WAYPOINT}{OUTPUT}sample_period_s = 1e-9\n"),
            "field `output.sample_period_s`: expected a number from 5e-4 to 1 s, got 1e-9",
        ),
        (
            "crawling_arm",
            format!("{ARM}joint_speed_limit_rad_s = 1e-300\n{WAYPOINT}{OUTPUT}"),
            "expected a number of at least 0.001 rad/s, got 1e-300",
        ),
        (
            "endless_hold",
            format!("{ARM}{WAYPOINT}hold_s = 1e308\n{OUTPUT}"),
            "field `trajectory.waypoints[0].hold_s`: expected a number of seconds from 0 to 3600",
        ),
        (
            "negative_speed",
            format!("{ARM}joint_speed_limit_rad_s = -0.1\n{WAYPOINT}{OUTPUT}"),
            "arm.joint_speed_limit_rad_s",
        ),
        (
            "joint_count",
            format!("[arm]\nurdf = URDF\ninitial_joints_deg = [0, -90, 90]\n{WAYPOINT}{OUTPUT}"),
            "arm.initial_joints_deg",
        ),
        (
            "nan_joint",
            format!(
                "[arm]\nurdf = URDF\ninitial_joints_deg = [0, nan, 90, -90, -90, 0]\n{WAYPOINT}{OUTPUT}"
            ),
            "arm.initial_joints_deg[1]",
        ),
        (
            "outside_limits",
            format!(
                "[arm]\nurdf = URDF\ninitial_joints_deg = [0, -90, 200, -90, -90, 0]\n{WAYPOINT}{OUTPUT}"
            ),
            "arm.initial_joints_deg[2]",
        ),
        (
            "both_kinds",
            format!(
                "{ARM}[[trajectory.waypoints]]\nposition_m = [0.5, 0, 0.3]\nrpy_deg = [180, 0, 0]\njoints_deg = [0,0,0,0,0,0]\n{OUTPUT}"
            ),
            "trajectory.waypoints[0]",
        ),
        (
            "half_pose",
            format!("{ARM}[[trajectory.waypoints]]\nposition_m = [0.5, 0, 0.3]\n{OUTPUT}"),
            "trajectory.waypoints[0]",
        ),
        (
            "unreachable",
            format!(
                "{ARM}{WAYPOINT}[[trajectory.waypoints]]\nposition_m = [2.0, 0, 0.3]\nrpy_deg = [180, 0, 0]\n{OUTPUT}"
            ),
            "trajectory.waypoints[1]",
        ),
        (
            "inf_position",
            format!(
                "{ARM}[[trajectory.waypoints]]\nposition_m = [inf, 0, 0.3]\nrpy_deg = [180, 0, 0]\n{OUTPUT}"
            ),
            "trajectory.waypoints[0].position_m[0]",
        ),
        (
            "negative_hold",
            format!(
                "{ARM}[[trajectory.waypoints]]\njoints_deg = [0, -80, 80, -90, -90, 0]\nhold_s = -1\n{OUTPUT}"
            ),
            "trajectory.waypoints[0].hold_s",
        ),
        (
            "no_waypoints",
            format!("{ARM}[trajectory]\nwaypoints = []\n{OUTPUT}"),
            "trajectory.waypoints",
        ),
        (
            "unknown_link",
            format!("{ARM}tip_link = \"flange\"\n{WAYPOINT}{OUTPUT}"),
            "flange",
        ),
        (
            "zero_period",
            format!("{ARM}{WAYPOINT}{OUTPUT}sample_period_s = 0.0\n"),
            "output.sample_period_s",
        ),
        (
            "bad_version",
            format!("version = 2\n{ARM}{WAYPOINT}{OUTPUT}"),
            "version",
        ),
        (
            "cyclic_urdf",
            format!("{cyclic_arm}{WAYPOINT}{OUTPUT}"),
            "cycle",
        ),
        ("not_toml", "[arm\nurdf = ".to_string(), "line 1"),
        (
            "explore_with_waypoints",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"map\"\n{WAYPOINT}{OUTPUT}"
            ),
            "trajectory.waypoints",
        ),
        (
            "explore_without_sensing",
            format!("{ARM}{box_object}[explore]\ntask = \"map\"\n{OUTPUT}"),
            "sensing",
        ),
        (
            "explore_bad_strategy",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"map\"\nstrategy = \"random\"\n{OUTPUT}"
            ),
            "strategy",
        ),
        (
            "explore_missing_map",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"recognise\"\nmaps = {{ box = \"nowhere.json\" }}\n{OUTPUT}"
            ),
            "explore.maps.box",
        ),
        (
            "explore_corrupt_map",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"recognise\"\nmaps = {{ box = {:?} }}\n{OUTPUT}",
                repo("scenarios/quickstart.toml").display().to_string()
            ),
            "explore.maps.box",
        ),
        (
            "explore_unknown_object",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"map\"\nobject = \"mug\"\n{OUTPUT}"
            ),
            "explore.object",
        ),
        (
            "explore_bad_cone",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"map\"\n[explore.placement]\ncone_deg = 120\n{OUTPUT}"
            ),
            "explore.placement.cone_deg",
        ),
        (
            "explore_bad_decay",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}[explore]\ntask = \"map\"\n[explore.recognition]\ndecay = 1.5\n{OUTPUT}"
            ),
            "explore.recognition.decay",
        ),
        (
            "whisking_shift_past_the_limit",
            format!(
                "sensing = \"physics\"\n{ARM}[array.whisking]\nspread_reduction = true\ncentre_shift_deg = 30\n{WAYPOINT}{OUTPUT}"
            ),
            "array.whisking.centre_shift_deg",
        ),
        (
            "whisking_fraction",
            format!(
                "sensing = \"kinematic\"\n{ARM}[array.whisking]\nspread_reduction = true\nrange_fraction = 0\n{WAYPOINT}{OUTPUT}"
            ),
            "array.whisking.range_fraction",
        ),
        (
            "whisking_release",
            format!(
                "sensing = \"physics\"\n{ARM}[array.whisking]\nspread_reduction = true\nrelease_cycles = 0\n{WAYPOINT}{OUTPUT}"
            ),
            "array.whisking.release_cycles",
        ),
        (
            "rcp_amplitude_gain_negative",
            format!(
                "sensing = \"physics\"\n{ARM}[array]\nrcp = \"noise\"\nrcp_control = \"amplitude\"\nrcp_amplitude_gain = -1\n{WAYPOINT}{OUTPUT}"
            ),
            "array.rcp_amplitude_gain",
        ),
        (
            "rcp_amplitude_gain_with_retract",
            format!(
                "sensing = \"physics\"\n{ARM}[array]\nrcp = \"noise\"\nrcp_amplitude_gain = 2\n{WAYPOINT}{OUTPUT}"
            ),
            "array.rcp_amplitude_gain",
        ),
        (
            "rcp_control_unknown",
            format!(
                "sensing = \"physics\"\n{ARM}[array]\nrcp = \"noise\"\nrcp_control = \"halt\"\n{WAYPOINT}{OUTPUT}"
            ),
            "rcp_control",
        ),
        (
            "whisking_unknown",
            format!(
                "sensing = \"physics\"\n{ARM}[array.whisking]\nspread = true\n{WAYPOINT}{OUTPUT}"
            ),
            "spread",
        ),
        (
            "object_jitter",
            format!(
                "sensing = \"kinematic\"\n{ARM}{box_object}jitter_yaw_deg = 200\n{WAYPOINT}{OUTPUT}"
            ),
            "objects[0].jitter_yaw_deg",
        ),
    ];
    for (name, body, field) in &cases {
        let (o, path) = run_bad(tmp.path(), name, body);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains(path.file_name().unwrap().to_str().unwrap())
                || err.contains("cyclic.urdf")
                || err.contains("nowhere.toml"),
            "{name}: file not named: {err}"
        );
        assert!(err.contains(field), "{name}: {field:?} not named: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(
            !tmp.path().join(format!("out-{name}")).exists(),
            "{name}: wrote output"
        );
    }
    let (o, _) = run_bad(tmp.path(), "missing", "");
    assert_eq!(o.status.code(), Some(2));
    let o = whisker(&["run", tmp.path().join("absent.toml").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("absent.toml"));
}

#[test]
fn bad_command_lines_exit_2() {
    let urdf = repo("assets/urdf/ur5_whisker_array.urdf");
    let u = urdf.to_str().unwrap();
    for (args, needle) in [
        (
            vec!["urdf", "fk", u, "--joints", "0,0,zero,0,0,0"],
            "value 3",
        ),
        (
            vec!["urdf", "fk", u, "--joints", "0,0,0"],
            "expected 6 values",
        ),
        (
            vec!["urdf", "fk", u, "--joints", "0,0,0,0,0,0", "--link", "nose"],
            "nose",
        ),
        (
            vec!["urdf", "fk", "/no/such.urdf", "--joints", "0"],
            "/no/such.urdf",
        ),
        (vec!["urdf", "info", "/no/such.urdf"], "/no/such.urdf"),
        (vec!["frobnicate"], "frobnicate"),
        // Accepted (substeps 0, unknown labels) or run for hours (a 5 m whisker's
        // ring-down) before #37.
        (
            vec!["soak", "--substeps", "0"],
            "--substeps 0: expected 1 to 64",
        ),
        (vec!["soak", "--whiskers", "A1,Z9"], "no whisker \"Z9\""),
        (
            vec!["bench", "physics", "--repeat", "0"],
            "--repeat: expected 1 to 100, got 0",
        ),
        (
            vec!["characterize", "--length", "1.5"],
            "first mode is about 0.312 Hz",
        ),
        // A NaN first mode, named neither option nor range, before #37 (fuzzing).
        (
            vec!["characterize", "--length", "1e308"],
            "--length: length must be a number from 0.001 to 2 m, got 1e308",
        ),
    ] {
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

/// A command that fails after creating its output removes what it created (#37: each of
/// these left its `--out` behind, with whatever it had written by then).
#[test]
fn failed_commands_leave_nothing_behind() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let file = t.join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    let under_file = file.join("x.rrd");
    let rrd = under_file.to_str().unwrap();
    let out = |name: &str| t.join(name).to_str().unwrap().to_string();
    let quickstart = repo("scenarios/quickstart.toml");
    let maze = repo("scenarios/maze_short.toml");
    let (q, m) = (quickstart.to_str().unwrap(), maze.to_str().unwrap());
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "run".into(),
                q.into(),
                "--out".into(),
                out("run"),
                "--rrd".into(),
                rrd.into(),
            ],
            "is a file, not a directory",
        ),
        (
            vec![
                "maze-slam".into(),
                m.into(),
                "--out".into(),
                out("maze"),
                "--rrd".into(),
                rrd.into(),
            ],
            "is a file, not a directory",
        ),
        (
            vec![
                "maze-slam".into(),
                m.into(),
                "--out".into(),
                out("images"),
                "--images".into(),
                out("no-such-dir"),
            ],
            "no-such-dir",
        ),
        (
            vec![
                "object-slam".into(),
                "--objects".into(),
                "mug".into(),
                "--out".into(),
                out("objects"),
                "--rrd".into(),
                rrd.into(),
            ],
            "is a file, not a directory",
        ),
    ];
    for (args, needle) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
        let left: Vec<_> = std::fs::read_dir(t)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("a-file")], "{args:?}");
    }
}
