//! Exploration trajectories around an object for the §5.2 experiments (thesis Fig 5.14a):
//! trajectory A, which builds the object map, and a novel trajectory B.
//!
//! Both are loops of array poses around the object's vertical axis, each facing the
//! object's centre along a line of sight whose azimuth advances one step per whisk and
//! whose elevation undulates, the array face a fixed distance out from the surface along
//! that line, and the array's "up" kept towards +z (the yaw held relative to gravity, as
//! the thesis' surface placement does, §6.1.1.1):
//! - A: azimuth 0°, 12°, 24°… (the thesis' ~12° steps; 3° for the Box, whose steps were
//!   3 cm / 3°), elevation 20°·sin(2φ), face 4 cm out;
//! - B: azimuth shifted half a step, elevation −15°·sin(φ + 45°), face 5 cm out.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::query::Ray;
use parry3d_f64::shape::SharedShape;

/// Which trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trajectory {
    /// Map building.
    A,
    /// Novel, for validation.
    B,
}

impl Trajectory {
    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Trajectory::A => "A",
            Trajectory::B => "B",
        }
    }
}

/// Azimuth step of trajectory A for an object (degrees).
pub fn step_deg(object: &str) -> f64 {
    if object == "box" { 3.0 } else { 12.0 }
}

/// The poses of one lap of `which` around an object (`shape`, bounding box `size`,
/// standing on z = 0 centred on the z axis).
pub fn lap(
    which: Trajectory,
    object: &str,
    shape: &SharedShape,
    size: [f64; 3],
) -> Vec<Isometry3<f64>> {
    let step = step_deg(object).to_radians();
    let n = (std::f64::consts::TAU / step).round() as usize;
    let centre = Vector3::new(0.0, 0.0, 0.5 * size[2]);
    (0..n)
        .map(|k| {
            let (azimuth, elevation, standoff) = match which {
                Trajectory::A => {
                    let a = step * k as f64;
                    (a, 20f64.to_radians() * (2.0 * a).sin(), 0.04)
                }
                Trajectory::B => {
                    let a = step * (k as f64 + 0.5);
                    (
                        a,
                        -15f64.to_radians() * (a + 45f64.to_radians()).sin(),
                        0.05,
                    )
                }
            };
            let dir = Vector3::new(
                elevation.cos() * azimuth.cos(),
                elevation.cos() * azimuth.sin(),
                elevation.sin(),
            );
            let outside = centre + dir * 2.0;
            let ray = Ray::new(
                PVector::new(outside.x, outside.y, outside.z),
                PVector::new(-dir.x, -dir.y, -dir.z),
            );
            let surface = shape.cast_local_ray(&ray, 2.0, true).unwrap_or(2.0);
            let at = outside - dir * surface + dir * standoff;
            facing(at, -dir)
        })
        .collect()
}

/// The array pose at `at` whose whisker axis (+z) points along `forward`, its +y as near
/// world +z as the direction allows.
fn facing(at: Vector3<f64>, forward: Vector3<f64>) -> Isometry3<f64> {
    let z = forward.normalize();
    let up = Vector3::z();
    let x = up.cross(&z).try_normalize(1e-9).unwrap_or_else(Vector3::x);
    let y = z.cross(&x);
    let r = nalgebra::Matrix3::from_columns(&[x, y, z]);
    Isometry3::from_parts(Translation3::from(at), UnitQuaternion::from_matrix(&r))
}

/// Mean step of a lap between consecutive poses: (translation m, rotation rad).
pub fn mean_step(poses: &[Isometry3<f64>]) -> (f64, f64) {
    let n = poses.len().max(2) - 1;
    poses.windows(2).fold((0.0, 0.0), |(t, r), w| {
        let (dt, dr) = whisker_slam::pose::distance(&w[0], &w[1]);
        (t + dt / n as f64, r + dr / n as f64)
    })
}
