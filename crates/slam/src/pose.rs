//! Pose conventions and conversions (docs/design.md, "Rules every crate keeps").
//!
//! Poses are [`Isometry3<f64>`]. Roll/pitch/yaw angles follow URDF and ROS:
//! R = Rz(yaw)·Ry(pitch)·Rx(roll) (extrinsic x-y-z), which is nalgebra's
//! [`UnitQuaternion::from_euler_angles`]. Degrees appear only at the edges (config, output).
//! Planar poses (RatSLAM's maps, the mobile base) are [`Pose2`], with the composition and
//! difference of thesis Eq 3.3.

use nalgebra::{
    Isometry3, Matrix3, Matrix4, Point3, Rotation3, Translation3, UnitQuaternion, Vector3,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

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

/// The rigid motion `T` that best maps the points `from` onto `to` (paired by index) in the
/// least-squares sense, min Σ |T·from_i − to_i|² over rotations and translations (no scale,
/// no reflection): the SVD solution of Umeyama (1991), Eq 39–42 with c = 1. A map made by
/// SLAM is defined only up to such a motion, so its error is measured after this fit (the
/// absolute trajectory error of Sturm et al. 2012). `None` for fewer than 3 pairs or
/// mismatched lengths; any rotation minimises it for points on one line, and then the
/// SVD's choice is returned.
pub fn rigid_fit(from: &[Point3<f64>], to: &[Point3<f64>]) -> Option<Isometry3<f64>> {
    if from.len() != to.len() || from.len() < 3 {
        return None;
    }
    let n = from.len() as f64;
    let mean = |p: &[Point3<f64>]| p.iter().map(|q| q.coords).sum::<Vector3<f64>>() / n;
    let (mf, mt) = (mean(from), mean(to));
    let mut sigma = Matrix3::zeros();
    for (a, b) in from.iter().zip(to) {
        sigma += (b.coords - mt) * (a.coords - mf).transpose();
    }
    let svd = sigma.svd(true, true);
    let (u, v_t) = (svd.u?, svd.v_t?);
    let mut s = Matrix3::identity();
    if u.determinant() * v_t.determinant() < 0.0 {
        s[(2, 2)] = -1.0;
    }
    let r = Rotation3::from_matrix_unchecked(u * s * v_t);
    let t = mt - r * mf;
    Some(Isometry3::from_parts(
        Translation3::from(t),
        UnitQuaternion::from_rotation_matrix(&r),
    ))
}

/// A planar pose in the map frame: x, y (m), θ (rad, from +x towards +y).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose2 {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Heading (rad).
    pub th: f64,
}

/// An angle wrapped to (−π, π].
pub fn wrap(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(TAU) - PI;
    if w == -PI { PI } else { w }
}

impl Pose2 {
    /// `b` expressed in this pose's frame (b ⊖ self, Eq 3.3).
    pub fn relative(&self, b: &Pose2) -> Pose2 {
        let (dx, dy) = (b.x - self.x, b.y - self.y);
        let (s, c) = self.th.sin_cos();
        Pose2 {
            x: c * dx + s * dy,
            y: -s * dx + c * dy,
            th: wrap(b.th - self.th),
        }
    }

    /// `b`, given in this pose's frame, in the frame this pose is given in (self ⊕ b: the
    /// inverse of [`relative`](Self::relative)).
    pub fn compose(&self, b: &Pose2) -> Pose2 {
        let (s, c) = self.th.sin_cos();
        Pose2 {
            x: self.x + c * b.x - s * b.y,
            y: self.y + s * b.x + c * b.y,
            th: wrap(self.th + b.th),
        }
    }
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

    /// A point set moved by a known rigid motion is fitted back exactly; with a reflection
    /// the best proper rotation is returned, not the mirror.
    #[test]
    fn rigid_fit_recovers_a_known_motion_and_refuses_a_reflection() {
        let pts: Vec<Point3<f64>> = (0..20)
            .map(|i| {
                let f = i as f64;
                Point3::new((f * 0.7).sin(), (f * 1.3).cos() * 0.5, f * 0.01 - 0.1)
            })
            .collect();
        let truth = from_xyz_rpy([0.3, -1.2, 0.05], [2.5, -0.7, 1.9]);
        let moved: Vec<_> = pts.iter().map(|p| truth * p).collect();
        let fit = rigid_fit(&pts, &moved).unwrap();
        let (dt, dr) = distance(&fit, &truth);
        assert!(dt < 1e-12 && dr < 1e-12, "{dt} {dr}");
        // Mirror images through the plane z = 0: the fit is a rotation (det +1), and as a
        // least-squares optimum it leaves no more residual than the identity does.
        let mirrored: Vec<_> = pts.iter().map(|p| Point3::new(p.x, p.y, -p.z)).collect();
        let fit = rigid_fit(&pts, &mirrored).unwrap();
        let det = fit.rotation.to_rotation_matrix().matrix().determinant();
        assert!((det - 1.0).abs() < 1e-12);
        let residual = |t: &Isometry3<f64>| -> f64 {
            pts.iter()
                .zip(&mirrored)
                .map(|(a, b)| (t * a - b).norm_squared())
                .sum()
        };
        assert!(residual(&fit) <= residual(&Isometry3::identity()) + 1e-12);
        assert!(rigid_fit(&pts[..2], &moved[..2]).is_none());
    }
}
