//! `[explore]`: the closed loop of thesis Chapter 6 — the robot chooses where to whisk,
//! moves there with the arm and either builds an object map (§6.1.3) or recognises the
//! object against loaded maps (§6.1.2, §6.2). Documented field by field in
//! `scenarios/README.md`, with the reading taken wherever the thesis gives no value.

use crate::error::{Error, Result};
use crate::paths::relative_to;
use crate::sensing::Sensing;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use whisker_slam::exploration::lsr::LsrParams;
use whisker_slam::exploration::odometry_noise::OdometryNoise;
use whisker_slam::exploration::placement::PlacementParams;
use whisker_slam::invalid::Invalid;
use whisker_slam::recognition::RecognitionParams;
use whisker_slam::whisker_ratslam::object_map::{ObjectMap, SensedBy};

/// What the loop is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Task {
    /// Build an object map of the object (§6.1.3): the ellipsoid's faces, `map_loops` times.
    Map,
    /// Recognise the object against `maps` (§6.2).
    Recognise,
}

/// Where map building's goals lie (§6.1.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MapGoals {
    /// At whisker reach: `standoff_m` beyond the object's surface along each ray from its
    /// centre (the stand-off of the §5.2 trajectories), the array pointing at the nearest
    /// point of the object (issue #35).
    Reach,
    /// The ellipsoid with semi-axes √3 × the object's half extents + `standoff_m`, the
    /// array along its inward normals: ~11 cm from the Box's sides, beyond most whiskers'
    /// reach (the default for now: `assets/maps` were built on it, and maps built at
    /// reach recognise less; issue #35).
    #[default]
    Ellipsoid,
}

/// How the next region is chosen once an object is likely (§6.1.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// The sphere around the object, face by face (§6.1.3.2).
    #[default]
    Default,
    /// Follow experience history (§6.1.2.2).
    Feh,
    /// Least similar region (§6.1.2.3).
    Lsr,
}

impl Strategy {
    /// The name used in scenarios and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Default => "default",
            Strategy::Feh => "feh",
            Strategy::Lsr => "lsr",
        }
    }
}

pub use whisker_slam::exploration::tour::StepPose;

/// `[explore]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExploreConfig {
    /// `"map"` or `"recognise"`.
    pub task: Task,
    /// The `[[objects]]` entry explored, by name [default: the only object].
    pub object: Option<String>,
    /// Recognise: the object maps loaded and appended, name → file (relative to the
    /// scenario), e.g. `{ box = "../assets/maps/box.json" }`.
    #[serde(default)]
    pub maps: BTreeMap<String, PathBuf>,
    /// Recognise: accept maps sensed the other way than the run senses, or whose sensing
    /// is not recorded (the transfer experiment: kinematic maps on physics whiskers and
    /// back) [false: such maps are refused].
    #[serde(default)]
    pub transfer: bool,
    /// Recognise: `"default"`, `"feh"` or `"lsr"`.
    #[serde(default)]
    pub strategy: Strategy,
    /// Surface placement control after every move (§6.1.1).
    #[serde(default = "yes")]
    pub spc: bool,
    /// The most whisks (iterations) of a run: the time limit T_max.
    #[serde(default = "max_iterations")]
    pub max_iterations: usize,
    /// Recognise: a run stops early once every object's IC has reached this (900: one run
    /// serves the thresholds 100–900 of Fig 6.7).
    #[serde(default = "stop_ic")]
    pub stop_ic: f64,
    /// Recognise: stop at the first object's IC crossing the recognition threshold (the
    /// decision), as object mode on the mobile robot does (`[navigate.object]`) [false].
    #[serde(default)]
    pub stop_on_identity: bool,
    /// Map: passes over the ellipsoid's faces (2, §6.1.3.1).
    #[serde(default = "two")]
    pub map_loops: usize,
    /// Bands and sectors of the goal meshes (20, as MATLAB's `ellipsoid`/`sphere`).
    #[serde(default = "twenty")]
    pub mesh_faces: usize,
    /// Map: where the goals lie, `"reach"` or `"ellipsoid"` ([`MapGoals`]).
    #[serde(default)]
    pub map_goals: MapGoals,
    /// Map: the goals' distance beyond the surface along each ray (`reach`), or what
    /// the ellipsoid adds to √3 × the object's half extents (`ellipsoid`) (m).
    #[serde(default = "standoff")]
    pub standoff_m: f64,
    /// Recognise: radius of the default trajectory's sphere (m) [default: the object's
    /// bounding sphere + `placement.near_m`].
    pub sphere_radius_m: Option<f64>,
    /// Goal faces whose centroid lies lower than this above the table are skipped (m).
    #[serde(default = "min_height")]
    pub min_height_m: f64,
    /// FEH/LSR: the longest segment of a step between experiences (m; 3 cm, §6.1.2.2).
    #[serde(default = "segment")]
    pub segment_m: f64,
    /// FEH/LSR: which relative pose a step uses.
    #[serde(default)]
    pub step_pose: StepPose,
    /// `[explore.placement]`: the SPC's parameters.
    #[serde(default)]
    pub placement: PlacementParams,
    /// `[explore.odometry]`: the odometry noise (Eq 6.4–6.11).
    #[serde(default)]
    pub odometry: OdometryNoise,
    /// `[explore.recognition]`: RC and IC (§6.2).
    #[serde(default)]
    pub recognition: RecognitionParams,
    /// `[explore.lsr]`: Eq 6.3's weights.
    #[serde(default)]
    pub lsr: LsrParams,
    /// `[explore.slam]`: WhiskerRatSLAM's parameters (the §5.2 defaults).
    #[serde(default)]
    pub slam: whisker_slam::whisker_ratslam::slam::Params,
}

fn yes() -> bool {
    true
}
/// The most whisks of one closed loop (the thesis' runs took hundreds).
pub const MAX_ITERATIONS: usize = 100_000;

/// The most passes over the ellipsoid of `task = "map"`.
pub const MAX_MAP_LOOPS: usize = 100;

/// The shortest FEH/LSR segment (m).
pub const MIN_SEGMENT_M: f64 = 1e-3;

fn max_iterations() -> usize {
    1000
}
fn stop_ic() -> f64 {
    900.0
}
fn two() -> usize {
    2
}
fn twenty() -> usize {
    20
}
fn standoff() -> f64 {
    0.04
}
fn min_height() -> f64 {
    0.02
}
fn segment() -> f64 {
    0.03
}

impl ExploreConfig {
    /// Checks the section for a run sensed by `sensing`; errors name the file and the
    /// field.
    pub fn validate(&self, file: &Path, objects: &[String], sensing: Sensing) -> Result {
        let bad =
            |field: &str, msg: String| Err(Error::field(file, &format!("explore.{field}"), msg));
        self.object_name(file, objects)?;
        if self.task == Task::Recognise {
            if self.maps.is_empty() {
                return bad(
                    "maps",
                    "task = \"recognise\" needs at least one object map".into(),
                );
            }
            for (name, path) in &self.maps {
                let p = relative_to(file, path);
                if !p.is_file() {
                    return bad(
                        &format!("maps.{name}"),
                        format!("no such file: {}", p.display()),
                    );
                }
            }
        } else if !self.maps.is_empty() {
            return bad("maps", "only used with task = \"recognise\"".into());
        }
        self.check_map_sensing(file, sensing)?;
        if !(1..=MAX_ITERATIONS).contains(&self.max_iterations) {
            return bad(
                "max_iterations",
                format!(
                    "expected 1 to {MAX_ITERATIONS}, got {}",
                    self.max_iterations
                ),
            );
        }
        if !(1..=MAX_MAP_LOOPS).contains(&self.map_loops) {
            return bad(
                "map_loops",
                format!("expected 1 to {MAX_MAP_LOOPS}, got {}", self.map_loops),
            );
        }
        if !(3..=200).contains(&self.mesh_faces) {
            return bad(
                "mesh_faces",
                format!("expected 3 to 200, got {}", self.mesh_faces),
            );
        }
        if !(self.stop_ic.is_finite() && self.stop_ic > 0.0) {
            return bad(
                "stop_ic",
                format!("expected a positive number, got {}", self.stop_ic),
            );
        }
        // A nanometre segment cut a step into more pieces than memory holds (a panic).
        if !(self.segment_m.is_finite() && self.segment_m >= MIN_SEGMENT_M) {
            return bad(
                "segment_m",
                format!(
                    "expected a length of at least {MIN_SEGMENT_M} m, got {}",
                    whisker_slam::message::short(self.segment_m)
                ),
            );
        }
        for (f, v) in [
            ("standoff_m", self.standoff_m),
            ("min_height_m", self.min_height_m),
        ] {
            if !v.is_finite() {
                return bad(f, format!("expected a finite number, got {v}"));
            }
        }
        if self.map_goals == MapGoals::Reach && self.standoff_m <= 0.0 {
            return bad(
                "standoff_m",
                format!(
                    "map_goals = \"reach\" needs a positive distance beyond the surface, got {}",
                    self.standoff_m
                ),
            );
        }
        if let Some(r) = self.sphere_radius_m
            && !(r.is_finite() && r > 0.0)
        {
            return bad(
                "sphere_radius_m",
                format!("expected a positive number, got {r}"),
            );
        }
        let sub = |name: &str, r: Result<(), Invalid>| {
            r.map_err(|e| Error::field(file, &format!("explore.{name}.{}", e.field), e.message))
        };
        sub("placement", self.placement.validate())?;
        sub("odometry", self.odometry.validate())?;
        sub("recognition", self.recognition.validate())?;
        for (f, v) in [
            ("translation_per_m", self.lsr.translation_per_m),
            ("rotation_per_rad", self.lsr.rotation_per_rad),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(
                    &format!("lsr.{f}"),
                    format!("expected a finite number ≥ 0, got {v}"),
                );
            }
        }
        self.slam
            .pose_cells
            .validate()
            .map_err(|m| Error::field(file, "explore.slam.pose_cells", m))
    }

    /// Refuses a map sensed otherwise than the run (`sensing`), or whose sensing is not
    /// recorded, unless `transfer` asks for it: physics contacts matched against a
    /// kinematic map are the transfer experiment, not recognition.
    fn check_map_sensing(&self, file: &Path, sensing: Sensing) -> Result {
        let run = match sensing {
            Sensing::Physics => SensedBy::Physics,
            Sensing::Kinematic => SensedBy::Kinematic,
            Sensing::None => return Ok(()),
        };
        if self.transfer || self.task != Task::Recognise {
            return Ok(());
        }
        for (name, path) in self.map_files(file) {
            let field = format!("explore.maps.{name}");
            let map = ObjectMap::load(&path).map_err(|e| Error::field(file, &field, e))?;
            let why = match map.sensing.map(|s| s.mode) {
                Some(mode) if mode == run => continue,
                Some(mode) => format!(
                    "{} was built on {} sensing and this run senses {}: give maps built on {} \
                     sensing, or set explore.transfer = true to match across sensing (the \
                     transfer experiment)",
                    path.display(),
                    mode.name(),
                    run.name(),
                    run.name()
                ),
                None => format!(
                    "{} records no sensing (a version 1 map): rebuild it (task = \"map\"), or \
                     set explore.transfer = true to use it on {} sensing anyway",
                    path.display(),
                    run.name()
                ),
            };
            return Err(Error::field(file, &field, why));
        }
        Ok(())
    }

    /// The explored object's name among the scenario's `objects`.
    pub fn object_name(&self, file: &Path, objects: &[String]) -> Result<String> {
        match (&self.object, objects) {
            (Some(o), _) if objects.contains(o) => Ok(o.clone()),
            (Some(o), _) => Err(Error::field(
                file,
                "explore.object",
                format!("no [[objects]] entry is named {o:?}; the objects are {objects:?}"),
            )),
            (None, [one]) => Ok(one.clone()),
            (None, _) => Err(Error::field(
                file,
                "explore.object",
                format!(
                    "expected the name of one of the [[objects]] ({objects:?}): the loop explores one object"
                ),
            )),
        }
    }

    /// The map files, resolved against the scenario file.
    pub fn map_files(&self, file: &Path) -> Vec<(String, PathBuf)> {
        self.maps
            .iter()
            .map(|(k, p)| (k.clone(), relative_to(file, p)))
            .collect()
    }
}
