//! Whisker contacts: what the front end extracts from one whisk cycle and what SLAM and
//! recognition consume (thesis §4.1.2, §5.1.1.1).
//!
//! A [`Contact`] is one whisker's first contact of a whisk cycle: when and at which whisk
//! angle it happened, how far along the shaft (radial distance), where (the contact point
//! in the array frame A at that time) and the slope of the contacted surface. The
//! physics front end estimates them from the follicle signals (Chapter 4); the kinematic
//! sensing mode ("anticipated intersect", §4.1.2.3) computes them geometrically, with
//! the noise of §6.1.3.1.2. Both fill these same types.

use nalgebra::{Isometry3, Point3};

/// One whisker's contact in one whisk cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Whisker index 0–17 (tactile-image pixel, `sensor` module).
    pub whisker: usize,
    /// Time of contact (s).
    pub time_s: f64,
    /// Whisk angle at contact (rad, from the module's base plane, 40°–140°).
    pub angle_rad: f64,
    /// Distance from the shaft's base to the contact along the shaft (m).
    pub radial_distance: f64,
    /// Contact point in the array frame A at the time of contact (m).
    pub point: Point3<f64>,
    /// Slope of the contacted surface, n_y / n_x in the whisker base frame (Eq 6.14):
    /// the ratio of the surface normal's components along the sensor's y (sweep) and x
    /// (whisk axis) directions. Unbounded: a surface whose normal lies in the sweep plane
    /// has n_x = 0.
    pub slope: f64,
}

/// The contacts of one whisk cycle of the whole array.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactCycle {
    /// Index of the whisk cycle.
    pub index: u64,
    /// Start time of the cycle (s).
    pub start_s: f64,
    /// Array pose in the world at the start of the cycle (ground truth in simulation).
    pub array_pose: Isometry3<f64>,
    /// Contacts, at most one per whisker, in whisker order.
    pub contacts: Vec<Contact>,
}
