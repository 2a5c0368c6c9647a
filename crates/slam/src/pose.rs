//! Pose conventions and conversions (DESIGN.md "Conventions").
//!
//! Poses are [`Isometry3<f64>`]. Roll/pitch/yaw angles follow URDF and ROS:
//! R = Rz(yaw)·Ry(pitch)·Rx(roll) (extrinsic x-y-z), which is nalgebra's
//! [`UnitQuaternion::from_euler_angles`]. Degrees appear only at the edges (config, output).

use nalgebra::{Isometry3, Matrix4, Translation3, UnitQuaternion, Vector3};

/// A pose from a position (m) and roll, pitch, yaw (rad).
pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// Roll, pitch, yaw (rad) of a rotation, inverse of [`from_xyz_rpy`] (pitch in [-π/2, π/2]).
pub fn rpy(rotation: &UnitQuaternion<f64>) -> [f64; 3] {
    let (r, p, y) = rotation.euler_angles();
    [r, p, y]
}

/// The homogeneous 4×4 matrix of a pose.
pub fn matrix(pose: &Isometry3<f64>) -> Matrix4<f64> {
    pose.to_homogeneous()
}

/// Quaternion components in (x, y, z, w) order, the order of ROS and Rerun.
pub fn quaternion_xyzw(rotation: &UnitQuaternion<f64>) -> [f64; 4] {
    let q = rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}

/// Distance between two poses: (translation error in m, rotation angle between them in rad).
pub fn distance(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let dt = (a.translation.vector - b.translation.vector).norm();
    let dr = a.rotation.angle_to(&b.rotation);
    (dt, dr)
}

/// Rotation vector (axis × angle, rad) taking orientation `from` to `to`, expressed in
/// the frame both are given in: `exp([v]×)·from = to`.
pub fn rotation_error(from: &UnitQuaternion<f64>, to: &UnitQuaternion<f64>) -> Vector3<f64> {
    (to * from.inverse()).scaled_axis()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// URDF's rpy is extrinsic x-y-z: roll about the fixed x axis first.
    #[test]
    fn rpy_is_extrinsic_xyz() {
        let p = from_xyz_rpy([0.0; 3], [FRAC_PI_2, 0.0, FRAC_PI_2]);
        // Rx(90°) takes y to z; then Rz(90°) leaves z alone.
        let y = p.rotation * Vector3::y();
        assert!((y - Vector3::z()).norm() < 1e-12);
        // Rx(90°) leaves x; Rz(90°) takes x to y.
        let x = p.rotation * Vector3::x();
        assert!((x - Vector3::y()).norm() < 1e-12);
    }

    #[test]
    fn rpy_round_trip() {
        for &(r, p, y) in &[(0.1, -0.4, 2.9), (-3.0, 1.2, -0.3), (0.0, 0.0, 0.0)] {
            let q = from_xyz_rpy([0.0; 3], [r, p, y]).rotation;
            let back = rpy(&q);
            assert!((back[0] - r).abs() < 1e-12 && (back[1] - p).abs() < 1e-12);
            assert!((back[2] - y).abs() < 1e-12);
        }
    }

    #[test]
    fn rotation_error_maps_from_onto_to() {
        let a = from_xyz_rpy([0.0; 3], [0.3, -0.2, 1.0]).rotation;
        let b = from_xyz_rpy([0.0; 3], [-0.5, 0.4, 2.0]).rotation;
        let v = rotation_error(&a, &b);
        let c = UnitQuaternion::from_scaled_axis(v) * a;
        assert!(c.angle_to(&b) < 1e-12);
        assert!((v.norm() - a.angle_to(&b)).abs() < 1e-12);
    }
}
