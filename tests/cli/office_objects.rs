//! Object mode in the office (issue #36): where the base stops and what it explores,
//! checked against the office's geometry; the terrain-only baseline and the fused run on
//! the same route and seed differ only in the landmarks; the kidnapped robot re-localises
//! onto an experience made where it truly is.

use super::office::{OBJECTS, office_run as run, swap};
use super::*;

/// Every stop of the default run, checked by the office's geometry: a stop named after an
/// object stands within 1.2 m of that object's centre and its turn faces it (within 30°:
/// the turn aims at the outline seen in the drifting odometry frame); a stop at a wall
/// is farther than 1 m from every object. The outcomes add up in the summary.
#[test]
fn stops_face_the_object_they_explore() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, summary) = run(tmp.path(), "stops", |s| s);
    let stops = rows(&out.join("stops.csv"));
    assert!(!stops.is_empty());
    let path: Vec<Vec<String>> = rows(&out.join("path.csv"));
    let mut outcomes = std::collections::BTreeMap::<String, u64>::new();
    for s in &stops {
        let update: usize = s[0].parse().unwrap();
        let (x, y): (f64, f64) = (s[1].parse().unwrap(), s[2].parse().unwrap());
        let heading: f64 = path[update][4].parse().unwrap();
        assert_eq!(
            (
                path[update][2].parse::<f64>().unwrap(),
                path[update][3].parse::<f64>().unwrap()
            ),
            (x, y)
        );
        let turn = s[3].parse::<f64>().unwrap().to_radians();
        *outcomes.entry(s[9].clone()).or_default() += 1;
        match OBJECTS.iter().find(|o| o.0 == s[7]) {
            Some(&(name, ox, oy)) => {
                assert!((ox - x).hypot(oy - y) < 1.2, "{s:?} far from {name}");
                let bearing = (oy - y).atan2(ox - x);
                let off = (bearing - heading - turn)
                    .sin()
                    .atan2((bearing - heading - turn).cos());
                assert!(
                    off.abs() < 30f64.to_radians(),
                    "{s:?}: {off} rad off {name}"
                );
                assert!(
                    ["correct", "wrong", "none"].contains(&s[9].as_str()),
                    "{s:?}"
                );
                // A learned map (object-<n>) is scored by where it was built.
                if !s[8].starts_with("object-") {
                    assert_eq!(s[9] == "correct", s[8] == name, "{s:?}");
                }
                // Recognising nothing, the stop maps the object.
                assert_eq!(s[9] == "none", s[15].starts_with("object-"), "{s:?}");
            }
            None => {
                assert_eq!((s[7].as_str(), s[9].as_str()), ("", "wall"), "{s:?}");
                for (name, ox, oy) in OBJECTS {
                    assert!((ox - x).hypot(oy - y) > 1.0, "{s:?} near {name}");
                }
            }
        }
    }
    let o = &summary["objects"];
    assert_eq!(o["stops"].as_u64().unwrap(), stops.len() as u64, "{o}");
    let mapped = stops.iter().filter(|s| !s[15].is_empty()).count() as u64;
    assert!(mapped > 0, "the Barrel has no map: a stop there maps it");
    assert_eq!(o["mapped"].as_u64().unwrap(), mapped, "{o}");
    for (k, n) in outcomes {
        assert_eq!(o[&k].as_u64().unwrap(), n, "{k}: {o}");
    }
}

/// The terrain-only baseline (`navigate.fusion = false`) and the fused run share the route,
/// the odometry, the whisks and the stops with their results; only the landmarks differ:
/// the baseline makes none.
#[test]
fn the_baseline_and_the_fused_run_differ_only_in_the_fusion() {
    let tmp = tempfile::tempdir().unwrap();
    let (fused, f) = run(tmp.path(), "fused", |s| s);
    let (base, b) = run(tmp.path(), "baseline", |s| {
        swap(s, "laps = 2", "laps = 2\nfusion = false")
    });
    assert_eq!(
        (f["fusion"].clone(), b["fusion"].clone()),
        (true.into(), false.into())
    );
    let (pf, pb) = (rows(&fused.join("path.csv")), rows(&base.join("path.csv")));
    assert_eq!(pf.len(), pb.len());
    for (a, c) in pf.iter().zip(&pb) {
        // update, time, truth (3), odometry (3), contacts; verdict and piece.
        for i in [0, 1, 2, 3, 4, 5, 6, 7, 11, 15, 16] {
            assert_eq!(a[i], c[i], "column {i}: {a:?} vs {c:?}");
        }
    }
    let (sf, sb) = (
        rows(&fused.join("stops.csv")),
        rows(&base.join("stops.csv")),
    );
    assert_eq!(sf.len(), sb.len());
    for (a, c) in sf.iter().zip(&sb) {
        assert_eq!(a[..12], c[..12], "{a:?} vs {c:?}");
        assert_eq!(a[14..], c[14..], "{a:?} vs {c:?}");
        assert_eq!((c[12].as_str(), c[13].as_str()), ("", ""), "{c:?}");
    }
    assert_eq!(b["objects"]["landmarks"], 0);
    let identified = sf.iter().filter(|s| !s[8].is_empty()).count() as u64;
    assert_eq!(f["objects"]["landmarks"].as_u64().unwrap(), identified);
}

/// The kidnapped robot: carried from A (the corridor) to C (the east room) at the start of
/// the last lap — the truth jumps there while the odometry does not move — it re-localises
/// onto an experience made (by `path.csv`'s truth columns) within 0.3 m of where it is.
#[test]
fn the_kidnapped_robot_relocalises_where_it_truly_is() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, summary) = run(tmp.path(), "kidnap", |s| {
        swap(s, "laps = 2", "laps = 2\nkidnap = true")
    });
    let rows = rows(&out.join("path.csv"));
    let r = &summary["recovery"];
    let j = r["after_update"].as_u64().unwrap() as usize;
    let num = |k: usize, i: usize| rows[k][i].parse::<f64>().unwrap();
    assert_eq!((num(j - 1, 2), num(j - 1, 3)), (0.7, 0.7));
    assert_eq!((num(j, 2), num(j, 3)), (5.5, 3.3));
    assert_eq!((num(j, 5), num(j, 6)), (num(j - 1, 5), num(j - 1, 6)));
    assert_eq!(r["recovered"], 1, "{r}");
    let at = r["recovered_at"].as_u64().unwrap() as usize;
    assert!(at >= j);
    if r["by_landmark"] == 0 {
        assert_eq!(rows[at][14], "relocalised");
        let exp = &rows[at][13];
        let made = rows
            .iter()
            .position(|row| &row[13] == exp && row[14] == "created")
            .unwrap();
        assert!(made < j, "made at {made}, after the carry at {j}");
        let d = (num(made, 2) - num(at, 2)).hypot(num(made, 3) - num(at, 3));
        assert!(d <= 0.3, "{d} m");
    }
}

/// Physics sensing on the moving base (`sensing = "physics"`): a short stretch along the
/// south wall, with the array 4 cm nearer the wall than the default posture (there the
/// longest whiskers' tips only graze it, below the sensor's RCP threshold). The physics
/// whiskers touch the wall on the same whisks as the kinematic sweep, give or take one,
/// and nothing collides.
#[test]
fn physics_whiskers_touch_the_wall_where_the_kinematic_sweep_does() {
    let tmp = tempfile::tempdir().unwrap();
    let short = |sensing: &'static str| {
        move |s: String| {
            let s = swap(
                s,
                "sensing = \"kinematic\"",
                &format!("sensing = \"{sensing}\""),
            );
            let s = swap(
                s,
                "route_m = [[0.7, 0.7], [5.5, 0.7], [5.5, 3.3], [0.7, 3.3]]   # A, B, C, D\nlaps = 2",
                "route_m = [[0.7, 0.7], [1.3, 0.7]]\nlaps = 1",
            );
            let a = s.find("[navigate.object.explore]").unwrap();
            let b = s.find("[navigate.base]").unwrap();
            format!(
                "{}{}\n[navigate.terrain]\narray_position_m = [0.0, -0.52, -0.1]\n",
                &s[..a],
                &s[b..]
            )
        }
    };
    let (_, physics) = run(tmp.path(), "physics", short("physics"));
    let (_, kinematic) = run(tmp.path(), "kinematic", short("kinematic"));
    let touched = |s: &serde_json::Value| s["whisks_with_contact"].as_i64().unwrap();
    assert!(touched(&physics) >= 5, "{physics}");
    assert!(
        (touched(&physics) - touched(&kinematic)).abs() <= 1,
        "physics {} vs kinematic {}",
        touched(&physics),
        touched(&kinematic)
    );
    assert_eq!(physics["arm_collisions"], 0);
    assert_eq!(physics["base_collisions"], 0);
}
