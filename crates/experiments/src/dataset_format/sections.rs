//! The manifest's experiment sections (docs/dataset.md, `dataset.json`): what each
//! experiment's replay needs of the run — the maze's RatSLAM (`maze`), the object walks
//! (`object_slam`), the closed loop's `[explore]` (`closed_loop`) and the office run's robot
//! (`navigate`). Re-exported by [`super::manifest`].

use serde::{Deserialize, Serialize};
use whisker_slam::frontend::contact::FrontEndParams;
use whisker_slam::invalid::Invalid;
use whisker_slam::ratslam::RatSlamParams;

/// `maze`: the maze experiment's parameters (§3.1–§3.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MazeInfo {
    /// SLAM updates per second.
    pub update_hz: f64,
    /// Number of updates.
    pub updates: usize,
    /// Height of the array's plane (world z, m).
    pub plane_z_m: f64,
    /// Height of the board's top (world z, m).
    pub board_z_m: f64,
    /// Yaw of the array at heading 0 (rad).
    pub yaw0_rad: f64,
    /// The update where each circuit starts.
    pub circuit_starts: Vec<usize>,
    /// Run the kidnapped variant too.
    pub kidnap: bool,
    /// The image sets and the front end's estimate of each (`max_angle`,
    /// `contact_angle`; `contacts` at level contacts).
    pub image_sets: Vec<(String, String)>,
    /// Each whisker's front-end detection parameters (level streams).
    pub frontend: Option<Vec<FrontEndParams>>,
    /// RatSLAM's parameters.
    pub ratslam: RatSlamParams,
    /// The scenario's `[maze_slam.tuned]` entries (absent: none).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub tuned: std::collections::BTreeMap<String, whisker_scenario::maze_slam::Tuned>,
}

/// `object_slam`: the walks around each object (§5.2, Fig 5.14a).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSlamInfo {
    /// `kinematic` (level contacts) or `physics` (level streams: one whisk file per pose
    /// under `log/<object>/<A|B>/whisks/`, the radial-distance model in
    /// `log/radial_model.json`).
    pub sensing: String,
    /// Where the objects sat relative to the trajectories (`whisker object-slam
    /// --placement`): `thesis` or `centred` (provenance: the true poses are in `truth/`).
    /// Datasets written before the option had centred objects, and read as such.
    #[serde(default = "centred")]
    pub placement: String,
    /// Every walk, each object's A (two laps) then B (one lap).
    pub walks: Vec<WalkInfo>,
    /// Level streams: each whisker's detection levels as the walks were detected (since
    /// the noise rule, issue #61); absent in older datasets, which were detected at the
    /// written defaults (500 counts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frontend: Option<Vec<FrontEndParams>>,
}

/// `object_slam.placement` of a dataset that predates it.
fn centred() -> String {
    "centred".into()
}

/// One walk around an object: a whisk at each pose, one per second.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WalkInfo {
    /// Catalogue object.
    pub object: String,
    /// `A` or `B`.
    pub trajectory: String,
    /// Laps of the trajectory.
    pub laps: usize,
    /// Whisks (poses).
    pub whisks: usize,
}

/// `closed_loop`: what the replay needs of the run's `[explore]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClosedLoopInfo {
    /// `recognise` or `map`.
    pub task: String,
    /// Whisks (iterations).
    pub whisks: usize,
    /// The known objects, in order (their maps: `log/maps/<name>.json`).
    pub maps: Vec<String>,
    /// The odometry noise the log holds (Eq 6.4–6.11; `[explore.odometry]`).
    pub odometry_noise: whisker_slam::exploration::odometry_noise::OdometryNoise,
    /// WhiskerRatSLAM's parameters (`[explore.slam]`).
    pub slam: whisker_slam::whisker_ratslam::slam::Params,
    /// Recognition's parameters (`[explore.recognition]`).
    pub recognition: whisker_slam::recognition::RecognitionParams,
    /// Level streams: each whisker's detection levels as the run detected (the scenario's
    /// `[frontend.detection]` fitted to its RCP threshold); absent in older datasets,
    /// which were detected at the default levels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frontend: Option<Vec<FrontEndParams>>,
}

/// `navigate`: what the replay of an office run needs (issue #36): the robot, not the
/// office.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NavigateInfo {
    /// SLAM updates (one whisk each) and their rate (Hz).
    pub updates: usize,
    pub update_hz: f64,
    /// Whether recognised objects became landmarks in the planar map.
    pub fusion: bool,
    /// Provenance: the run was the kidnapped variant (the carry is in the ground truth).
    pub kidnap: bool,
    /// The base's odometry error the log holds (`[navigate.odometry]`: the wheeled-base
    /// model, docs/navigation.md).
    pub odometry_noise: whisker_slam::navigation::base_odometry::BaseOdometryNoise,
    /// How the arm holds the array over the base.
    pub posture: PostureInfo,
    /// The mode-switch cue (`[navigate.switch]`).
    pub switch: whisker_slam::navigation::mode_switch::ModeSwitch,
    /// Planar RatSLAM (`[navigate.ratslam]`).
    pub ratslam: RatSlamParams,
    /// Object mode (`[navigate.object]`; none: the cue only reported).
    pub object: Option<NavigateObjectInfo>,
}

impl NavigateInfo {
    /// The numbers a replay needs sane: (field, what was expected).
    pub(super) fn check(&self) -> Result<(), Invalid> {
        let bad = |f: &str, e: &str| Err(Invalid::field(f, e));
        if self.updates == 0 {
            return bad("updates", "expected at least 1");
        }
        if !(self.update_hz.is_finite() && self.update_hz > 0.0) {
            return bad("update_hz", "expected a rate > 0 (Hz)");
        }
        let p = &self.posture;
        let numbers = p.array_position_m.iter().chain(&p.array_quaternion);
        if !(numbers.chain([&p.mount_height_m]).all(|v| v.is_finite())) {
            return bad("posture", "expected finite numbers");
        }
        let norm = p.array_quaternion.iter().map(|q| q * q).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > 1e-9 {
            return bad("posture.array_quaternion", "expected a unit quaternion");
        }
        if let Some(o) = &self.object {
            for (f, v) in [
                ("dock_distance_m", o.dock_distance_m),
                ("revisit_m", o.revisit_m),
                ("landmark_energy", o.landmark_energy),
                ("landmark_gate_m", o.landmark_gate_m),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return bad(&format!("object.{f}"), "expected a number ≥ 0");
                }
            }
        }
        Ok(())
    }
}

/// `navigate.posture`: the arm's joints, the arm's base above the floor, the array in
/// the arm's base frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PostureInfo {
    pub joints_rad: Vec<f64>,
    pub mount_height_m: f64,
    pub array_position_m: [f64; 3],
    /// A unit quaternion x, y, z, w.
    pub array_quaternion: [f64; 4],
}

/// `navigate.object`: what the robot's stops need.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NavigateObjectInfo {
    /// `arm` (the shoulder's pan turns the arm) or `base` (the base turns and drives).
    pub dock: String,
    pub dock_distance_m: f64,
    pub revisit_m: f64,
    pub landmark_energy: f64,
    pub landmark_gate_m: f64,
    /// The known objects, in order (their maps: `log/maps/<name>.json`).
    pub maps: Vec<String>,
    /// The stops' 6-D odometry error (Eq 6.4–6.11; `[navigate.object.explore.odometry]`).
    pub odometry_noise: whisker_slam::exploration::odometry_noise::OdometryNoise,
    /// WhiskerRatSLAM (`[navigate.object.explore.slam]`) and recognition
    /// (`[navigate.object.explore.recognition]`).
    pub slam: whisker_slam::whisker_ratslam::slam::Params,
    pub recognition: whisker_slam::recognition::RecognitionParams,
    /// Number of stops (rows of `log/stops.csv`).
    pub stops: usize,
}
