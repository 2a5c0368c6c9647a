//! Planar odometry of the arm at 1.5 Hz and its measured error model (thesis §3.1.2): per
//! update, the yaw change first, then the distance travelled (the order RatSLAM
//! integrates them: rotate, then translate). The thesis measured the linear displacement
//! error to be strictly positive, Lognormal(μ −4.3, σ 0.45) (m: median 13.6 mm), and the
//! angular one Normal(8.39e-4, 0.3); the latter's unit is not stated — read as degrees
//! here (in radians, 17° of error per update would make path integration meaningless,
//! unlike the drift of Fig 3.3). Both are configurable. [`true_steps`] and [`noisy_steps`]
//! turn a path into the odometry of every update, without and with the errors.

use super::experience_map::{Pose2, wrap};
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
}

impl Default for OdometryNoise {
    fn default() -> Self {
        Self {
            enabled: true,
            linear_lognormal: [-4.3, 0.45],
            angular_normal_deg: [8.39e-4, 0.3],
        }
    }
}

impl OdometryNoise {
    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        let [mu, s] = self.linear_lognormal;
        let [m, sd] = self.angular_normal_deg;
        if !(mu.is_finite() && s.is_finite() && s >= 0.0) {
            return Err(format!(
                "linear_lognormal {:?}: expected [μ, σ ≥ 0]",
                self.linear_lognormal
            ));
        }
        if !(m.is_finite() && sd.is_finite() && sd >= 0.0) {
            return Err(format!(
                "angular_normal_deg {:?}: expected [mean, σ ≥ 0]",
                self.angular_normal_deg
            ));
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
        (distance + linear, dtheta + angular.to_radians())
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
            let (d, t) = noise.apply(0.05, 0.1, &mut rng);
            lin.push((d - 0.05f64).ln());
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
}
