//! The `whisker trials` command family: run a batch, `merge`, `slurm`, `report`; and
//! `whisker bench trials`.

use super::{Batch, batch, merge, report, slurm};
use crate::error::{CliError, CliResult};
use std::path::PathBuf;
use std::time::Instant;

/// `whisker trials`.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    /// The scenario with a `[trials]` section.
    #[arg(required = true)]
    pub scenario: Option<PathBuf>,
    #[command(flatten)]
    pub run: Option<batch::Options>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// `whisker trials <command>`.
#[derive(clap::Subcommand, Debug)]
pub enum Command {
    /// Merge shard directories into the directory of one unsharded batch.
    Merge(merge::Options),
    /// Write Slurm job-array and merge scripts for a batch.
    Slurm(slurm::Options),
    /// Write report.md and figures/ of a batch directory.
    Report {
        /// The batch directory.
        dir: PathBuf,
    },
}

/// Runs `whisker trials …`.
pub fn run(args: &Args, recordings: &dyn crate::record::Recordings) -> CliResult {
    match (&args.command, &args.scenario, &args.run) {
        (Some(Command::Merge(o)), _, _) => {
            let n = merge::merge(o)?;
            println!(
                "merged     {n} trials of {} shard directories into {}",
                o.dirs.len(),
                o.out.display()
            );
            Ok(())
        }
        (Some(Command::Slurm(o)), _, _) => {
            let submit = slurm::write(o)?;
            println!(
                "wrote      {}/{{array.sh, merge.sh, submit.sh}}",
                submit.parent().unwrap_or(&submit).display()
            );
            println!("submit     bash {}", submit.display());
            Ok(())
        }
        (Some(Command::Report { dir }), _, _) => {
            println!("wrote      {}", report::write(dir)?.display());
            Ok(())
        }
        (None, Some(scenario), Some(o)) => {
            let batch = Batch::load(scenario)?;
            let outcome = batch::run(&batch, o, recordings)?;
            println!(
                "trials     {} run now, {} finished before; rows in {}",
                outcome.ran,
                outcome.already,
                o.out.join(super::journal::CSV).display()
            );
            if outcome.failed > 0 {
                return Err(CliError::Failure(format!(
                    "{} trial(s) failed: their errors are in {}",
                    outcome.failed,
                    o.out.join(super::journal::CSV).display()
                )));
            }
            Ok(())
        }
        _ => Err(CliError::Input(
            "whisker trials: expected SCENARIO --out DIR, or one of merge, slurm, report".into(),
        )),
    }
}

/// `whisker bench trials`.
#[derive(clap::Args, Debug)]
pub struct BenchOptions {
    /// The scenario with `[trials]` [default: the §6.3 batch].
    #[arg(default_value = "scenarios/trials_strategies.toml")]
    pub scenario: PathBuf,
    /// How many of its trials (the first in the batch's order).
    #[arg(long, default_value_t = 30)]
    pub trials: usize,
    /// Scratch directory [default: a temporary one].
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs the first `trials` trials on 1 and then on 2 workers, side by side in one process,
/// checks that both give the same `trials.csv` and prints the speed-up.
pub fn bench(o: &BenchOptions, recordings: &dyn crate::record::Recordings) -> CliResult {
    let mut batch = Batch::load(&o.scenario)?;
    batch.trials.truncate(o.trials.max(1));
    let scratch = match &o.out {
        Some(d) => d.clone(),
        None => std::env::temp_dir().join(format!("whisker-bench-trials-{}", std::process::id())),
    };
    let mut seconds = Vec::new();
    let mut tables = Vec::new();
    for jobs in [1, 2] {
        let dir = scratch.join(format!("jobs-{jobs}"));
        if dir.exists() {
            std::fs::remove_dir_all(&dir)
                .map_err(|e| CliError::Failure(format!("{}: {e}", dir.display())))?;
        }
        let options = batch::Options {
            out: dir.clone(),
            jobs: Some(jobs),
            shard: None,
            resume: false,
            force: false,
            retry_failed: false,
            no_report: true,
        };
        let started = Instant::now();
        let outcome = batch::run(&batch, &options, recordings)?;
        seconds.push(started.elapsed().as_secs_f64());
        tables.push(std::fs::read(dir.join(super::journal::CSV)).unwrap_or_default());
        if outcome.failed > 0 {
            return Err(CliError::Failure(format!(
                "{} trials failed on {jobs} job(s)",
                outcome.failed
            )));
        }
    }
    if o.out.is_none() {
        let _ = std::fs::remove_dir_all(&scratch);
    }
    println!(
        "bench trials: {} trials of {}",
        batch.trials.len(),
        o.scenario.display()
    );
    println!("  --jobs 1  {:8.1} s", seconds[0]);
    println!("  --jobs 2  {:8.1} s", seconds[1]);
    println!(
        "  speed-up  {:8.2}×   trials.csv identical: {}",
        seconds[0] / seconds[1],
        tables[0] == tables[1]
    );
    if tables[0] != tables[1] {
        return Err(CliError::Failure(
            "trials.csv differs between 1 and 2 jobs".into(),
        ));
    }
    Ok(())
}
