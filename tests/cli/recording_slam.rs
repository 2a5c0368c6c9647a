//! The recordings of the SLAM commands (docs/recording.md), read back with Rerun's own
//! decoder: maze-slam records every update of every run, object-slam the walks and the
//! maps, the same content on any thread count.

use super::recording::{checked, ok_with};
use super::*;
use whisker_recording::decode;

/// maze-slam: per run every update's tactile image (the bytes of images-*.csv), pose cells
/// and true position; the last map has the run's experiences; the same on 2 threads.
#[test]
fn maze_slam_records_every_update_of_every_run() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |name: &str, threads: &str| {
        let out = tmp.path().join(name);
        let scenario = repo("scenarios/maze_kinematic.toml");
        let text = ok_with(
            threads,
            &[
                "maze-slam",
                scenario.to_str().unwrap(),
                "--kidnap",
                "--json",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        (
            out,
            serde_json::from_str::<serde_json::Value>(&text).unwrap(),
        )
    };
    let (out, report) = run("one", "1");
    let runs = report["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    let mut expected = Vec::new();
    let names: Vec<String> = runs
        .iter()
        .map(|r| {
            format!(
                "{}_{}_s{}",
                r["images"].as_str().unwrap().replace('/', "_"),
                r["variant"].as_str().unwrap(),
                r["seed"]
            )
        })
        .collect();
    for n in &names {
        for e in [
            "tactile_image",
            "pose_cells",
            "map/experiences",
            "map/links",
        ] {
            expected.push(format!("slam/{n}/{e}"));
        }
        for e in ["array", "true", "estimated"] {
            expected.push(format!("world/runs/{n}/{e}"));
        }
    }
    let expected: Vec<&str> = expected.iter().map(String::as_str).collect();
    let chunks = checked(&out.join("run.rrd"), &expected);
    for (r, n) in runs.iter().zip(&names) {
        let updates = r["updates"].as_u64().unwrap() as usize;
        let images = decode::blobs(
            &chunks,
            &format!("/slam/{n}/tactile_image"),
            "Image:buffer",
            "update",
        );
        assert_eq!(images.len(), updates, "{n}");
        let poses = decode::rows::<[f32; 3]>(
            &chunks,
            &format!("/world/runs/{n}/array"),
            "Points3D:positions",
            "update",
        );
        assert_eq!(poses.len(), updates, "{n}");
        let nodes = decode::rows::<[f32; 2]>(
            &chunks,
            &format!("/slam/{n}/map/experiences"),
            "Points2D:positions",
            "update",
        );
        assert_eq!(nodes.last().unwrap().0 as usize, updates - 1);
        assert_eq!(
            nodes.last().unwrap().1.len() as u64,
            r["experiences"].as_u64().unwrap()
        );
        // The normal run's images are images-*.csv's, update by update.
        if r["variant"] == "normal" {
            let file = std::fs::read_dir(&out)
                .unwrap()
                .map(|e| e.unwrap().path())
                .find(|p| {
                    p.file_name()
                        .unwrap()
                        .to_string_lossy()
                        .starts_with("images-")
                })
                .unwrap();
            let csv = rows(&file);
            assert_eq!(csv.len(), updates);
            for ((k, pixels), row) in images.iter().zip(&csv) {
                let want: Vec<u8> = row[1..].iter().map(|v| v.parse().unwrap()).collect();
                assert_eq!(pixels, &want, "update {k}");
            }
        }
    }
    let (two, _) = run("two", "2");
    let (_, again) = decode::read(&two.join("run.rrd")).unwrap();
    decode::same_content(&chunks, &again).unwrap();
}

/// object-slam: the walks of the best set, their maps (the saved map's experiences) and
/// the identification confidence; parallel localisation runs, the same on 1 and 2 threads.
#[test]
fn object_slam_records_the_walks_and_maps_alike_on_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |name: &str, threads: &str| {
        let out = tmp.path().join(name);
        ok_with(
            threads,
            &[
                "object-slam",
                "--objects",
                "mug",
                "--json",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        out
    };
    let out = run("one", "1");
    let chunks = checked(
        &out.join("run.rrd"),
        &[
            "world/objects/mug",
            "world/objects/mug/mesh",
            "world/objects/mug/A/array",
            "world/objects/mug/A/estimated",
            "world/objects/mug/A/contacts/true",
            "world/objects/mug/A/contacts/estimated",
            "world/objects/mug/A/contacts/error",
            "world/objects/mug/B/true",
            "slam/mug-A/pose_cells",
            "slam/mug-A/map/experiences",
            "slam/mug-B/map/links",
            "recognition/mug-A/mug",
        ],
    );
    // A's last map is the map saved for the mug.
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("maps/mug.json")).unwrap()).unwrap();
    let nodes = decode::rows::<[f32; 2]>(
        &chunks,
        "/slam/mug-A/map/experiences",
        "Points2D:positions",
        "whisk",
    );
    assert_eq!(
        nodes.last().unwrap().1.len(),
        map["experiences"].as_array().unwrap().len()
    );
    // An estimate per whisk beside each true pose; at the first whisk both are the origin.
    let entities = decode::entities(&chunks);
    let (truth, estimate) = (
        decode::rows::<[f32; 3]>(
            &chunks,
            "/world/objects/mug/A/array",
            "Transform3D:translation",
            "whisk",
        ),
        decode::rows::<[f32; 3]>(
            &chunks,
            "/world/objects/mug/A/estimated",
            "Points3D:positions",
            "whisk",
        ),
    );
    assert_eq!(entities["/world/objects/mug/A/estimated"].rows, truth.len());
    let d: f32 = (0..3)
        .map(|i| (truth[0].1[0][i] - estimate[0].1[0][i]).powi(2))
        .sum();
    assert!(
        d.sqrt() < 1e-6,
        "first estimate {d} m² off the first true pose"
    );
    let two = run("two", "2");
    let (_, again) = decode::read(&two.join("run.rrd")).unwrap();
    decode::same_content(&chunks, &again).unwrap();
}
