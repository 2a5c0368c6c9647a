//! The features of one whisk (thesis §5.1.1.1), as WhiskerRatSLAM matches them: the PFH
//! of the contact points and the SDA of the slopes.

use super::pfh::{PfhParams, histogram};
use super::sda::Sda;
use super::similarity::Features;
use crate::contact::ContactCycle;
use crate::sensor::WHISKERS;
use nalgebra::Point3;

/// |slope| beyond which SDA entries are clipped.
pub const SLOPE_CLIP: f64 = 10.0;

/// The features of one whisk (§5.1.1.1): the point feature histogram of the contact
/// `points` (array frame) and the slope distribution array of the cycle's slopes, clipped
/// to ±10 (Eq 6.14 is unbounded when the contacted normal lies in the sweep plane).
pub fn whisk_features(cycle: &ContactCycle, points: &[Point3<f64>]) -> Features {
    let mut sda = Sda::from_cycle(cycle, WHISKERS);
    for s in sda.0.iter_mut().flatten() {
        *s = s.clamp(-SLOPE_CLIP, SLOPE_CLIP);
    }
    Features {
        pfh: histogram(points, &Point3::origin(), &PfhParams::default()),
        sda,
    }
}
