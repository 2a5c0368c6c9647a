//! Running a batch: `whisker trials SCENARIO --out DIR [--jobs N] [--shard I/K]
//! [--resume [--force]]`.
//!
//! N worker threads take the trials in order; each trial runs on one thread (its own
//! one-thread rayon pool) so that N workers keep N cores busy and no trial's result depends
//! on how many there are. As a trial ends its entry is appended to the journal and synced,
//! `trials.csv` is rewritten, and the log says so; a failing trial (an error, or a panic)
//! is recorded as failed and the batch goes on. Resuming reads the journal, deletes the
//! half-written outputs of trials that were running when the process died, and runs each
//! missing trial once.

use crate::journal::{self, CSV, Entry, Journal, Meta, RUNS, Status};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use whisker_experiments::record::{Context, Reporter};
use whisker_scenario::grid::{Batch, Shard, Trial};
use whisker_scenario::trials::{HEAVY, Outputs, TrialCommand};
use whisker_scenario::{Error, Result};

/// How a batch runs (`whisker trials SCENARIO …`).
#[derive(Debug, Clone)]
pub struct Settings {
    /// Output directory (created): trials.json, journal.jsonl, trials.csv, log.txt,
    /// runs/<key>/, report.md and figures/.
    pub out: PathBuf,
    /// Worker threads, one trial each [default: the available cores].
    pub jobs: Option<usize>,
    /// Run only part I of K (from 0): trials I, I+K, I+2K… of the fixed order.
    pub shard: Option<Shard>,
    /// Finish a batch in an existing directory: run each trial its journal lacks.
    pub resume: bool,
    /// With `resume`: continue although the scenario changed since the batch began.
    pub force: bool,
    /// With `resume`: run the trials that failed again (their journal lines are dropped).
    pub retry_failed: bool,
    /// Do not write report.md and the figures at the end.
    pub no_report: bool,
}

/// Hears a batch's progress: the CLI draws a bar on a terminal, a line per trial
/// otherwise.
pub trait Progress: Sync {
    /// `total` trials are about to run.
    fn start(&self, total: usize);
    /// A trial ended: its journal entry.
    fn trial(&self, entry: &Entry);
    /// The last trial ended.
    fn finish(&self);
}

/// What a batch did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outcome {
    /// Trials run now.
    pub ran: usize,
    /// Trials finished earlier (resume).
    pub already: usize,
    /// Failed trials in the directory's journal (earlier ones included).
    pub failed: usize,
}

/// Runs (or resumes) `batch` into `o.out`.
pub fn run(batch: &Batch, o: &Settings, ctx: Context, progress: &dyn Progress) -> Result<Outcome> {
    let dir = &o.out;
    whisker_scenario::files::create_dir(dir)?;
    let _lock = crate::lock::Lock::exclusive(dir)?;
    let meta = Meta::of(batch, o.shard);
    prepare(dir, &meta, o)?;
    let mut entries = journal::read(dir)?;
    if o.retry_failed && entries.iter().any(|e| e.status == Status::Failed) {
        entries.retain(|e| e.status == Status::Ok);
        journal::rewrite(dir, &entries)?;
    }
    let done: std::collections::BTreeSet<String> = entries.iter().map(|e| e.key.clone()).collect();
    let part = batch.shard(o.shard);
    let todo: Vec<&Trial> = part
        .iter()
        .copied()
        .filter(|t| !done.contains(&t.key))
        .collect();
    let already = part.len() - todo.len();
    for t in &todo {
        // Outputs of a trial that was running when the batch was killed.
        let half = dir.join(RUNS).join(&t.key);
        if half.exists() {
            std::fs::remove_dir_all(&half)
                .map_err(|e| Error::Output(format!("cannot clear {}: {e}", half.display())))?;
        }
    }
    let jobs = o
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    ctx.note(&format!(
        "trials     {} of {} trials{} to run on {jobs} worker{} ({already} finished before) into {}",
        todo.len(),
        batch.trials.len(),
        o.shard.map_or(String::new(), |s| format!(" (shard {s})")),
        if jobs == 1 { "" } else { "s" },
        dir.display()
    ));
    let mut journal = Journal::open(dir)?;
    // A kill between a journal line and its log line: the journal is the record, the log
    // catches up.
    let logged = journal::finished_in_log(dir);
    for e in entries.iter().filter(|e| !logged.contains(&e.key)) {
        journal.log(e.status.name(), &e.key)?;
    }
    progress.start(todo.len());
    let shared = Mutex::new((journal, std::mem::take(&mut entries)));
    let next = AtomicUsize::new(0);
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    std::thread::scope(|scope| {
        for _ in 0..jobs.min(todo.len()) {
            scope.spawn(|| {
                loop {
                    if whisker_scenario::stop::requested().is_some() {
                        break;
                    }
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let Some(&trial) = todo.get(i) else { break };
                    if let Err(e) = one(batch, dir, trial, &meta, &shared, progress, ctx) {
                        // The machine failed, or a signal asked: stop taking trials.
                        first_error
                            .lock()
                            .expect("no panic holds it")
                            .get_or_insert(e);
                        next.store(todo.len(), Ordering::SeqCst);
                        break;
                    }
                }
            });
        }
    });
    progress.finish();
    let stopped = first_error.into_inner().expect("no panic holds it");
    if let Some(e) = stopped.or_else(|| whisker_scenario::stop::check().err()) {
        return Err(stopped_batch(e, batch, o));
    }
    let (_, entries) = shared.into_inner().expect("no panic holds it");
    // Written after each trial too; again here for a batch stopped between a trial's
    // journal line and its trials.csv (nothing left to run on --resume).
    whisker_scenario::files::write_atomic(
        &dir.join(CSV),
        journal::csv(&meta.factors, &entries).as_bytes(),
    )?;
    let failed = entries
        .iter()
        .filter(|e| e.status == Status::Failed)
        .count();
    if !o.no_report {
        let written = crate::report::write(dir)?;
        ctx.note(&format!("report     {}", written.display()));
    }
    Ok(Outcome {
        ran: todo.len(),
        already,
        failed,
    })
}

/// The error that stopped a batch, with what was kept and the command that finishes it.
fn stopped_batch(e: Error, batch: &Batch, o: &Settings) -> Error {
    let resume = format!(
        "whisker trials {} --out {}{} --resume",
        batch.file.display(),
        o.out.display(),
        o.shard.map_or(String::new(), |s| format!(" --shard {s}"))
    );
    let kept = "the finished trials are journalled; the trials that were running are not, \
                and --resume runs them again";
    match e {
        Error::Interrupted { signal, message } => Error::Interrupted {
            signal,
            message: format!("{message}: the batch stopped; {kept}. Finish it with: {resume}"),
        },
        Error::Output(m) => Error::Output(format!(
            "{m}: the batch stopped, since this is a failure of the machine, not of a trial \
             (no space, an I/O error, a permission); {kept}. Free the space or fix the \
             cause, then: {resume}"
        )),
        other => other,
    }
}

/// Checks (resume) or writes (new batch) the directory's metadata.
fn prepare(dir: &Path, meta: &Meta, o: &Settings) -> Result {
    let exists = dir.join(journal::META).exists();
    match (exists, o.resume) {
        (false, _) => meta.write(dir),
        (true, false) => Err(Error::Input(format!(
            "{} already holds a batch ({}): add --resume to finish it, or choose another --out",
            dir.display(),
            journal::META
        ))),
        (true, true) => {
            let old = Meta::read(dir)?;
            if old.shard != meta.shard {
                return Err(Error::Input(format!(
                    "--shard: {} holds shard {} of the batch, not {}",
                    dir.display(),
                    old.shard.map_or("none".into(), |s| s.to_string()),
                    meta.shard.map_or("none".into(), |s| s.to_string())
                )));
            }
            if old.scenario_hash != meta.scenario_hash {
                if !o.force {
                    return Err(Error::Input(format!(
                        "{}: the scenario changed since the batch in {} began (hash {} then, {} now): \
                         its finished rows would not match new ones. Use another --out, or add --force \
                         to keep the finished rows and run the rest with the scenario as it is now",
                        meta.scenario,
                        dir.display(),
                        &old.scenario_hash[..12],
                        &meta.scenario_hash[..12]
                    )));
                }
                meta.write(dir)?;
            }
            Ok(())
        }
    }
}

/// Runs one trial and records it. A trial that failed is journalled `failed`; one whose
/// outputs could not be written (the machine's failure) is not journalled: the error
/// stops the batch and a plain `--resume` runs the trial again.
fn one(
    batch: &Batch,
    dir: &Path,
    trial: &Trial,
    meta: &Meta,
    shared: &Mutex<(Journal, Vec<Entry>)>,
    progress: &dyn Progress,
    ctx: Context,
) -> Result {
    shared
        .lock()
        .expect("no panic holds it")
        .0
        .log("start", &trial.key)?;
    let started = Instant::now();
    let result = match run_trial(batch, trial, &dir.join(RUNS).join(&trial.key), ctx) {
        Ok(summary) => Ok(summary),
        Err(Failed::Trial(e)) => Err(e),
        Err(Failed::Stopped(e)) => return Err(e),
    };
    let entry = Entry::new(batch, trial, result, started.elapsed().as_secs_f64());
    let mut guard = shared.lock().expect("no panic holds it");
    let (journal, entries) = &mut *guard;
    journal.append(&entry)?;
    journal.log(entry.status.name(), &trial.key)?;
    progress.trial(&entry);
    entries.push(entry);
    whisker_scenario::files::write_atomic(
        &dir.join(CSV),
        journal::csv(&meta.factors, entries).as_bytes(),
    )
}

/// Why a trial gave no row.
#[derive(Debug)]
pub enum Failed {
    /// The trial itself failed (an error of its run, or a panic): journalled `failed`.
    Trial(String),
    /// The batch must stop: the trial's outputs could not be written ([`Error::Output`],
    /// the machine failed), or a signal asked ([`Error::Interrupted`]).
    Stopped(Error),
}

/// Runs `trial` into `dir` on one thread; its summary, or why not (a panic included).
pub fn run_trial(
    batch: &Batch,
    trial: &Trial,
    dir: &Path,
    batch_ctx: Context,
) -> Result<serde_json::Value, Failed> {
    let work = || -> Result<serde_json::Value> {
        let scenario = batch.scenario(trial)?;
        whisker_scenario::files::create_dir(dir)?;
        let path = dir.join("stdout.txt");
        whisker_scenario::files::wrote(&path);
        let mut file = std::fs::File::create(&path).map_err(|e| Error::output(&path, e))?;
        use std::io::Write;
        let _ = writeln!(file, "# trial {}: {}", trial.key, batch.command(trial));
        let say = ToFile(Mutex::new(file), batch_ctx.reporter, &trial.key);
        let ctx = Context {
            reporter: &say,
            ..batch_ctx
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| Error::Failure(format!("thread pool: {e}")))?;
        // A trial's recording (outputs = "all") is named after the trial.
        let stem = batch.file.file_stem().unwrap_or_default().to_string_lossy();
        let rrd = whisker_experiments::record::Target {
            id: Some(format!("{stem}-{}", trial.key)),
            ..Default::default()
        };
        pool.install(|| match batch.config.experiment {
            TrialCommand::Run => whisker_experiments::run::execute(&scenario, dir, &rrd, ctx),
            TrialCommand::MazeSlam => {
                whisker_experiments::maze_slam::trial(&scenario, dir, &rrd, ctx)
            }
        })?;
        if batch.config.outputs == Outputs::Light {
            drop_heavy(dir)?;
        }
        let summary = dir.join("summary.json");
        let text = std::fs::read_to_string(&summary).map_err(|e| Error::output(&summary, e))?;
        serde_json::from_str(&text)
            .map_err(|e| Error::Failure(format!("{}: {e}", summary.display())))
    };
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
        Ok(Ok(summary)) => Ok(summary),
        Ok(Err(e @ (Error::Output(_) | Error::Interrupted { .. }))) => Err(Failed::Stopped(e)),
        Ok(Err(e)) => Err(Failed::Trial(e.to_string())),
        Err(panic) => Err(Failed::Trial(format!(
            "panicked: {}",
            panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        ))),
    }
}

/// A trial's account, written to its `stdout.txt`, and its notes too (a long physics
/// trial's progress can be followed there with `tail -f`): on the batch's stderr, trials
/// running side by side would interleave them between the batch's progress lines. Warnings
/// reach the batch's stderr as well, named by the trial.
struct ToFile<'a>(Mutex<std::fs::File>, &'a dyn Reporter, &'a str);

impl Reporter for ToFile<'_> {
    fn say(&self, line: &str) {
        use std::io::Write;
        let _ = writeln!(self.0.lock().expect("no panic holds it"), "{line}");
    }

    fn note(&self, line: &str) {
        self.say(line);
        if line.starts_with("warning") {
            self.1.note(&format!("{line} (trial {})", self.2));
        }
    }
}

/// Deletes the heavy outputs ([`HEAVY`]) of a light trial.
fn drop_heavy(dir: &Path) -> Result {
    let fail = |e: std::io::Error| Error::output(dir, e);
    for item in std::fs::read_dir(dir).map_err(fail)? {
        let item = item.map_err(fail)?;
        let name = item.file_name().to_string_lossy().into_owned();
        if HEAVY.iter().any(|h| name.starts_with(h)) {
            std::fs::remove_file(item.path()).map_err(fail)?;
        }
    }
    Ok(())
}
