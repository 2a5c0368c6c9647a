//! The scenario file format, version 1 (documented field by field in
//! `scenarios/README.md`).
//!
//! A scenario is a TOML file. Unknown fields are rejected, every number is checked to be
//! finite and in range, and every error names the file and the field. Paths of inputs
//! (the URDF, package search directories) are relative to the scenario file; the output
//! directory is relative to the working directory.

use crate::error::{Error, Result};
use crate::paths::relative_to;
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
    /// `[explore]`: the closed loop of Chapter 6 (the robot chooses where to whisk).
    pub explore: Option<crate::explore::ExploreConfig>,
    /// `[navigate]`: a mobile robot driving a route round the `[office]` (Fig 5.1).
    pub navigate: Option<crate::navigate::NavigateConfig>,
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

/// `[frontend]`: the signal front end of `sensing = "physics"` (thesis Ch 4).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrontEndConfig {
    /// Radial-distance model (a `whisker radial train` output), relative to the scenario
    /// file; default: the built-in svr10.
    pub radial_model: Option<PathBuf>,
    /// `[frontend.detection]`: contact-detection parameters (thesis defaults).
    #[serde(default)]
    pub detection: whisker_slam::frontend::contact::FrontEndParams,
}

impl FrontEndConfig {
    /// Checks the detection parameters; names the offending field.
    pub fn validate(&self, file: &Path) -> Result {
        let d = &self.detection;
        let p = &d.peaks;
        let checks: [(&str, bool); 7] = [
            ("peaks.max_peaks", p.max_peaks >= 1),
            ("smoothing_span", d.smoothing_span >= 1),
            ("baseline_samples", d.baseline_samples >= 1),
            (
                "confirm_counts",
                d.confirm_counts.is_finite() && d.confirm_counts >= 0.0,
            ),
            (
                "contact_angle_rate",
                d.contact_angle_rate.is_finite() && d.contact_angle_rate > 0.0,
            ),
            (
                "peaks.min_width",
                p.min_width.is_finite() && p.min_width >= 0.0,
            ),
            (
                "peaks.min_prominence",
                p.min_prominence.is_finite() && p.min_prominence >= 0.0,
            ),
        ];
        for (name, ok) in checks {
            if !ok {
                return Err(Error::field(
                    file,
                    &format!("frontend.detection.{name}"),
                    "expected a finite number ≥ 0 (spans and counts ≥ 1, rates > 0)",
                ));
            }
        }
        self.model(file).map(|_| ())
    }

    /// The radial-distance model: `radial_model` (relative to the scenario `file`), or the
    /// built-in svr10.
    pub fn model(&self, file: &Path) -> Result<whisker_slam::radial::RadialEstimator> {
        match &self.radial_model {
            Some(m) => crate::radial_model::load(&relative_to(file, m))
                .map_err(|e| Error::field(file, "frontend.radial_model", e)),
            None => crate::radial_model::load_or_default(None),
        }
    }
}

/// Sensing mode of a scenario.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Sensing {
    /// No whisker simulation: the arm moves, nothing senses.
    #[default]
    None,
    /// Rapier simulates every whisker at 2 kHz (`whiskers.csv`, and the anticipated
    /// contacts as ground truth in `anticipated.csv`).
    Physics,
    /// Rigid whiskers swept once per whisk cycle, anticipated intersect with noise
    /// (§4.1.2.3, §6.1.3.1.2; `contacts.csv`).
    Kinematic,
}

impl Sensing {
    /// The name used in scenarios.
    pub fn name(self) -> &'static str {
        match self {
            Sensing::None => "none",
            Sensing::Physics => "physics",
            Sensing::Kinematic => "kinematic",
        }
    }
}

/// How whisker contacts are sensed by a command that needs them (`--sensing`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensingMode {
    /// The anticipated intersect with noise.
    Kinematic,
    /// Rapier whiskers, the front end and a radial-distance model.
    Physics,
}

impl crate::choice::Choice for SensingMode {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            SensingMode::Kinematic,
            "kinematic",
            "Anticipated intersect with noise",
        ),
        (
            SensingMode::Physics,
            "physics",
            "Rapier whiskers, the front end and a radial-distance model",
        ),
    ];
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
    /// The scenario file's TOML table merged over its base (if any).
    pub fn resolved_table(path: &Path) -> Result<toml::Table> {
        let (_, table) = crate::base::read_table(path)?;
        crate::base::resolve(path, table, 0)
    }

    /// Reads and checks a scenario file with `overrides` applied (`whisker run --set`).
    pub fn load_with(path: &Path, overrides: &[crate::overrides::Override]) -> Result<Self> {
        if overrides.is_empty() {
            return Self::load(path);
        }
        let mut table = Self::resolved_table(path)?;
        for o in overrides {
            o.apply(&mut table).map_err(|e| {
                Error::Input(format!("{}: --set {}: {e}", path.display(), o.dotted()))
            })?;
        }
        Self::from_table(path, table, "with --set")
    }

    /// The scenario of `table` (read from `path`, base merged in, then changed as
    /// `context` says), checked.
    pub fn from_table(path: &Path, table: toml::Table, context: &str) -> Result<Self> {
        let mut scenario: Self = match table.clone().try_into() {
            Ok(s) => s,
            Err(e) => {
                let e: toml::de::Error = e;
                // A table has no lines, and toml names the field of only some errors
                // (not those of enums or untagged enums): the path-keeping reading does.
                return Err(match crate::strict::check::<Self>(&table) {
                    Err((field, message)) if !field.is_empty() => Error::Input(format!(
                        "{} ({context}): field `{field}`: {message}",
                        path.display()
                    )),
                    _ => Error::Input(format!(
                        "{} ({context}): {}",
                        path.display(),
                        e.to_string().trim_end()
                    )),
                });
            }
        };
        Self::check_shapes(path, &table)?;
        scenario.validate(path)?;
        Ok(scenario)
    }

    /// Reads and checks a scenario file (what does not depend on the URDF).
    pub fn load(path: &Path) -> Result<Self> {
        let (text, table) = crate::base::read_table(path)?;
        if table.contains_key("base") {
            // Merged over its base: errors name the field, no longer the line.
            let merged = crate::base::resolve(path, table, 0)?;
            return Self::from_table(path, merged, "merged over its base");
        }
        let mut scenario: Self = toml::from_str(&text).map_err(|e| {
            Error::Input(format!("{}: {}", path.display(), e.to_string().trim_end()))
        })?;
        Self::check_shapes(path, &table)?;
        scenario.validate(path)?;
        Ok(scenario)
    }

    /// Refuses an array (or any non-table) where a table is expected, which serde would
    /// read positionally (see [`strict`]); after the `toml` reading, whose errors carry
    /// the line.
    fn check_shapes(path: &Path, table: &toml::Table) -> Result {
        crate::strict::check::<Self>(table)
            .map_err(|(field, message)| Error::field(path, &field, message))
    }

    /// The 18 whiskers' configurations of `[array]` (RCP thresholds not yet calibrated):
    /// those checked at loading, or, for a scenario without sensing, checked now.
    pub fn whisker_configs(&self, file: &Path) -> Result<Vec<WhiskerConfig>> {
        match &self.whiskers {
            Some(w) => Ok(w.clone()),
            None => self.array.whisker_configs(file),
        }
    }

    fn validate(&mut self, file: &Path) -> Result {
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
        } else if self.explore.is_some() {
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
        self.check_driver(file)?;
        if let Some(n) = &self.navigate {
            n.validate(file, office.as_ref())?;
            if let Some(o) = &n.object {
                o.validate(file, &self.object_names())?;
            }
        }
        if let Some(e) = &self.explore {
            e.validate(file, &self.object_names())?;
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

    /// The URDF path, resolved against the scenario file's directory.
    pub fn urdf_path(&self, file: &Path) -> PathBuf {
        relative_to(file, &self.arm.urdf)
    }

    /// The environment of `[[objects]]`, `[maze]` and `[office]`, loaded (mesh files read, checked
    /// and repaired; the maze built).
    pub fn environment(&self, file: &Path) -> Result<crate::environment::LoadedEnvironment> {
        crate::environment::load(
            file,
            &self.objects,
            self.maze.as_ref(),
            self.office.as_ref(),
            self.seed,
        )
    }

    /// The package search directories, resolved against the scenario file's directory.
    pub fn package_paths(&self, file: &Path) -> Vec<PathBuf> {
        self.arm
            .package_paths
            .iter()
            .map(|p| relative_to(file, p))
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
