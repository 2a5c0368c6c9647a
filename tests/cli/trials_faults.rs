//! `whisker trials` against its operators and its machine (issue #68): killed with
//! SIGKILL at three chosen moments and at seeded random ones, stopped by SIGTERM and
//! SIGINT, a second process on a running batch, a write failure injected into the output
//! layer. Each ends, after a plain `--resume`, with the uninterrupted batch's trials.csv,
//! every trial journalled once and no `failed` row caused by the machine.

use super::trials::{ok, read, trials, uninterrupted};
use super::*;
use rand::RngExt;
use serde_json::Value;
use std::collections::BTreeMap;
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

/// Starts `whisker trials ARGS` in the background (stderr kept).
fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_whisker"))
        .arg("trials")
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Waits until `ready` holds of `dir` (or the child ended, or 120 s passed).
fn wait_until(child: &mut Child, dir: &Path, ready: impl Fn(&Path) -> bool) {
    let deadline = Instant::now() + Duration::from_secs(120);
    while !ready(dir) && Instant::now() < deadline {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Starts a batch and kills it with SIGKILL once `ready` holds of its directory (or at
/// the deadline).
fn kill_when(args: &[&str], dir: &Path, ready: impl Fn(&Path) -> bool) {
    let mut child = spawn(args);
    wait_until(&mut child, dir, ready);
    let _ = child.kill(); // SIGKILL
    child.wait().unwrap();
}

/// Sends `signal` (`TERM`, `INT`) to the child and returns its exit status and stderr.
fn signal(child: Child, signal: &str) -> Output {
    let status = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    child.wait_with_output().unwrap()
}

/// The journal's keys in order, and its `failed` rows.
fn journal(dir: &Path) -> (Vec<String>, usize) {
    let text = std::fs::read_to_string(dir.join("journal.jsonl")).unwrap_or_default();
    let entries: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let keys = entries
        .iter()
        .map(|e| e["key"].as_str().unwrap().to_string())
        .collect();
    let failed = entries.iter().filter(|e| e["status"] == "failed").count();
    (keys, failed)
}

/// After a final `--resume`: the uninterrupted bytes, each of the 6 keys journalled once,
/// no `failed` row.
fn finished_as_uninterrupted(f: &str, dir: &Path, whole: &Path) {
    ok(&trials(&[
        f,
        "--out",
        dir.to_str().unwrap(),
        "--jobs",
        "2",
        "--resume",
    ]));
    assert_eq!(
        read(&dir.join("trials.csv")),
        read(&whole.join("trials.csv"))
    );
    let (keys, failed) = journal(dir);
    assert_eq!(failed, 0, "a failed row");
    let unique: std::collections::BTreeSet<&String> = keys.iter().collect();
    assert_eq!(
        (keys.len(), unique.len()),
        (6, 6),
        "a key missing or journalled twice"
    );
}

fn journal_lines(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("journal.jsonl"))
        .map(|t| t.matches('\n').count())
        .unwrap_or(0)
}

fn started(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("log.txt"))
        .map(|t| t.lines().filter(|l| l.contains(" start ")).count())
        .unwrap_or(0)
}

#[test]
fn killed_three_times_and_resumed_gives_the_uninterrupted_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, whole) = uninterrupted(tmp.path(), 80);
    let f = file.to_str().unwrap();
    let dir = tmp.path().join("killed");
    let d = dir.to_str().unwrap();
    // 1: while the first trials run, before any has finished.
    kill_when(&[f, "--out", d, "--jobs", "2"], &dir, |p| started(p) >= 2);
    assert_eq!(
        journal_lines(&dir),
        0,
        "killed too late to test the first moment"
    );
    // 2: right after the second row became durable.
    kill_when(&[f, "--out", d, "--jobs", "2", "--resume"], &dir, |p| {
        journal_lines(p) >= 2
    });
    // 3: in the middle of a later trial.
    kill_when(&[f, "--out", d, "--jobs", "1", "--resume"], &dir, |p| {
        journal_lines(p) >= 4 && started(p) > journal_lines(p) + 2
    });
    assert!(
        journal_lines(&dir) < 6,
        "the batch finished before the third kill"
    );
    ok(&trials(&[f, "--out", d, "--jobs", "2", "--resume"]));
    assert_eq!(
        read(&dir.join("trials.csv")),
        read(&whole.join("trials.csv"))
    );
    // From the log: every trial finished exactly once and never started again after.
    let log = std::fs::read_to_string(dir.join("log.txt")).unwrap();
    let mut finished: BTreeMap<String, usize> = BTreeMap::new();
    for line in log.lines().filter(|l| !l.is_empty()) {
        let parts: Vec<&str> = line.split(' ').collect();
        assert_eq!(parts.len(), 4, "a torn log line: {line:?}");
        let (what, key) = (parts[2], parts[3].to_string());
        match what {
            "start" => assert!(
                !finished.contains_key(&key),
                "{key} started after it finished"
            ),
            "ok" | "failed" => *finished.entry(key).or_default() += 1,
            other => panic!("unexpected log line {other}"),
        }
    }
    assert_eq!(finished.len(), 6);
    assert!(finished.values().all(|&n| n == 1), "{finished:?}");
    // Every trial's outputs are whole (the killed ones' were cleared and redone).
    for key in finished.keys() {
        assert_eq!(
            read(&dir.join("runs").join(key).join("summary.json")),
            read(&whole.join("runs").join(key).join("summary.json"))
        );
    }
}

/// Killed at seeded random moments — SIGKILL and SIGTERM in turn, 5 times — then resumed:
/// the uninterrupted bytes.
#[test]
fn killed_at_random_moments_and_resumed_gives_the_uninterrupted_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, whole) = uninterrupted(tmp.path(), 80);
    let f = file.to_str().unwrap();
    let dir = tmp.path().join("killed");
    let d = dir.to_str().unwrap();
    let mut rng = whisker_slam::rng::substream(68, "tests/kill-moments");
    for round in 0..5 {
        let mut args = vec![f, "--out", d, "--jobs", "2"];
        if dir.join("trials.json").exists() {
            args.push("--resume");
        }
        let mut child = spawn(&args);
        std::thread::sleep(Duration::from_millis(rng.random_range(20..900)));
        if round % 2 == 0 {
            let _ = child.kill();
            child.wait().unwrap();
        } else {
            let out = signal(child, "TERM");
            // Stopped by the signal (143), or finished (0) or still starting (killed by
            // SIGTERM's default before the handler was set: no code).
            assert!(
                matches!(out.status.code(), Some(0 | 143) | None),
                "{:?}: {}",
                out.status,
                stderr(&out)
            );
        }
    }
    finished_as_uninterrupted(f, &dir, &whole);
}

/// SIGTERM (Slurm's time limit or preemption) and SIGINT (Ctrl-C) on a running batch:
/// it exits with 143 and 130, says how to resume, leaves the running trials unjournalled
/// and no `failed` row; `--resume` finishes with the uninterrupted bytes.
#[test]
fn sigterm_and_sigint_stop_the_batch_cleanly() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, whole) = uninterrupted(tmp.path(), 400);
    let f = file.to_str().unwrap();
    let dir = tmp.path().join("signalled");
    let d = dir.to_str().unwrap();
    for (sig, code, resume) in [("TERM", 143, false), ("INT", 130, true)] {
        let mut args = vec![f, "--out", d, "--jobs", "2"];
        if resume {
            args.push("--resume");
        }
        let before = started(&dir);
        let mut child = spawn(&args);
        wait_until(&mut child, &dir, |p| started(p) >= before + 2);
        let asked = Instant::now();
        let out = signal(child, sig);
        assert_eq!(out.status.code(), Some(code), "SIG{sig}: {}", stderr(&out));
        assert!(
            asked.elapsed() < Duration::from_secs(15),
            "SIG{sig}: the running trials took {:?} to stop",
            asked.elapsed()
        );
        assert!(stderr(&out).contains("--resume"), "{}", stderr(&out));
        let (keys, failed) = journal(&dir);
        assert_eq!(failed, 0);
        assert!(keys.len() < 6, "SIG{sig} came after the batch finished");
    }
    finished_as_uninterrupted(f, &dir, &whole);
}

/// A second process on a running batch — `--resume`, `report`, `merge` from it — is
/// refused (exit 2) naming the holder's pid; once the holder is killed (SIGKILL) nothing
/// blocks the resume.
#[test]
fn a_second_process_on_a_running_batch_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, whole) = uninterrupted(tmp.path(), 400);
    let f = file.to_str().unwrap();
    let dir = tmp.path().join("busy");
    let d = dir.to_str().unwrap();
    let mut child = spawn(&[f, "--out", d, "--jobs", "1"]);
    wait_until(&mut child, &dir, |p| started(p) >= 1);
    let holder = format!("pid {}", child.id());
    let merged = tmp.path().join("merged");
    for args in [
        vec![f, "--out", d, "--resume"],
        vec!["report", d],
        vec!["merge", d, "--out", merged.to_str().unwrap()],
    ] {
        let o = trials(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(&holder), "{args:?}: {}", stderr(&o));
    }
    assert!(
        child.try_wait().unwrap().is_none(),
        "the holder ended early"
    );
    let _ = child.kill();
    child.wait().unwrap();
    finished_as_uninterrupted(f, &dir, &whole);
}

/// A write failure injected into the output layer (`WHISKER_FAIL_WRITES_FROM`, as a disk
/// filling up) stops the batch with exit 1 naming the machine's failure, journals no
/// trial `failed`, and a plain `--resume` once the disk has room gives the uninterrupted
/// bytes.
#[test]
fn a_full_disk_stops_the_batch_and_a_plain_resume_finishes_it() {
    let tmp = tempfile::tempdir().unwrap();
    let (file, whole) = uninterrupted(tmp.path(), 80);
    let f = file.to_str().unwrap();
    let dir = tmp.path().join("full");
    let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(["trials", f, "--out", dir.to_str().unwrap(), "--jobs", "2"])
        .env(whisker_scenario::files::FAULT_ENV, "9")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("failure of the machine"),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    let (keys, failed) = journal(&dir);
    assert_eq!(failed, 0, "the machine's failure journalled as a trial's");
    assert!(keys.len() < 6, "the fault came after the batch finished");
    finished_as_uninterrupted(f, &dir, &whole);
}
