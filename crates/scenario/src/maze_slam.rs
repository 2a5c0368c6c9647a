//! `[maze_slam]`: the planar RatSLAM experiment of `whisker maze-slam` (thesis Ch 3).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use whisker_slam::ratslam::RatSlamParams;
use whisker_slam::ratslam::odometry::OdometryNoise;

/// The front end's estimate of a contact's angle that makes the tactile image (§3.1.1,
/// §3.3.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AngleEstimate {
    /// The largest whisk angle of the contact's whisk (the protraction limit when the
    /// whisker is not stopped).
    MaxAngle,
    /// The angle where the deflection starts to rise fast (|dy/dt| above 5000 counts/s).
    ContactAngle,
}

impl AngleEstimate {
    /// The name used in scenarios and reports.
    pub fn name(self) -> &'static str {
        match self {
            AngleEstimate::MaxAngle => "max_angle",
            AngleEstimate::ContactAngle => "contact_angle",
        }
    }
}

/// `[maze_slam]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MazeSlamConfig {
    /// Physics sensing: the angle estimates that make images, each its own RatSLAM run on
    /// the same simulation (default both).
    #[serde(default = "both")]
    pub images: Vec<AngleEstimate>,
    /// Also run the kidnapped variant: the same data with a quarter circuit cut out at the
    /// start of the 4th circuit (§3.3.1).
    #[serde(default)]
    pub kidnap: bool,
    /// How many circuits of the run to make, from the start of §3.2's protocol (3
    /// clockwise, 3 anticlockwise, one of each): 8 by default; at least 2 (the first is
    /// the metrics' base set), at least 4 with `kidnap`. Fewer make quick, short runs.
    #[serde(default = "all_circuits")]
    pub circuits: usize,
    /// `[maze_slam.ratslam]`: RatSLAM's parameters (`pose_cells`, `local_view`,
    /// `experience_map`; Table 3.1 by default).
    #[serde(default)]
    pub ratslam: RatSlamParams,
    /// `[maze_slam.odometry]`: the odometry error model (§3.1.2 by default).
    #[serde(default)]
    pub odometry: OdometryNoise,
    /// `[maze_slam.tuned]`: the local-view parameters per image set and variant, keyed
    /// `<images>/<variant>` (`"rcp-amplitude/contact_angle/kidnapped"`), as `whisker
    /// maze-slam --tune` chose them (§3.2.1: RatSLAM retuned per variant); runs without an
    /// entry take `ratslam.local_view`.
    #[serde(default)]
    pub tuned: BTreeMap<String, Tuned>,
}

/// One `[maze_slam.tuned]` entry: the two parameters §3.2.1 tuned.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Tuned {
    /// Local-view match threshold (Eq 3.1).
    pub match_threshold: f64,
    /// Pose-cell inject energy.
    pub inject_energy: f64,
}

impl Tuned {
    /// `base` with this entry's local-view parameters.
    pub fn over(&self, base: RatSlamParams) -> RatSlamParams {
        let mut p = base;
        p.local_view.match_threshold = self.match_threshold;
        p.local_view.inject_energy = self.inject_energy;
        p
    }
}

impl Default for MazeSlamConfig {
    fn default() -> Self {
        Self {
            images: both(),
            kidnap: false,
            circuits: all_circuits(),
            ratslam: RatSlamParams::default(),
            odometry: OdometryNoise::default(),
            tuned: BTreeMap::new(),
        }
    }
}

/// The circuits of the maze run (§3.2): 3 clockwise, 3 anticlockwise, one of each
/// (`true` = anticlockwise, i.e. the corners reversed); `circuits` takes the first few.
pub const CIRCUITS: [bool; 8] = [false, false, false, true, true, true, false, true];

fn all_circuits() -> usize {
    CIRCUITS.len()
}

fn both() -> Vec<AngleEstimate> {
    vec![AngleEstimate::MaxAngle, AngleEstimate::ContactAngle]
}

impl MazeSlamConfig {
    /// Checks the section; errors name the file and the field.
    pub fn validate(&self, file: &Path) -> Result {
        if self.images.is_empty() {
            return Err(Error::field(
                file,
                "maze_slam.images",
                "expected at least one of \"max_angle\", \"contact_angle\"",
            ));
        }
        let most = all_circuits();
        if !(2..=most).contains(&self.circuits) {
            return Err(Error::field(
                file,
                "maze_slam.circuits",
                format!("expected 2 to {most}, got {}", self.circuits),
            ));
        }
        self.ratslam
            .validate()
            .map_err(|e| Error::field(file, "maze_slam.ratslam", e))?;
        for (key, t) in &self.tuned {
            t.over(self.ratslam)
                .validate()
                .map_err(|e| Error::field(file, &format!("maze_slam.tuned.\"{key}\""), e))?;
            let variant = key
                .rsplit_once('/')
                .map(|(images, v)| (images.is_empty(), v));
            if !matches!(variant, Some((false, "normal" | "kidnapped"))) {
                return Err(Error::field(
                    file,
                    &format!("maze_slam.tuned.\"{key}\""),
                    "expected a key <images>/<variant>, e.g. \"open-loop/max_angle/normal\" \
                     or \"kinematic/kidnapped\"",
                ));
            }
        }
        self.odometry
            .validate()
            .map_err(|e| Error::field(file, "maze_slam.odometry", e))
    }
}
