//! Office datasets (experiment `navigate`, issue #36; docs/dataset.md): `whisker slam`
//! replays the robot's decisions on the logged whisks, odometry and stops — the stops'
//! closed loops open loop, map building included — and reproduces the live run's files
//! but for what needs the office itself; without ground truth the truth's columns and
//! metrics are empty or null; a log whose stops the robot would not make is refused.

use super::dataset::{copy_dir, ok, refused, rehash, s};
use super::office::{office, office_run};
use super::*;

/// `csv`'s rows with the columns named `names` emptied.
fn without(csv: &[Vec<String>], header: &str, names: &[&str]) -> Vec<Vec<String>> {
    let gone: Vec<usize> = header
        .split(',')
        .enumerate()
        .filter(|(_, h)| names.contains(h))
        .map(|(i, _)| i)
        .collect();
    csv.iter()
        .map(|r| {
            r.iter()
                .enumerate()
                .map(|(i, c)| {
                    if gone.contains(&i) {
                        String::new()
                    } else {
                        c.clone()
                    }
                })
                .collect()
        })
        .collect()
}

fn header(path: &Path) -> String {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_string()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The fields of `summary.json` that need the office itself (null in a replay).
const WORLD: [&str; 4] = ["arm_collisions", "base_collisions", "collisions", "switch"];

/// Writes `name`'s office run (with `edit`) live and as a dataset, replays it, and checks
/// that the replay equals the live run but for the world's fields. Returns the dataset
/// and the live run's directory.
fn live_equals_replay(
    t: &Path,
    name: &str,
    edit: impl Fn(String) -> String + Copy,
) -> (PathBuf, PathBuf) {
    let (live, summary) = office_run(t, name, edit);
    let scenario = office(t, &format!("{name}-d"), edit);
    let d = t.join(format!("{name}-dataset"));
    ok(2, &["dataset", s(&scenario), "--out", s(&d)]);
    let r = t.join(format!("{name}-replay"));
    ok(1, &["slam", s(&d), "--out", s(&r)]);
    // path.csv: every column but the piece a contact touched.
    let h = header(&live.join("path.csv"));
    assert_eq!(header(&r.join("path.csv")), h);
    let lp = rows(&live.join("path.csv"));
    assert_eq!(rows(&r.join("path.csv")), without(&lp, &h, &["touched"]));
    assert!(
        lp.iter().any(|r| !r[16].is_empty()),
        "the live run names pieces"
    );
    // stops.csv: byte for byte — where it stopped, how it docked, what each closed loop
    // identified and built, the landmarks.
    assert_eq!(
        std::fs::read_to_string(r.join("stops.csv")).unwrap(),
        std::fs::read_to_string(live.join("stops.csv")).unwrap()
    );
    let mut expected = summary.clone();
    for k in WORLD {
        expected[k] = serde_json::Value::Null;
    }
    assert_eq!(json(&r.join("summary.json")), expected);
    (d, live)
}

/// The default office, seed 0: live = replay; its stops identified and mapped objects and
/// made landmarks, so the replay re-ran recognition against known and learned maps. The
/// same log without `truth/`: the robot's columns are unchanged, the truth's empty, the
/// metrics judged against the truth null. A log with a stop removed or moved is refused.
#[test]
fn office_dataset_replays_the_live_run() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let (d, live) = live_equals_replay(t, "office", |s| s);
    let stops = rows(&live.join("stops.csv"));
    assert!(
        stops.iter().any(|s| !s[8].is_empty()),
        "something identified"
    );
    assert!(stops.iter().any(|s| !s[15].is_empty()), "something mapped");
    assert!(stops.iter().any(|s| !s[12].is_empty()), "a landmark made");
    let m = dataset::manifest(&d);
    assert_eq!(m["experiment"], "navigate");
    assert_eq!(m["navigate"]["object"]["stops"], stops.len());
    for s in &stops {
        let dir = format!(
            "log/stops/{:06}/recognise/contacts.csv",
            s[0].parse::<usize>().unwrap()
        );
        // A loop ran exactly at the stops at objects.
        assert_eq!(d.join(&dir).exists(), !s[7].is_empty(), "{dir}");
    }

    // Without ground truth.
    let bare = t.join("bare");
    copy_dir(&d, &bare);
    std::fs::remove_dir_all(bare.join("truth")).unwrap();
    let r = t.join("bare-replay");
    let o = ok(1, &["slam", s(&bare), "--out", s(&r)]);
    assert!(stdout(&o).contains("map error  – m rms"), "{}", stdout(&o));
    let h = header(&live.join("path.csv"));
    let truth_cols = ["true_x_m", "true_y_m", "true_heading_rad", "touched"];
    assert_eq!(
        rows(&r.join("path.csv")),
        without(&rows(&live.join("path.csv")), &h, &truth_cols)
    );
    let sh = header(&live.join("stops.csv"));
    let stop_truth = ["true_x_m", "true_y_m", "object", "outcome"];
    assert_eq!(
        rows(&r.join("stops.csv")),
        without(&stops, &sh, &stop_truth)
    );
    let bare_summary = json(&r.join("summary.json"));
    let live_summary = json(&live.join("summary.json"));
    for k in [
        "map_error",
        "closures",
        "arr",
        "energy_metric",
        "first_lap_end",
    ] {
        assert!(bare_summary[k].is_null(), "{k}: {bare_summary}");
    }
    for k in [
        "templates",
        "experiences",
        "time_s",
        "contacts",
        "posture_joints_deg",
    ] {
        assert_eq!(bare_summary[k], live_summary[k], "{k}");
    }
    assert!(bare_summary["objects"]["correct"].is_null());
    assert_eq!(
        bare_summary["objects"]["landmarks"],
        live_summary["objects"]["landmarks"]
    );

    // A stop the robot made is missing from the log; a stop moved to another update.
    let text = std::fs::read_to_string(d.join("log/stops.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let cases = [
        (
            "a stop removed",
            lines[..lines.len() - 1].join("\n") + "\n",
            "lists no more stops",
        ),
        (
            "a stop moved",
            text.replacen(
                &format!("\n{},", stops[0][0]),
                &format!("\n{},", stops[0][0].parse::<usize>().unwrap() + 1),
                1,
            ),
            "the robot stops after update",
        ),
    ];
    for (name, bad, expected) in cases {
        let dir = t.join(format!("bad-{}", name.replace(' ', "-")));
        copy_dir(&d, &dir);
        std::fs::write(dir.join("log/stops.csv"), bad).unwrap();
        rehash(&dir, "log/stops.csv");
        let out = t.join(format!("out-{}", name.replace(' ', "-")));
        let o = whisker(&["slam", s(&dir), "--out", s(&out)]);
        refused(&o, name, &["log/stops.csv", expected], &out);
    }
}

/// The kidnapped robot docking by its base (seed 2): the dock's legs are in the logged
/// odometry and the carry only in the truth; the replay equals the live run, recovery
/// included.
#[test]
fn kidnapped_office_dataset_replays_the_live_run() {
    let tmp = tempfile::tempdir().unwrap();
    let edit = |s: String| {
        office::swap(s, "seed = 0", "seed = 2")
            .replacen("laps = 2", "laps = 2\nkidnap = true", 1)
            .replacen(
                "[navigate.object.explore]",
                "[navigate.object]\ndock = \"base\"\n\n[navigate.object.explore]",
                1,
            )
    };
    let (d, live) = live_equals_replay(tmp.path(), "kidnap", edit);
    let summary = json(&live.join("summary.json"));
    assert!(summary["recovery"]["after_update"].is_u64(), "{summary}");
    let drives = rows(&live.join("stops.csv"))
        .iter()
        .filter(|s| s[4].parse::<f64>().unwrap() > 0.0)
        .count();
    assert!(drives > 0, "the base drove to dock");
    let m = dataset::manifest(&d);
    assert_eq!(m["navigate"]["kidnap"], true);
    assert_eq!(m["navigate"]["object"]["dock"], "base");
}

/// The office on physics whiskers (issue #62; one lap, the fast sweep-plane whiskers,
/// 4-whisk recognitions and 6-whisk map buildings at the stops to keep it short): the run touches at ≥ 90 % of the updates where the
/// kinematic sweep touches on the same route, and its dataset — the front end's contacts
/// with the sensor noise declared — replays to the live run's files.
#[test]
fn physics_office_touches_as_kinematic_does_and_its_dataset_replays_the_live_run() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let short = |s: String| {
        let s = office::swap(s, "laps = 2", "laps = 1");
        office::swap(s, "max_iterations = 800", "max_iterations = 4")
    };
    let physics = move |s: String| {
        let s = office::swap(short(s), "sensing = \"kinematic\"", "sensing = \"physics\"");
        s.replace("/assets/maps/", "/assets/maps/physics/")
            + "\n[array]\nrcp = \"saturation\"\nbending = \"sweep-plane\"\nsegments = 8\nsubsteps = 2\n"
            + "[navigate.object]\nmap_whisks = 6\n"
    };
    let (kinematic, _) = office_run(t, "kin", short);
    let (d, live) = live_equals_replay(t, "phys", physics);
    let touched = |dir: &Path| -> Vec<bool> {
        rows(&dir.join("path.csv"))
            .iter()
            .map(|r| r[11].parse::<usize>().unwrap() > 0)
            .collect()
    };
    let (k, p) = (touched(&kinematic), touched(&live));
    assert_eq!(k.len(), p.len(), "the same route, update by update");
    let both = k.iter().zip(&p).filter(|(a, b)| **a && **b).count();
    let kinematic_touched = k.iter().filter(|a| **a).count();
    assert!(kinematic_touched > 50, "{kinematic_touched}");
    assert!(
        both as f64 >= 0.9 * kinematic_touched as f64,
        "physics touched at {both} of the {kinematic_touched} updates kinematic touched"
    );
    let m = dataset::manifest(&d);
    assert_eq!(m["level"], "contacts");
    assert!(m["noise"]["contacts"].is_null());
    assert!(m["noise"]["sensor"]["deflection_counts"].as_f64().unwrap() > 0.0);
    let scenario = std::fs::read_to_string(d.join("truth/scenario.toml")).unwrap();
    assert!(scenario.contains("sensing = \"physics\""));
}
