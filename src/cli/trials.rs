//! `whisker trials`: run a batch, `merge`, `slurm`, `report`; the batch's progress.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use whisker_experiments::record::Context;
use whisker_scenario::grid::{Batch, Shard};
use whisker_scenario::{Error, Result};
use whisker_trials::batch::{self, Progress};
use whisker_trials::journal::{self, Entry, Status};
use whisker_trials::{merge, report, slurm};

/// `whisker trials`.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    /// The scenario with a `[trials]` section.
    #[arg(required = true)]
    pub scenario: Option<PathBuf>,
    #[command(flatten)]
    pub run: Option<BatchArgs>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// `whisker trials SCENARIO …`.
#[derive(clap::Args, Debug, Clone)]
pub struct BatchArgs {
    /// Output directory (created): trials.json, journal.jsonl, trials.csv, log.txt,
    /// runs/<key>/, report.md and figures/.
    #[arg(long)]
    pub out: PathBuf,
    /// Worker threads, one trial each [default: the available cores].
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only part I of K (from 0): trials I, I+K, I+2K… of the fixed order.
    #[arg(long, value_parser = Shard::parse)]
    pub shard: Option<Shard>,
    /// Finish a batch in an existing directory: run each trial its journal lacks.
    #[arg(long)]
    pub resume: bool,
    /// With --resume: continue although the scenario changed since the batch began.
    #[arg(long, requires = "resume")]
    pub force: bool,
    /// With --resume: run the trials that failed again (their journal lines are dropped).
    #[arg(long, requires = "resume")]
    pub retry_failed: bool,
    /// Do not write report.md and the figures at the end.
    #[arg(long)]
    pub no_report: bool,
    /// On SIGTERM or SIGINT: seconds the running trials have to stop (each stops at its
    /// next whisk, update or simulated second) before the process leaves them and exits
    #[arg(long, default_value_t = super::signals::GRACE_S)]
    pub grace: f64,
}

/// `whisker trials <command>`.
#[derive(clap::Subcommand, Debug)]
pub enum Command {
    /// Merge shard directories into the directory of one unsharded batch.
    Merge {
        /// The shard directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// The merged batch's directory (created; not one of the shards).
        #[arg(long)]
        out: PathBuf,
    },
    /// Write Slurm job-array and merge scripts for a batch.
    Slurm(SlurmArgs),
    /// Write report.md and figures/ of a batch directory.
    Report {
        /// The batch directory.
        dir: PathBuf,
    },
}

/// `whisker trials slurm`.
#[derive(clap::Args, Debug)]
pub struct SlurmArgs {
    /// The scenario with `[trials]`.
    pub scenario: PathBuf,
    /// The batch directory (scripts in slurm/, shards in shards/, merged results here).
    #[arg(long)]
    pub out: PathBuf,
    /// Number of array tasks K (each runs every K-th trial).
    #[arg(long)]
    pub shards: usize,
    /// CPUs per task (worker threads of each shard).
    #[arg(long, default_value_t = 1)]
    pub cpus_per_task: usize,
    /// Extra `#SBATCH` option for both jobs, e.g. `--sbatch=--partition=short`
    /// (repeatable).
    #[arg(long = "sbatch", value_name = "OPTION", allow_hyphen_values = true)]
    pub sbatch: Vec<String>,
    /// The `whisker` binary the jobs run [default: this one].
    #[arg(long)]
    pub whisker: Option<PathBuf>,
}

/// Runs `whisker trials …`.
pub fn run(args: &Args, ctx: Context) -> Result {
    match (&args.command, &args.scenario, &args.run) {
        (Some(Command::Merge { dirs, out }), _, _) => {
            let n = merge::merge(dirs, out)?;
            println!(
                "merged     {n} trials of {} shard directories into {}",
                dirs.len(),
                out.display()
            );
            Ok(())
        }
        (Some(Command::Slurm(a)), _, _) => {
            let submit = slurm::write(&slurm::Settings {
                scenario: a.scenario.clone(),
                out: a.out.clone(),
                shards: a.shards,
                cpus_per_task: a.cpus_per_task,
                sbatch: a.sbatch.clone(),
                whisker: a.whisker.clone(),
            })?;
            println!("submit     bash {}", submit.display());
            Ok(())
        }
        (Some(Command::Report { dir }), _, _) => {
            report::command(dir)?;
            print!("{}", report_legend());
            Ok(())
        }
        (None, Some(scenario), Some(a)) => {
            let batch = Batch::load(scenario)?;
            super::signals::stop_on_signals(a.grace)?;
            let settings = batch::Settings {
                out: a.out.clone(),
                jobs: a.jobs,
                shard: a.shard,
                resume: a.resume,
                force: a.force,
                retry_failed: a.retry_failed,
                no_report: a.no_report,
            };
            let outcome = batch::run(&batch, &settings, ctx, &Lines::new())?;
            let csv = a.out.join(journal::CSV);
            println!(
                "trials     {} run now, {} finished before; rows in {}",
                outcome.ran,
                outcome.already,
                csv.display()
            );
            print!("{}", report_legend());
            if outcome.failed > 0 {
                return Err(Error::Failure(format!(
                    "{} trial(s) failed: their errors are in {}",
                    outcome.failed,
                    csv.display()
                )));
            }
            Ok(())
        }
        _ => Err(Error::Input(
            "whisker trials: expected SCENARIO --out DIR, or one of merge, slurm, report".into(),
        )),
    }
}

/// What a batch's files hold.
fn report_legend() -> String {
    whisker_scenario::console::legend(
        "what the files hold",
        &[
            (
                "trials.csv",
                "one row per trial: its factors, seed, status and every metric of its summary.json (docs: scenarios/README.md, [trials])",
            ),
            (
                "report.md",
                "per metric and stratum: n, median and IQR per factor level, Kruskal–Wallis across levels and pairwise Mann–Whitney, Holm-corrected (exact for small n); p < 0.05 = a difference unlikely by chance",
            ),
            (
                "figures/",
                "notched box plots per metric and factor (notch = ~95 % interval of the median: notches that do not overlap differ), threshold lines where a metric has one",
            ),
            (
                "runs/",
                "each trial's own outputs and stdout.txt (its account and progress notes: tail -f it to follow a long trial), named by its key",
            ),
        ],
    )
}

/// A batch's progress on stderr: a bar with ETA on a terminal, a line per trial otherwise.
pub struct Lines {
    bar: Mutex<Option<ProgressBar>>,
    total: AtomicUsize,
    done: AtomicUsize,
    started: Mutex<Instant>,
}

impl Lines {
    pub fn new() -> Self {
        Self {
            bar: Mutex::new(None),
            total: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            started: Mutex::new(Instant::now()),
        }
    }
}

impl Progress for Lines {
    fn start(&self, total: usize) {
        self.total.store(total, Ordering::SeqCst);
        self.done.store(0, Ordering::SeqCst);
        *self.started.lock().expect("no panic holds it") = Instant::now();
        *self.bar.lock().expect("no panic holds it") = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(total as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} trials  {elapsed_precise} elapsed, ETA {eta_precise}  {msg}",
                )
                .expect("a valid template"),
            );
            bar
        });
    }

    fn trial(&self, e: &Entry) {
        let done = self.done.fetch_add(1, Ordering::SeqCst) + 1;
        let total = self.total.load(Ordering::SeqCst);
        let status = match e.status {
            Status::Ok => "ok",
            Status::Failed => "FAILED",
        };
        if let Some(bar) = &*self.bar.lock().expect("no panic holds it") {
            bar.set_message(format!("{status} {}", e.key));
            bar.inc(1);
            if let Some(err) = &e.error {
                bar.println(format!("trial {} failed: {err}", e.key));
            }
            return;
        }
        let elapsed = self
            .started
            .lock()
            .expect("no panic holds it")
            .elapsed()
            .as_secs_f64();
        let eta = elapsed / done as f64 * (total - done) as f64;
        eprintln!(
            "trials     {done}/{total} {status} {} ({:.1} s; elapsed {}, ETA {}){}",
            e.key,
            e.wall_s,
            clock(elapsed),
            clock(eta),
            e.error
                .as_ref()
                .map_or(String::new(), |err| format!(": {err}"))
        );
    }

    fn finish(&self) {
        if let Some(bar) = &*self.bar.lock().expect("no panic holds it") {
            bar.finish();
        }
    }
}

/// Seconds as `1h02m03s`, `2m03s` or `3s`.
fn clock(s: f64) -> String {
    let s = s.round() as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, sec) => format!("{sec}s"),
        (0, m, sec) => format!("{m}m{sec:02}s"),
        (h, m, sec) => format!("{h}h{m:02}m{sec:02}s"),
    }
}
