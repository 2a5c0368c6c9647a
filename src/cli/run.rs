//! `whisker run` and `whisker check`.

use super::RrdArgs;
use std::path::PathBuf;
use whisker_experiments::record::Context;
use whisker_scenario::Result;
use whisker_scenario::overrides::Override;

/// Run a scenario: simulate it and write its results and Rerun recording.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// The scenario TOML file.
    pub scenario: PathBuf,
    /// Output directory (overrides `output.dir` of the scenario).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Seed of every random sub-stream (overrides `seed` of the scenario).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Change a scenario field by its dotted path, e.g. `--set explore.strategy=feh`
    /// (VALUE is TOML; a bare word is a string). Repeatable.
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
    #[command(flatten)]
    pub rrd: RrdArgs,
}

/// Validate a scenario and print what would run; writes nothing.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The scenario TOML file.
    pub scenario: PathBuf,
    /// Also write each `[[objects]]` mesh as loaded (repaired or replaced, in its own
    /// frame, metres, z up) to DIR/NAME.obj, to look at what the repair made of it.
    #[arg(long, value_name = "DIR")]
    pub meshes: Option<PathBuf>,
}

/// `whisker run`.
pub fn run(a: &RunArgs, ctx: Context) -> Result {
    whisker_experiments::run::run(
        &a.scenario,
        a.out.clone(),
        a.seed,
        &a.set,
        &a.rrd.target(),
        ctx,
    )
}

/// `whisker check`.
pub fn check(a: &CheckArgs, ctx: Context) -> Result {
    whisker_experiments::check::check(&a.scenario, a.meshes.as_deref(), ctx)
}
