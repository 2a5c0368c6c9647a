//! `whisker maze-slam`.

use super::{RrdArgs, choice, print_json};
use std::path::PathBuf;
use whisker_experiments::dataset_format::manifest::Manifest;
use whisker_experiments::maze_slam::{self, Settings};
use whisker_experiments::record::Context;
use whisker_scenario::Result;
use whisker_scenario::SensingMode;
use whisker_scenario::overrides::Override;
use whisker_sim::whisker::beam::Bending;

/// Planar RatSLAM on the maze with tactile images (thesis Ch 3): ARR, ARCR, EM. Every
/// option but the scenario overrides the scenario.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scenario with a `[maze]`, pose waypoints (the loop's corners) and optionally
    /// `[maze_slam]`.
    #[arg(default_value = "scenarios/maze.toml")]
    pub scenario: PathBuf,
    /// Seeds (comma-separated): one run per seed [default: the scenario's `seed`].
    #[arg(long, value_delimiter = ',')]
    pub seeds: Option<Vec<u64>>,
    /// Also run the kidnapped variant of every seed (§3.3.1) [scenario:
    /// `maze_slam.kidnap`].
    #[arg(long)]
    pub kidnap: bool,
    /// Local-view matching threshold (Eq 3.1) [scenario:
    /// `maze_slam.ratslam.local_view.match_threshold`]. Several (comma-separated) run
    /// RatSLAM once per value on the same images and odometry — a tuning sweep at the
    /// cost of one physics run.
    #[arg(long, value_delimiter = ',')]
    pub match_threshold: Option<Vec<f64>>,
    /// Pose-cell injection energy (Eq 5.8) [scenario:
    /// `maze_slam.ratslam.local_view.inject_energy`]; several as for `--match-threshold`.
    #[arg(long, value_delimiter = ',')]
    pub inject_energy: Option<Vec<f64>>,
    /// Directory for `trajectory-<images>-<variant>-<seed>.csv` and `images-….csv`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Read each seed's tactile images from the `images-….csv` an earlier `--out` wrote
    /// to this directory, instead of sensing (re-running RatSLAM on recorded images).
    #[arg(long)]
    pub images: Option<PathBuf>,
    /// Tune (§3.2.1): per image set and variant, choose from the `--match-threshold` ×
    /// `--inject-energy` grid, among the pairs whose mean Energy Metric over the seeds is
    /// within 25 % of the lowest, the one of highest mean ARR × ARCR (ties: the lower EM),
    /// and write FILE, beside the scenario, as a scenario over it
    /// (`[maze_slam.tuned]`). Tune on seeds that are not reported.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["dataset", "mcap"])]
    pub tune: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// How tactile images are made [scenario: `sensing`]: the kinematic sweep's contact
    /// angles, or physics whiskers through the front end.
    #[arg(long, value_parser = choice::<SensingMode>())]
    pub sensing: Option<SensingMode>,
    /// Physics: whisk with Chapter 3's RCP, §3.2.2's amplitude controller at 20 × the
    /// free-whisking σ [scenario: `array.rcp = "noise"`, `array.rcp_control = "amplitude"`].
    #[arg(long)]
    pub rcp: bool,
    /// Physics: shaft joint model [scenario: `array.bending`].
    #[arg(long, value_parser = choice::<Bending>())]
    pub bending: Option<Bending>,
    /// Physics: segments per whisker [scenario: `array.segments`].
    #[arg(long)]
    pub segments: Option<usize>,
    /// Physics: Rapier substeps per 0.5 ms step [scenario: `array.substeps`].
    #[arg(long)]
    pub substeps: Option<usize>,
    /// Change a scenario field by its dotted path, as `whisker run --set` (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
    /// Run RatSLAM from a dataset (`whisker dataset`; docs/dataset.md) instead of the
    /// simulator: its log, its parameters and, when present, its ground truth.
    #[arg(long, conflicts_with_all = ["seeds", "images", "sensing", "rcp", "bending", "segments", "substeps", "set"])]
    pub dataset: Option<PathBuf>,
    /// Run from the dataset a ROS 2 bag carries (`whisker export --mcap`): as `--dataset`.
    #[arg(long, conflicts_with_all = ["dataset", "seeds", "images", "sensing", "rcp", "bending", "segments", "substeps", "set"])]
    pub mcap: Option<PathBuf>,
    #[command(flatten)]
    pub rrd: RrdArgs,
}

/// Runs it.
pub fn run(a: &Args, ctx: Context) -> Result {
    let settings = Settings {
        scenario: a.scenario.clone(),
        seeds: a.seeds.clone(),
        kidnap: a.kidnap,
        match_threshold: a.match_threshold.clone(),
        inject_energy: a.inject_energy.clone(),
        out: a.out.clone(),
        images: a.images.clone(),
        sensing: a.sensing,
        rcp: a.rcp,
        bending: a.bending,
        segments: a.segments,
        substeps: a.substeps,
        set: a.set.clone(),
        rrd: a.rrd.target(),
    };
    let (dataset, _unpacked) = super::export::dataset(a.dataset.as_ref(), a.mcap.as_ref())?;
    let report = match &dataset {
        Some(dir) => maze_slam::replay(&settings, dir, &Manifest::read(dir)?, ctx)?,
        None => maze_slam::run(&settings, ctx)?,
    };
    if let Some(file) = &a.tune {
        let command: Vec<String> = std::env::args().collect();
        let command = format!("whisker {}", command[1..].join(" "));
        for c in maze_slam::tuning::tune(file, &a.scenario, &report.runs, &command)? {
            eprintln!("tuned      {c}");
        }
    }
    match a.json {
        true => print_json(&report, false),
        false => print!("{report}"),
    }
    Ok(())
}
