//! Where the array flies over the maze and how its tactile images are scaled (thesis
//! §3.1.1), and the rate of RatSLAM's updates (§3.1.2).

use super::path::Sample;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::PI;
use whisker_sim::sensing::kinematic::RigidWhisker;
use whisker_slam::contact::ContactCycle;
use whisker_slam::ratslam::local_view::TactileImage;

/// Updates per second (§3.1.2).
pub const UPDATE_HZ: f64 = 1.5;

/// Where the array flies and how tactile images are scaled.
pub struct Geometry {
    /// Height of the array plane (world z, m).
    pub plane_z: f64,
    /// Height of the board (world z, m).
    pub board_z: f64,
    /// Yaw of the array at heading 0 (rad).
    pub yaw0: f64,
}

impl Geometry {
    /// The array's pose at a path sample: facing down from the plane, turned about the
    /// vertical by the heading.
    pub fn pose(&self, p: &Sample) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(p.x, p.y, self.plane_z),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), p.th)
                * UnitQuaternion::from_euler_angles(PI, 0.0, self.yaw0),
        )
    }

    /// The height above the board of `whisker`'s straight shaft tip at whisk angle `angle`
    /// (forward kinematics, §3.1.1), at least 0. The array flies level and turns only about
    /// the vertical, so the height does not depend on where in the plane it is: it is
    /// computed at the plane's origin, heading 0 — the same number from the simulator and
    /// from a log.
    pub fn tip_height(&self, whisker: &RigidWhisker, angle: f64) -> f64 {
        let pose = self.pose(&Sample::default());
        let tip = whisker.shaft_point(&pose, angle, whisker.module.beam.length);
        (tip.z - self.board_z).max(0.0)
    }

    /// The tactile image of per-whisker heights, full scale the array's height.
    pub fn image(&self, heights: &[Option<f64>]) -> TactileImage {
        TactileImage::from_heights(heights, self.plane_z - self.board_z)
    }

    /// The tactile image of one whisk's contacts: each contacted whisker's pixel from its
    /// contact angle.
    pub fn contact_image(&self, cycle: &ContactCycle, whiskers: &[RigidWhisker]) -> TactileImage {
        let mut heights = vec![None; whiskers.len()];
        for c in &cycle.contacts {
            heights[c.whisker] = Some(self.tip_height(&whiskers[c.whisker], c.angle_rad));
        }
        self.image(&heights)
    }
}
