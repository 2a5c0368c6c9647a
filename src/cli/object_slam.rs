//! `whisker object-slam`.

use super::{RrdArgs, choice, print_json};
use std::path::PathBuf;
use whisker_experiments::object_slam::{self, Placement, Settings, SlamVersion};
use whisker_experiments::record::Context;
use whisker_scenario::Result;
use whisker_scenario::SensingMode;
use whisker_sim::sensing::noise::PointNoise;

/// WhiskerRatSLAM on the catalogue objects (thesis §5.2): localisation and identification.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Catalogue objects (comma-separated) [default: all eight].
    #[arg(long, value_delimiter = ',')]
    pub objects: Vec<String>,
    /// Seed of every random draw.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Directory for object maps and CSV results (created; files written atomically).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object instead of tables.
    #[arg(long)]
    pub json: bool,
    /// How contacts are sensed: the kinematic sweep with the noise of §6.1.3.1.2, or
    /// physics whiskers through the signal front end and a radial-distance model (slow:
    /// about 10 CPU-minutes per object).
    #[arg(long, value_parser = choice::<SensingMode>(), default_value = "kinematic")]
    pub sensing: SensingMode,
    /// With `--sensing physics`: the radial-distance model file (`whisker radial train`)
    /// [default: the built-in svr10].
    #[arg(long)]
    pub radial_model: Option<PathBuf>,
    /// Which WhiskerRatSLAM: with the corrections of issue #19, or Alg 2 as printed (the
    /// closed loop's default; robust relaxation on in both).
    #[arg(long, value_parser = choice::<SlamVersion>(), default_value = "corrected")]
    pub slam: SlamVersion,
    /// Where each object sits relative to its trajectories (§5.2.2.1): the thesis' set-up
    /// (the Kettle on the trajectory's centre, the others 5 cm off it) or every object
    /// centred.
    #[arg(long, value_parser = choice::<Placement>(), default_value = "thesis")]
    pub placement: Placement,
    /// Kinematic sensing: which way the contact noise displaces a point — on each
    /// coordinate, or along the whisker's shaft (the thesis' model, §6.1.3.1.2).
    #[arg(long, value_parser = choice::<PointNoise>(), default_value = "along-whisker")]
    pub point_noise: PointNoise,
    /// Run from a dataset (`whisker dataset object-slam`; docs/dataset.md) instead of the
    /// simulator: its objects, seed and contacts.
    #[arg(long, conflicts_with_all = ["objects", "seed", "sensing", "radial_model", "placement", "point_noise"])]
    pub dataset: Option<PathBuf>,
    /// Run from the dataset a ROS 2 bag carries (`whisker export --mcap`): as `--dataset`.
    #[arg(long, conflicts_with_all = ["dataset", "objects", "seed", "sensing", "radial_model", "placement", "point_noise"])]
    pub mcap: Option<PathBuf>,
    #[command(flatten)]
    pub rrd: RrdArgs,
}

/// Runs it.
pub fn run(a: &Args, ctx: Context) -> Result {
    let settings = Settings {
        objects: a.objects.clone(),
        seed: a.seed,
        out: a.out.clone(),
        sensing: a.sensing,
        radial_model: a.radial_model.clone(),
        slam: a.slam,
        placement: a.placement,
        point_noise: a.point_noise,
        rrd: a.rrd.target(),
    };
    let (dataset, _unpacked) = super::export::dataset(a.dataset.as_ref(), a.mcap.as_ref())?;
    let report = match &dataset {
        Some(dir) => object_slam::replay(&settings, dir, ctx)?,
        None => object_slam::run(&settings, ctx)?,
    };
    match a.json {
        true => print_json(&report, false),
        false => print!("{report}"),
    }
    Ok(())
}
