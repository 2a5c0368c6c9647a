//! Contact localisation (thesis §5.1.1.1.2, Eq 5.1–5.2): the contact point of whisker i
//! is the origin of T_BE · T_EW_i · Rz(θ) · Ty(r) — the end effector's pose in the arm's
//! base frame, the whisker base's pose in the end effector's frame (at zero whisk angle;
//! the whisker rotates about its z axis and its shaft lies along its y axis, the thesis'
//! frame convention), the whisk angle at contact onset θ, and the radial distance r.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

/// The contact point in the arm's base frame.
pub fn contact_point(
    base_to_effector: &Isometry3<f64>,
    effector_to_whisker: &Isometry3<f64>,
    theta: f64,
    radial_distance: f64,
) -> Point3<f64> {
    let rz = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta),
    );
    let ty = Isometry3::translation(0.0, radial_distance, 0.0);
    (base_to_effector * effector_to_whisker * rz * ty) * Point3::origin()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn composed_transforms_place_a_contact_at_a_hand_computed_point() {
        // End effector at (1, 0, 0.5), yawed 90° (its x is the base's y). Whisker base 0.1
        // along the effector's x, pitched so nothing else changes: identity rotation.
        // θ = 30°, r = 0.08: in the whisker frame the point is Rz(30°)·(0, 0.08, 0) =
        // (−0.04, 0.0693, 0); in the effector frame (0.06, 0.0693, 0); rotated by 90° about
        // z: (−0.0693, 0.06, 0); plus (1, 0, 0.5).
        let be = Isometry3::from_parts(
            Translation3::new(1.0, 0.0, 0.5),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
        );
        let ew = Isometry3::translation(0.1, 0.0, 0.0);
        let p = contact_point(&be, &ew, 30f64.to_radians(), 0.08);
        let s = 0.08 * 30f64.to_radians().cos();
        let want = Point3::new(1.0 - s, 0.1 - 0.04, 0.5);
        assert!((p - want).norm() < 1e-12, "{p}");
    }
}
