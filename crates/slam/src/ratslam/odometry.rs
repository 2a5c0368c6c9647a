//! Planar odometry of the arm at 1.5 Hz and its measured error model (thesis §3.1.2): per
//! update, the yaw change first, then the distance travelled (the order RatSLAM
//! integrates them: rotate, then translate). The thesis measured the linear displacement
//! error to be strictly positive, Lognormal(μ −4.3, σ 0.45) (m: median 13.6 mm), and the
//! angular one Normal(8.39e-4, 0.3); the latter's unit is not stated — read as degrees
//! here (in radians, 17° of error per update would make path integration meaningless,
//! unlike the drift of Fig 3.3). Both are configurable. [`true_steps`] and [`noisy_steps`]
//! turn a path into the odometry of every update, without and with the errors.
//!
//! The linear error was measured on the thesis' own steps, which Table 3.1 fixes: path
//! integration moves one pose cell per update (§3.2.1) and a cell is 15 mm
//! (`pc_cell_x_size`), so an update travelled ~15 mm. The error is therefore scaled to
//! the distance of each update, X · d / 15 mm with X ~ Lognormal(−4.3, 0.45) m
//! ([`OdometryNoise::reference_step_m`]): on a 15 mm step it is the thesis' error, and a
//! pure turn (d = 0: the path's corners turn in place) gets none — added unscaled, each
//! 10° turn update would move the estimate ~14 mm forward. On 15 mm steps the model as
//! printed makes every distance read ~2× too long on average (E[X] = 15.0 mm): the
//! estimated loop is about twice the true one. That is what the thesis' numbers say,
//! although its Fig 3.3 calls the drift "small"; `linear_lognormal` changes it.

use crate::invalid::Invalid;
use crate::pose::{Pose2, wrap};
use crate::rng::{StreamRng, substream};
use rand_distr::{Distribution, LogNormal, Normal};
use serde::{Deserialize, Serialize};

/// The odometry error model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OdometryNoise {
    /// Whether errors are added.
    pub enabled: bool,
    /// μ and σ of the lognormal linear error (of ln metres).
    pub linear_lognormal: [f64; 2],
    /// Mean and standard deviation of the angular error (degrees).
    pub angular_normal_deg: [f64; 2],
    /// The step the linear error was measured on (m): the error added to an update of
    /// distance d is X · d / this (Table 3.1's 15 mm cell, one per update). 0 adds X to
    /// every update whatever its distance, turns included.
    pub reference_step_m: f64,
}

impl Default for OdometryNoise {
    fn default() -> Self {
        Self {
            enabled: true,
            linear_lognormal: [-4.3, 0.45],
            angular_normal_deg: [8.39e-4, 0.3],
            reference_step_m: REFERENCE_STEP_M,
        }
    }
}

/// The thesis' step per update (m): Table 3.1's `pc_cell_x_size`, one cell per update.
pub const REFERENCE_STEP_M: f64 = 0.015;

impl OdometryNoise {
    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), Invalid> {
        let [mu, s] = self.linear_lognormal;
        let [m, sd] = self.angular_normal_deg;
        if !(mu.is_finite() && s.is_finite() && s >= 0.0) {
            return Err(format!(
                "linear_lognormal {:?}: expected [μ, σ ≥ 0]",
                self.linear_lognormal
            )
            .into());
        }
        if !(m.is_finite() && sd.is_finite() && sd >= 0.0) {
            return Err(format!(
                "angular_normal_deg {:?}: expected [mean, σ ≥ 0]",
                self.angular_normal_deg
            )
            .into());
        }
        if !(self.reference_step_m.is_finite() && self.reference_step_m >= 0.0) {
            return Err(format!(
                "reference_step_m {}: expected a distance ≥ 0 (m; 0 = unscaled)",
                self.reference_step_m
            )
            .into());
        }
        Ok(())
    }

    /// The measured odometry of a true (distance m, turn rad): both with their errors
    /// added, drawn from `rng`.
    pub fn apply(&self, distance: f64, dtheta: f64, rng: &mut StreamRng) -> (f64, f64) {
        if !self.enabled {
            return (distance, dtheta);
        }
        let [mu, s] = self.linear_lognormal;
        let [m, sd] = self.angular_normal_deg;
        let linear = LogNormal::new(mu, s).map_or(0.0, |d| d.sample(rng));
        let angular = Normal::new(m, sd).map_or(m, |d| d.sample(rng));
        let scale = match self.reference_step_m > 0.0 {
            true => distance / self.reference_step_m,
            false => 1.0,
        };
        (distance + linear * scale, dtheta + angular.to_radians())
    }

    /// What the model does, in one line for the console: the errors, how they scale, and
    /// how much longer than the truth distances read on average on a `step` (m).
    pub fn describe(&self, step: f64) -> String {
        if !self.enabled {
            return "none (odometry is the true motion)".to_owned();
        }
        let [mu, s] = self.linear_lognormal;
        let [m, sd] = self.angular_normal_deg;
        let mean = (mu + s * s / 2.0).exp();
        let added = match self.reference_step_m > 0.0 {
            true => mean * step / self.reference_step_m,
            false => mean,
        };
        let scaling = match self.reference_step_m > 0.0 {
            true => format!(
                "per {:.0} mm travelled (none on a turn in place)",
                self.reference_step_m * 1e3
            ),
            false => "added to every update, turns included".to_owned(),
        };
        format!(
            "distance + Lognormal({mu}, {s}) m {scaling}: on {:.0} mm steps distances read ×{:.2} on average; heading + N({m}°, {sd}°) per update (§3.1.2)",
            step * 1e3,
            (step + added) / step
        )
    }
}

/// The true distance and turn of every update (0 at the first): the noise-free odometry.
pub fn true_steps(truth: &[Pose2]) -> Vec<(f64, f64)> {
    (0..truth.len())
        .map(|k| match k {
            0 => (0.0, 0.0),
            _ => {
                let (p, q) = (truth[k], truth[k - 1]);
                ((p.x - q.x).hypot(p.y - q.y), wrap(p.th - q.th))
            }
        })
        .collect()
}

/// `steps` with the odometry error model of §3.1.2 (sub-stream `maze-slam/odometry` of
/// `seed`).
pub fn noisy_steps(steps: &[(f64, f64)], noise: &OdometryNoise, seed: u64) -> Vec<(f64, f64)> {
    let mut rng = substream(seed, "maze-slam/odometry");
    steps
        .iter()
        .map(|&(d, t)| noise.apply(d, t, &mut rng))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_follow_the_configured_distributions() {
        let noise = OdometryNoise::default();
        let mut rng = substream(3, "test/odometry");
        let n = 20_000;
        let (mut lin, mut ang) = (Vec::new(), Vec::new());
        for _ in 0..n {
            // On the reference step the error is unscaled.
            let (d, t) = noise.apply(REFERENCE_STEP_M, 0.1, &mut rng);
            lin.push((d - REFERENCE_STEP_M).ln());
            ang.push((t - 0.1f64).to_degrees());
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let sd = |v: &[f64]| {
            let m = mean(v);
            (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
        };
        // ln(error) ~ N(−4.3, 0.45) and the angular error ~ N(8.39e-4°, 0.3°), within
        // 3 standard errors.
        let se = |s: f64| 3.0 * s / (n as f64).sqrt();
        assert!((mean(&lin) + 4.3).abs() < se(0.45));
        assert!((sd(&lin) - 0.45).abs() < se(0.45) / 2f64.sqrt());
        assert!((mean(&ang) - 8.39e-4).abs() < se(0.3));
        assert!((sd(&ang) - 0.3).abs() < se(0.3) / 2f64.sqrt());
        let off = OdometryNoise {
            enabled: false,
            ..noise
        };
        assert_eq!(off.apply(0.05, 0.1, &mut rng), (0.05, 0.1));
    }

    #[test]
    fn the_linear_error_scales_with_the_distance_and_spares_a_turn_in_place() {
        let noise = OdometryNoise::default();
        let unscaled = OdometryNoise {
            reference_step_m: 0.0,
            ..noise
        };
        // The same draws (one sub-stream each) on a 15 mm step, a 30 mm step and a turn.
        for (d, factor) in [(0.015, 1.0), (0.03, 2.0), (0.0, 0.0)] {
            let (mut a, mut b) = (substream(5, "t"), substream(5, "t"));
            for _ in 0..100 {
                let (scaled, _) = noise.apply(d, 0.1, &mut a);
                let (raw, _) = unscaled.apply(d, 0.1, &mut b);
                // Unscaled: X added whatever d; scaled: X · d / 15 mm.
                assert!(((scaled - d) - factor * (raw - d)).abs() < 1e-15, "{d}");
                assert!(raw - d > 0.0);
            }
        }
        // E[X] = exp(μ + σ²/2) = 15.0 mm: on 15 mm steps distances read ×2.00.
        assert!(
            noise.describe(0.015).contains("×2.00"),
            "{}",
            noise.describe(0.015)
        );
        assert!(noise.describe(0.015).contains("none on a turn in place"));
        assert!(
            OdometryNoise {
                reference_step_m: -1.0,
                ..noise
            }
            .validate()
            .unwrap_err()
            .to_string()
            .contains("reference_step_m")
        );
    }
}
