//! The compliant follicle and its Hall-effect deflection sensor (thesis §2.2.2, Fig 2.7).
//!
//! The shaft's bulbous base sits in polyurethane rubber that lets it pivot about a point
//! near the centre of the bulb. A magnet in the base, below the pivot, moves when the
//! shaft is bent; the Hall-effect sensor under it reads that displacement in two
//! orthogonal directions. Here the bulb is a small rigid body joined to the follicle by a
//! spherical joint at the pivot with a rotational spring of stiffness `stiffness` about
//! the two bending axes (and a stiff twist); the reading is the magnet's displacement,
//! `magnet_lever` × the bulb's rotation (small angles).

/// The follicle's mechanical design (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollicleDesign {
    /// Rotational stiffness of the rubber mount about each bending axis (N·m/rad).
    pub stiffness: f64,
    /// Distance from the pivot up to where the shaft leaves the bulb (m).
    pub pivot_depth: f64,
    /// Distance from the pivot down to the magnet (m).
    pub magnet_lever: f64,
    /// Mass of the bulb with its magnet (kg).
    pub bulb_mass: f64,
}

impl Default for FollicleDesign {
    /// A stiff rubber mount (0.2 N·m/rad: a few times the bending stiffness the shaft
    /// presents to a contact, so the shaft, not the mount, does most of the bending),
    /// a 3 mm bulb above the pivot, the magnet 2 mm below it, 0.3 g.
    fn default() -> Self {
        Self {
            stiffness: 0.2,
            pivot_depth: 3.0e-3,
            magnet_lever: 2.0e-3,
            bulb_mass: 0.3e-3,
        }
    }
}

/// The softest follicle (N·m/rad), a two-hundredth of the default: a 5 mN load 8 cm out
/// already turns it through 20°, and softer shafts swing about the pivot rather than bend.
pub const MIN_STIFFNESS_NM_PER_RAD: f64 = 1e-3;

/// The stiffest follicle (N·m/rad): ten million times the default's, where the
/// follicle reading is already below a nanometre; stiffer is a rigid clamp (stiffness 0).
pub const MAX_STIFFNESS_NM_PER_RAD: f64 = 1e6;

impl FollicleDesign {
    /// Checks that every value is finite and physical; names the first bad field.
    pub fn validate(&self) -> Result<(), Invalid> {
        super::require_positive(
            "follicle ",
            &[
                ("stiffness", self.stiffness),
                ("pivot_depth", self.pivot_depth),
                ("magnet_lever", self.magnet_lever),
                ("bulb_mass", self.bulb_mass),
            ],
        )?;
        if self.stiffness < MIN_STIFFNESS_NM_PER_RAD || self.stiffness > MAX_STIFFNESS_NM_PER_RAD {
            return Err(format!(
                "follicle stiffness must be from {MIN_STIFFNESS_NM_PER_RAD} to \
                 {MAX_STIFFNESS_NM_PER_RAD:e} N·m/rad (softer swings freely, stiffer is rigid: \
                 0 clamps the shaft), got {}",
                super::short(self.stiffness)
            )
            .into());
        }
        Ok(())
    }

    /// Principal moments of inertia of the bulb about its centre of mass (kg·m²): a
    /// solid cylinder of radius 1 mm spanning the pivot depth and the magnet lever.
    pub fn bulb_inertia(&self) -> (f64, f64) {
        let (r, h) = (1.0e-3, self.pivot_depth + self.magnet_lever);
        let transverse = self.bulb_mass * (3.0 * r * r + h * h) / 12.0;
        let axial = self.bulb_mass * r * r / 2.0;
        (transverse, axial)
    }

    /// Offset of the bulb's centre of mass from the pivot along the shaft axis (m).
    pub fn bulb_com(&self) -> f64 {
        (self.pivot_depth - self.magnet_lever) / 2.0
    }
}
use whisker_slam::invalid::Invalid;
