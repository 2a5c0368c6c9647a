//! Fuzzing (#37): structured and byte-level mutations of the project's real inputs, run
//! through the `whisker` binary, with the promises of `docs/limits.md` as the property:
//! the run ends within 60 s, by itself (no abort, no signal), with exit code 0 or 2 (never
//! 101, a panic); a refusal names one of the files involved; and a refused command leaves
//! the working and input directories as they were.
//!
//! Bounded for CI (a fixed seed, a few dozen cases per input kind, ~2 min on 2 cores).
//! The longer run of `docs/limits.md`:
//!
//! ```text
//! WHISKER_FUZZ_CASES=2000 WHISKER_FUZZ_SEED=random cargo test --release --test cli fuzz::
//! ```
//!
//! `WHISKER_FUZZ_VERBOSE=1` prints each case's exit code and first line of its message.
//! A failing case is shrunk by proptest and its seed saved under `proptest-regressions/`
//! (replayed first on every later run); the cases found while building this are kept as
//! named tests in `regressions.rs`.

mod command_line;
mod datasets;
mod files;
mod mutate;
mod regressions;
mod scenario;

use proptest::test_runner::{Config, RngSeed, TestCaseError};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest any case may run (the issue's definition of a hang).
pub const LIMIT: Duration = Duration::from_secs(60);

/// The proptest configuration: `default_cases` cases (or `WHISKER_FUZZ_CASES`), the fixed
/// seed 37 (or `WHISKER_FUZZ_SEED`: a number, or `random`).
pub fn config(default_cases: u32) -> Config {
    let cases = std::env::var("WHISKER_FUZZ_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(default_cases);
    let seed = match std::env::var("WHISKER_FUZZ_SEED").as_deref() {
        Ok("random") => {
            use std::hash::{BuildHasher, RandomState};
            RandomState::new().hash_one(std::process::id())
        }
        Ok(s) => s.parse().expect("WHISKER_FUZZ_SEED: a number or `random`"),
        Err(_) => 37,
    };
    eprintln!("fuzz: WHISKER_FUZZ_SEED={seed} WHISKER_FUZZ_CASES={cases}");
    Config {
        cases,
        rng_seed: RngSeed::Fixed(seed),
        // Shrinking re-runs the binary; a few minutes at most.
        max_shrink_time: 180_000,
        ..Config::default()
    }
}

/// How a case ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Exit code 0.
    Accepted,
    /// Exit code 2, a file named.
    Refused,
}

/// One invocation of `whisker` and what its refusal must name.
pub struct Case<'a> {
    /// The arguments.
    pub args: Vec<String>,
    /// The working directory (its content must not change on a refusal).
    pub cwd: &'a Path,
    /// A refusal names at least one of these (file names or fragments of a path); empty:
    /// any message.
    pub names: Vec<String>,
    /// More directories whose content must not change on a refusal.
    pub watch: Vec<PathBuf>,
}

/// Runs `case` and checks the promises; the outcome, or why the case fails.
pub fn run(case: &Case) -> Result<Outcome, TestCaseError> {
    let dirs: Vec<&Path> = std::iter::once(case.cwd)
        .chain(case.watch.iter().map(PathBuf::as_path))
        .collect();
    let before: Vec<_> = dirs.iter().map(|d| listing(d)).collect();
    let log = tempfile::tempdir().unwrap();
    let (out_path, err_path) = (log.path().join("out"), log.path().join("err"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(&case.args)
        .current_dir(case.cwd)
        .env("RAYON_NUM_THREADS", "2")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .spawn()
        .expect("whisker runs");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > LIMIT {
            child.kill().ok();
            child.wait().ok();
            return Err(TestCaseError::fail(format!(
                "hang: {:?} ran for more than {LIMIT:?}",
                case.args
            )));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let err = std::fs::read_to_string(&err_path).unwrap_or_default();
    let show = || format!("{:?}\n{}", case.args, tail(&err));
    let Some(code) = status.code() else {
        return Err(TestCaseError::fail(format!(
            "ended by a signal ({status}): {}",
            show()
        )));
    };
    if std::env::var_os("WHISKER_FUZZ_VERBOSE").is_some() {
        eprintln!(
            "fuzz: exit {code} {:?}: {}",
            &case.args[..case.args.len().min(2)],
            err.lines().next().unwrap_or("")
        );
    }
    if err.contains("panicked") || code == 101 {
        return Err(TestCaseError::fail(format!("panic: {}", show())));
    }
    match code {
        0 => Ok(Outcome::Accepted),
        2 => {
            if !case.names.is_empty() && !case.names.iter().any(|n| err.contains(n.as_str())) {
                return Err(TestCaseError::fail(format!(
                    "refusal names none of {:?}: {}",
                    case.names,
                    show()
                )));
            }
            for (d, was) in dirs.iter().zip(&before) {
                let now = listing(d);
                if &now != was {
                    let new: Vec<_> = now.difference(was).collect();
                    let gone: Vec<_> = was.difference(&now).collect();
                    return Err(TestCaseError::fail(format!(
                        "refused but changed {}: new {new:?}, gone {gone:?}: {}",
                        d.display(),
                        show()
                    )));
                }
            }
            Ok(Outcome::Refused)
        }
        c => Err(TestCaseError::fail(format!("exit code {c}: {}", show()))),
    }
}

/// Every path under `dir` (relative) with its size.
pub fn listing(dir: &Path) -> BTreeSet<(String, u64)> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeSet<(String, u64)>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
            let meta = e.metadata().unwrap();
            out.insert((rel, if meta.is_dir() { 0 } else { meta.len() }));
            if meta.is_dir() {
                walk(root, &p, out);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(dir, dir, &mut out);
    out
}

/// The last few lines of a message.
fn tail(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(12)..].join("\n")
}

/// A string argument.
pub fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// `text` (a scenario of the repository) with its relative paths to `assets/` made
/// absolute, so that it can be read from any directory.
pub fn absolute_assets(text: &str) -> String {
    let assets = super::repo("assets").display().to_string();
    text.replace("\"../assets", &format!("\"{assets}"))
        .replace("'../assets", &format!("'{assets}"))
}
