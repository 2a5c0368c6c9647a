//! How faithful a map built in closed loop is (§6.1.3): each experience's map pose against
//! where the array truly was when the experience was made, and each re-localisation into the
//! run's own map against where that experience was made. Written to `summary.json`'s
//! `map_accuracy` (documented in `scenarios/README.md`).

use nalgebra::{Isometry3, Point3};
use serde_json::json;
use std::collections::HashMap;
use whisker_slam::pose;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// Errors above this count as misses (m): the closed-loop acceptance's 2 cm.
pub const TOLERANCE_M: f64 = 0.02;
/// A re-localisation is a true revisit within [`TOLERANCE_M`] and this angle (deg).
pub const REVISIT_DEG: f64 = 10.0;

/// Largest and median of a set of errors (m) and how many exceed [`TOLERANCE_M`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    pub max: f64,
    pub median: f64,
    pub over: usize,
}

impl Spread {
    fn of(errors: Vec<f64>) -> Self {
        Spread {
            max: errors.iter().cloned().fold(0.0, f64::max),
            over: errors.iter().filter(|&&e| e > TOLERANCE_M).count(),
            median: whisker_slam::stats::median(errors),
        }
    }
}

/// The map's accuracy.
#[derive(Debug, Clone, PartialEq)]
pub struct MapAccuracy {
    /// Experiences checked (those made in this run).
    pub checked: usize,
    /// Position errors with the first experience's map pose laid on its true pose: what the
    /// map says about where the array was relative to where it started.
    pub from_first: Spread,
    /// Position errors after the best rigid fit of every map position onto the true ones
    /// ([`pose::rigid_fit`]): the map's shape, whatever its placement (a map is defined only
    /// up to a rigid motion, and one misplaced first experience moves every error above).
    pub aligned: Spread,
    /// Re-localisations into an experience made earlier in this run.
    pub revisits: usize,
    /// Of those, the ones where the array truly was within [`TOLERANCE_M`] and
    /// [`REVISIT_DEG`] of where the experience was made; the rest join places touch could
    /// not tell apart (a box's faces under its symmetries) and fold the map.
    pub true_revisits: usize,
    /// Median distance (m) and angle (deg) between the two true poses of a re-localisation.
    pub revisit_median: (f64, f64),
}

/// The accuracy of `map` given the true array pose at each experience's creation
/// (`created`, in order of creation) and at each re-localisation into one of them
/// (`revisited`: the experience and the true pose then). `None` when no experience was made.
pub fn measure(
    map: &ObjectMap,
    created: &[(usize, Isometry3<f64>)],
    revisited: &[(usize, Isometry3<f64>)],
) -> Option<MapAccuracy> {
    let (first, w0) = created.first()?;
    let m0 = map.pose(*first).inverse();
    let w0 = w0.inverse();
    let from_first = Spread::of(
        created
            .iter()
            .map(|(e, w)| pose::distance(&(m0 * map.pose(*e)), &(w0 * w)).0)
            .collect(),
    );
    let mapped: Vec<Point3<f64>> = created
        .iter()
        .map(|(e, _)| Point3::from(map.pose(*e).translation.vector))
        .collect();
    let truth: Vec<Point3<f64>> = created
        .iter()
        .map(|(_, w)| Point3::from(w.translation.vector))
        .collect();
    let aligned = match pose::rigid_fit(&mapped, &truth) {
        Some(fit) => Spread::of(
            mapped
                .iter()
                .zip(&truth)
                .map(|(m, t)| (fit * m - t).norm())
                .collect(),
        ),
        // One or two experiences: laid on their true positions.
        None => from_first,
    };
    let made: HashMap<usize, &Isometry3<f64>> = created.iter().map(|(e, w)| (*e, w)).collect();
    let gaps: Vec<(f64, f64)> = revisited
        .iter()
        .filter_map(|(e, w)| made.get(e).map(|m| pose::distance(m, w)))
        .map(|(d, r)| (d, r.to_degrees()))
        .collect();
    let true_revisits = gaps
        .iter()
        .filter(|(d, r)| *d <= TOLERANCE_M && *r <= REVISIT_DEG)
        .count();
    let revisit_median = (
        whisker_slam::stats::median(gaps.iter().map(|g| g.0).collect()),
        whisker_slam::stats::median(gaps.iter().map(|g| g.1).collect()),
    );
    Some(MapAccuracy {
        checked: created.len(),
        from_first,
        aligned,
        revisits: gaps.len(),
        true_revisits,
        revisit_median,
    })
}

impl MapAccuracy {
    /// `summary.json`'s `map_accuracy`.
    pub fn json(&self) -> serde_json::Value {
        let nan_null = |v: f64| if v.is_finite() { json!(v) } else { json!(null) };
        json!({
            "experiences_checked": self.checked,
            "max_error_m": self.from_first.max,
            "median_error_m": self.from_first.median,
            "over_2cm": self.from_first.over,
            "aligned": {
                "max_error_m": self.aligned.max,
                "median_error_m": self.aligned.median,
                "over_2cm": self.aligned.over,
            },
            "revisits": {
                "count": self.revisits,
                "true": self.true_revisits,
                "median_distance_m": nan_null(self.revisit_median.0),
                "median_angle_deg": nan_null(self.revisit_median.1),
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_slam::pose::from_xyz_rpy;

    /// Poses on a ring of 0.2 m radius, facing its centre.
    fn ring(n: usize) -> Vec<Isometry3<f64>> {
        (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                from_xyz_rpy([0.2 * a.cos(), 0.2 * a.sin(), 0.1], [0.0, 0.0, a])
            })
            .collect()
    }

    fn map_of(poses: &[Isometry3<f64>]) -> ObjectMap {
        let mut m = ObjectMap::default();
        for p in poses {
            m.add(Default::default(), [0.0; 6], p, None);
        }
        m
    }

    /// A map that is the truth moved rigidly is exact after the fit, and exact from the
    /// first experience too; turning only the first experience's orientation leaves the
    /// positions, so the aligned errors stay 0, while every error from it swings.
    #[test]
    fn a_rigidly_moved_map_is_exact_and_a_turned_first_experience_is_only_its_own_error() {
        let truth = ring(12);
        let created: Vec<_> = truth.iter().cloned().enumerate().collect();
        let shift = from_xyz_rpy([1.0, -2.0, 0.5], [0.3, 0.2, -1.0]);
        let moved: Vec<_> = truth.iter().map(|p| shift * p).collect();
        let a = measure(&map_of(&moved), &created, &[]).unwrap();
        assert_eq!(a.checked, 12);
        assert!(a.from_first.max < 1e-12 && a.aligned.max < 1e-12, "{a:?}");
        assert_eq!((a.revisits, a.true_revisits), (0, 0));
        assert!(a.revisit_median.0.is_nan());
        // The first experience turned 30° about z in place: seen from it, experience k
        // (at distance d_k from it) is off by 2·d_k·sin(15°); the farthest, across the
        // ring's diameter 0.4 m, by 0.8·sin(15°) = 0.207 m.
        let mut turned = truth.clone();
        turned[0] *= from_xyz_rpy([0.0; 3], [0.0, 0.0, 30f64.to_radians()]);
        let a = measure(&map_of(&turned), &created, &[]).unwrap();
        let expected = 0.8 * 15f64.to_radians().sin();
        assert!((a.from_first.max - expected).abs() < 1e-9, "{a:?}");
        assert!(a.aligned.max < 1e-12, "positions unchanged: {a:?}");
    }

    /// One point of a ring of n = 24 off by 12 cm across the ring's plane: to first order
    /// the fit tilts and lifts the plane by the least-squares plane fit's leverage at that
    /// point, 3/n, so 0.12·(1 − 3/n) = 0.105 m is left on it and at most 0.12·3/n = 15 mm
    /// on each other point.
    #[test]
    fn one_misplaced_experience_stands_out_after_the_fit() {
        let truth = ring(24);
        let created: Vec<_> = truth.iter().cloned().enumerate().collect();
        let mut bent = truth.clone();
        bent[5].translation.vector.z += 0.12;
        let a = measure(&map_of(&bent), &created, &[]).unwrap();
        assert_eq!(a.aligned.over, 1, "{a:?}");
        assert!((a.aligned.max - 0.105).abs() < 1e-3, "{a:?}");
        assert!(a.aligned.median < 0.015, "{a:?}");
        // Seen from the first experience, only the moved one is off, by all 12 cm.
        assert!((a.from_first.max - 0.12).abs() < 1e-12 && a.from_first.median < 1e-12);
    }

    /// Revisits are scored against where the experience was made; those to experiences
    /// not made in this run (a loaded map's) are not counted.
    #[test]
    fn revisits_are_scored_against_the_experience_s_true_pose() {
        let truth = ring(8);
        let created: Vec<_> = truth.iter().cloned().enumerate().collect();
        let near = truth[2] * from_xyz_rpy([0.01, 0.0, 0.0], [0.0, 0.0, 0.05]);
        let turned = truth[3] * from_xyz_rpy([0.0; 3], [0.0, 0.0, 0.5]);
        let far = truth[6];
        let revisited = vec![(2, near), (3, turned), (1, far), (99, far)];
        let a = measure(&map_of(&truth), &created, &revisited).unwrap();
        assert_eq!((a.revisits, a.true_revisits), (3, 1));
        // The three distances: 0.01, 0 and the chord |p6 − p1| = 0.4·sin(112.5°): the median
        // is 0.01.
        assert!((a.revisit_median.0 - 0.01).abs() < 1e-12, "{a:?}");
        // Angles: 0.05 rad, 0.5 rad and 5 × 45° = 225° → 135°: the median is 0.5 rad.
        assert!(
            (a.revisit_median.1 - 0.5f64.to_degrees()).abs() < 1e-9,
            "{a:?}"
        );
    }
}
