//! Rerun recordings (docs/recording.md), read back with Rerun's own decoder: every entity
//! is documented with its archetype, the 2 kHz streams hold every sample with the values
//! of `whiskers.csv`, the contacts are those of the CSV files, the closed loop's map has
//! the SLAM's experience count, and one seed gives the same content on 1 and 2 threads.

use super::*;
use std::collections::BTreeMap;
use whisker_recording::decode;
use whisker_recording::decode::Chunk;

/// The entity table of docs/recording.md: path pattern → archetype.
fn documented() -> Vec<(String, String)> {
    let text = std::fs::read_to_string(repo("docs/recording.md")).unwrap();
    let table = text.split("## Entity tree").nth(1).unwrap();
    table
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (cells[1].trim_matches('`').to_string(), cells[2].to_string())
        })
        .collect()
}

/// Whether `path` (e.g. `/sensors/A1`) matches `pattern` (e.g. `sensors/<label>`).
fn matches(pattern: &str, path: &str) -> bool {
    let p: Vec<&str> = pattern.split('/').collect();
    let q: Vec<&str> = path.trim_start_matches('/').split('/').collect();
    p.len() == q.len() && p.iter().zip(&q).all(|(a, b)| a.starts_with('<') || a == b)
}

/// Checks that every entity of the recording at `file` is documented with its archetype,
/// that every path of `expected` is present, and returns the chunks.
pub fn checked(file: &Path, expected: &[&str]) -> Vec<Chunk> {
    let (_, chunks) = decode::read(file).unwrap();
    let entities = decode::entities(&chunks);
    let docs = documented();
    for (path, e) in &entities {
        let (_, archetype) = docs
            .iter()
            .find(|(p, _)| matches(p, path))
            .unwrap_or_else(|| panic!("{path} is not in docs/recording.md"));
        // The documented archetypes (e.g. "Transform3D (+ static TransformAxes3D)") name
        // every archetype the entity's components belong to.
        for c in &e.components {
            let arch = c.split(':').next().unwrap();
            assert!(
                archetype.contains(arch),
                "{path}: component {c} is not of the documented {archetype}"
            );
        }
    }
    for want in expected {
        assert!(
            entities.keys().any(|p| p.trim_start_matches('/') == *want),
            "{want} missing from {}: {:?}",
            file.display(),
            entities.keys().collect::<Vec<_>>()
        );
    }
    chunks
}

/// The world columns (x, y, z) of a contacts CSV, per cycle start time (µs).
fn csv_points(path: &Path) -> BTreeMap<i64, Vec<[f32; 3]>> {
    let mut out: BTreeMap<i64, Vec<[f32; 3]>> = BTreeMap::new();
    for r in rows(path) {
        let t: f64 = r[1].parse().unwrap();
        let p = [10, 11, 12].map(|k| r[k].parse::<f64>().unwrap() as f32);
        out.entry((t * 1e6).round() as i64).or_default().push(p);
    }
    out
}

/// The points of a recording's entity per time (µs), empty rows dropped.
fn rrd_points(chunks: &[Chunk], entity: &str) -> BTreeMap<i64, Vec<[f32; 3]>> {
    decode::points(chunks, entity)
        .into_iter()
        .filter(|(_, p)| !p.is_empty())
        .map(|(t, p)| ((t * 1e6).round() as i64, p))
        .collect()
}

const KETTLE: &str = "sensing = \"physics\"\n{ARM}[array]\nsegments = 8\nbending = \"sweep-plane\"\n\
     [[objects]]\nmesh = MESH\nposition_m = [0.5, 0.0, 0.0]\nrpy_deg = [0, 0, 90]\n\
     [[trajectory.waypoints]]\nposition_m = [0.50, -0.12, 0.25]\nrpy_deg = [180.0, 0.0, -90.0]\n\
     hold_s = 1.05\n{OUTPUT}";

/// A short physics run over the kettle, into `dir/out-<name>`, with `threads` threads.
fn kettle_run(dir: &Path, name: &str, threads: &str) -> PathBuf {
    let body = KETTLE
        .replace("{ARM}", ARM)
        .replace("{OUTPUT}", OUTPUT)
        .replace(
            "MESH",
            &format!(
                "{:?}",
                repo("assets/meshes/kettle.obj").display().to_string()
            ),
        );
    let path = dir.join(format!("{name}.toml"));
    let out = dir.join(format!("out-{name}"));
    let text = with_urdf(&body).replace("OUT", &format!("{:?}", out.display().to_string()));
    std::fs::write(&path, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(["run", path.to_str().unwrap()])
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

#[test]
fn a_physics_run_records_every_sample_and_contact_reproducibly() {
    let tmp = tempfile::tempdir().unwrap();
    let out = kettle_run(tmp.path(), "one", "1");
    let chunks = checked(
        &out.join("run.rrd"),
        &[
            "world",
            "world/environment/object_kettle",
            "world/arm/skeleton",
            "world/arm/tip",
            "world/arm/tip_path",
            "world/array",
            "world/whiskers",
            "world/contacts/true",
            "world/contacts/estimated",
            "world/contacts/error",
            "sensors/A1",
            "sensors/F3",
        ],
    );
    let (id, _) = decode::read(&out.join("run.rrd")).unwrap();
    assert_eq!(id, "one-seed0");
    // Every 2 kHz sample of every whisker, with the values of whiskers.csv.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let duration = summary["duration_s"].as_f64().unwrap();
    // Every whole 0.5 ms step of the run (the arm's path need not end on one).
    let samples = (duration * 2000.0 + 1e-6).floor() as usize;
    assert_eq!(
        summary["whisker_samples"].as_u64().unwrap() as usize,
        samples
    );
    let csv = rows(&out.join("whiskers.csv"));
    let labels = whisker_sim::whisker::array::labels();
    for (w, label) in labels.iter().enumerate() {
        let series = decode::scalars(&chunks, &format!("/sensors/{label}"));
        assert_eq!(series.len(), samples, "{label}");
        for (row, (t, v)) in csv.iter().zip(&series) {
            let f = |k: usize| row[k].parse::<f64>().unwrap();
            assert!(
                (t - f(0)).abs() < 1e-9,
                "{label}: time {t} against {}",
                f(0)
            );
            assert!((v[0] - f(1 + 3 * w).to_degrees()).abs() < 1e-9);
            assert_eq!(v[1], f(2 + 3 * w));
            assert_eq!(v[2], f(3 + 3 * w));
            assert!(v[3] == 0.0 || v[3] == 1.0);
        }
    }
    // The contacts are those of anticipated.csv and frontend.csv, cycle by cycle.
    assert_eq!(
        rrd_points(&chunks, "/world/contacts/true"),
        csv_points(&out.join("anticipated.csv"))
    );
    let estimated = rrd_points(&chunks, "/world/contacts/estimated");
    assert!(!estimated.is_empty());
    assert_eq!(estimated, csv_points(&out.join("frontend.csv")));

    // The same seed on 2 threads: the same content.
    let two = kettle_run(tmp.path(), "two", "2");
    let (_, again) = decode::read(&two.join("run.rrd")).unwrap();
    decode::same_content(&chunks, &again).unwrap();
}

#[test]
fn rrd_options_choose_the_file_or_none() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = arm_tour_in(tmp.path());
    let other = tmp.path().join("elsewhere/tour.rrd");
    let o = whisker(&[
        "run",
        scenario.to_str().unwrap(),
        "--out",
        tmp.path().join("a").to_str().unwrap(),
        "--rrd",
        other.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(other.is_file());
    assert!(!tmp.path().join("a/run.rrd").exists());
    checked(
        &other,
        &[
            "world/arm/skeleton",
            "world/arm/tip_path",
            "world/waypoints",
        ],
    );
    let o = whisker(&[
        "run",
        scenario.to_str().unwrap(),
        "--out",
        tmp.path().join("b").to_str().unwrap(),
        "--no-rrd",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(tmp.path().join("b/path.csv").is_file());
    assert!(!tmp.path().join("b/run.rrd").exists());
    // No temporary file is left beside the outputs.
    let names: Vec<String> = std::fs::read_dir(tmp.path().join("elsewhere"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["tour.rrd"]);
}

/// The quickstart's closed loop (shortened): its map, its confidence and its contacts.
#[test]
fn a_closed_loop_records_its_map_confidence_and_contacts() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |name: &str, threads: &str| {
        let out = tmp.path().join(name);
        let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
            .args([
                "run",
                repo("scenarios/quickstart.toml").to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--set",
                "explore.max_iterations=60",
            ])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        out
    };
    let out = run("one", "1");
    let chunks = checked(
        &out.join("run.rrd"),
        &[
            "world/environment/object_box",
            "world/arm/skeleton",
            "world/array",
            "world/whiskers",
            "world/explore/goal",
            "world/contacts/true",
            "world/contacts/estimated",
            "slam/pose_cells",
            "slam/map/experiences",
            "slam/map/links",
            "recognition/raw/box",
            "recognition/integrated/box_stack",
            "events",
            "legend",
        ],
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let iterations = summary["iterations"].as_u64().unwrap() as usize;
    // One confidence per whisk, equal to explore.csv's.
    let text = std::fs::read_to_string(out.join("explore.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "ic_box").unwrap();
    let ic: Vec<f64> = decode::scalars(&chunks, "/recognition/integrated/box")
        .into_iter()
        .map(|(_, v)| v[0])
        .collect();
    assert_eq!(ic.len(), iterations);
    for (row, v) in text.lines().skip(1).zip(&ic) {
        let want: f64 = row.split(',').nth(col).unwrap().parse().unwrap();
        assert!((want - v).abs() <= 1e-9 * want.abs().max(1.0));
    }
    // The last map logged has the run's experiences (the loaded maps' and its own).
    let nodes = decode::rows::<[f32; 2]>(
        &chunks,
        "/slam/map/experiences",
        "Points2D:positions",
        "whisk",
    );
    let last = nodes.last().expect("map logged");
    assert_eq!(
        last.1.len() as u64,
        summary["experiences"].as_u64().unwrap()
    );
    // The estimated contacts are contacts.csv's, whisk by whisk.
    let mut from_csv: Vec<[f32; 3]> = Vec::new();
    for r in rows(&out.join("contacts.csv")) {
        from_csv.push([10, 11, 12].map(|k| r[k].parse::<f64>().unwrap() as f32));
    }
    let recorded: Vec<[f32; 3]> = decode::points(&chunks, "/world/contacts/estimated")
        .into_iter()
        .flat_map(|(_, p)| p)
        .collect();
    assert_eq!(recorded, from_csv);
    // On the whisk timeline the viewer opens on: the arm once per whisk (it would be
    // invisible there without it), the tip's trail of the last whisks (at most 11 points,
    // each the whisk's tip), and the IC threshold beside the ICs.
    let skeleton = decode::strips(&chunks, "/world/arm/skeleton", "whisk");
    assert_eq!(skeleton.len(), iterations);
    let trail = decode::strips(&chunks, "/world/arm/tip_path", "whisk");
    assert_eq!(trail.len(), iterations);
    for (k, (whisk, strips)) in trail.iter().enumerate() {
        assert_eq!(*whisk, k as i64);
        assert_eq!(strips[0].len(), (k + 1).min(11), "whisk {k}");
        // The trail ends where the skeleton ends (the tip).
        assert_eq!(strips[0].last(), skeleton[k].1[0].last());
    }
    let threshold = decode::scalars(&chunks, "/recognition/integrated/threshold");
    assert_eq!(threshold.len(), iterations);
    assert!(threshold.iter().all(|(_, v)| v[0] == 300.0));
    // Named in the viewer (static: once, not per whisk).
    let properties = &decode::entities(&chunks)["/__properties"];
    assert!(properties.components.contains("RecordingInfo:name"));
    assert!(
        properties.static_rows == 1 && properties.rows == 0,
        "{properties:?}"
    );

    let two = run("two", "2");
    let (_, again) = decode::read(&two.join("run.rrd")).unwrap();
    decode::same_content(&chunks, &again).unwrap();
}

/// Runs `whisker` with `threads` threads; must succeed; returns stdout.
pub fn ok_with(threads: &str, args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o)
}

/// soak --rrd: every simulated whisker's 2 kHz samples, and the shafts every 10 ms.
#[test]
fn soak_records_the_streams_of_the_simulated_whiskers() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("soak.rrd");
    let text = ok_with(
        "2",
        &[
            "soak",
            "--duration",
            "0.1",
            "--objects",
            "box",
            "--whiskers",
            "D1,C2",
            "--json",
            "--rrd",
            file.to_str().unwrap(),
        ],
    );
    let report: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(report[0]["whiskers_simulated"], 2);
    let chunks = checked(
        &file,
        &[
            "world/cases/box",
            "world/cases/box/whiskers",
            "sensors/box/D1",
            "sensors/box/C2",
        ],
    );
    for w in ["D1", "C2"] {
        let series = decode::scalars(&chunks, &format!("/sensors/box/{w}"));
        assert_eq!(series.len(), 200, "{w}");
        assert!((series[199].0 - 0.1).abs() < 1e-9);
        assert!(
            series.iter().all(|(_, v)| v[3] == 0.0),
            "open loop: RCP never fires"
        );
    }
    // The shafts every 10 ms (20 steps).
    assert_eq!(
        decode::entities(&chunks)["/world/cases/box/whiskers"].rows,
        10
    );
}

/// A kinematic run: the noisy contacts of contacts.csv as the estimate, the noise-free
/// intersect as the truth, an error arrow per whisker the noise did not drop, and the
/// straight shafts at every output sample.
#[test]
fn a_kinematic_run_records_truth_estimate_and_error() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("objects");
    ok_with(
        "2",
        &[
            "run",
            repo("scenarios/objects.toml").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let chunks = checked(
        &out.join("run.rrd"),
        &[
            "world/contacts/true",
            "world/contacts/estimated",
            "world/contacts/error",
            "world/whiskers",
        ],
    );
    let estimated = rrd_points(&chunks, "/world/contacts/estimated");
    assert!(!estimated.is_empty());
    assert_eq!(estimated, csv_points(&out.join("contacts.csv")));
    // Truth: the intersect without noise, so at least the estimate's whiskers per cycle
    // (detection drops some), each error arrow from a true point (one per estimate whose
    // whisker has a truth).
    let truth = rrd_points(&chunks, "/world/contacts/true");
    let arrows = decode::rows::<[f32; 3]>(
        &chunks,
        "/world/contacts/error",
        "Arrows3D:origins",
        "sim_time",
    );
    for (t, origins) in arrows.into_iter().filter(|(_, o)| !o.is_empty()) {
        let key = (t as f64 * 1e-3).round() as i64;
        let cycle_truth = &truth[&key];
        assert!(origins.len() <= cycle_truth.len());
        assert!(origins.iter().all(|o| cycle_truth.contains(o)));
        assert!(origins.len() <= estimated.get(&key).map_or(0, Vec::len));
    }
    // The shafts at every sample of path.csv.
    let samples = rows(&out.join("path.csv")).len();
    assert_eq!(decode::entities(&chunks)["/world/whiskers"].rows, samples);
}
