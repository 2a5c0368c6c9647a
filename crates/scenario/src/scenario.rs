//! The scenario file format, version 1 (documented field by field in
//! `scenarios/README.md`).
//!
//! A scenario is a TOML file. Unknown fields are rejected, every number is checked to be
//! finite and in range, and every error names the file and the field. Paths of inputs
//! (the URDF, package search directories) are relative to the scenario file; the output
//! directory is relative to the working directory.

use crate::error::{Error, Result};
use crate::experiment::Experiment;
use crate::explore::ExploreConfig;
use crate::navigate::NavigateConfig;
use crate::sensing::{FrontEndConfig, Sensing};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use whisker_sim::sensing::physics::WhiskerConfig;

/// Default joint-speed limit (rad/s): the thesis moved the arm at 0.1 rad/s (§2.2.1).
pub const DEFAULT_JOINT_SPEED_RAD_S: f64 = 0.1;

/// The slowest joint-speed limit (rad/s): a radian in about 17 minutes.
pub const MIN_JOINT_SPEED_RAD_S: f64 = 1e-3;

/// The range of `output.sample_period_s` (s): from the sensors' 0.5 ms to one second
/// (the period is also the arm's physics step).
pub const SAMPLE_PERIOD_RANGE_S: (f64, f64) = (5e-4, 1.0);

/// The most `[[objects]]` in one scenario (2,000 kettles took over a minute to check).
pub const MAX_OBJECTS: usize = 256;

/// The longest hold at a waypoint (s).
pub const MAX_HOLD_S: f64 = 3600.0;

/// A whole scenario.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Format version; 1.
    #[serde(default = "one")]
    pub version: u32,
    /// Seed of every random sub-stream of the experiment.
    #[serde(default)]
    pub seed: u64,
    /// The arm.
    pub arm: ArmConfig,
    /// How whisker readings are produced: `"none"` (the arm only), `"physics"` or
    /// `"kinematic"`.
    #[serde(default)]
    pub sensing: Sensing,
    /// `[kinematic]`: options of `sensing = "kinematic"`.
    #[serde(default)]
    pub kinematic: crate::environment::KinematicConfig,
    /// `[[objects]]`: meshes placed in the world.
    #[serde(default)]
    pub objects: Vec<crate::environment::ObjectConfig>,
    /// `[maze]`: the maze board.
    pub maze: Option<crate::environment::MazeConfig>,
    /// `[office]`: rooms, corridors and doors (the world of `[navigate]`).
    pub office: Option<crate::office::OfficeConfig>,
    /// The whisker array (used with `sensing = "physics"`).
    #[serde(default)]
    pub array: crate::array::ArrayConfig,
    /// `[maze_slam]`: options of `whisker maze-slam` over the `[maze]`.
    #[serde(default)]
    pub maze_slam: crate::maze_slam::MazeSlamConfig,
    /// `[frontend]`: the signal front end of physics runs.
    #[serde(default)]
    pub frontend: FrontEndConfig,
    /// `[explore]`: the closed loop of Chapter 6 (the robot chooses where to whisk), as
    /// read; moved into [`Scenario::experiment`] once checked.
    #[serde(rename = "explore")]
    explore_section: Option<ExploreConfig>,
    /// `[navigate]`: a mobile robot driving a route round the `[office]` (Fig 5.1), as
    /// read; moved into [`Scenario::experiment`] once checked.
    #[serde(rename = "navigate")]
    navigate_section: Option<NavigateConfig>,
    /// What the scenario runs — its waypoints, `[explore]` or `[navigate]` — chosen when
    /// it was read.
    #[serde(skip)]
    pub experiment: Experiment,
    /// Where the arm goes (scripted waypoints; none with `[explore]`).
    #[serde(default)]
    pub trajectory: TrajectoryConfig,
    /// What is written.
    #[serde(default)]
    pub output: OutputConfig,
    /// `[trials]`: a batch of runs over seeds and factors (`whisker trials`); `whisker run`
    /// ignores it.
    pub trials: Option<crate::trials::TrialsConfig>,
    /// The whiskers of `[array]`, checked once when the scenario was loaded (with sensing);
    /// see [`Scenario::whisker_configs`].
    #[serde(skip)]
    whiskers: Option<Vec<WhiskerConfig>>,
}

/// `[arm]`: the robot description and its initial state.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmConfig {
    /// URDF file, relative to the scenario file.
    pub urdf: PathBuf,
    /// Directories searched for `package://` mesh references, relative to the scenario.
    #[serde(default)]
    pub package_paths: Vec<PathBuf>,
    /// The link the chain starts at (poses are expressed in it).
    #[serde(default = "base_link")]
    pub base_link: String,
    /// The link whose pose trajectory waypoints give.
    #[serde(default = "whisker_array")]
    pub tip_link: String,
    /// Initial position of each chain joint, base to tip (deg; m for prismatic joints).
    pub initial_joints_deg: Vec<f64>,
    /// Speed limit of every joint (rad/s), further capped by the URDF's own limits.
    #[serde(default = "default_speed")]
    pub joint_speed_limit_rad_s: f64,
}

/// `[trajectory]`: waypoints visited in order from the initial configuration.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct TrajectoryConfig {
    /// The waypoints.
    pub waypoints: Vec<Waypoint>,
}

/// One `[[trajectory.waypoints]]` entry: either a pose of the tip link
/// (`position_m` + `rpy_deg`) or a joint configuration (`joints_deg`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Waypoint {
    /// Tip-link position in the base link frame (m).
    pub position_m: Option<[f64; 3]>,
    /// Tip-link orientation as roll, pitch, yaw in the base link frame (deg).
    pub rpy_deg: Option<[f64; 3]>,
    /// Joint configuration (deg; m for prismatic joints).
    pub joints_deg: Option<Vec<f64>>,
    /// Time the arm stays at the waypoint once there (s).
    #[serde(default)]
    pub hold_s: f64,
}

/// `[output]`: where results go.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputConfig {
    /// Output directory, relative to the working directory.
    #[serde(default = "out_dir")]
    pub dir: PathBuf,
    /// Period of the rows of `path.csv` and of the arm's simulation step (s).
    #[serde(default = "sample_period")]
    pub sample_period_s: f64,
    /// Whether to write the Rerun recording `run.rrd`.
    #[serde(default = "yes")]
    pub recording: bool,
}

impl Default for OutputConfig {
    fn default() -> Self {
        Self {
            dir: out_dir(),
            sample_period_s: sample_period(),
            recording: true,
        }
    }
}

fn one() -> u32 {
    1
}
fn yes() -> bool {
    true
}
fn base_link() -> String {
    "base_link".into()
}
fn whisker_array() -> String {
    "whisker_array".into()
}
fn default_speed() -> f64 {
    DEFAULT_JOINT_SPEED_RAD_S
}
fn out_dir() -> PathBuf {
    PathBuf::from("out")
}
fn sample_period() -> f64 {
    0.01
}

/// A waypoint resolved to what it asks for.
#[derive(Debug, Clone)]
pub enum Target {
    /// Tip pose: position (m) and roll, pitch, yaw (rad).
    Pose { position: [f64; 3], rpy: [f64; 3] },
    /// Chain joint positions as written (deg; m for prismatic joints).
    Joints(Vec<f64>),
}

impl Scenario {
    /// Refuses an array (or any non-table) where a table is expected, which serde would
    /// read positionally (see `strict`); after the `toml` reading, whose errors carry
    /// the line.
    pub(crate) fn check_shapes(path: &Path, table: &toml::Table) -> Result {
        crate::strict::check::<Self>(table).map_err(|e| Error::field(path, &e.field, e.message))
    }

    /// The 18 whiskers' configurations of `[array]` (RCP thresholds not yet calibrated):
    /// those checked at loading, or, for a scenario without sensing, checked now.
    pub(crate) fn whisker_configs(&self, file: &Path) -> Result<Vec<WhiskerConfig>> {
        match &self.whiskers {
            Some(w) => Ok(w.clone()),
            None => self.array.whisker_configs(file),
        }
    }

    /// Checks what does not depend on the URDF and chooses the [`Experiment`]; every
    /// error names `file` and the field.
    pub(crate) fn validate(&mut self, file: &Path) -> Result {
        let bad = |field: &str, msg: String| Err(Error::field(file, field, msg));
        if self.version != 1 {
            return bad("version", format!("expected 1, got {}", self.version));
        }
        finite_all(file, "arm.initial_joints_deg", &self.arm.initial_joints_deg)?;
        // Positive is not enough: a nanosecond period or a nanoradian per second wrote
        // rows (and ran) for ever.
        within(
            file,
            "arm.joint_speed_limit_rad_s",
            self.arm.joint_speed_limit_rad_s,
            (MIN_JOINT_SPEED_RAD_S, f64::INFINITY),
            "rad/s",
        )?;
        within(
            file,
            "output.sample_period_s",
            self.output.sample_period_s,
            SAMPLE_PERIOD_RANGE_S,
            "s",
        )?;
        if self.sensing == Sensing::Physics {
            let ratio = self.output.sample_period_s * whisker_slam::sensor::SAMPLE_RATE_HZ;
            if (ratio - ratio.round()).abs() > 1e-9 || ratio.round() < 1.0 {
                return bad(
                    "output.sample_period_s",
                    format!(
                        "with sensing = \"physics\" expected a whole multiple of the sensors' 0.5 ms period, got {}",
                        self.output.sample_period_s
                    ),
                );
            }
            self.whiskers = Some(self.array.whisker_configs(file)?);
            self.frontend.validate(file)?;
        }
        if self.sensing == Sensing::Kinematic {
            self.kinematic.noise(file)?;
            self.whiskers = Some(self.array.whisker_configs(file)?);
        }
        if self.objects.len() > MAX_OBJECTS {
            return bad(
                "objects",
                format!(
                    "{} objects: expected at most {MAX_OBJECTS} (each mesh is read, repaired and swept)",
                    self.objects.len()
                ),
            );
        }
        self.maze_slam.validate(file)?;
        // A triangle soup serves the kinematic sweep only.
        let needs_solids = if self.sensing == Sensing::Physics {
            Some("sensing = \"physics\"")
        } else if self.explore_section.is_some() {
            Some("[explore] (its placement checks depth inside the object)")
        } else {
            None
        };
        if let Some(why) = needs_solids
            && let Some(i) = self.objects.iter().position(|o| o.repair == "soup")
        {
            return bad(
                &format!("objects[{i}].repair"),
                format!(
                    "\"soup\" keeps the mesh's triangles for kinematic sensing only; {why} \
                     needs a closed solid: expected \"auto\", \"hull\" or \"voxel\""
                ),
            );
        }
        let office = match (&self.maze, &self.office) {
            (Some(_), Some(_)) => {
                return bad(
                    "office",
                    "expected either a [maze] or an [office], not both".into(),
                );
            }
            (_, Some(o)) => Some(o.checked_plan(file)?),
            _ => None,
        };
        crate::experiment::check_driver(
            file,
            (
                self.explore_section.is_some(),
                self.navigate_section.is_some(),
            ),
            self.trajectory.waypoints.len(),
            self.sensing,
        )?;
        if let Some(n) = &self.navigate_section {
            n.validate(file, office.as_ref())?;
            if let Some(o) = &n.object {
                o.validate(file, &self.object_names(), self.sensing)?;
            }
        }
        if let Some(e) = &self.explore_section {
            e.validate(file, &self.object_names(), self.sensing)?;
        }
        for (k, w) in self.trajectory.waypoints.iter().enumerate() {
            let field = format!("trajectory.waypoints[{k}]");
            w.target(file, &field)?;
            if !(w.hold_s >= 0.0 && w.hold_s <= MAX_HOLD_S) {
                return bad(
                    &format!("{field}.hold_s"),
                    format!(
                        "expected a number of seconds from 0 to {MAX_HOLD_S}, got {}",
                        whisker_slam::message::short(w.hold_s)
                    ),
                );
            }
        }
        // Checked: one of them at most.
        self.experiment = match (self.explore_section.take(), self.navigate_section.take()) {
            (Some(e), _) => Experiment::ClosedLoop(Box::new(e)),
            (None, Some(n)) => Experiment::Navigate(Box::new(n)),
            (None, None) => Experiment::Scripted,
        };
        Ok(())
    }

    /// The names of the `[[objects]]`, in order.
    pub fn object_names(&self) -> Vec<String> {
        self.objects
            .iter()
            .enumerate()
            .map(|(i, o)| o.display_name(i))
            .collect()
    }
}

impl Waypoint {
    /// What the waypoint asks for, or an error naming `field` if it is ill-formed.
    pub fn target(&self, file: &Path, field: &str) -> Result<Target> {
        match (&self.position_m, &self.rpy_deg, &self.joints_deg) {
            (Some(p), Some(r), None) => {
                finite_all(file, &format!("{field}.position_m"), p)?;
                finite_all(file, &format!("{field}.rpy_deg"), r)?;
                Ok(Target::Pose {
                    position: *p,
                    rpy: r.map(f64::to_radians),
                })
            }
            (None, None, Some(q)) => {
                finite_all(file, &format!("{field}.joints_deg"), q)?;
                Ok(Target::Joints(q.clone()))
            }
            _ => Err(Error::field(
                file,
                field,
                "expected either `position_m` and `rpy_deg` (a tip pose) or `joints_deg` (a joint configuration), not both or parts",
            )),
        }
    }
}

fn finite_all(file: &Path, field: &str, values: &[f64]) -> Result {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(Error::field(
            file,
            &format!("{field}[{i}]"),
            format!("expected a finite number, got {}", values[i]),
        )),
        None => Ok(()),
    }
}

/// `v` finite and within `[min, max]` (`unit` in the message).
fn within(file: &Path, field: &str, v: f64, (min, max): (f64, f64), unit: &str) -> Result {
    if v.is_finite() && (min..=max).contains(&v) {
        return Ok(());
    }
    let short = whisker_slam::message::short;
    let range = if max.is_finite() {
        format!("from {} to {} {unit}", short(min), short(max))
    } else {
        format!("of at least {} {unit}", short(min))
    };
    Err(Error::field(
        file,
        field,
        format!("expected a number {range}, got {}", short(v)),
    ))
}
