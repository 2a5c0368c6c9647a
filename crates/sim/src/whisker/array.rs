//! Geometry of the 18-whisker array (thesis §2.2.2, Fig 2.5, Fig 2.15) and the mapping
//! from whisker to tactile-image pixel (§3.1.1, Fig 3.2).
//!
//! The modules sit on the `whisker_array` link (frame A: z points forward, away from
//! the arm) in three concentric rings of six, like a shrew's snout: short whiskers in
//! front and close to the axis, long ones behind and further out. The thesis gives no
//! coordinates (its Fig 2.15 is a CAD drawing), so these are chosen to resemble it:
//!
//! | ring | row | whisker length | ring radius | axial offset (z) | azimuths |
//! |---|---|---|---|---|---|
//! | rostral | 1 | 60 mm | 25 mm | 0 mm | 30°, 90°, …, 330° |
//! | middle | 2 | 100 mm | 40 mm | −20 mm | 30°, 90°, …, 330° |
//! | caudal | 3 | 160 mm | 55 mm | −40 mm | 30°, 90°, …, 330° |
//!
//! Module frame M at the pivot: X along the ring's tangent (the whisking motor's axis),
//! Z radially outward, Y = Z × X forward (+z of A). Each whisker sweeps in the plane
//! through the array axis: at whisk angle θ (measured from the module's base plane,
//! 40° fully retracted … 140° fully protracted, Fig 2.8) its shaft points along
//! cos(θ−90°)·Z + sin(θ−90°)·Y, i.e. radially outward at 90°, 50° backwards when
//! retracted and 50° forwards when protracted. The whisker frame F
//! ([`super::body::Whisker`]) is M turned about X by 90° − θ.
//!
//! Whisker index i = 6·(row − 1) + column, columns A–F being azimuth indices 0–5
//! (A at 30°, counter-clockwise about +z seen from the front); tactile-image pixel
//! (row r, column c) is whisker i.

use super::beam::BeamDesign;
use nalgebra::{Isometry3, Rotation3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::FRAC_PI_2;

/// Rings of the array, rostral first: (whisker length m, ring radius m, axial offset m).
pub const RINGS: [(f64, f64, f64); 3] = [
    (0.060, 0.025, 0.0),
    (0.100, 0.040, -0.020),
    (0.160, 0.055, -0.040),
];

/// Whisker modules per ring.
pub const PER_RING: usize = 6;

/// Column letters of the tactile image.
pub const COLUMNS: [char; 6] = ['A', 'B', 'C', 'D', 'E', 'F'];

/// Fully retracted whisk angle (rad), 40° (Fig 2.8).
pub const RETRACTED: f64 = 40.0 * std::f64::consts::PI / 180.0;
/// Fully protracted whisk angle (rad), 140° (Fig 2.8).
pub const PROTRACTED: f64 = 140.0 * std::f64::consts::PI / 180.0;

/// One whisker module of the array.
#[derive(Debug, Clone, PartialEq)]
pub struct Module {
    /// Index 0–17.
    pub index: usize,
    /// Ring 0–2 (rostral to caudal); tactile-image row is ring + 1.
    pub ring: usize,
    /// Azimuth index 0–5; tactile-image column letter `COLUMNS[column]`.
    pub column: usize,
    /// Pose of the module frame M (at the pivot) in the array frame A.
    pub pose: Isometry3<f64>,
    /// The whisker shaft's design.
    pub beam: BeamDesign,
}

impl Module {
    /// Tactile-image pixel label, e.g. "C2".
    pub fn pixel(&self) -> String {
        format!("{}{}", COLUMNS[self.column], self.ring + 1)
    }

    /// Pose of the whisker frame F at whisk angle `theta` (rad), in the array frame.
    pub fn whisker_pose(&self, theta: f64) -> Isometry3<f64> {
        self.pose * Isometry3::rotation(Vector3::x() * (FRAC_PI_2 - theta))
    }
}

/// The 18 whiskers' tactile-image labels (A1 … F3), by module index.
pub fn labels() -> Vec<String> {
    modules().iter().map(Module::pixel).collect()
}

/// The array's 18 modules with the default whisker designs.
pub fn modules() -> Vec<Module> {
    let mut out = Vec::with_capacity(RINGS.len() * PER_RING);
    for (ring, &(length, radius, z)) in RINGS.iter().enumerate() {
        for column in 0..PER_RING {
            let phi = (30.0 + 60.0 * column as f64).to_radians();
            let radial = Vector3::new(phi.cos(), phi.sin(), 0.0);
            let tangent = Vector3::new(-phi.sin(), phi.cos(), 0.0);
            let forward = radial.cross(&tangent);
            let rotation = Rotation3::from_basis_unchecked(&[tangent, forward, radial]);
            out.push(Module {
                index: ring * PER_RING + column,
                ring,
                column,
                pose: Isometry3::from_parts(
                    Translation3::from(radial * radius + Vector3::z() * z),
                    UnitQuaternion::from_rotation_matrix(&rotation),
                ),
                beam: BeamDesign::with_length(length),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whiskers_point_outwards_and_sweep_from_back_to_front() {
        for m in modules() {
            let radial = m.pose.translation.vector.xy().normalize();
            let shaft = |theta: f64| m.whisker_pose(theta).rotation * Vector3::z();
            // 90°: radially outward, in the array's cross-section plane.
            let mid = shaft(FRAC_PI_2);
            assert!((mid.xy() - radial).norm() < 1e-12 && mid.z.abs() < 1e-12);
            // Protracted: 50° forwards (+z); retracted: 50° backwards.
            assert!((shaft(PROTRACTED).z - 50f64.to_radians().sin()).abs() < 1e-12);
            assert!((shaft(RETRACTED).z + 50f64.to_radians().sin()).abs() < 1e-12);
            // The sweep plane holds the array axis: the whisk axis is tangential.
            let axis = m.pose.rotation * Vector3::x();
            assert!(axis.dot(&Vector3::z()).abs() < 1e-12 && axis.xy().dot(&radial).abs() < 1e-12);
            // Protraction moves the shaft towards the whisker frame's +Y.
            let f = m.whisker_pose(1.2);
            let dtheta = shaft(1.2 + 1e-6) - shaft(1.2);
            assert!((f.rotation * Vector3::y()).dot(&dtheta) > 0.0);
        }
    }

    #[test]
    fn indices_rows_and_columns_map_one_to_one_onto_pixels() {
        let ms = modules();
        assert_eq!(ms.len(), 18);
        let mut labels: Vec<String> = ms.iter().map(Module::pixel).collect();
        assert_eq!(labels[0], "A1");
        assert_eq!(labels[17], "F3");
        for (i, m) in ms.iter().enumerate() {
            assert_eq!(m.index, i);
            assert_eq!(i, 6 * m.ring + m.column);
        }
        labels.sort();
        labels.dedup();
        assert_eq!(labels.len(), 18);
        // Lengths grow from rostral to caudal.
        assert!(ms[0].beam.length < ms[6].beam.length && ms[6].beam.length < ms[12].beam.length);
    }
}
