//! `whisker characterize` and runs with `sensing = "physics"`.

use super::*;

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
    // The console explains the lines, lists the files and shows progress while it runs
    // (a line a tenth off a terminal).
    let out = tmp.path().join("out-physics");
    console::assert_console(&o, "Run a scenario", &["front end", "whisking"], Some(&out));
    assert!(
        stdout(&o).contains("recording  none (switched off"),
        "{}",
        stdout(&o)
    );
    assert!(
        stderr(&o)
            .lines()
            .filter(|l| l.starts_with("progress   "))
            .count()
            >= 5,
        "{}",
        stderr(&o)
    );
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

/// Overrides apply from the most general level to the most specific: `[array.shaft]`,
/// then the ring, then the whisker; `check` lists the resulting design of every whisker.
#[test]
fn array_overrides_apply_by_precedence() {
    let tmp = tempfile::tempdir().unwrap();
    let body = PHYSICS
        .replace("[array]\n", "[array]\nshaft = { youngs_modulus_pa = 2.0e9 }\n")
        .replacen("[[array.rings]]\nfrequency_hz = 2.0\n[[array.rings]]\nfrequency_hz = 2.0\n", "[[array.rings]]\nfrequency_hz = 2.0\n[[array.rings]]\nfrequency_hz = 3.0\nlength_m = 0.09\n", 1)
        .replace("[[trajectory", "[array.whiskers.C2]\nlength_m = 0.095\nyoungs_modulus_pa = 2.8e9\n[[trajectory");
    let path = tmp.path().join("overrides.toml");
    std::fs::write(&path, with_urdf(&body).replace("OUT", "\"out\"")).unwrap();
    let o = whisker(&["check", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let line = |pixel: &str| {
        text.lines()
            .find(|l| l.trim_start().starts_with(pixel))
            .unwrap_or_else(|| panic!("{pixel} missing: {text}"))
            .to_string()
    };
    assert!(
        line("A1").contains("L  60.0 mm")
            && line("A1").contains("E 2.00 GPa")
            && line("A1").contains("at 2 Hz"),
        "{}",
        line("A1")
    );
    assert!(
        line("B2").contains("L  90.0 mm")
            && line("B2").contains("E 2.00 GPa")
            && line("B2").contains("at 3 Hz"),
        "{}",
        line("B2")
    );
    assert!(
        line("C2").contains("L  95.0 mm") && line("C2").contains("E 2.80 GPa"),
        "{}",
        line("C2")
    );
    assert!(line("C3").contains("L 160.0 mm"), "{}", line("C3"));
}
