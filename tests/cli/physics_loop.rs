//! The closed loop on physics whiskers (issue #61): the scenario's `[frontend.detection]`
//! and `[array] rcp` are what the held whisks detect with, a map records how it was
//! sensed and a map sensed the other way is refused unless the scenario asks for the
//! transfer, and the same seed gives the same bytes on 1 and 2 threads.

use super::*;
use whisker_scenario::ScenarioFile;
use whisker_scenario::overrides::Override;

/// `recognise_box_physics.toml` with the fast sweep-plane whiskers, `whisks` whisks, and
/// `extra` overrides.
fn physics_loop(whisks: usize, extra: &[&str]) -> ScenarioFile {
    let n = format!("explore.max_iterations={whisks}");
    let mut sets = vec![
        n.as_str(),
        "array.bending=\"sweep-plane\"",
        "array.segments=8",
        "array.substeps=2",
    ];
    sets.extend_from_slice(extra);
    let overrides: Vec<Override> = sets.iter().map(|s| Override::parse(s).unwrap()).collect();
    ScenarioFile::load_with(&repo("scenarios/recognise_box_physics.toml"), &overrides).unwrap()
}

fn contacts(out: &whisker_experiments::closed_loop::Outcome) -> usize {
    out.cycles.iter().map(|c| c.contacts.len()).sum()
}

/// A least peak width longer than the whisk leaves the whisks empty; RCP at 20 σ against
/// none changes the streams and so the contacts (the shaft keeps pressing after it would
/// have retracted; at saturation, 2047 counts, these few whisks may never retract), and
/// without RCP a confirmation above the sensor's range — written
/// (`levels = "as-written"`) or as a multiple of the free-whisking σ (the default noise
/// rule) — leaves the whisks empty too (with RCP it is cut to half the threshold,
/// `sensing::detection`). Before issue #61 the held whisk used the default detection and
/// RCP at saturation whatever the scenario said.
#[test]
fn the_scenarios_detection_and_rcp_change_what_the_physics_loop_detects() {
    let base = closed_loop(&physics_loop(8, &[]));
    assert!(contacts(&base) >= 8, "{} contacts", contacts(&base));
    let wide = closed_loop(&physics_loop(
        8,
        &["frontend.detection.peaks.min_width=1e6"],
    ));
    assert_eq!(contacts(&wide), 0);
    let open = closed_loop(&physics_loop(8, &["array.rcp=\"off\""]));
    assert!(contacts(&open) >= 8, "{} contacts", contacts(&open));
    let rcp = closed_loop(&physics_loop(8, &["array.rcp=\"noise\""]));
    assert_ne!(open.contacts_csv, rcp.contacts_csv);
    for deaf in [
        [
            "frontend.levels=\"as-written\"",
            "frontend.detection.confirm_counts=1e6",
        ],
        ["frontend.levels=\"noise\"", "frontend.noise_multiple=1e6"],
    ] {
        let deaf = closed_loop(&physics_loop(8, &["array.rcp=\"off\"", deaf[0], deaf[1]]));
        assert_eq!(contacts(&deaf), 0);
    }
}

/// A physics loop gives the same bytes on 1 and 2 threads.
#[test]
fn a_physics_loop_gives_the_same_bytes_on_one_and_two_threads() {
    let file = physics_loop(12, &[]);
    let outputs: Vec<(String, String, String)> = [1, 2]
        .iter()
        .map(|&threads| {
            on_threads(threads, || {
                let out = closed_loop(&file);
                (out.csv, out.summary.to_string(), out.contacts_csv)
            })
        })
        .collect();
    assert_eq!(outputs[0], outputs[1]);
}

/// A kinematic map given to a physics run is refused (exit 2, the map and the way out
/// named) unless `explore.transfer = true`; a map built by a run records its sensing.
#[test]
fn maps_sensed_the_other_way_are_refused_unless_the_transfer_is_asked_for() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = repo("scenarios/recognise_box_physics.toml");
    let s = scenario.to_str().unwrap();
    let kinematic_maps = [
        "--set",
        "explore.maps.box=\"../assets/maps/box.json\"",
        "--set",
        "explore.maps.box_stack=\"../assets/maps/box_stack.json\"",
    ];
    let out = tmp.path().join("refused");
    let mut args = vec!["run", s, "--out", out.to_str().unwrap()];
    args.extend_from_slice(&kinematic_maps);
    let o = whisker(&args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("explore.maps.box")
            && e.contains("built on kinematic sensing")
            && e.contains("explore.transfer = true"),
        "{e}"
    );
    assert!(!out.exists());
    keep_refusal(&args, &o);
    // The same maps with the transfer asked for: the run goes.
    let out = tmp.path().join("transfer");
    let mut args = vec!["run", s, "--out", out.to_str().unwrap()];
    args.extend_from_slice(&kinematic_maps);
    args.extend_from_slice(&[
        "--set",
        "explore.transfer=true",
        "--set",
        "explore.max_iterations=2",
        "--set",
        "array.bending=\"sweep-plane\"",
        "--set",
        "array.segments=8",
    ]);
    let o = whisker(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    // The other way: a physics map on kinematic whiskers.
    let out = tmp.path().join("back");
    let args = [
        "run",
        s,
        "--out",
        out.to_str().unwrap(),
        "--set",
        "sensing=\"kinematic\"",
    ];
    let o = whisker(&args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("built on physics sensing"),
        "{}",
        stderr(&o)
    );
    // A map built by a run says how it was sensed.
    let map_out = tmp.path().join("map");
    let o = whisker(&[
        "run",
        repo("scenarios/explore_map_box.toml").to_str().unwrap(),
        "--out",
        map_out.to_str().unwrap(),
        "--set",
        "explore.max_iterations=3",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(map_out.join("map.json")).unwrap()).unwrap();
    assert_eq!(map["version"], 2);
    assert_eq!(map["sensing"]["mode"], "kinematic");
    assert!(
        map["sensing"]["array"]
            .as_str()
            .unwrap()
            .starts_with("18 straight whiskers swept kinematically"),
        "{}",
        map["sensing"]
    );
}

/// `whisker fidelity` refuses an unknown object and zero poses (exit 2, the option named),
/// writing nothing.
#[test]
fn fidelity_refuses_unknown_objects_and_no_poses() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("fidelity");
    let o = out.to_str().unwrap();
    for (args, named) in [
        (
            vec!["fidelity", "--objects", "teapot", "--out", o],
            "--objects",
        ),
        (vec!["fidelity", "--poses", "0", "--out", o], "--poses"),
    ] {
        let r = whisker(&args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", stderr(&r));
        assert!(stderr(&r).contains(named), "{}", stderr(&r));
        assert!(!out.exists());
        keep_refusal(&args, &r);
    }
}
