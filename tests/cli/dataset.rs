//! `whisker dataset` and SLAM from datasets (docs/dataset.md): live runs and replays agree
//! byte for byte, datasets are reproducible and independent of the thread count, noise
//! changes the log and not the ground truth, a log without ground truth still runs
//! (malformed datasets: `dataset_malformed.rs`).

use super::*;

/// Runs `whisker` with `threads` worker threads; must succeed.
pub fn ok(threads: usize, args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(args)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .expect("whisker runs");
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every file under `dir` (relative path -> bytes; a Rerun recording only by name: its
/// bytes differ on every write, its content is compared by `decode::same_content`).
pub fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut std::collections::BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                let bytes = if rel.ends_with(".rrd") {
                    b"(a recording)".to_vec()
                } else {
                    std::fs::read(&p).unwrap()
                };
                out.insert(rel, bytes);
            }
        }
    }
    let mut out = Default::default();
    walk(dir, dir, &mut out);
    out
}

pub fn manifest(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("dataset.json")).unwrap()).unwrap()
}

/// Lists `rel` in `dir`'s manifest with its current size and SHA-256, as a converter that
/// wrote a bad file would (so that the reader, not the checksum, meets the defect).
pub fn rehash(dir: &Path, rel: &str) {
    let mut m = manifest(dir);
    let bytes = std::fs::read(dir.join(rel)).unwrap();
    let entry = m["files"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|f| f["path"] == rel)
        .unwrap();
    entry["bytes"] = bytes.len().into();
    entry["sha256"] = whisker_experiments::dataset_format::manifest::sha256(&bytes).into();
    std::fs::write(dir.join("dataset.json"), m.to_string()).unwrap();
}

/// Runs `scenario` live (seed `seed`, 2 threads) and from `dataset` (1 thread), each with
/// `extra` options and `--json --out` into `t`; both must print and write the same bytes.
/// Returns the live run.
fn live_equals_replay(
    t: &Path,
    scenario: &Path,
    seed: u64,
    dataset: &Path,
    extra: &[&str],
) -> Output {
    let (a, b) = (t.join("live"), t.join("replay"));
    let seed = seed.to_string();
    let live = ok(
        2,
        &[
            &[
                "maze-slam",
                s(scenario),
                "--seeds",
                &seed,
                "--json",
                "--out",
                s(&a),
            ],
            extra,
        ]
        .concat(),
    );
    let replay = ok(
        1,
        &[
            &[
                "maze-slam",
                "--dataset",
                s(dataset),
                "--json",
                "--out",
                s(&b),
            ],
            extra,
        ]
        .concat(),
    );
    assert_eq!(stdout(&live), stdout(&replay));
    assert_eq!(files(&a), files(&b));
    live
}

/// `text` with field `column` (0-based) of line `line` (0-based, the header is 0) set to
/// `value`.
pub fn set_field(text: &str, line: usize, column: usize, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut fields: Vec<&str> = lines[line].split(',').collect();
    fields[column] = value;
    lines[line] = fields.join(",");
    lines.join("\n") + "\n"
}

/// `o` exited with code 2, its message holds every one of `expected`, and `out` was not
/// created.
pub fn refused(o: &Output, name: &str, expected: &[&str], out: &Path) {
    assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(o));
    for e in expected {
        assert!(
            stderr(o).contains(e),
            "{name}: expected {e:?} in {}",
            stderr(o)
        );
    }
    assert!(!out.exists(), "{name}: output written");
}

pub fn copy_dir(from: &Path, to: &Path) {
    for (rel, bytes) in files(from) {
        let p = to.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }
}

/// The kinematic maze: live = replay (metrics, trajectories, images), the dataset the
/// same with 1 and 2 threads, another seed changes the log and not the ground truth, a
/// log without ground truth runs with its metrics unavailable, and noise added later.
#[test]
fn kinematic_maze_dataset_replays_the_live_run() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let scenario = repo("scenarios/maze_kinematic.toml");
    let (d1, d2, d3) = (t.join("d1"), t.join("d2"), t.join("d3"));
    ok(
        1,
        &["dataset", s(&scenario), "--seed", "0", "--out", s(&d1)],
    );
    ok(
        2,
        &["dataset", s(&scenario), "--seed", "0", "--out", s(&d2)],
    );
    ok(
        2,
        &["dataset", s(&scenario), "--seed", "3", "--out", s(&d3)],
    );
    let (f1, f2, f3) = (files(&d1), files(&d2), files(&d3));
    assert_eq!(f1, f2, "the dataset depends on the thread count");
    // The lab layout and the ground truth, every file listed with its checksum.
    for rel in [
        "log/contacts.csv",
        "log/odometry.csv",
        "log/poses.csv",
        "truth/poses.csv",
        "truth/odometry.csv",
        "truth/contacts.csv",
        "truth/scenario.toml",
    ] {
        let listed = manifest(&d1)["files"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["path"] == rel)
            .cloned()
            .unwrap_or_else(|| panic!("{rel} not listed"));
        // An independent SHA-256 (FIPS 180-4 test vector first).
        assert_eq!(
            whisker_experiments::dataset_format::manifest::sha256(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            listed["sha256"],
            whisker_experiments::dataset_format::manifest::sha256(&f1[rel])
        );
        let seed_changes = f1[rel] != f3[rel];
        assert_eq!(seed_changes, rel.starts_with("log/"), "{rel}");
    }
    // The pose log: 1 Hz, unit quaternions, the first pose the true start.
    let poses = rows(&d1.join("log/poses.csv"));
    let truth = rows(&d1.join("truth/poses.csv"));
    assert_eq!(poses.len(), (truth.len() - 1) * 2 / 3 + 1);
    assert_eq!(
        (poses[0][1].as_str(), poses[0][2].as_str()),
        (truth[0][2].as_str(), truth[0][3].as_str())
    );
    for p in &poses {
        let q: f64 = p[4..8]
            .iter()
            .map(|v| v.parse::<f64>().unwrap().powi(2))
            .sum();
        assert!((q - 1.0).abs() < 1e-12);
    }
    // Noise-free odometry is the true motion: the distances add up to the path length.
    let clean: f64 = rows(&d1.join("truth/odometry.csv"))
        .iter()
        .map(|r| r[3].parse::<f64>().unwrap())
        .sum();
    let length: f64 = truth
        .windows(2)
        .map(|w| {
            let p = |r: &Vec<String>, i: usize| r[i].parse::<f64>().unwrap();
            (p(&w[1], 2) - p(&w[0], 2)).hypot(p(&w[1], 3) - p(&w[0], 3))
        })
        .sum();
    assert!((clean - length).abs() < 1e-9, "{clean} vs {length}");

    // Live vs replay: same JSON, same files.
    let live = live_equals_replay(t, &scenario, 0, &d1, &["--kidnap"]);
    let general = ok(2, &["slam", s(&d1), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&general)).unwrap();
    let l: serde_json::Value = serde_json::from_str(&stdout(&live)).unwrap();
    assert_eq!(v["runs"][0], l["runs"][0]);

    // The lab layout alone: ground truth deleted, SLAM still runs, the same map; the
    // metrics that need the truth are unavailable (null), not zero.
    let lab = t.join("lab");
    copy_dir(&d1, &lab);
    std::fs::remove_dir_all(lab.join("truth")).unwrap();
    let o = ok(
        2,
        &["slam", s(&lab), "--json", "--out", s(&t.join("lab-out"))],
    );
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let run = &v["runs"][0];
    for k in ["arr", "arcr", "energy_metric", "relocalisations"] {
        assert!(run[k].is_null(), "{k}: {run}");
    }
    assert_eq!(run["experiences"], l["runs"][0]["experiences"]);
    let trajectory = rows(&t.join("lab-out/trajectory-kinematic-normal-0.csv"));
    let live_trajectory = rows(&t.join("live/trajectory-kinematic-normal-0.csv"));
    for (a, b) in trajectory.iter().zip(&live_trajectory) {
        assert_eq!(&a[1..4], &["", "", ""]);
        assert_eq!(a[7], b[7], "the same experience at every update");
        for i in 4..7 {
            let (x, y): (f64, f64) = (a[i].parse().unwrap(), b[i].parse().unwrap());
            assert!(
                (x - y).abs() < 1e-9,
                "the estimate starts at the logged start pose"
            );
        }
    }
    let table = ok(2, &["slam", s(&lab)]);
    assert!(stdout(&table).contains("n/a"), "{}", stdout(&table));

    // Written clean, noised later: seed M changes the log, not the truth; again the same.
    let clean = t.join("clean");
    ok(
        2,
        &[
            "dataset",
            s(&scenario),
            "--seed",
            "0",
            "--clean",
            "--out",
            s(&clean),
        ],
    );
    let (n5, n5b, n6) = (t.join("n5"), t.join("n5b"), t.join("n6"));
    for (threads, seed, out) in [(2, "5", &n5), (1, "5", &n5b), (2, "6", &n6)] {
        ok(
            threads,
            &[
                "dataset",
                "noise",
                s(&clean),
                "--seed",
                seed,
                "--out",
                s(out),
            ],
        );
    }
    assert_eq!(files(&n5), files(&n5b));
    let (c, a, b) = (files(&clean), files(&n5), files(&n6));
    for rel in c.keys().filter(|k| k.as_str() != "dataset.json") {
        assert_eq!(a[rel] != b[rel], rel.starts_with("log/"), "{rel}");
        assert_eq!(a[rel] != c[rel], rel.starts_with("log/"), "{rel}");
    }
    // Clean: the logged contacts are the anticipated ones; noised: 2 % are missed.
    assert_eq!(c["log/contacts.csv"], c["truth/contacts.csv"]);
    let (before, after) = (
        rows(&clean.join("log/contacts.csv")).len() as f64,
        rows(&n5.join("log/contacts.csv")).len() as f64,
    );
    let sd = (before * 0.02 * 0.98).sqrt();
    assert!(
        ((before - after) - 0.02 * before).abs() < 4.0 * sd,
        "{before} -> {after}"
    );
    assert_eq!(manifest(&n5)["noise"]["added_with_seed"], 5);
    ok(2, &["slam", s(&n5)]);
    // A noisy dataset is not noised again.
    let again = whisker(&[
        "dataset",
        "noise",
        s(&n5),
        "--seed",
        "1",
        "--out",
        s(&t.join("x")),
    ]);
    assert_eq!(again.status.code(), Some(2));
    assert!(stderr(&again).contains("dataset.json") && !t.join("x").exists());
    // Noise along the whisker (the default) needs each whisker's shaft: a manifest naming a
    // whisker outside the standard array is refused, naming the field, and nothing written.
    let odd = t.join("odd");
    copy_dir(&clean, &odd);
    let mut m = manifest(&odd);
    m["array"]["labels"][0] = serde_json::json!("Z9");
    std::fs::write(odd.join("dataset.json"), m.to_string()).unwrap();
    let refused = whisker(&[
        "dataset",
        "noise",
        s(&odd),
        "--seed",
        "1",
        "--out",
        s(&t.join("y")),
    ]);
    assert_eq!(refused.status.code(), Some(2));
    let e = stderr(&refused);
    assert!(
        e.contains("dataset.json") && e.contains("array.labels") && e.contains("\"Z9\""),
        "{e}"
    );
    assert!(!t.join("y").exists());
}

/// The physics maze (the short scenario): the dataset is the same on 1 and 2 threads and
/// replays into the live run's bytes; the lab layout is the thesis' (one file per whisk cycle, 4
/// columns per whisker); noise added to its streams has the requested σ.
#[test]
fn physics_maze_dataset_replays_the_live_run() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let scenario = repo("scenarios/maze_short.toml");
    let d = t.join("d");
    ok(1, &["dataset", s(&scenario), "--seed", "1", "--out", s(&d)]);
    // The same on 2 threads: the same bytes (checksums and all).
    let d2 = t.join("d2");
    ok(
        2,
        &["dataset", s(&scenario), "--seed", "1", "--out", s(&d2)],
    );
    assert_eq!(
        files(&d),
        files(&d2),
        "the physics dataset depends on the thread count"
    );
    let live = live_equals_replay(t, &scenario, 1, &d, &[]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&live)).unwrap();
    assert!(v["runs"][0]["relocalisations"].as_u64().unwrap() > 0, "{v}");
    // The lab layout: a whisk file per 1 Hz cycle, 2000 rows of 18 × 4 integer columns.
    let m = manifest(&d);
    let whisks = m["sensor"]["whisks"].as_u64().unwrap() as usize;
    let updates = m["maze"]["updates"].as_u64().unwrap() as f64;
    assert_eq!(whisks, ((updates - 1.0) / 1.5).floor() as usize);
    let first = std::fs::read_to_string(d.join("log/whisks/whisk_000000.csv")).unwrap();
    let header: Vec<&str> = first.lines().next().unwrap().split(',').collect();
    assert_eq!(header.len(), 72);
    assert_eq!(&header[..4], &["A1_angle", "A1_x", "A1_y", "A1_spare"]);
    assert_eq!(header[71], "F3_spare");
    assert_eq!(first.lines().count(), 2001);
    // The angle column is the whisk: 40°–140° over the cycle, in counts of the resolution.
    let q = m["sensor"]["angle_resolution_rad"].as_f64().unwrap();
    let angles: Vec<f64> = first
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse::<f64>().unwrap() * q)
        .collect();
    let (lo, hi) = angles
        .iter()
        .fold((9.0f64, -9.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(
        (lo.to_degrees() - 40.0).abs() < 2.0 && (hi.to_degrees() - 140.0).abs() < 2.0,
        "{lo} {hi}"
    );
    // Sensor noise added later: a "clean" copy (the manifest says so) noised with
    // σ = 5 counts differs from it by N(0, 5) after rounding (variance 25 + 1/12).
    let clean = t.join("clean");
    copy_dir(&d, &clean);
    let mut mc = manifest(&clean);
    mc["noise"] = serde_json::json!({"added_with_seed": null, "sensor": null, "odometry": null, "contacts": null});
    std::fs::write(clean.join("dataset.json"), mc.to_string()).unwrap();
    let noisy = t.join("noisy");
    ok(
        2,
        &[
            "dataset",
            "noise",
            s(&clean),
            "--seed",
            "9",
            "--deflection-counts",
            "5",
            "--out",
            s(&noisy),
        ],
    );
    let read = |p: &Path| -> Vec<f64> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .skip(1)
            .flat_map(|l| {
                l.split(',')
                    .enumerate()
                    .filter(|(i, _)| i % 4 == 1 || i % 4 == 2)
                    .map(|(_, v)| v.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let (a, b) = (
        read(&clean.join("log/whisks/whisk_000003.csv")),
        read(&noisy.join("log/whisks/whisk_000003.csv")),
    );
    let diffs: Vec<f64> = a
        .iter()
        .zip(&b)
        .filter(|(x, _)| x.abs() < 2000.0)
        .map(|(x, y)| y - x)
        .collect();
    let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
    let var = diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / diffs.len() as f64;
    assert!(
        mean.abs() < 0.1 && (var - 25.083).abs() < 1.0,
        "mean {mean}, variance {var}"
    );
    ok(2, &["slam", s(&noisy)]);
    // Malformed whisk files (a converter's bugs): cut short, a fraction in an integer
    // column. Exit 2 naming the file and line, nothing written.
    type Damage = fn(String) -> String;
    let cases: [(&str, Damage, &[&str]); 2] = [
        (
            "short",
            |t| t.lines().take(1991).collect::<Vec<_>>().join("\n") + "\n",
            &["whisk_000002.csv", "line 1991", "expected 2000 samples"],
        ),
        (
            "fraction",
            |t| set_field(&t, 4, 1, "1.5"),
            &[
                "whisk_000002.csv",
                "line 5",
                "column 2 (A1_x): expected an integer",
            ],
        ),
    ];
    for (name, damage, expected) in cases {
        let bad = t.join(name);
        copy_dir(&d, &bad);
        let rel = "log/whisks/whisk_000002.csv";
        std::fs::write(
            bad.join(rel),
            damage(std::fs::read_to_string(bad.join(rel)).unwrap()),
        )
        .unwrap();
        rehash(&bad, rel);
        let out = t.join(format!("{name}-out"));
        let o = whisker(&["maze-slam", "--dataset", s(&bad), "--out", s(&out)]);
        refused(&o, name, expected, &out);
    }
}
