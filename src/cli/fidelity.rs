//! `whisker fidelity`.

use std::path::PathBuf;
use whisker_experiments::fidelity::{self, Settings};
use whisker_experiments::record::Context;
use whisker_scenario::Result;

/// The physics front end against the anticipated contacts, per whisking mode (issue #61).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Catalogue objects (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "box,box_stack,mug,kettle"
    )]
    pub objects: Vec<String>,
    /// Array poses per object.
    #[arg(long, default_value_t = Settings::default().poses)]
    pub poses: usize,
    /// Seed of the sensor noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output directory.
    #[arg(long, default_value = "out/fidelity")]
    pub out: PathBuf,
}

/// Runs it.
pub fn run(a: &Args, ctx: Context) -> Result {
    let settings = Settings {
        objects: a.objects.clone(),
        poses: a.poses,
        seed: a.seed,
    };
    fidelity::run(&settings, &a.out, ctx).map(|_| ())
}
