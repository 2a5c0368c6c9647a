//! The arm holding the array while the base drives (terrain mode, issue #36): the
//! joints that hold `[navigate.terrain]`'s array pose, found by IK, and the array's pose
//! in the world at any pose of the base, the arm's base link `mount_height_m` above the
//! floor at the base's centre.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::path::Path;
use whisker_scenario::navigate::TerrainConfig;
use whisker_scenario::{Error, Result};
use whisker_sim::kinematics::Chain;
use whisker_sim::kinematics::ik::{self, IkOptions};
use whisker_slam::pose;
use whisker_slam::pose::Pose2;

/// The arm holding the array for terrain mode.
#[derive(Debug, Clone)]
pub struct Posture {
    /// The chain's joints (rad).
    pub q: Vec<f64>,
    /// The array's pose in the arm's base frame (forward kinematics of `q`).
    pub array: Isometry3<f64>,
    /// Height of the arm's base link above the floor (m).
    pub mount: f64,
}

impl Posture {
    /// The joints that hold `config`'s array pose, by IK from `start`; the error names
    /// the field.
    ///
    /// The posture belongs to the robot, not to a run: IK's restarts (if the descent from
    /// `start` fails) draw from seed 0 whatever the run's seed.
    pub fn solve(
        config: &TerrainConfig,
        chain: &Chain,
        start: &[f64],
        file: &Path,
    ) -> Result<Self> {
        let rpy = config.array_rpy_deg.map(f64::to_radians);
        let target = pose::from_xyz_rpy(config.array_position_m, rpy);
        let options = IkOptions {
            seed: 0,
            ..IkOptions::default()
        };
        let q = ik::solve(chain, &target, start, &options).map_err(|e| {
            Error::field(
                file,
                "navigate.terrain.array_position_m / array_rpy_deg",
                format!("the arm cannot hold the array there: {e}"),
            )
        })?;
        Ok(Self {
            array: chain.fk(&q),
            q,
            mount: config.mount_height_m,
        })
    }

    /// The arm's base link in the world with the base at `b`.
    pub fn arm_base(&self, b: &Pose2) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(b.x, b.y, self.mount),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), b.th),
        )
    }

    /// The array in the world with the base at `b`.
    pub fn array_pose(&self, b: &Pose2) -> Isometry3<f64> {
        self.arm_base(b) * self.array
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    /// The array's world pose at base pose (x, y, θ) is the posture's (a, in the arm's
    /// base frame) turned by θ about the vertical, raised by the mount and moved to
    /// (x, y): computed here by hand for θ = 90°, where (aₓ, a_y) turns to (−a_y, aₓ).
    #[test]
    fn the_array_rides_on_the_base() {
        let array = Isometry3::from_parts(
            Translation3::new(0.1, -0.48, -0.1),
            UnitQuaternion::from_euler_angles(0.3, 0.2, 0.1),
        );
        let posture = Posture {
            q: vec![],
            array,
            mount: 0.35,
        };
        let b = Pose2 {
            x: 2.0,
            y: 1.0,
            th: std::f64::consts::FRAC_PI_2,
        };
        let world = posture.array_pose(&b);
        let want = Point3::new(2.0 + 0.48, 1.0 + 0.1, 0.35 - 0.1);
        assert!((world.translation.vector - want.coords).norm() < 1e-12);
        let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), b.th) * array.rotation;
        assert!(world.rotation.angle_to(&turned) < 1e-12);
    }
}
