//! `whisker bench trials`: the first trials of a batch on 1 and then on 2 workers, side by
//! side in one process; both must give the same `trials.csv`.

use crate::batch::{self, Progress};
use crate::journal;
use serde::Serialize;
use std::fmt;
use std::path::PathBuf;
use std::time::Instant;
use whisker_experiments::record::Context;
use whisker_scenario::grid::Batch;
use whisker_scenario::{Error, Result};

/// What `whisker bench trials` runs.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The scenario with `[trials]`.
    pub scenario: PathBuf,
    /// How many of its trials (the first in the batch's order).
    pub trials: usize,
    /// Scratch directory [default: a temporary one].
    pub out: Option<PathBuf>,
}

/// What it measured.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub scenario: String,
    pub trials: usize,
    pub seconds_1_job: f64,
    pub seconds_2_jobs: f64,
    pub identical: bool,
}

/// Runs the batch twice; an error if the two `trials.csv` differ or a trial failed.
pub fn run(o: &Settings, ctx: Context, progress: &dyn Progress) -> Result<Report> {
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
                .map_err(|e| Error::Failure(format!("{}: {e}", dir.display())))?;
        }
        let settings = batch::Settings {
            out: dir.clone(),
            jobs: Some(jobs),
            shard: None,
            resume: false,
            force: false,
            retry_failed: false,
            no_report: true,
        };
        let started = Instant::now();
        let outcome = batch::run(&batch, &settings, ctx, progress)?;
        seconds.push(started.elapsed().as_secs_f64());
        tables.push(std::fs::read(dir.join(journal::CSV)).unwrap_or_default());
        if outcome.failed > 0 {
            return Err(Error::Failure(format!(
                "{} trials failed on {jobs} job(s)",
                outcome.failed
            )));
        }
    }
    if o.out.is_none() {
        let _ = std::fs::remove_dir_all(&scratch);
    }
    Ok(Report {
        scenario: o.scenario.display().to_string(),
        trials: batch.trials.len(),
        seconds_1_job: seconds[0],
        seconds_2_jobs: seconds[1],
        identical: tables[0] == tables[1],
    })
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "bench trials: {} trials of {}",
            self.trials, self.scenario
        )?;
        writeln!(f, "  --jobs 1  {:8.1} s", self.seconds_1_job)?;
        writeln!(f, "  --jobs 2  {:8.1} s", self.seconds_2_jobs)?;
        writeln!(
            f,
            "  speed-up  {:8.2}×   trials.csv identical: {}",
            self.seconds_1_job / self.seconds_2_jobs,
            self.identical
        )
    }
}
