//! `whisker dataset` (write one, add noise) and `whisker slam DIR`.

use super::{choice, print_json};
use std::path::PathBuf;
use whisker_experiments::dataset_runs::noise::Settings as NoiseSettings;
use whisker_experiments::dataset_runs::{self, ScenarioDataset};
use whisker_experiments::object_slam::Placement;
use whisker_experiments::object_slam::dataset::ObjectDataset;
use whisker_experiments::record::Context;
use whisker_scenario::SensingMode;
use whisker_scenario::overrides::Override;
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::noise::PointNoise;

/// Write a seeded dataset in the lab's log layout with ground truth beside it
/// (docs/dataset.md), or add noise to a clean one (`dataset noise`).
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub write: WriteArgs,
}

/// `whisker dataset noise` and `whisker dataset object-slam`.
#[derive(clap::Subcommand, Debug)]
pub enum Command {
    /// Add noise to a dataset written with `--clean`: sensor noise to the streams,
    /// detection misses and contact noise to contacts, odometry error; a new seed.
    Noise(NoiseArgs),
    /// The walks of `whisker object-slam` around catalogue objects (§5.2; kinematic).
    ObjectSlam(ObjectArgs),
}

/// `whisker dataset SCENARIO --seed N --out DIR`.
#[derive(clap::Args, Debug)]
pub struct WriteArgs {
    /// A maze scenario (`[maze]`, run as `whisker maze-slam` runs it), a closed loop
    /// (`[explore]`, run as `whisker run` runs it: the path it took) or an office run
    /// (`[navigate]`, as `whisker run` runs it: whisks, odometry and the stops' loops).
    #[arg(required = true)]
    pub scenario: Option<PathBuf>,
    /// Seed [default: the scenario's `seed`].
    #[arg(long)]
    pub seed: Option<u64>,
    /// The dataset's directory (must not exist).
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
    /// Write without noise (no sensor noise, odometry error or contact noise), to be
    /// noised later by `whisker dataset noise`.
    #[arg(long)]
    pub clean: bool,
    /// Change a scenario field by its dotted path, as `whisker run --set` (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
    /// Also write the dataset as a ROS 2 bag (MCAP) to this file (must not exist;
    /// docs/dataset.md, "ROS 2 bags").
    #[arg(long)]
    pub mcap: Option<PathBuf>,
}

/// `whisker dataset noise`.
#[derive(clap::Args, Debug)]
pub struct NoiseArgs {
    /// The clean dataset.
    pub input: PathBuf,
    /// Seed of the noise.
    #[arg(long)]
    pub seed: u64,
    /// The noisy dataset's directory (must not exist).
    #[arg(long)]
    pub out: PathBuf,
    /// σ of the deflection noise (counts).
    #[arg(long, default_value_t = 2.0)]
    pub deflection_counts: f64,
    /// σ of the angle noise (degrees).
    #[arg(long, default_value_t = 0.05)]
    pub angle_deg: f64,
    /// Probability that a contact is registered (level contacts).
    #[arg(long, default_value_t = 0.98)]
    pub detection: f64,
    /// σ of the contact point's noise as a fraction of the whisker's length.
    #[arg(long, default_value_t = 0.25)]
    pub point_fraction: f64,
    /// Which way it displaces the point.
    #[arg(long, value_parser = choice::<PointNoise>(), default_value = "along-whisker")]
    pub point_noise: PointNoise,
    /// σ of the contact slope.
    #[arg(long, default_value_t = 0.33)]
    pub slope_sigma: f64,
    /// Also write the dataset as a ROS 2 bag (MCAP) to this file (must not exist;
    /// docs/dataset.md, "ROS 2 bags").
    #[arg(long)]
    pub mcap: Option<PathBuf>,
}

/// `whisker dataset object-slam`.
#[derive(clap::Args, Debug)]
pub struct ObjectArgs {
    /// Catalogue objects (comma-separated) [default: all eight].
    #[arg(long, value_delimiter = ',')]
    pub objects: Vec<String>,
    /// Seed of every random draw.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// The dataset's directory (must not exist).
    #[arg(long)]
    pub out: PathBuf,
    /// Write without noise (contact noise and odometry error left out; kinematic only).
    #[arg(long)]
    pub clean: bool,
    /// How contacts are sensed: the kinematic sweep (level contacts) or physics whiskers
    /// (level streams: one whisk file per pose, the front end at replay; slow, as
    /// `whisker object-slam --sensing physics`).
    #[arg(long, value_parser = choice::<SensingMode>(), default_value = "kinematic")]
    pub sensing: SensingMode,
    /// With `--sensing physics`: the radial-distance model [default: the built-in svr10];
    /// copied into the dataset.
    #[arg(long)]
    pub radial_model: Option<PathBuf>,
    /// Where each object sits relative to its trajectories (as `whisker object-slam
    /// --placement`); recorded in the manifest.
    #[arg(long, value_parser = choice::<Placement>(), default_value = "thesis")]
    pub placement: Placement,
    /// Also write the dataset as a ROS 2 bag (MCAP) to this file (must not exist;
    /// docs/dataset.md, "ROS 2 bags").
    #[arg(long)]
    pub mcap: Option<PathBuf>,
}

/// Run the front end and the SLAM a dataset's manifest names, from the dataset alone.
#[derive(clap::Args, Debug)]
pub struct SlamArgs {
    /// The dataset's directory.
    #[arg(required_unless_present = "mcap")]
    pub dataset: Option<PathBuf>,
    /// Replay the dataset a ROS 2 bag carries (`whisker export --mcap`) instead of a
    /// directory: the same result.
    #[arg(long, conflicts_with = "dataset")]
    pub mcap: Option<PathBuf>,
    /// Directory for the results (as the experiment's own command writes them).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `whisker dataset …`.
pub fn run(a: &Args, ctx: Context) -> Result {
    let mcap = match &a.command {
        Some(Command::Noise(n)) => n.mcap.as_ref(),
        Some(Command::ObjectSlam(o)) => o.mcap.as_ref(),
        None => a.write.mcap.as_ref(),
    };
    super::export::check_new(mcap)?;
    let written = match &a.command {
        Some(Command::Noise(n)) => dataset_runs::noise::run(&NoiseSettings {
            input: n.input.clone(),
            seed: n.seed,
            out: n.out.clone(),
            deflection_counts: n.deflection_counts,
            angle_deg: n.angle_deg,
            detection: n.detection,
            point_fraction: n.point_fraction,
            point_model: n.point_noise,
            slope_sigma: n.slope_sigma,
        })?,
        Some(Command::ObjectSlam(o)) => {
            let settings = ObjectDataset {
                objects: o.objects.clone(),
                seed: o.seed,
                out: o.out.clone(),
                clean: o.clean,
                sensing: o.sensing,
                radial_model: o.radial_model.clone(),
                placement: o.placement,
            };
            dataset_runs::write_objects(&settings, ctx)?
        }
        None => {
            let w = &a.write;
            let (Some(scenario), Some(out)) = (&w.scenario, &w.out) else {
                return Err(Error::Input(
                    "whisker dataset: expected SCENARIO and --out DIR".into(),
                ));
            };
            let settings = ScenarioDataset {
                scenario: scenario.clone(),
                seed: w.seed,
                out: out.clone(),
                clean: w.clean,
                set: w.set.clone(),
            };
            dataset_runs::write_scenario(&settings, ctx)?
        }
    };
    eprint!("{written}");
    super::export::also(&written.out, mcap)
}

/// `whisker slam DIR`.
pub fn slam(a: &SlamArgs, ctx: Context) -> Result {
    let (dir, _unpacked) = super::export::dataset(a.dataset.as_ref(), a.mcap.as_ref())?;
    let dir = dir.ok_or_else(|| Error::Input("expected a dataset DIR or --mcap FILE".into()))?;
    let report = dataset_runs::slam(&dir, a.out.as_deref(), ctx)?;
    match a.json {
        true => print_json(&report, false),
        false => print!("{report}"),
    }
    Ok(())
}
