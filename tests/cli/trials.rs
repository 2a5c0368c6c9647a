//! `whisker trials`: rows independent of the worker count and equal to single `whisker run`s
//! with the same overrides (kills, signals, locks and write failures: trials_faults.rs),
//! shards merged into the unsharded bytes
//! (a missing shard named), a failing trial recorded while the batch goes on, and bad
//! `[trials]` input.

use super::*;
use serde_json::Value;

/// A small closed-loop batch: recognition of the Box, 2 strategies × 3 seeds, 60 whisks a
/// trial (about half a second each). `extra` goes into `[trials.factors]`.
pub(super) fn scenario(dir: &Path, iterations: usize, extra: &str) -> PathBuf {
    let abs = |p: &str| repo(p).display().to_string();
    let text = format!(
        r#"version = 1
seed = 0
sensing = "kinematic"

[arm]
urdf = "{urdf}"
initial_joints_deg = [0.0, -115.0, 137.5, -22.5, 90.0, 0.0]

[[objects]]
mesh = "{mesh}"
name = "box"
position_m = [0.55, 0.0, 0.0]

[explore]
task = "recognise"
max_iterations = {iterations}
maps = {{ box = "{box_map}", box_stack = "{stack_map}" }}

[trials]
seeds = [0, 1, 2]

[trials.factors]
explore.strategy = ["default", "feh"]
{extra}
"#,
        urdf = abs("assets/urdf/ur5_whisker_array.urdf"),
        mesh = abs("assets/meshes/box.obj"),
        box_map = abs("assets/maps/box.json"),
        stack_map = abs("assets/maps/box_stack.json"),
    );
    let file = dir.join("batch.toml");
    std::fs::write(&file, text).unwrap();
    file
}

pub(super) fn trials(args: &[&str]) -> Output {
    let mut all = vec!["trials"];
    all.extend_from_slice(args);
    whisker(&all)
}

pub(super) fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

pub(super) fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Fields of one CSV line (quotes understood).
fn fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(String::new()),
            (c, _) => out.last_mut().unwrap().push(c),
        }
    }
    out
}

/// A summary value at a dotted path, as trials.csv would print it.
fn at(summary: &Value, dotted: &str) -> String {
    let mut v = summary;
    for k in dotted.split('.') {
        v = &v[k];
    }
    match v {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

#[test]
fn rows_do_not_depend_on_jobs_and_equal_single_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let file = scenario(tmp.path(), 40, "");
    let (a, b) = (tmp.path().join("j1"), tmp.path().join("j2"));
    let f = file.to_str().unwrap();
    ok(&trials(&[f, "--out", a.to_str().unwrap(), "--jobs", "1"]));
    let o = trials(&[f, "--out", b.to_str().unwrap(), "--jobs", "2"]);
    console::assert_console(
        &o,
        "Batch trials",
        &["trials.csv", "report.md", "figures/", "runs/"],
        Some(&b),
    );
    let csv = read(&a.join("trials.csv"));
    assert_eq!(csv, read(&b.join("trials.csv")), "--jobs 1 and 2 differ");
    let text = String::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    let header = fields(lines.next().unwrap());
    let rows: Vec<Vec<String>> = lines.map(fields).collect();
    assert_eq!(rows.len(), 6);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let error = col("error");
    for row in &rows {
        assert_eq!(row[col("status")], "ok", "{row:?}");
        let (seed, strategy) = (&row[col("seed")], &row[col("explore.strategy")]);
        // The same trial as one `whisker run`: the same summary.json bytes, and the row
        // holds its values.
        let single = tmp.path().join(format!("single-{strategy}-{seed}"));
        ok(&whisker(&[
            "run",
            f,
            "--seed",
            seed,
            "--set",
            &format!("explore.strategy={strategy}"),
            "--out",
            single.to_str().unwrap(),
        ]));
        let summary_bytes = read(&single.join("summary.json"));
        assert_eq!(
            summary_bytes,
            read(&a.join("runs").join(&row[0]).join("summary.json")),
            "trial {} differs from whisker run",
            row[0]
        );
        let summary: Value = serde_json::from_slice(&summary_bytes).unwrap();
        assert_eq!(summary["strategy"], strategy.as_str());
        for (i, name) in header.iter().enumerate().skip(error + 1) {
            assert_eq!(row[i], at(&summary, name), "{} column {name}", row[0]);
        }
        assert_eq!(
            read(&single.join("explore.csv")),
            read(&a.join("runs").join(&row[0]).join("explore.csv"))
        );
        // Light outputs: the heavy contacts.csv and the recording stay out of the batch.
        assert!(single.join("contacts.csv").is_file() && single.join("run.rrd").is_file());
        let kept = a.join("runs").join(&row[0]);
        assert!(!kept.join("contacts.csv").exists() && !kept.join("run.rrd").exists());
    }
    // The report exists and names both strategies' box plots.
    let report = std::fs::read_to_string(a.join("report.md")).unwrap();
    assert!(report.contains("## By `explore.strategy`"), "{report}");
    assert!(
        a.join("figures/recognition.final_ic.box--by--explore.strategy.svg")
            .is_file()
    );
    // A new batch in a used directory is refused.
    let again = trials(&[f, "--out", a.to_str().unwrap()]);
    assert_eq!(again.status.code(), Some(2));
}

/// The small batch with `iterations` whisks a trial, run whole on 2 workers into
/// `dir/whole`: the reference bytes.
pub(super) fn uninterrupted(dir: &Path, iterations: usize) -> (PathBuf, PathBuf) {
    let file = scenario(dir, iterations, "");
    let whole = dir.join("whole");
    ok(&trials(&[
        file.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
        "--jobs",
        "2",
    ]));
    (file, whole)
}

#[test]
fn shards_merge_into_the_unsharded_bytes_and_a_missing_shard_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, whole) = uninterrupted(tmp.path(), 30);
    let f = file.to_str().unwrap();
    let shards: Vec<PathBuf> = (0..4).map(|i| tmp.path().join(format!("s{i}"))).collect();
    for (i, s) in shards.iter().enumerate() {
        ok(&trials(&[
            f,
            "--out",
            s.to_str().unwrap(),
            "--shard",
            &format!("{i}/4"),
            "--jobs",
            "1",
        ]));
    }
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge"];
    args.extend(shards.iter().map(|s| s.to_str().unwrap()));
    args.extend(["--out", merged.to_str().unwrap()]);
    ok(&trials(&args));
    assert_eq!(
        read(&merged.join("trials.csv")),
        read(&whole.join("trials.csv"))
    );
    assert!(merged.join("report.md").is_file());
    // Shard 2 left out: named, nothing written.
    let partial = tmp.path().join("partial");
    let out = trials(&[
        "merge",
        shards[0].to_str().unwrap(),
        shards[1].to_str().unwrap(),
        shards[3].to_str().unwrap(),
        "--out",
        partial.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("shards not given: 2/4"), "{err}");
    assert!(!partial.join("trials.csv").exists());
    // The same shard twice: the duplicated trials are named.
    let out = trials(&[
        "merge",
        shards[0].to_str().unwrap(),
        shards[0].to_str().unwrap(),
        shards[1].to_str().unwrap(),
        shards[2].to_str().unwrap(),
        shards[3].to_str().unwrap(),
        "--out",
        partial.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("seed=0 is in"));
}

#[test]
fn a_failing_trial_is_recorded_and_the_batch_goes_on() {
    let tmp = tempfile::tempdir().unwrap();
    // The second map "file" exists but is not a map: those trials fail when they load it.
    // (With `explore.transfer = true` the maps' sensing is not checked, so they are first
    // read by the run; without it the check reads them and refuses the batch up front.)
    let not_a_map = repo("assets/urdf/ur5_whisker_array.urdf");
    let extra = format!(
        "explore.maps.box_stack = [\"{}\", \"{}\"]",
        repo("assets/maps/box_stack.json").display(),
        not_a_map.display()
    );
    let file = scenario(tmp.path(), 20, &extra);
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replace("[explore]\n", "[explore]\ntransfer = true\n"),
    )
    .unwrap();
    let dir = tmp.path().join("out");
    let out = trials(&[file.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("trials.csv")).unwrap();
    let status: Vec<String> = csv.lines().skip(1).map(|l| fields(l)[1].clone()).collect();
    assert_eq!(status.len(), 12);
    assert_eq!(status.iter().filter(|s| *s == "failed").count(), 6, "{csv}");
    assert!(csv.contains("explore.maps.box_stack=#1"), "{csv}");
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("## Failed trials"));
    // --resume leaves failed trials be; --retry-failed runs them (and only them) again.
    let d = dir.to_str().unwrap();
    let f = file.to_str().unwrap();
    let again = trials(&[f, "--out", d, "--resume"]);
    assert_eq!(again.status.code(), Some(1));
    let log = || std::fs::read_to_string(dir.join("log.txt")).unwrap();
    let starts = |log: &str| log.lines().filter(|l| l.contains(" start ")).count();
    assert_eq!(starts(&log()), 12);
    let retried = trials(&[f, "--out", d, "--resume", "--retry-failed"]);
    assert_eq!(retried.status.code(), Some(1));
    assert_eq!(starts(&log()), 18);
    let journal = std::fs::read_to_string(dir.join("journal.jsonl")).unwrap();
    assert_eq!(journal.lines().count(), 12, "one line per trial");
    assert_eq!(
        std::fs::read_to_string(dir.join("trials.csv")).unwrap(),
        csv
    );
}

#[test]
fn bad_trials_input_names_the_field_and_a_changed_scenario_is_refused_on_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let cases = [
        (
            "explore.spc = [true, \"maybe\"]",
            "trials.factors.explore.spc[1]",
        ),
        ("explore.bogus = [1, 2]", "bogus"),
        (
            "explore.max_iterations = 5",
            "trials.factors.explore.max_iterations",
        ),
        ("seed = [1, 2]", "trials.factors.seed"),
        // A NaN inside a table-valued level: passed `check` and failed every trial at
        // run time (exit 1) before #37.
        (
            "objects = [[{ mesh = \"box.obj\", position_m = [nan, 0.0, 0.0] }]]",
            "trials.factors.objects[0]`: ",
        ),
    ];
    for (extra, want) in cases {
        let file = scenario(tmp.path(), 20, extra);
        let dir = tmp.path().join("never");
        let out = trials(&[file.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra}: {err}");
        assert!(
            err.contains(want) && err.contains("batch.toml"),
            "{extra}: {err}"
        );
        if extra.contains("nan") {
            assert!(
                err.contains("position_m[0]`: expected a finite number"),
                "{err}"
            );
        }
        assert!(!dir.exists(), "{extra}: wrote output");
    }
    // A batch begun, then the scenario edited: --resume refuses, --force proceeds.
    let file = scenario(tmp.path(), 10, "");
    let dir = tmp.path().join("out");
    let (f, d) = (file.to_str().unwrap(), dir.to_str().unwrap());
    ok(&trials(&[f, "--out", d, "--no-report"]));
    scenario(tmp.path(), 11, "");
    let out = trials(&[f, "--out", d, "--resume"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("the scenario changed"));
    ok(&trials(&[
        f,
        "--out",
        d,
        "--resume",
        "--force",
        "--no-report",
    ]));
}

/// A maze-slam trial (`experiment = "maze-slam"`, one shard of the §3.3 batch: seed 0)
/// holds the figures `whisker maze-slam` prints for that seed.
#[test]
fn a_maze_slam_trial_row_equals_whisker_maze_slam() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = repo("scenarios/trials_maze.toml");
    let s = scenario.to_str().unwrap();
    let dir = tmp.path().join("out");
    let batch = trials(&[s, "--out", dir.to_str().unwrap(), "--shard", "0/10"]);
    ok(&batch);
    // The trial's notes go to its stdout.txt, not between the batch's progress lines.
    let notes = std::fs::read_to_string(dir.join("runs/seed=0/stdout.txt")).unwrap();
    assert!(notes.contains("seed 0 normal kinematic: "), "{notes}");
    assert!(!stderr(&batch).contains(" updates"), "{}", stderr(&batch));
    let text = std::fs::read_to_string(dir.join("trials.csv")).unwrap();
    let mut lines = text.lines();
    let header = fields(lines.next().unwrap());
    let row = fields(lines.next().unwrap());
    assert!(lines.next().is_none(), "shard 0/10 is seed 0 alone");
    let o = whisker(&["maze-slam", s, "--seeds", "0", "--json"]);
    ok(&o);
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 2, "normal and kidnapped");
    let mut checked = 0;
    for run in runs {
        let prefix = format!(
            "{}.{}",
            run["variant"].as_str().unwrap(),
            run["images"].as_str().unwrap()
        );
        for figure in ["arr", "arcr", "energy_metric", "experiences", "templates"] {
            let column = header
                .iter()
                .position(|h| *h == format!("{prefix}.{figure}"))
                .unwrap();
            assert_eq!(row[column], run[figure].to_string(), "{prefix}.{figure}");
            checked += 1;
        }
    }
    assert_eq!(checked, 10);
}
