//! ROS 2 bags (`whisker export --mcap`, docs/dataset.md "ROS 2 bags"): a dataset exported
//! and read back is the same dataset byte for byte, its replay from the bag equals the
//! replay from the directory, the standard messages decode (by hand, from the CDR rules) to
//! the dataset's own numbers, and a damaged bag is refused naming the byte.

use super::dataset::{files, ok, s};
use super::*;

/// The payload of every message on `topic` of the MCAP file `path`, in file order, read
/// with the `mcap` crate's own reader (not the one under test).
fn messages(path: &Path, topic: &str) -> Vec<Vec<u8>> {
    let buf = std::fs::read(path).unwrap();
    ::mcap::MessageStream::new(&buf)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == topic)
        .map(|m| m.data.into_owned())
        .collect()
}

fn f64_at(b: &[u8], at: usize) -> f64 {
    f64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}

/// The kinematic maze: export, read back byte for byte, replay from the bag = replay
/// from the directory (`whisker slam` and `whisker maze-slam`), and the pose log's
/// `geometry_msgs/PoseStamped` view decodes to the log's numbers.
#[test]
fn maze_bag_replays_as_the_dataset() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let d = t.join("d");
    let bag = t.join("maze.mcap");
    ok(
        2,
        &[
            "dataset",
            s(&repo("scenarios/maze_kinematic.toml")),
            "--seed",
            "0",
            "--out",
            s(&d),
            "--mcap",
            s(&bag),
        ],
    );
    let back = t.join("back");
    whisker_experiments::ros2_bag::import(&bag, &back).unwrap();
    assert_eq!(
        files(&d),
        files(&back),
        "the bag does not carry the dataset"
    );
    // The same dataset elsewhere exports to the same bytes.
    let again = t.join("again.mcap");
    ok(2, &["export", s(&back), "--mcap", s(&again)]);
    assert!(std::fs::read(&bag).unwrap() == std::fs::read(&again).unwrap());
    let (a, b) = (t.join("a"), t.join("b"));
    let dir = ok(1, &["slam", s(&d), "--json", "--out", s(&a)]);
    let from_bag = ok(1, &["slam", "--mcap", s(&bag), "--json", "--out", s(&b)]);
    assert_eq!(stdout(&dir), stdout(&from_bag));
    assert_eq!(files(&a), files(&b));
    let (c, e) = (t.join("c"), t.join("e"));
    let dir = ok(
        1,
        &["maze-slam", "--dataset", s(&d), "--json", "--out", s(&c)],
    );
    let from_bag = ok(
        1,
        &["maze-slam", "--mcap", s(&bag), "--json", "--out", s(&e)],
    );
    assert_eq!(stdout(&dir), stdout(&from_bag));
    assert_eq!(files(&c), files(&e));
    // PoseStamped by hand: sec, nanosec, frame "world" (4 + 6 bytes), padding to 24, then
    // position x y z and orientation x y z w as float64.
    let poses = messages(&bag, "/log/poses/pose");
    let logged = rows(&d.join("log/poses.csv"));
    assert_eq!(poses.len(), logged.len());
    for (m, r) in poses.iter().zip(&logged) {
        assert_eq!(&m[..4], &[0, 1, 0, 0]);
        let stamp = u32::from_le_bytes(m[4..8].try_into().unwrap()) as f64
            + u32::from_le_bytes(m[8..12].try_into().unwrap()) as f64 * 1e-9;
        assert!((stamp - r[0].parse::<f64>().unwrap()).abs() < 1e-9);
        assert_eq!(&m[12..22], b"\x06\0\0\0world\0");
        for (k, col) in (1..8).enumerate() {
            assert_eq!(
                f64_at(m, 28 + 8 * k),
                r[col].parse::<f64>().unwrap(),
                "{r:?}"
            );
        }
    }
    // The contacts' table topic has one message per row.
    assert_eq!(
        messages(&bag, "/log/contacts").len(),
        rows(&d.join("log/contacts.csv")).len()
    );
}

/// A physics closed loop (level streams): the whisk files travel as Hall samples and come
/// back byte for byte; the whisk-angle `JointState` view is the file's counts times the
/// angle resolution; the replay from the bag equals the replay from the directory.
#[test]
fn streams_bag_carries_the_whisk_files() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let d = t.join("d");
    ok(
        2,
        &[
            "dataset",
            s(&repo("scenarios/recognise_box_physics.toml")),
            "--seed",
            "2",
            "--out",
            s(&d),
            "--set",
            "explore.max_iterations=3",
            "--set",
            "array.bending=sweep-plane",
            "--set",
            "array.segments=8",
            "--set",
            "array.substeps=2",
        ],
    );
    let bag = t.join("loop.mcap");
    ok(1, &["export", s(&d), "--mcap", s(&bag)]);
    let back = t.join("back");
    whisker_experiments::ros2_bag::import(&bag, &back).unwrap();
    assert_eq!(files(&d), files(&back));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("dataset.json")).unwrap()).unwrap();
    let resolution = m["sensor"]["angle_resolution_rad"].as_f64().unwrap();
    let n = m["sensor"]["samples_per_whisk"].as_u64().unwrap() as usize;
    let angles = messages(&bag, "/log/whisks/joint_states");
    assert_eq!(angles.len(), 3 * n);
    let first = rows(&d.join("log/whisks/whisk_000001.csv"));
    // JointState: header (stamp 8, frame "" 4+1 → 17), names (count + 18 strings), then
    // the positions: found after the last name, aligned to 8.
    let msg = &angles[n + 10];
    let mut at = 4 + 8 + 5;
    let pad4 = |at: usize| 4 + (at - 4).div_ceil(4) * 4;
    at = pad4(at);
    let names = u32::from_le_bytes(msg[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(names, 18);
    at += 4;
    for _ in 0..names {
        at = pad4(at);
        let len = u32::from_le_bytes(msg[at..at + 4].try_into().unwrap()) as usize;
        at += 4 + len;
    }
    at = pad4(at);
    assert_eq!(u32::from_le_bytes(msg[at..at + 4].try_into().unwrap()), 18);
    at += 4;
    at = 4 + (at - 4).div_ceil(8) * 8;
    for w in 0..18 {
        let counts: f64 = first[10][4 * w].parse().unwrap();
        assert_eq!(f64_at(msg, at + 8 * w), counts * resolution);
    }
    let (a, b) = (t.join("a"), t.join("b"));
    let dir = ok(1, &["slam", s(&d), "--json", "--out", s(&a)]);
    let from_bag = ok(1, &["slam", "--mcap", s(&bag), "--json", "--out", s(&b)]);
    assert_eq!(stdout(&dir), stdout(&from_bag));
    assert_eq!(files(&a), files(&b));
}

/// Damaged bags are refused with exit 2 naming the byte, never a crash: truncated
/// anywhere, a byte flipped inside a chunk, not MCAP at all; a run's export (no
/// manifest) cannot be replayed; an existing file is never written over.
#[test]
fn damaged_bags_are_refused_naming_the_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let d = t.join("d");
    let bag = t.join("maze.mcap");
    ok(
        1,
        &[
            "dataset",
            s(&repo("scenarios/maze_kinematic.toml")),
            "--set",
            "maze_slam.circuits=2",
            "--out",
            s(&d),
        ],
    );
    ok(1, &["export", s(&d), "--mcap", s(&bag)]);
    let again = whisker(&["export", s(&d), "--mcap", s(&bag)]);
    assert_eq!(again.status.code(), Some(2));
    assert!(stderr(&again).contains("already exists"));
    let bytes = std::fs::read(&bag).unwrap();
    let broken = t.join("broken.mcap");
    let refused = |what: &str, b: &[u8]| {
        std::fs::write(&broken, b).unwrap();
        let o = whisker(&["slam", "--mcap", s(&broken), "--out", s(&t.join("x"))]);
        assert_eq!(o.status.code(), Some(2), "{what}: {}", stderr(&o));
        assert!(stderr(&o).contains("byte "), "{what}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{what}: {}", stderr(&o));
        assert!(!t.join("x").exists());
    };
    for k in 1..12 {
        let cut = bytes.len() * k / 12;
        refused(&format!("truncated at {cut}"), &bytes[..cut]);
    }
    // The first chunk (opcode 0x06) after the header record: a byte in its compressed
    // data flipped.
    let chunk = (8..bytes.len()).find(|&i| bytes[i] == 0x06).unwrap();
    let mut flipped = bytes.clone();
    let at = chunk + 9 + 100;
    flipped[at] ^= 0x5a;
    refused("a flipped byte", &flipped);
    refused("not MCAP", b"update,time_s\n0,0.0\n");
    // A byte flipped anywhere: refused naming the byte, or — where the flip lands on what
    // the reader does not use (an index, the summary's repeats) — the same replay.
    let expected = stdout(&ok(1, &["slam", s(&d), "--json"])).to_string();
    for k in 0..24 {
        let at = 8 + (bytes.len() - 16) * k / 24 + k;
        let mut b = bytes.clone();
        b[at] ^= 0xa5;
        std::fs::write(&broken, &b).unwrap();
        let o = whisker(&["slam", "--mcap", s(&broken), "--json"]);
        match o.status.code() {
            Some(0) => assert_eq!(stdout(&o), expected, "flip at {at}"),
            Some(2) => assert!(
                stderr(&o).contains(s(&broken)),
                "flip at {at}: {}",
                stderr(&o)
            ),
            c => panic!("flip at {at}: exit {c:?}: {}", stderr(&o)),
        }
    }
    // A run's output exports (for the ROS tools) but is no dataset.
    let run = t.join("run");
    ok(
        1,
        &[
            "run",
            s(&repo("scenarios/quickstart.toml")),
            "--set",
            "explore.max_iterations=5",
            "--out",
            s(&run),
            "--no-rrd",
        ],
    );
    let run_bag = t.join("run.mcap");
    ok(1, &["export", s(&run), "--mcap", s(&run_bag)]);
    assert!(!messages(&run_bag, "/explore/joint_states").is_empty());
    assert!(!messages(&run_bag, "/explore/pose").is_empty());
    assert!(!messages(&run_bag, "/explore/goal_pose").is_empty());
    let o = whisker(&["slam", "--mcap", s(&run_bag)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("no dataset.json attachment"),
        "{}",
        stderr(&o)
    );
}

/// Object walks (`dataset object-slam … --mcap`): `object-slam --mcap` equals
/// `object-slam --dataset`, and the walks' pose logs are views of their own.
#[test]
fn object_walks_bag_replays_as_the_dataset() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let (d, bag) = (t.join("d"), t.join("walks.mcap"));
    ok(
        2,
        &[
            "dataset",
            "object-slam",
            "--objects",
            "box",
            "--out",
            s(&d),
            "--mcap",
            s(&bag),
        ],
    );
    let dir = ok(
        2,
        &["object-slam", "--dataset", s(&d), "--json", "--no-rrd"],
    );
    let from_bag = ok(2, &["object-slam", "--mcap", s(&bag), "--json", "--no-rrd"]);
    assert_eq!(stdout(&dir), stdout(&from_bag));
    for walk in ["A", "B"] {
        let poses = messages(&bag, &format!("/log/box/{walk}/poses/pose"));
        assert_eq!(
            poses.len(),
            rows(&d.join(format!("log/box/{walk}/poses.csv"))).len()
        );
    }
}
