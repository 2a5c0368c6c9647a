//! `whisker maze-slam` (thesis Ch 3): planar RatSLAM over the maze with tactile images.

use super::*;

#[test]
fn kidnapping_raises_the_energy_metric_and_runs_are_reproducible() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let scenario = repo("scenarios/maze.toml");
    let args = [
        "maze-slam",
        scenario.to_str().unwrap(),
        "--kidnap",
        "--seeds",
        "0",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = whisker(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let runs = v["runs"].as_array().unwrap();
    let get = |i: usize, k: &str| runs[i][k].as_f64().unwrap();
    // The kidnapped run's map holds a jump its odometry never saw: the relative poses of
    // its estimate disagree more with the truth (§3.3.1, Fig 3.5).
    assert!(get(1, "energy_metric") > 2.0 * get(0, "energy_metric"));
    for i in 0..2 {
        assert!((0.0..=1.0).contains(&get(i, "arr")) && (0.0..=1.0).contains(&get(i, "arcr")));
    }
    // The second circuit re-localises onto the first, mostly correctly.
    assert!(get(0, "arr") > 0.2 && get(0, "arcr") > 0.8, "{}", runs[0]);
    let trajectory = rows(&out.join("trajectory-kinematic-normal-0.csv"));
    assert_eq!(trajectory.len() as f64, get(0, "updates"));
    // Same seed, same bytes.
    let again = whisker(&args);
    assert_eq!(stdout(&again), stdout(&o));
    // A scenario without a maze is refused, naming the file and the field.
    let bad = whisker(&[
        "maze-slam",
        repo("scenarios/quickstart.toml").to_str().unwrap(),
    ]);
    assert_eq!(bad.status.code(), Some(2), "{}", stderr(&bad));
    assert!(stderr(&bad).contains("quickstart.toml") && stderr(&bad).contains("maze"));
}
