//! The scripted arm tour (`scenarios/arm_tour.toml`) and `check`.

use super::*;
use std::path::Path;

#[test]
fn the_arm_tour_reaches_its_waypoints_within_the_joint_speed_limit() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = arm_tour_in(tmp.path());
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
    let chunks = recording::checked(
        path,
        &[
            "world/arm/skeleton",
            "world/arm/tip",
            "world/arm/tip_path",
            "world/waypoints",
        ],
    );
    let entities = whisker_recording::decode::entities(&chunks);
    assert!(entities.values().all(|e| !e.timelines.contains("log_time")));
    assert_eq!(entities["/world/arm/tip"].rows, samples);
    assert_eq!(entities["/world/arm/skeleton"].rows, samples);
}

#[test]
fn check_validates_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = arm_tour_in(tmp.path());
    let o = whisker(&["check", scenario.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("base_link -> whisker_array, 6 joints") && text.trim_end().ends_with("ok"),
        "{text}"
    );
    assert!(!tmp.path().join("out").exists());
}
