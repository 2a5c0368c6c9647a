//! Odometry of a wheeled mobile base and its error model.
//!
//! The thesis measured odometry only for the arm (§3.1.2, Eq 6.4–6.11); for the "mobile
//! wheel based platform" of its conclusions this uses the standard odometry motion model
//! of a wheeled base (Thrun, Burgard & Fox, *Probabilistic Robotics*, 2005, §5.4): a
//! relative motion between two planar poses is read as a turn `rot1` towards the new
//! position, a straight drive `trans`, and a turn `rot2` to the new heading; each reading
//! gets zero-mean Gaussian noise whose standard deviation grows with the motion:
//!
//! - σ(rot1) = α₁·|rot1| + α₂·trans,
//! - σ(trans) = α₃·trans + α₄·(|rot1| + |rot2|),
//! - σ(rot2) = α₁·|rot2| + α₂·trans.
//!
//! (The book's later printings state the model with these standard deviations; its
//! first printing puts the same sums under a square root as variances.) The defaults,
//! α = (0.05 rad/rad, 0.05 rad/m, 0.05 m/m, 0.01 m/rad), are those of a typical indoor
//! differential-drive base: 5 % of each turn and of each distance, 2.9° of heading per
//! metre driven, 1 cm of distance per radian turned. They are scenario fields.

use crate::invalid::Invalid;
use crate::pose::{Pose2, wrap};
use crate::rng::StreamRng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// A relative motion as the odometry reads it: turn, drive, turn.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct BaseMotion {
    /// First turn, towards the new position (rad).
    pub rot1: f64,
    /// Distance driven (m, ≥ 0).
    pub trans: f64,
    /// Second turn, to the new heading (rad).
    pub rot2: f64,
}

/// Distances below this (m) are a turn in place: all of it is `rot2`.
const IN_PLACE_M: f64 = 1e-9;

impl BaseMotion {
    /// The motion from `a` to `b`.
    pub fn between(a: &Pose2, b: &Pose2) -> Self {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let trans = dx.hypot(dy);
        let rot1 = match trans < IN_PLACE_M {
            true => 0.0,
            false => wrap(dy.atan2(dx) - a.th),
        };
        Self {
            rot1,
            trans,
            rot2: wrap(b.th - a.th - rot1),
        }
    }

    /// Where the motion takes a base that starts at `from`.
    pub fn apply(&self, from: &Pose2) -> Pose2 {
        let heading = from.th + self.rot1;
        Pose2 {
            x: from.x + self.trans * heading.cos(),
            y: from.y + self.trans * heading.sin(),
            th: wrap(heading + self.rot2),
        }
    }
}

/// The odometry error model (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BaseOdometryNoise {
    /// Whether errors are added.
    pub enabled: bool,
    /// α₁ … α₄ (rad/rad, rad/m, m/m, m/rad).
    pub alpha: [f64; 4],
}

impl Default for BaseOdometryNoise {
    fn default() -> Self {
        Self {
            enabled: true,
            alpha: [0.05, 0.05, 0.05, 0.01],
        }
    }
}

impl BaseOdometryNoise {
    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), Invalid> {
        if self.alpha.iter().all(|a| a.is_finite() && *a >= 0.0) {
            Ok(())
        } else {
            Err(format!(
                "alpha {:?}: expected four numbers ≥ 0 (rad/rad, rad/m, m/m, m/rad)",
                self.alpha
            )
            .into())
        }
    }

    /// The standard deviations of the errors of `rot1`, `trans` and `rot2` for `m`.
    pub fn sigmas(&self, m: &BaseMotion) -> [f64; 3] {
        if !self.enabled {
            return [0.0; 3];
        }
        let [a1, a2, a3, a4] = self.alpha;
        [
            a1 * m.rot1.abs() + a2 * m.trans,
            a3 * m.trans + a4 * (m.rot1.abs() + m.rot2.abs()),
            a1 * m.rot2.abs() + a2 * m.trans,
        ]
    }

    /// The odometry's reading of the true motion `m`, errors drawn from `rng`.
    pub fn read(&self, m: &BaseMotion, rng: &mut StreamRng) -> BaseMotion {
        let [s1, st, s2] = self.sigmas(m);
        let mut noise = |sd: f64| match sd > 0.0 {
            true => Normal::new(0.0, sd).map_or(0.0, |d| d.sample(rng)),
            false => 0.0,
        };
        BaseMotion {
            rot1: m.rot1 + noise(s1),
            trans: m.trans + noise(st),
            rot2: m.rot2 + noise(s2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::substream;
    use std::f64::consts::PI;

    #[test]
    fn a_motion_between_two_poses_takes_the_first_to_the_second() {
        let poses = [
            Pose2 {
                x: 0.0,
                y: 0.0,
                th: 0.0,
            },
            Pose2 {
                x: 1.0,
                y: 2.0,
                th: 3.0,
            },
            Pose2 {
                x: -0.5,
                y: 0.3,
                th: -2.9,
            },
            Pose2 {
                x: -0.5,
                y: 0.3,
                th: 1.0,
            },
        ];
        for a in &poses {
            for b in &poses {
                let m = BaseMotion::between(a, b);
                let c = m.apply(a);
                assert!((c.x - b.x).abs() < 1e-12 && (c.y - b.y).abs() < 1e-12);
                assert!(wrap(c.th - b.th).abs() < 1e-12, "{a:?} {b:?} {c:?}");
                assert!(m.trans >= 0.0);
            }
        }
        // Driving 1 m along +y from heading 0: turn +90°, drive, turn back.
        let m = BaseMotion::between(
            &poses[0],
            &Pose2 {
                x: 0.0,
                y: 1.0,
                th: 0.0,
            },
        );
        assert!((m.rot1 - PI / 2.0).abs() < 1e-12 && (m.rot2 + PI / 2.0).abs() < 1e-12);
        // In place: the whole turn is the second one.
        let m = BaseMotion::between(&poses[2], &poses[3]);
        assert_eq!((m.rot1, m.trans), (0.0, 0.0));
    }

    #[test]
    fn errors_are_unbiased_with_the_model_standard_deviations() {
        let noise = BaseOdometryNoise::default();
        let truth = BaseMotion {
            rot1: 0.4,
            trans: 0.5,
            rot2: -0.2,
        };
        // Independently: 0.05·0.4 + 0.05·0.5, 0.05·0.5 + 0.01·0.6, 0.05·0.2 + 0.05·0.5.
        let expected = [0.045, 0.031, 0.035];
        let sigmas = noise.sigmas(&truth);
        for (s, e) in sigmas.iter().zip(expected) {
            assert!((s - e).abs() < 1e-15, "{sigmas:?}");
        }
        let mut rng = substream(1, "test/base-odometry");
        let n = 20_000;
        let draws: Vec<[f64; 3]> = (0..n)
            .map(|_| {
                let r = noise.read(&truth, &mut rng);
                [
                    r.rot1 - truth.rot1,
                    r.trans - truth.trans,
                    r.rot2 - truth.rot2,
                ]
            })
            .collect();
        for k in 0..3 {
            let mean = draws.iter().map(|d| d[k]).sum::<f64>() / n as f64;
            let sd =
                (draws.iter().map(|d| (d[k] - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
            let se = expected[k] / (n as f64).sqrt();
            assert!(mean.abs() < 4.0 * se, "{k}: mean {mean}");
            assert!((sd / expected[k] - 1.0).abs() < 0.03, "{k}: sd {sd}");
        }
        let off = BaseOdometryNoise {
            enabled: false,
            ..noise
        };
        assert_eq!(off.read(&truth, &mut rng), truth);
        // Standing still reads exactly still.
        assert_eq!(
            noise.read(&BaseMotion::default(), &mut rng),
            BaseMotion::default()
        );
        let bad = BaseOdometryNoise {
            alpha: [0.1, -0.1, 0.0, 0.0],
            ..noise
        };
        assert!(bad.validate().unwrap_err().to_string().contains("alpha"));
    }
}
