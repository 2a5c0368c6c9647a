//! `whisker radial`: data sets, the Table 4.1 models, validation (thesis Ch 4).

use super::{RrdArgs, choice, print_json};
use std::path::PathBuf;
use whisker_experiments::radial::eval::{self, EvalSettings};
use whisker_experiments::radial::generate::{self, GenerateSettings, Set};
use whisker_experiments::radial::train::{self, TrainSettings};
use whisker_experiments::record::Context;
use whisker_scenario::Result;
use whisker_sim::sensing::physics::DEFAULT_SUBSTEPS;

/// The subcommands.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Generate the training (rod) or validation (Box) data set by physics (§4.1.2).
    Generate(GenerateArgs),
    /// Train the twelve regressors of Table 4.1 on a training set.
    Train(TrainArgs),
    /// Validate trained regressors, the tip assumption and a random guess (Figs 4.8–4.9).
    Eval(EvalArgs),
}

/// `whisker radial generate`.
#[derive(clap::Args, Debug)]
pub struct GenerateArgs {
    /// Which set.
    #[arg(long, value_parser = choice::<Set>())]
    pub set: Set,
    /// Output CSV file.
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of every random draw (frequencies, rod angles, waypoints, sensor noise).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Training: whisks (each at its own frequency) per whisker length and distance.
    #[arg(long, default_value_t = 3)]
    pub frequencies: usize,
    /// Training: only these whisker lengths (mm, comma-separated) [default: all eight].
    #[arg(long, value_delimiter = ',')]
    pub lengths: Vec<f64>,
    /// Validation: array poses held still around the Box.
    #[arg(long, default_value_t = 24)]
    pub waypoints: usize,
    /// Validation: whisks (1 Hz) per pose.
    #[arg(long, default_value_t = 2)]
    pub whisks: usize,
    /// Rapier substeps per 0.5 ms step.
    #[arg(long, default_value_t = DEFAULT_SUBSTEPS)]
    pub substeps: usize,
    #[command(flatten)]
    pub rrd: RrdArgs,
}

/// `whisker radial train`.
#[derive(clap::Args, Debug)]
pub struct TrainArgs {
    /// The training set (CSV of `whisker radial generate`).
    #[arg(long)]
    pub data: PathBuf,
    /// Directory the models are written to.
    #[arg(long)]
    pub out: PathBuf,
    /// Models to train (labels of Table 4.1, comma-separated) [default: all twelve].
    #[arg(long, value_delimiter = ',')]
    pub models: Vec<String>,
    /// Seed of the cross-validation folds and the MLP weights.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// `whisker radial eval`.
#[derive(clap::Args, Debug)]
pub struct EvalArgs {
    /// The validation set (CSV of `whisker radial generate --set validation`).
    #[arg(long)]
    pub data: PathBuf,
    /// Directory of trained models (`<label>.json`, from `whisker radial train`).
    #[arg(long)]
    pub models: PathBuf,
    /// Seed of the random guess.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Ground-truth limit as a fraction of the whisker length.
    #[arg(long, default_value_t = 0.7)]
    pub max_fraction: f64,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs a `whisker radial` subcommand.
pub fn run(command: &Command, ctx: Context) -> Result {
    match command {
        Command::Generate(a) => {
            let settings = GenerateSettings {
                set: a.set,
                out: a.out.clone(),
                seed: a.seed,
                frequencies: a.frequencies,
                lengths: a.lengths.clone(),
                waypoints: a.waypoints,
                whisks: a.whisks,
                substeps: a.substeps,
                rrd: a.rrd.target(),
            };
            print!("{}", generate::run(&settings, ctx)?);
        }
        Command::Train(a) => {
            let settings = TrainSettings {
                data: a.data.clone(),
                out: a.out.clone(),
                models: a.models.clone(),
                seed: a.seed,
            };
            print!("{}", train::run(&settings)?);
        }
        Command::Eval(a) => {
            let settings = EvalSettings {
                data: a.data.clone(),
                models: a.models.clone(),
                seed: a.seed,
                max_fraction: a.max_fraction,
            };
            let report = eval::run(&settings)?;
            match a.json {
                true => print_json(&report, false),
                false => print!("{report}"),
            }
        }
    }
    Ok(())
}
