//! The odometry of the §5.2 object walks (thesis §5.2.2): the true motion between
//! consecutive whisk poses, one whisk per second, and its error model — Gaussian, 5 % of
//! the step per translation axis and 0.5° per rotation axis.

use crate::rng::substream;
use crate::sensor::Odometry;
use nalgebra::{Isometry3, Vector3};
use rand_distr::{Distribution, Normal};

/// The exact odometry of a walk through `truth`, one whisk per second (the first: no
/// motion).
pub fn clean_odometry(truth: &[Isometry3<f64>]) -> Vec<Odometry> {
    (0..truth.len())
        .map(|k| match k {
            0 => Odometry {
                dt: 1.0,
                ..Odometry::default()
            },
            _ => Odometry::between(&truth[k - 1], &truth[k], 1.0),
        })
        .collect()
}

/// The walk's odometry errors on `clean` odometry (all but the first, which is no
/// motion): Gaussian, 5 % of the step per translation axis and 0.5° per rotation axis,
/// from sub-stream `<stream>/odometry` of `seed`.
pub fn noisy_odometry(clean: &[Odometry], seed: u64, stream: &str) -> Vec<Odometry> {
    let mut rng = substream(seed, &format!("{stream}/odometry"));
    let angle = Normal::new(0.0, 0.5f64.to_radians()).expect("valid sigma");
    clean
        .iter()
        .enumerate()
        .map(|(k, &o)| {
            let mut o = o;
            if k > 0 {
                let step = Vector3::from(o.v).norm();
                let s = Normal::new(0.0, 0.05 * step.max(1e-12)).expect("valid sigma");
                for a in 0..3 {
                    o.v[a] += s.sample(&mut rng);
                    o.omega[a] += angle.sample(&mut rng);
                }
            }
            o
        })
        .collect()
}
