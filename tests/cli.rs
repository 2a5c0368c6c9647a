//! End-to-end tests of the `whisker` binary: the quickstart run, `check`, `urdf fk` on
//! any standard UR5 description, and bad input (exit code 2, file and field named,
//! nothing written).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn whisker(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(args)
        .output()
        .expect("whisker runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs `scenario` with its output redirected to `out` (which is returned); must succeed.
fn run_into(scenario: &Path, out: &Path) -> PathBuf {
    let o = whisker(&[
        "run",
        scenario.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    out.to_path_buf()
}

/// The quickstart scenario's text with its output directory and URDF made absolute, so
/// it can be run from a temporary directory.
fn quickstart_in(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo("scenarios/quickstart.toml")).unwrap();
    let urdf = repo("assets/urdf/ur5_whisker_array.urdf");
    let text = text
        .replace(
            "\"../assets/urdf/ur5_whisker_array.urdf\"",
            &format!("{:?}", urdf.display().to_string()),
        )
        .replace(
            "\"out/quickstart\"",
            &format!("{:?}", dir.join("out").display().to_string()),
        );
    let path = dir.join("quickstart.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn quickstart_reaches_its_waypoints_within_the_joint_speed_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = quickstart_in(tmp.path());
    let o = whisker(&["run", scenario.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("out");

    // Every pose waypoint of the scenario is reached by the tip (FK of the IK answer).
    let spec: toml::Value = toml::from_str(&std::fs::read_to_string(&scenario).unwrap()).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let wanted = spec["trajectory"]["waypoints"].as_array().unwrap();
    let reached = summary["waypoints"].as_array().unwrap();
    assert_eq!(reached.len(), wanted.len() + 1, "start + waypoints");
    let floats = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    for (w, r) in wanted.iter().zip(&reached[1..]) {
        if let Some(p) = w.get("position_m") {
            let p: Vec<f64> = p
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_float().unwrap())
                .collect();
            let got = floats(&r["tip_position_m"]);
            for i in 0..3 {
                assert!(
                    (p[i] - got[i]).abs() < 1e-6,
                    "waypoint {w:?}: tip at {got:?}"
                );
            }
        }
    }

    // path.csv: the documented header, a row per sample, joint speeds ≤ 0.1 rad/s, and the
    // final row at the last waypoint.
    let csv = std::fs::read_to_string(out.join("path.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "t_s");
    assert_eq!(header[1], "shoulder_pan_joint_rad");
    assert_eq!(
        header[7..],
        [
            "tip_x_m",
            "tip_y_m",
            "tip_z_m",
            "tip_qx",
            "tip_qy",
            "tip_qz",
            "tip_qw",
            "arm_collision"
        ]
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len() as u64, summary["samples"].as_u64().unwrap());
    let mut peak: f64 = 0.0;
    for w in rows.windows(2) {
        let dt = w[1][0] - w[0][0];
        if dt <= 0.0 {
            continue;
        }
        for (a, b) in w[0][1..7].iter().zip(&w[1][1..7]) {
            peak = peak.max((b - a).abs() / dt);
        }
    }
    assert!(peak <= 0.1 + 1e-9, "a joint moved at {peak} rad/s");
    assert!(
        peak > 0.099,
        "the slowest-limited joint should move at the limit, peak {peak}"
    );
    let last = rows.last().unwrap();
    let home = floats(&reached[0]["joints_rad"]);
    for j in 0..6 {
        assert!((last[1 + j] - home[j]).abs() < 1e-9);
    }
    // The unit quaternion columns are normalised.
    for r in &rows {
        let n = (r[10] * r[10] + r[11] * r[11] + r[12] * r[12] + r[13] * r[13]).sqrt();
        assert!((n - 1.0).abs() < 1e-9);
    }
    check_recording(&out.join("run.rrd"), rows.len());
    // No temporary files are left behind.
    for entry in std::fs::read_dir(&out).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.starts_with('.'), "left over: {name}");
    }

    // Same seed, same bytes (results do not depend on anything but the scenario).
    let again = run_into(&scenario, &tmp.path().join("again"));
    assert_eq!(
        std::fs::read(out.join("path.csv")).unwrap(),
        std::fs::read(again.join("path.csv")).unwrap()
    );
}

/// Reads `run.rrd` back with Rerun's decoder: the documented entities are there, the tip
/// frame is logged once per sample on the `sim_time` timeline, and there is no wall-clock
/// `log_time` timeline.
fn check_recording(path: &Path, samples: usize) {
    use rerun::external::re_log_encoding::DecoderApp;
    use rerun::log::{Chunk, LogMsg};
    let reader = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut rows = std::collections::BTreeMap::<String, usize>::new();
    for msg in DecoderApp::decode_eager(reader).expect("an RRD file") {
        if let LogMsg::ArrowMsg(_, arrow) = msg.expect("decodes") {
            let chunk = Chunk::from_arrow_msg(&arrow).expect("a chunk");
            assert!(!chunk.timelines().keys().any(|t| t.as_str() == "log_time"));
            *rows.entry(chunk.entity_path().to_string()).or_default() += chunk.num_rows();
        }
    }
    for entity in [
        "/world/arm/skeleton",
        "/world/arm/tip",
        "/world/arm/tip_path",
        "/world/waypoints",
    ] {
        assert!(rows.contains_key(entity), "{entity} missing from {rows:?}");
    }
    assert_eq!(rows["/world/arm/tip"], samples);
    assert_eq!(rows["/world/arm/skeleton"], samples);
}

#[test]
fn check_validates_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = quickstart_in(tmp.path());
    let o = whisker(&["check", scenario.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("base_link -> whisker_array, 6 joints") && text.trim_end().ends_with("ok"),
        "{text}"
    );
    assert!(!tmp.path().join("out").exists());
}

#[test]
fn urdf_fk_gives_the_published_ur5_poses_for_any_standard_description() {
    let cases = [
        ("0,0,0,0,0,0", [0.817250, 0.191450, -0.005491]),
        (
            "0,-1.5707963267948966,0,-1.5707963267948966,0,0",
            [0.0, 0.191450, 1.001059],
        ),
        ("0.1,-0.5,0.8,-1.2,1.5,0.3", [0.857037, 0.201539, 0.182468]),
    ];
    for urdf in [
        "assets/urdf/ur5_whisker_array.urdf",
        "tests/fixtures/ur5_ros_style.urdf",
    ] {
        let path = repo(urdf);
        for (q, expected) in cases {
            let o = whisker(&[
                "urdf",
                "fk",
                path.to_str().unwrap(),
                "--joints",
                q,
                "--json",
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
            assert_eq!(v["base"], "base_link");
            assert_eq!(v["link"], "tool0");
            for i in 0..3 {
                let got = v["position_m"][i].as_f64().unwrap();
                assert!(
                    (got - expected[i]).abs() < 1e-6,
                    "{urdf} q={q}: {got} vs {}",
                    expected[i]
                );
                assert_eq!(v["matrix"][i][3].as_f64().unwrap(), got);
            }
            let quat: Vec<f64> = (0..4)
                .map(|i| v["quaternion_xyzw"][i].as_f64().unwrap())
                .collect();
            assert!((quat.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }
    // --base and --link choose the frames; the array mount is 60 mm beyond tool0.
    let path = repo("assets/urdf/ur5_whisker_array.urdf");
    let o = whisker(&[
        "urdf",
        "fk",
        path.to_str().unwrap(),
        "--joints",
        "0,0,0,0,0,0",
        "--base",
        "base_link",
        "--link",
        "whisker_array",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert!((v["position_m"][1].as_f64().unwrap() - (0.191450 + 0.060)).abs() < 1e-6);
    let info = whisker(&["urdf", "info", path.to_str().unwrap()]);
    assert!(info.status.success());
    assert!(stdout(&info).contains("chain  base_link -> tool0: 6 joints"));
}

/// Writes a scenario holding `body` (with `URDF` replaced by the project's arm) and runs it.
fn run_bad(dir: &Path, name: &str, body: &str) -> (Output, PathBuf) {
    let urdf = repo("assets/urdf/ur5_whisker_array.urdf");
    let path = dir.join(format!("{name}.toml"));
    let text = body
        .replace("URDF", &format!("{:?}", urdf.display().to_string()))
        .replace(
            "OUT",
            &format!(
                "{:?}",
                dir.join(format!("out-{name}")).display().to_string()
            ),
        );
    std::fs::write(&path, text).unwrap();
    (whisker(&["run", path.to_str().unwrap()]), path)
}

const ARM: &str = "[arm]\nurdf = URDF\ninitial_joints_deg = [0, -90, 90, -90, -90, 0]\n";
const WAYPOINT: &str = "[[trajectory.waypoints]]\njoints_deg = [0, -80, 80, -90, -90, 0]\n";
const OUTPUT: &str = "[output]\ndir = OUT\n";

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
    let cases: Vec<(&str, String, &str)> = vec![
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
        ("missing_section", format!("{ARM}{OUTPUT}"), "trajectory"),
        (
            "missing_urdf_file",
            format!(
                "[arm]\nurdf = \"nowhere.urdf\"\ninitial_joints_deg = [0,0,0,0,0,0]\n{WAYPOINT}{OUTPUT}"
            ),
            "arm.urdf",
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
    ];
    for (name, body, field) in &cases {
        let (o, path) = run_bad(tmp.path(), name, body);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains(path.file_name().unwrap().to_str().unwrap())
                || err.contains("cyclic.urdf"),
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
    ] {
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn broken_urdfs_exit_2_naming_file_and_element() {
    let tmp = tempfile::tempdir().unwrap();
    let j = |name: &str, parent: &str, child: &str, extra: &str| {
        format!(
            r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>"#
        )
    };
    let links = r#"<link name="a"/><link name="b"/><link name="c"/>"#;
    let cases = [
        (
            "missing_parent",
            format!("{links}{}{}", j("j1", "x", "b", ""), j("j2", "b", "c", "")),
            "<joint name=\"j1\">",
        ),
        (
            "cycle",
            format!(
                "{links}{}{}{}",
                j("j1", "a", "b", ""),
                j("j2", "b", "c", ""),
                j("j3", "c", "a", "")
            ),
            "cycle",
        ),
        (
            "two_roots",
            format!("{links}{}", j("j1", "a", "b", "")),
            "root links (a, c)",
        ),
        (
            "nan",
            format!(
                "{links}{}{}",
                j("j1", "a", "b", ""),
                j("j2", "b", "c", r#"<origin xyz="0 nan 0"/>"#)
            ),
            "<joint name=\"j2\">",
        ),
        (
            "bad_number",
            format!(
                "{links}{}{}",
                j("j1", "a", "b", ""),
                j("j2", "b", "c", r#"<origin rpy="0 0 1.5.7"/>"#)
            ),
            "rpy=\"0 0 1.5.7\"",
        ),
    ];
    for (name, body, needle) in cases {
        let path = tmp.path().join(format!("{name}.urdf"));
        std::fs::write(&path, format!("<robot name=\"r\">{body}</robot>")).unwrap();
        for args in [
            vec!["urdf", "info", path.to_str().unwrap()],
            vec!["urdf", "fk", path.to_str().unwrap(), "--joints", "0,0"],
        ] {
            let o = whisker(&args);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{name}: {err}");
            assert!(
                err.contains(&format!("{name}.urdf")) && err.contains(needle),
                "{name}: {err}"
            );
        }
    }
}

#[test]
fn characterize_reports_a_whisker_in_moment_balance() {
    let o = whisker(&[
        "characterize",
        "--length",
        "0.06",
        "--segments",
        "10",
        "--force",
        "0.004",
        "--at",
        "0.05",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let get = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} missing"));
    // Statics: the base carries the load's moment; the shaft bends towards the load, more
    // at the tip than at the load point; the magnet moves the other way.
    assert!((get("base_moment_nm") / (0.004 * 0.05) - 1.0).abs() < 0.01);
    assert!(get("tip_deflection_m") > get("load_deflection_m") && get("load_deflection_m") > 0.0);
    assert!(get("follicle_deflection_m") < 0.0);
    // A 60 mm whisker rings at a few hundred hertz at most (clamped: 180 Hz).
    assert!((50.0..200.0).contains(&get("first_frequency_hz")));
    assert!((0.0..0.1).contains(&get("damping_ratio")));
    for (args, needle) in [
        (vec!["characterize", "--length", "-1"], "length"),
        (vec!["characterize", "--at", "0.5"], "--at"),
        (
            vec!["characterize", "--tip-diameter", "0.003"],
            "tip_diameter",
        ),
        (vec!["characterize", "--segments", "1"], "segments"),
        (
            vec!["characterize", "--follicle-stiffness", "nan"],
            "--follicle-stiffness",
        ),
    ] {
        let o = whisker(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}

const PHYSICS: &str = "sensing = \"physics\"\n[arm]\nurdf = URDF\ninitial_joints_deg = [0, -90, 90, -90, -90, 0]\n[array]\nsegments = 8\nbending = \"sweep-plane\"\n[[array.rings]]\nfrequency_hz = 2.0\n[[array.rings]]\nfrequency_hz = 2.0\n[[array.rings]]\nfrequency_hz = 2.0\n[[trajectory.waypoints]]\njoints_deg = [0, -90, 90, -90, -90, 0]\nhold_s = 0.5\n[output]\ndir = OUT\nrecording = false\n";

#[test]
fn physics_runs_write_reproducible_2_khz_whisker_streams() {
    let tmp = tempfile::tempdir().unwrap();
    let (o, _) = run_bad(tmp.path(), "physics", PHYSICS);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(tmp.path().join("out-physics/whiskers.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.len(), 1 + 18 * 3);
    assert_eq!(&header[1..4], ["A1_angle_rad", "A1_x", "A1_y"]);
    assert_eq!(header[54], "F3_y");
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 1000, "0.5 s at 2 kHz");
    for r in &rows {
        let t = r[0];
        // Open-loop whisking at 2 Hz between 40° and 140° (angle noise 0.05°, resolution 0.088°).
        let expected = 90.0 - 50.0 * (std::f64::consts::TAU * 2.0 * t).cos();
        for w in 0..18 {
            let (angle, x, y) = (r[1 + 3 * w].to_degrees(), r[2 + 3 * w], r[3 + 3 * w]);
            assert!(
                (angle - expected).abs() < 0.5,
                "t {t}: whisker {w} at {angle}° instead of {expected}°"
            );
            assert!(x.fract() == 0.0 && y.fract() == 0.0 && x.abs() <= 2047.0 && y.abs() <= 2047.0);
        }
    }
    // Same seed, same bytes.
    let again = run_into(&tmp.path().join("physics.toml"), &tmp.path().join("again"));
    assert_eq!(
        csv.as_bytes(),
        std::fs::read(again.join("whiskers.csv")).unwrap()
    );

    for (name, body, field) in [
        (
            "bad_pixel",
            PHYSICS.replace(
                "[[trajectory",
                "[array.whiskers.G7]\nlength_m = 0.1\n[[trajectory",
            ),
            "array.whiskers.G7",
        ),
        (
            "bad_frequency",
            PHYSICS.replacen("frequency_hz = 2.0", "frequency_hz = 0.0", 1),
            "array.rings[0].frequency_hz",
        ),
        (
            "bad_period",
            PHYSICS.replace(
                "recording = false",
                "recording = false\nsample_period_s = 0.0003",
            ),
            "output.sample_period_s",
        ),
        (
            "bad_shaft",
            PHYSICS.replace(
                "[[array.rings]]\nfrequency_hz = 2.0\n[[trajectory",
                "[[array.rings]]\nfrequency_hz = 2.0\ntip_diameter_m = 0.01\n[[trajectory",
            ),
            "tip_diameter",
        ),
        (
            "bad_bending",
            PHYSICS.replace("sweep-plane", "wobbly"),
            "bending",
        ),
    ] {
        let (o, _) = run_bad(tmp.path(), name, &body);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(field), "{name}: {}", stderr(&o));
    }
}
