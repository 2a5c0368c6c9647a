//! `whisker bench …`: timing, never part of the tests.

use super::{choice, print_json, trials::Lines};
use std::path::PathBuf;
use whisker_experiments::record::{Context, Silent};
use whisker_scenario::Result;
use whisker_scenario::overrides::Override;
use whisker_sim::sensing::physics::SolverPath;
use whisker_sim::whisker::beam::Bending;
use whisker_trials::bench::{physics, recording, sensing, slam, trials};

/// The benchmarks.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Real-time factor of the physics sensing mode (1 and 18 whiskers, free and in contact).
    Physics(PhysicsArgs),
    /// Whisk cycles per second of kinematic sensing (the full array near an object).
    Sensing(SensingArgs),
    /// The pose-cell networks (planar and 6-D), phase by phase, dense reference against the
    /// active-set default; a naive dense 6-D convolution; one point feature histogram.
    Slam(SlamArgs),
    /// What the Rerun recording costs a run: wall time with and without, and its size.
    Recording(RecordingArgs),
    /// Batch trials on 1 against 2 worker threads (speed-up; same trials.csv).
    Trials(TrialsArgs),
}

/// `whisker bench physics`.
#[derive(clap::Args, Debug)]
pub struct PhysicsArgs {
    /// Simulated time per case (s).
    #[arg(long, default_value_t = physics::Settings::default().duration)]
    pub duration: f64,
    /// Shaft joint model of every whisker.
    #[arg(long, value_parser = choice::<Bending>(), default_value = "spatial")]
    pub bending: Bending,
    /// Rapier substeps per 0.5 ms step.
    #[arg(long, default_value_t = physics::Settings::default().substeps)]
    pub substeps: usize,
    /// Segments per whisker [default: the array's].
    #[arg(long)]
    pub segments: Option<usize>,
    /// The scenario whose `[maze]` is the maze case.
    #[arg(long, default_value = "scenarios/maze.toml")]
    pub maze: PathBuf,
    /// Skip the segment-count scaling (8/12/16/24).
    #[arg(long)]
    pub no_scaling: bool,
    /// Time only this code path (e.g. under a profiler) [default: all].
    #[arg(long, value_parser = choice::<SolverPath>())]
    pub path: Option<SolverPath>,
    /// Instead: Rapier's stage timers for the array against the Box on 1 thread (the
    /// released, exact, composite, once-per-step and articulated paths, or --path); needs
    /// `--features profiler`.
    #[arg(long)]
    pub stages: bool,
    /// Time every path of a case this many times in turn and keep each one's fastest run
    /// (steadier ratios on a shared machine).
    #[arg(long, default_value_t = physics::Settings::default().repeat)]
    pub repeat: usize,
    /// Print a JSON list of {case, threads, path, real_time_factor, …}.
    #[arg(long)]
    pub json: bool,
}

/// `whisker bench sensing`.
#[derive(clap::Args, Debug)]
pub struct SensingArgs {
    /// Catalogue object the array sweeps.
    #[arg(long, default_value = "kettle")]
    pub object: String,
    /// Whisk cycles timed per case.
    #[arg(long, default_value_t = 20_000)]
    pub cycles: usize,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `whisker bench slam`.
#[derive(clap::Args, Debug)]
pub struct SlamArgs {
    /// Pose-cell updates timed.
    #[arg(long, default_value_t = 2000)]
    pub updates: usize,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `whisker bench recording`.
#[derive(clap::Args, Debug)]
pub struct RecordingArgs {
    /// The scenario (a physics run is the case the recording's 2 kHz streams weigh on).
    #[arg(default_value = "scenarios/whisking.toml")]
    pub scenario: PathBuf,
    /// Output directory (`without/`, `with/` below it).
    #[arg(long, default_value = "out/bench-recording")]
    pub out: PathBuf,
    /// Runs of each kind; the fastest counts.
    #[arg(long, default_value_t = 1)]
    pub repeats: usize,
    /// Change a scenario field, as `whisker run --set` (repeatable), e.g.
    /// `--set 'trajectory.waypoints=[{joints_deg=[0,-90,90,-90,-90,0],hold_s=60}]'`.
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `whisker bench trials`.
#[derive(clap::Args, Debug)]
pub struct TrialsArgs {
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

/// Prints `report`: JSON (pretty or not) or its table and what its figures mean.
fn show<R: serde::Serialize + std::fmt::Display>(report: &R, json: Option<bool>) {
    match json {
        Some(pretty) => print_json(report, pretty),
        None => print!(
            "{report}{}",
            whisker_scenario::console::legend(
                "how to read it",
                &[
                    (
                        "ratio",
                        "against the baseline measured in this same run, on this machine (higher = faster unless the column says otherwise); compare ratios, not the absolute times, across machines or runs"
                    ),
                    (
                        "times",
                        "wall-clock; a busy machine inflates them — benchmarks are never pass/fail tests"
                    ),
                ],
            )
        ),
    }
}

/// Runs one.
pub fn run(command: &Command, ctx: Context) -> Result {
    match command {
        Command::Physics(a) => {
            let settings = physics::Settings {
                duration: a.duration,
                bending: a.bending,
                substeps: a.substeps,
                segments: a.segments,
                maze: a.maze.clone(),
                no_scaling: a.no_scaling,
                path: a.path,
                stages: a.stages,
                repeat: a.repeat,
            };
            let quiet = Context {
                reporter: &Silent,
                ..ctx
            };
            let report = physics::physics(&settings, if a.json { quiet } else { ctx })?;
            show(&report, a.json.then_some(true));
        }
        Command::Sensing(a) => {
            let settings = sensing::Settings {
                object: a.object.clone(),
                cycles: a.cycles,
            };
            show(&sensing::sensing(&settings)?, a.json.then_some(false));
        }
        Command::Slam(a) => show(&slam::slam(a.updates)?, a.json.then_some(false)),
        Command::Recording(a) => {
            let settings = recording::Settings {
                scenario: a.scenario.clone(),
                out: a.out.clone(),
                repeats: a.repeats,
                set: a.set.clone(),
            };
            show(
                &recording::recording(&settings, ctx)?,
                a.json.then_some(false),
            );
        }
        Command::Trials(a) => {
            let settings = trials::Settings {
                scenario: a.scenario.clone(),
                trials: a.trials,
                out: a.out.clone(),
            };
            let report = trials::run(&settings, ctx, &Lines::new())?;
            show(&report, None);
            if !report.identical {
                return Err(whisker_scenario::Error::Failure(
                    "trials.csv differs between 1 and 2 jobs".into(),
                ));
            }
        }
    }
    Ok(())
}
