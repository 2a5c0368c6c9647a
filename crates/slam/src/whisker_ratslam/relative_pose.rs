//! Relative pose between experiences (thesis §5.1.2.4.1.1): odometry integrated since the
//! last experience — translation (Eq 5.13) and orientation by quaternion increments
//! (Alg 6, Eq 5.14–5.15).
//!
//! The translation of each interval is taken in the body frame at its start and
//! rotated into the frame of the last experience by the orientation accumulated so far,
//! so that the accumulated pose is exactly the rigid motion since that experience
//! (Eq 5.13 sums velocity components, which is the same when the orientation does not
//! change).

use crate::sensor::Odometry;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};

/// Alg 6 (Eq 5.14): the rotation of `omega` (rad/s, a rotation vector) over `dt`:
/// φ = ω·Δt/2; Δq = [cos‖φ‖, sin‖φ‖·φ/‖φ‖], or [1, φ] when ‖φ‖ = 0.
pub fn delta_q(omega: &Vector3<f64>, dt: f64) -> UnitQuaternion<f64> {
    let phi = omega * dt * 0.5;
    let angle = phi.norm();
    let q = if angle > 0.0 {
        let p = angle.sin() / angle;
        Quaternion::new(angle.cos(), p * phi.x, p * phi.y, p * phi.z)
    } else {
        Quaternion::new(1.0, phi.x, phi.y, phi.z)
    };
    UnitQuaternion::new_normalize(q)
}

/// The motion accumulated since the last experience.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accumulator {
    /// The rigid motion since the last experience (in its frame).
    pub pose: Isometry3<f64>,
}

impl Default for Accumulator {
    fn default() -> Self {
        Self {
            pose: Isometry3::identity(),
        }
    }
}

impl Accumulator {
    /// Adds one interval of odometry: d ← d + R·v·Δt, q ← q × Δq (Eq 5.13, 5.15).
    pub fn add(&mut self, odometry: &Odometry) {
        let step = Isometry3::from_parts(
            Translation3::from(odometry.translation()),
            delta_q(&Vector3::from(odometry.omega), odometry.dt),
        );
        self.pose *= step;
    }

    /// Takes the accumulated motion and starts again from zero (a new experience).
    pub fn take(&mut self) -> Isometry3<f64> {
        std::mem::take(self).pose
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn delta_q_by_hand() {
        // A quarter turn about z in one second: [cos π/4, 0, 0, sin π/4].
        let q = delta_q(&Vector3::new(0.0, 0.0, FRAC_PI_2), 1.0);
        let h = 0.5f64.sqrt();
        assert!((q.w - h).abs() < 1e-15 && (q.k - h).abs() < 1e-15);
        assert!(q.i.abs() < 1e-15 && q.j.abs() < 1e-15);
        assert_eq!(delta_q(&Vector3::zeros(), 0.5), UnitQuaternion::identity());
    }

    #[test]
    fn accumulated_odometry_reproduces_the_relative_pose() {
        // A wandering 6-D path; odometry between its poses, accumulated, gives first⁻¹·last.
        let poses: Vec<Isometry3<f64>> = (0..40)
            .map(|k| {
                let t = k as f64 * 0.1;
                crate::pose::from_xyz_rpy(
                    [0.3 * t.sin(), 0.2 * t, 0.1 * (2.0 * t).cos()],
                    [0.4 * t.sin(), 0.3 * t.cos(), 0.9 * t],
                )
            })
            .collect();
        let mut acc = Accumulator::default();
        for w in poses.windows(2) {
            acc.add(&Odometry::between(&w[0], &w[1], 0.5));
        }
        let want = poses[0].inverse() * poses[39];
        let got = acc.take();
        assert!((got.translation.vector - want.translation.vector).norm() < 1e-12);
        assert!(got.rotation.angle_to(&want.rotation) < 1e-12);
        assert_eq!(acc.pose, Isometry3::identity());
    }
}
