//! Surface placement control, SPC (thesis §6.1.1, Alg 7 and Alg 8, Fig 6.1): keep the
//! array at a consistent pose to the surface it touches, so that a region gives the same
//! features on every visit.
//!
//! Three conditions: (1) the median of the contact points lies inside a cone of
//! half-angle λ_θ about the array's pointing axis; (2) the median distance of the contacts
//! along that axis lies in [λ_l, λ_u]; (3) the array's yaw is held level with gravity.
//! Orientation is corrected first, then distance, each by a fraction 1/δ of the
//! correction per call (Alg 7's "division steps").
//!
//! Frames. The thesis' end-effector frame points along its y axis with z "up"; this
//! project's array frame A points along +z with +y "up" (the arm's tool convention, see
//! `assets/urdf`). The two are the same frame relabelled: y_thesis = z_A, z_thesis = y_A,
//! x_thesis = −x_A. Everything here is written in A: the pointing axis is z, the level
//! axis is y.
//!
//! Readings of the thesis' gaps (§6.1.1 gives no values; scenarios/README.md, `[explore]`,
//! lists the defaults taken): Alg 7's typos
//! are cleaned up (one `maintain_yaw`, a done flag, no result when fewer than μ contacts);
//! the distance branch translates along the pointing axis by (d − mid)/δ_x; Alg 8 follows
//! its maths (the level axis is the component of *up* orthogonal to the pointing axis),
//! with the singular case (pointing straight up or down) keeping the current level axis
//! projected onto the plane orthogonal to the pointing axis. The thesis gives no values
//! for the parameters; the defaults are stated on [`PlacementParams`].

use crate::invalid::Invalid;
pub use crate::stats::median;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Gravity points along −z of the world: "up" is +z (Alg 8).
pub const UP: Vector3<f64> = Vector3::new(0.0, 0.0, 1.0);

/// Parameters of the surface placement controller (Alg 7). The thesis gives none of
/// them; the defaults are this project's readings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlacementParams {
    /// μ: fewest contacts the controller acts on (4: a point feature histogram needs
    /// neighbours for its normals).
    pub min_contacts: usize,
    /// λ_θ: half-angle of the cone about the pointing axis that must hold the contacts'
    /// median (30°: with σ = 25 % of length the median of ~10 contacts wanders ~15°, and
    /// a 15° cone chases the noise; scenarios/README.md).
    pub cone_deg: f64,
    /// λ_l: nearest accepted median contact distance along the pointing axis, from the
    /// array frame's origin (the centre of the array's front face): 0.025 m.
    pub near_m: f64,
    /// λ_u: farthest accepted median distance (0.055 m). The band's middle, 0.04 m, is
    /// the face-to-surface distance of the §5.2 map-building trajectory; at it all three
    /// rings reach a facing plane (the rostral 60 mm whiskers reach 46 mm ahead, the
    /// caudal 160 mm ones 83 mm).
    pub far_m: f64,
    /// δ_θ: each orientation correction turns 1/δ_θ of the way (4: Fig 6.1 turns over
    /// six frames; at 2 the median, which a tilt shifts ~3× as far as the tilt itself
    /// because only the near side's whiskers reach, overshoots and oscillates).
    pub rotation_division: f64,
    /// δ_x: each distance correction moves 1/δ_x of the way to the band's middle (2).
    pub distance_division: f64,
    /// K: most adjustments per surface region (10, the thesis' physical value, §6.1.4).
    pub max_adjustments: usize,
    /// Radius of the keep-out cylinder behind the array's front face (m): the housing's
    /// radius (0.055 m) plus a margin. A correction is not made if it would leave a
    /// sensed contact inside that cylinder or less than `keep_out_m` in front of the face;
    /// the array backs off instead (Alg 7 has no such guard: on a box edge a 55 mm housing
    /// meets the two faces before the contacts' median distance drops under λ_u).
    pub housing_radius_m: f64,
    /// Margin (m) in front of the face and around the housing, 0.01.
    pub keep_out_m: f64,
    /// Distance (m) behind the front face of the point the contacts' median is sighted
    /// from for condition 1 (0.1 m; 0 is Alg 7 as written, which sights from the array's
    /// origin). This array's whiskers radiate sideways (the snout of Fig 2.15) and reach
    /// ~0.1 m out but only 0.05–0.08 m ahead, so a contact field cut by an edge moves the
    /// median sideways several times as far as ahead: sighted from the face it reads as a
    /// 50–60° error, every turn overshoots and the array loses the surface (measured:
    /// 13 of 100 starts near a box edge settled, against 96+ sighted from 0.1 m back).
    pub apex_m: f64,
}

impl Default for PlacementParams {
    fn default() -> Self {
        Self {
            min_contacts: 4,
            cone_deg: 30.0,
            near_m: 0.025,
            far_m: 0.055,
            rotation_division: 4.0,
            distance_division: 2.0,
            max_adjustments: 10,
            housing_radius_m: 0.055,
            keep_out_m: 0.01,
            apex_m: 0.1,
        }
    }
}

impl PlacementParams {
    /// Checks the values; returns the offending field and what was expected.
    pub fn validate(&self) -> Result<(), Invalid> {
        let bad = |f: &str, m: String| Err(Invalid::field(f, m));
        if self.min_contacts < 1 {
            return bad("min_contacts", "expected at least 1".into());
        }
        if !(self.cone_deg.is_finite() && self.cone_deg > 0.0 && self.cone_deg < 90.0) {
            return bad(
                "cone_deg",
                format!("expected 0 < λ_θ < 90, got {}", self.cone_deg),
            );
        }
        for (f, v) in [
            ("housing_radius_m", self.housing_radius_m),
            ("keep_out_m", self.keep_out_m),
            ("apex_m", self.apex_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(f, format!("expected a finite distance ≥ 0, got {v}"));
            }
        }
        if !(self.near_m.is_finite() && self.far_m.is_finite() && 0.0 <= self.near_m) {
            return bad(
                "near_m",
                format!("expected a finite distance ≥ 0, got {}", self.near_m),
            );
        }
        if self.far_m <= self.near_m {
            return bad(
                "far_m",
                format!(
                    "expected more than near_m ({}), got {}",
                    self.near_m, self.far_m
                ),
            );
        }
        for (f, v) in [
            ("rotation_division", self.rotation_division),
            ("distance_division", self.distance_division),
        ] {
            if !(v.is_finite() && v >= 1.0) {
                return bad(f, format!("expected a number ≥ 1, got {v}"));
            }
        }
        Ok(())
    }
}

/// What one call of the controller decided.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Placement {
    /// Fewer than μ contacts (Alg 7 leaves this open): approach the surface along the
    /// pointing axis by λ_u − λ_l. Nothing the whiskers sweep is in the way (they would
    /// have touched it), unless a contact lies in the keep-out region (then
    /// [`Placement::BackOff`]). The caller counts these: a run of them means the surface
    /// is lost.
    Approach(Isometry3<f64>),
    /// Turn towards the contacts' median (condition 1 failed): the next pose.
    Turn(Isometry3<f64>),
    /// Move along the pointing axis (condition 2 failed): the next pose.
    Move(Isometry3<f64>),
    /// A contact lies in the keep-out region of the current pose or of the correction:
    /// back off along the pointing axis by λ_l.
    BackOff(Isometry3<f64>),
    /// All three conditions hold: the pose, yaw levelled.
    Done(Isometry3<f64>),
}

impl Placement {
    /// The pose to go to.
    pub fn pose(&self) -> Option<Isometry3<f64>> {
        match self {
            Placement::Approach(p)
            | Placement::Turn(p)
            | Placement::Move(p)
            | Placement::BackOff(p)
            | Placement::Done(p) => Some(*p),
        }
    }
}

/// Alg 8, `maintain_yaw`: the array frame at `position` pointing along `pointing`, its
/// level axis (y) the component of [`UP`] orthogonal to the pointing axis, so that it
/// points as high as it can. When the pointing axis is vertical that component vanishes;
/// the frame then keeps `previous_level` (the current frame's level axis) projected onto
/// the plane orthogonal to the pointing axis, or, if that vanishes too, the world x axis.
/// The result is right-handed and orthonormal: x = y × z.
pub fn maintain_yaw(
    position: Vector3<f64>,
    pointing: &Vector3<f64>,
    previous_level: &Vector3<f64>,
) -> Isometry3<f64> {
    let z = pointing.normalize();
    let orthogonal = |v: &Vector3<f64>| (v - z * z.dot(v)).try_normalize(1e-9);
    let y = orthogonal(&UP)
        .or_else(|| orthogonal(previous_level))
        .or_else(|| orthogonal(&Vector3::x()))
        .unwrap_or_else(|| orthogonal(&Vector3::y()).expect("x and y are not both ∥ z"));
    let x = y.cross(&z);
    let r = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    Isometry3::from_parts(
        Translation3::from(position),
        UnitQuaternion::from_rotation_matrix(&r),
    )
}

/// The component-wise median of points (MATLAB's `median` of an n×3 matrix).
pub fn median_point(points: &[Point3<f64>]) -> Point3<f64> {
    let axis = |a: usize| median(points.iter().map(|p| p[a]).collect());
    Point3::new(axis(0), axis(1), axis(2))
}

/// Whether a contact (world) lies in the keep-out region of the array at `pose`.
fn intrudes(params: &PlacementParams, pose: &Isometry3<f64>, contacts: &[Point3<f64>]) -> bool {
    contacts.iter().any(|c| {
        let local = pose.inverse_transform_point(c);
        local.z < params.keep_out_m
            && local.xy().coords.norm() < params.housing_radius_m + params.keep_out_m
    })
}

/// Alg 7, `correct_pose`: one step of the controller for the array at `array` (world)
/// touching the surface at `contacts` (world points).
pub fn correct(
    params: &PlacementParams,
    array: &Isometry3<f64>,
    contacts: &[Point3<f64>],
) -> Placement {
    let p = array.translation.vector;
    let z = array.rotation * Vector3::z();
    let level = array.rotation * Vector3::y();
    let back_off = || Placement::BackOff(maintain_yaw(p - z * params.near_m, &z, &level));
    if intrudes(params, array, contacts) {
        return back_off();
    }
    if contacts.len() < params.min_contacts.max(1) {
        let next = maintain_yaw(p + z * (params.far_m - params.near_m), &z, &level);
        return if intrudes(params, &next, contacts) {
            back_off()
        } else {
            Placement::Approach(next)
        };
    }
    let m = median_point(contacts).coords;
    let Some(n) = (m - (p - z * params.apex_m)).try_normalize(1e-12) else {
        return back_off();
    };
    let angle = z.dot(&n).clamp(-1.0, 1.0).acos();
    if angle > params.cone_deg.to_radians() {
        // Orientation first (divide_steps: slerp 1/δ_θ of the way), then level the yaw.
        let goal = maintain_yaw(p, &n, &level);
        let turned = array
            .rotation
            .slerp(&goal.rotation, 1.0 / params.rotation_division);
        let next = maintain_yaw(p, &(turned * Vector3::z()), &level);
        return if intrudes(params, &next, contacts) {
            back_off()
        } else {
            Placement::Turn(next)
        };
    }
    let d = median(contacts.iter().map(|c| (c.coords - p).dot(&z)).collect());
    if d < params.near_m || d > params.far_m {
        let middle = 0.5 * (params.near_m + params.far_m);
        let s = (d - middle) / params.distance_division;
        let next = maintain_yaw(p + z * s, &z, &level);
        return if s > 0.0 && intrudes(params, &next, contacts) {
            back_off()
        } else {
            Placement::Move(next)
        };
    }
    Placement::Done(maintain_yaw(p, &z, &level))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::substream;
    use rand::RngExt;

    /// Alg 8 for 10,000 random pointing directions, exactly down and exactly up among
    /// them: an orthonormal right-handed frame pointing as asked, its level axis as high
    /// as it can be (y·up ≥ 0 and y in the plane of up and the pointing axis).
    #[test]
    fn maintain_yaw_gives_a_level_right_handed_frame_for_any_direction() {
        let mut rng = substream(0, "test/maintain_yaw");
        let mut dirs = vec![-UP, UP, Vector3::x(), Vector3::new(0.0, 1e-12, -1.0)];
        while dirs.len() < 10_000 {
            let v = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            if let Some(v) = v.try_normalize(1e-3) {
                dirs.push(v);
            }
        }
        for d in dirs {
            let previous = Vector3::new(rng.random::<f64>(), 1.0, 0.3);
            let f = maintain_yaw(Vector3::new(0.1, 0.2, 0.3), &d, &previous);
            let r = f.rotation.to_rotation_matrix();
            let (x, y, z) = (r * Vector3::x(), r * Vector3::y(), r * Vector3::z());
            assert!((r.matrix().transpose() * r.matrix() - Matrix3::identity()).norm() < 1e-12);
            assert!((r.matrix().determinant() - 1.0).abs() < 1e-12);
            assert!((x - y.cross(&z)).norm() < 1e-12);
            assert!((z - d).norm() < 1e-9, "pointing {z} for {d}");
            assert!(y.dot(&UP) >= -1e-12, "level axis {y} points down for {d}");
            assert!(
                y.dot(&UP.cross(&z)).abs() < 1e-9,
                "level axis off the vertical plane"
            );
            // As high as it can be: y·up equals the length of up's orthogonal part.
            let best = (UP - z * z.dot(&UP)).norm();
            assert!((y.dot(&UP) - best).abs() < 1e-9);
            assert_eq!(f.translation.vector, Vector3::new(0.1, 0.2, 0.3));
        }
        // Straight down: the level axis is the previous one projected.
        let f = maintain_yaw(Vector3::zeros(), &-UP, &Vector3::new(1.0, 1.0, 0.5));
        let y = f.rotation * Vector3::y();
        assert!((y - Vector3::new(1.0, 1.0, 0.0).normalize()).norm() < 1e-12);
    }

    /// A plane facing the array: the controller turns until the median is in the cone,
    /// then moves into the band, by the stated fractions.
    #[test]
    fn alg7_turns_first_then_moves_by_the_division_steps() {
        let params = PlacementParams::default();
        // Contacts on the plane x = 0.2, spread about (0.2, 0, 0.5); array at the origin
        // level at z = 0.5 pointing along +y: the median is 90° off the pointing axis.
        let contacts: Vec<Point3<f64>> = (0..9)
            .map(|i| {
                Point3::new(
                    0.2,
                    0.01 * (i % 3) as f64 - 0.01,
                    0.5 + 0.01 * (i / 3) as f64 - 0.01,
                )
            })
            .collect();
        let start = maintain_yaw(Vector3::new(0.0, 0.0, 0.5), &Vector3::y(), &UP);
        let Placement::Turn(next) = correct(&params, &start, &contacts) else {
            panic!("expected a turn");
        };
        // Sighted from 0.1 m behind the face the median is atan2(0.2, 0.1) off the axis;
        // the turn goes a quarter of the way (δ_θ = 4).
        let z = next.rotation * Vector3::z();
        let expected = 0.2f64.atan2(0.1).to_degrees() / 4.0;
        assert!((z.dot(&Vector3::y()).acos().to_degrees() - expected).abs() < 1e-9);
        assert_eq!(next.translation, start.translation);
        // Pointing at the median: d = 0.2, band [0.025, 0.055] → move (0.2 − 0.04)/2.
        let aimed = maintain_yaw(Vector3::new(0.0, 0.0, 0.5), &Vector3::x(), &UP);
        let Placement::Move(moved) = correct(&params, &aimed, &contacts) else {
            panic!("expected a move");
        };
        assert!((moved.translation.vector - Vector3::new(0.08, 0.0, 0.5)).norm() < 1e-12);
        // In the band: done, unchanged.
        let near = maintain_yaw(Vector3::new(0.16, 0.0, 0.5), &Vector3::x(), &UP);
        let Placement::Done(done) = correct(&params, &near, &contacts) else {
            panic!("expected done");
        };
        assert!((done.to_homogeneous() - near.to_homogeneous()).norm() < 1e-12);
        let Placement::Approach(closer) = correct(&params, &near, &contacts[..3]) else {
            panic!("expected an approach");
        };
        assert!((closer.translation.vector - Vector3::new(0.19, 0.0, 0.5)).norm() < 1e-12);
    }

    #[test]
    fn component_wise_median_by_hand() {
        let m = median_point(&[
            Point3::new(0.0, 5.0, 1.0),
            Point3::new(2.0, 0.0, 1.0),
            Point3::new(1.0, 1.0, 9.0),
        ]);
        assert_eq!(m, Point3::new(1.0, 1.0, 1.0));
    }
}
