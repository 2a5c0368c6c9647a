//! What a maze run senses (thesis §3.1): the array's geometry over the board and the
//! tactile image of a whisk's contacts (§3.1.1), the path and its odometry with the error
//! model of §3.1.2, and one seed's RatSLAM input — from the kinematic sweep, physics
//! whiskers ([`super::physics`]) or a dataset (`super::dataset`).

use super::geometry::{Geometry, UPDATE_HZ};
use super::images;
use super::path::{self, Sample};
use super::physics_images::{self as physics, PhysicsWhiskers};
use super::settings::Settings;
use crate::record::Context;
use whisker_scenario::ScenarioFile;
use whisker_scenario::array::{BendingConfig, RcpConfig};
use whisker_scenario::maze_slam::AngleEstimate;
use whisker_scenario::{Error, Result};
use whisker_scenario::{Sensing, SensingMode};
use whisker_sim::environment::Environment;
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::whisker::array;
use whisker_sim::whisker::beam::Bending;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_sim::whisker::strategies::WhiskingControl;
use whisker_slam::contact::ContactCycle;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::odometry::{noisy_steps, true_steps};
use whisker_slam::rng::substream_key;

/// The kinematic sweep's rigid whiskers (bases 3 mm inside the module).
pub fn kinematic_whiskers() -> Vec<RigidWhisker> {
    array::modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, 3.0e-3))
        .collect()
}

/// The contacts of every update from the kinematic sweep under the whisking strategies
/// `control` (the scenario's detection probability applies; sub-stream
/// `maze-slam/sensing` of the seed, as `key`).
pub fn kinematic_contacts(
    truth: &[Sample],
    target: &SweepTarget,
    noise: whisker_sim::sensing::noise::ContactNoise,
    key: u64,
    g: &Geometry,
    control: WhiskingControl,
) -> Vec<ContactCycle> {
    let whiskers = kinematic_whiskers();
    let patterns = vec![WhiskingPattern::default(); whiskers.len()];
    let mut sensing = KinematicArray::new(whiskers, patterns, noise, key).with_control(control);
    truth
        .iter()
        .enumerate()
        .map(|(k, p)| sensing.sense(target, k as u64, k as f64 / UPDATE_HZ, &g.pose(p)))
        .collect()
}

/// The loop's corners (x, y) from the scenario's pose waypoints, and the geometry: the
/// array plane at the first waypoint's height, its yaw at heading 0 from its `rpy_deg`,
/// the board's top at `board_z`.
fn corners(file: &ScenarioFile, board_z: f64) -> Result<(Vec<(f64, f64)>, Geometry)> {
    let scenario = &file.scenario;
    let poses: Vec<([f64; 3], [f64; 3])> = scenario
        .trajectory
        .waypoints
        .iter()
        .filter_map(|w| Some((w.position_m?, w.rpy_deg?)))
        .collect();
    if poses.len() < 3 {
        return Err(Error::field(
            &file.path,
            "trajectory.waypoints",
            "maze-slam needs at least 3 pose waypoints (the loop's corners)",
        ));
    }
    let mut corners: Vec<(f64, f64)> = poses.iter().map(|(p, _)| (p[0], p[1])).collect();
    if corners.len() > 3 && corners.first() == corners.last() {
        corners.pop();
    }
    let geometry = Geometry {
        plane_z: poses[0].0[2],
        board_z,
        yaw0: poses[0].1[2].to_radians(),
    };
    Ok((corners, geometry))
}

/// The physics whiskers: the scenario's `[array]` with the command line's overrides,
/// checked as the scenario's own values are.
fn physics_configs(file: &ScenarioFile, o: &Settings) -> Result<PhysicsWhiskers> {
    let scenario = &file.scenario;
    let mut array = scenario.array.clone();
    if let Some(b) = o.bending {
        array.bending = match b {
            Bending::Spatial => BendingConfig::Spatial,
            Bending::SweepPlane => BendingConfig::SweepPlane,
        };
    }
    array.segments = o.segments.or(array.segments);
    array.substeps = o.substeps.or(array.substeps);
    if o.rcp {
        // Chapter 3's RCP: §3.2.2's amplitude controller at 20 σ.
        array.rcp = RcpConfig::Noise;
        array.rcp_control = whisker_scenario::array::RcpControl::Amplitude;
        array.rcp_noise_multiple = Some(20.0);
    }
    let overridden = o.bending.is_some() || o.segments.is_some() || o.substeps.is_some();
    let configs = array.whisker_configs(&file.path).map_err(|e| match e {
        Error::Input(m) if overridden => Error::Input(format!(
            "{m} (with --bending / --segments / --substeps from the command line)"
        )),
        e => e,
    })?;
    Ok(PhysicsWhiskers {
        configs,
        contact: array.contact_mode(),
    })
}

/// One data set: a name and the tactile image of every update.
pub type ImageSet = (String, Vec<TactileImage>);

/// What a maze run senses with, from the scenario and the command line.
pub struct Setup {
    /// The array's plane and the images' scale.
    pub geometry: Geometry,
    /// The true pose of every update.
    pub truth: Vec<Sample>,
    /// Where each circuit starts.
    pub starts: Vec<usize>,
    /// Physics whiskers and RCP mode (None: kinematic sensing).
    pub physics: Option<PhysicsWhiskers>,
    /// The image sets, named as in reports and file names.
    pub set_names: Vec<String>,
}

impl Setup {
    /// The setup of the scenario in `read` with the command line's options `o`.
    pub fn new(o: &Settings, read: &ScenarioFile) -> Result<Self> {
        let (scenario, file) = (&read.scenario, read.path.as_path());
        let maze = scenario
            .maze
            .as_ref()
            .ok_or_else(|| Error::field(file, "maze", "maze-slam needs a [maze] section"))?;
        let config = &scenario.maze_slam;
        if (o.kidnap || config.kidnap) && config.circuits < 4 {
            return Err(Error::field(
                file,
                "maze_slam.circuits",
                format!(
                    "the kidnapped variant needs at least 4 circuits, got {}",
                    config.circuits
                ),
            ));
        }
        let (loop_corners, geometry) = corners(read, maze.position_m[2])?;
        let sensing = match (o.sensing, scenario.sensing) {
            (Some(s), _) => s,
            (None, Sensing::Physics) => SensingMode::Physics,
            (None, Sensing::Kinematic) => SensingMode::Kinematic,
            (None, Sensing::None) => {
                return Err(Error::field(
                    file,
                    "sensing",
                    "maze-slam needs \"physics\" or \"kinematic\" (or --sensing)",
                ));
            }
        };
        if sensing == SensingMode::Kinematic {
            refuse_physics_options(o)?;
        }
        let physics = match sensing {
            SensingMode::Physics => Some(physics_configs(read, o)?),
            SensingMode::Kinematic => None,
        };
        let (truth, starts) = path::path(&loop_corners, config.circuits);
        let set_names = match &physics {
            None => vec![kinematic_set_name(&read.whisker_configs()?[0].control)],
            Some(w) => image_set_names(&w.configs[0].control.name(), &config.images),
        };
        Ok(Self {
            geometry,
            truth,
            starts,
            physics,
            set_names,
        })
    }
}

/// The name of the kinematic image set: `kinematic`, or `kinematic/<strategies>` when
/// spread reduction or asymmetry change the sweep (RCP does not: the sweep stops at the
/// first contact anyway).
pub fn kinematic_set_name(control: &WhiskingControl) -> String {
    let sweep = WhiskingControl {
        rcp: false,
        ..*control
    };
    match sweep.couples() {
        false => "kinematic".into(),
        true => format!("kinematic/{}", sweep.name()),
    }
}

/// The names of physics image sets: `<control>/<estimate>`, the control being
/// `open-loop` or the strategies (`rcp`, `sr`, `rcp+sr`, … as
/// `WhiskingControl::name`).
pub fn image_set_names(control: &str, images: &[AngleEstimate]) -> Vec<String> {
    images
        .iter()
        .map(|e| format!("{control}/{}", e.name()))
        .collect()
}

/// One seed's data for RatSLAM, from the simulator or from a dataset.
pub struct Sensed {
    /// The seed (names output files).
    pub seed: u64,
    /// The true pose of every update (None: a log without ground truth).
    pub truth: Option<Vec<Sample>>,
    /// Where the estimate starts: the first true pose, or the log's first pose.
    pub start: Sample,
    /// Where each circuit starts.
    pub starts: Vec<usize>,
    /// The odometry of every update (distance, turn), with its errors.
    pub steps: Vec<(f64, f64)>,
    /// Each image set's name and images.
    pub image_sets: Vec<ImageSet>,
}

/// Refuses the options that change only physics whiskers (`--rcp`, `--bending`,
/// `--segments`, `--substeps`) in a run that senses kinematically, where they would be
/// silently ignored.
fn refuse_physics_options(o: &Settings) -> Result {
    let given: Vec<&str> = [
        ("--rcp", o.rcp),
        ("--bending", o.bending.is_some()),
        ("--segments", o.segments.is_some()),
        ("--substeps", o.substeps.is_some()),
    ]
    .into_iter()
    .filter_map(|(name, on)| on.then_some(name))
    .collect();
    if given.is_empty() {
        return Ok(());
    }
    let why = match o.sensing {
        Some(_) => "--sensing kinematic".to_string(),
        None => format!("{}: sensing = \"kinematic\"", o.scenario.display()),
    };
    Err(Error::Input(format!(
        "maze-slam: {} changes the physics whiskers only, and this run senses \
         kinematically ({why}): leave it out, or add --sensing physics",
        given.join(", ")
    )))
}

/// Senses one seed live (or reads `--images`).
pub(super) fn sense(
    o: &Settings,
    read: &ScenarioFile,
    setup: &Setup,
    environment: &Environment,
    target: &std::cell::OnceCell<SweepTarget>,
    seed: u64,
    ctx: Context,
) -> Result<Sensed> {
    let (scenario, file) = (&read.scenario, read.path.as_path());
    let config = &scenario.maze_slam;
    let (g, truth) = (&setup.geometry, &setup.truth);
    let image_sets: Vec<ImageSet> = match (&o.images, &setup.physics) {
        (Some(dir), _) => setup
            .set_names
            .iter()
            .map(|name| {
                let file = images::path(dir, name, seed);
                Ok((name.clone(), images::read(&file, truth.len())?))
            })
            .collect::<Result<_>>()?,
        (None, None) => {
            let target = target.get_or_init(|| SweepTarget::of(environment));
            let noise = scenario.kinematic.noise(file)?;
            let key = substream_key(seed, "maze-slam/sensing");
            let whiskers = kinematic_whiskers();
            let control = read.whisker_configs()?[0].control;
            let images = kinematic_contacts(truth, target, noise, key, g, control)
                .iter()
                .map(|c| g.contact_image(c, &whiskers))
                .collect();
            vec![(setup.set_names[0].clone(), images)]
        }
        (None, Some(whiskers)) => {
            let (max, contact) = physics::images(
                truth,
                &environment.physics_pieces(),
                whiskers,
                &crate::sensing::detection::Detection::of_scenario(scenario),
                substream_key(seed, "maze-slam/physics"),
                g,
                ctx.reporter,
            )?;
            physics_sets(&config.images, &setup.set_names, max, contact)
        }
    };
    Ok(Sensed {
        seed,
        truth: Some(truth.clone()),
        start: truth[0],
        starts: setup.starts.clone(),
        steps: noisy_steps(&true_steps(truth), &config.odometry, seed),
        image_sets,
    })
}

/// The physics image sets of `estimates` (named `names`) from both images.
pub fn physics_sets(
    estimates: &[AngleEstimate],
    names: &[String],
    max: Vec<TactileImage>,
    contact: Vec<TactileImage>,
) -> Vec<ImageSet> {
    estimates
        .iter()
        .zip(names)
        .map(|(e, name)| {
            let images = match e {
                AngleEstimate::MaxAngle => max.clone(),
                AngleEstimate::ContactAngle => contact.clone(),
            };
            (name.clone(), images)
        })
        .collect()
}
