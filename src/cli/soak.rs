//! `whisker soak`.

use super::{choice, print_json};
use std::path::PathBuf;
use whisker_experiments::record::{Context, Silent};
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::physics::{DEFAULT_SUBSTEPS, SolverPath};
use whisker_sim::whisker::beam::Bending;
use whisker_trials::soak::{self, Settings};

/// Long physics runs against every object and the maze: no tunnelling, no NaN.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Simulated time per case (s).
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// Catalogue objects to run (comma-separated) [default: all].
    #[arg(long, value_delimiter = ',')]
    pub objects: Vec<String>,
    /// A scenario whose `[maze]` is run as one more case (e.g. scenarios/maze.toml).
    #[arg(long)]
    pub maze: Option<PathBuf>,
    /// Shaft joint model.
    #[arg(long, value_parser = choice::<Bending>(), default_value = "spatial")]
    pub bending: Bending,
    /// Also simulate the whiskers that the kinematic sweep says touch nothing (they whisk
    /// freely and cannot tunnel; by default they are left out to save time).
    #[arg(long)]
    pub all_whiskers: bool,
    /// Simulate only these whiskers (pixel labels, comma-separated, e.g. D1,C2): each
    /// whisker has a world of its own, so one alone follows exactly its course in the array.
    #[arg(long, value_delimiter = ',')]
    pub whiskers: Vec<String>,
    /// Rapier substeps per 0.5 ms step.
    #[arg(long, default_value_t = DEFAULT_SUBSTEPS)]
    pub substeps: usize,
    /// Rapier's multibody code path (vendor/PATCHES.md) [default: the whiskers' default,
    /// articulated].
    #[arg(long, value_parser = choice::<SolverPath>())]
    pub path: Option<SolverPath>,
    /// One world step per 0.5 ms sample, as before speed-adaptive steps
    /// (`whisker_sim::sensing::adaptive_step`): for comparison.
    #[arg(long)]
    pub fixed_steps: bool,
    /// Also run each case N more times, the k-th with the array moved k nm along world x:
    /// far below any physical tolerance, so a result that changes is a chaotic coin flip
    /// of stick-slip contact, not a property of the set-up; prints how many runs tunnelled.
    #[arg(long, default_value_t = 0)]
    pub nudges: usize,
    /// Print one JSON list.
    #[arg(long)]
    pub json: bool,
    /// Write a Rerun recording to FILE: per case the environment, the shafts every 10 ms
    /// and the simulated whiskers' 2 kHz streams (docs/recording.md). Large: about 1 MB
    /// per simulated second per whisker.
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
}

/// Runs it; exit code 1 if a case tunnels or breaks.
pub fn run(a: &Args, ctx: Context) -> Result {
    let settings = Settings {
        duration: a.duration,
        objects: a.objects.clone(),
        maze: a.maze.clone(),
        bending: a.bending,
        all_whiskers: a.all_whiskers,
        whiskers: a.whiskers.clone(),
        substeps: a.substeps,
        path: a.path,
        fixed_steps: a.fixed_steps,
        nudges: a.nudges,
        rrd: a.rrd.clone(),
    };
    let quiet = Context {
        reporter: &Silent,
        ..ctx
    };
    let runs = soak::soak(&settings, if a.json { quiet } else { ctx })?;
    if a.json {
        print_json(&runs, false);
    }
    if runs.iter().all(|r| r.passed) {
        Ok(())
    } else {
        Err(Error::Failure(
            "soak: a whisker tunnelled or went non-finite (see above)".into(),
        ))
    }
}
