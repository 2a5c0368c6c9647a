//! The follicle sensor model: magnet displacement → ADC counts (thesis §2.2.2.1).
//!
//! The Hall-effect sensor's reading is linear in the magnet's displacement over its
//! range (gain in counts per metre), quantised to whole counts, clipped at the maximum
//! detectable deflection (saturation), with additive Gaussian noise drawn from the
//! whisker's own sub-stream of the scenario seed. The angle sensor reads the whisk angle
//! quantised to its resolution, with Gaussian noise.

use rand::Rng;
use rand_distr::{Distribution, Normal};
use whisker_slam::invalid::Invalid;
use whisker_slam::sensor::Sample;

/// Parameters of a module's sensors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorModel {
    /// Deflection gain (counts per metre of magnet displacement).
    pub gain_counts_per_m: f64,
    /// Maximum detectable deflection (counts); readings saturate at ±this.
    pub saturation_counts: f64,
    /// Standard deviation of the deflection noise (counts).
    pub noise_counts: f64,
    /// Angle sensor resolution (rad per count).
    pub angle_resolution_rad: f64,
    /// Standard deviation of the angle noise (rad).
    pub angle_noise_rad: f64,
}

impl Default for SensorModel {
    /// A 12-bit signed deflection channel spanning ±0.1 mm of magnet travel (2047 counts),
    /// 2 counts of noise; a 12-bit angle sensor over a full turn (0.088°) with 0.05° noise.
    fn default() -> Self {
        Self {
            gain_counts_per_m: 2047.0 / 1.0e-4,
            saturation_counts: 2047.0,
            noise_counts: 2.0,
            angle_resolution_rad: std::f64::consts::TAU / 4096.0,
            angle_noise_rad: 0.05f64.to_radians(),
        }
    }
}

impl SensorModel {
    /// Checks the parameters; names the first bad field.
    pub fn validate(&self) -> Result<(), Invalid> {
        super::require_positive(
            "",
            &[
                ("gain_counts_per_m", self.gain_counts_per_m),
                ("saturation_counts", self.saturation_counts),
                ("angle_resolution_rad", self.angle_resolution_rad),
            ],
        )?;
        for (name, v) in [
            ("noise_counts", self.noise_counts),
            ("angle_noise_rad", self.angle_noise_rad),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{name} must be a number ≥ 0, got {v}").into());
            }
        }
        Ok(())
    }

    fn deflection(&self, metres: f64, rng: &mut impl Rng) -> f64 {
        let noise = Normal::new(0.0, self.noise_counts)
            .expect("validated")
            .sample(rng);
        // `+ 0.0` turns a rounded −0 into 0.
        (metres * self.gain_counts_per_m + noise)
            .round()
            .clamp(-self.saturation_counts, self.saturation_counts)
            + 0.0
    }

    /// One reading from the true whisk angle (rad) and magnet displacement (m, x and y).
    pub fn read(&self, angle: f64, magnet: (f64, f64), rng: &mut impl Rng) -> Sample {
        let angle_noise = Normal::new(0.0, self.angle_noise_rad)
            .expect("validated")
            .sample(rng);
        let q = self.angle_resolution_rad;
        Sample {
            angle_rad: ((angle + angle_noise) / q).round() * q,
            x: self.deflection(magnet.0, rng),
            y: self.deflection(magnet.1, rng),
        }
    }

    /// Deflection in counts that a magnet displacement of `metres` would read without
    /// noise, quantisation or saturation.
    pub fn counts(&self, metres: f64) -> f64 {
        metres * self.gain_counts_per_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_slam::rng;

    #[test]
    fn readings_are_quantised_saturated_and_noisy_as_configured() {
        let m = SensorModel::default();
        let mut r = rng::substream(9, "test/sensor");
        let n = 20_000;
        let true_y = 1.234e-5;
        let ys: Vec<f64> = (0..n)
            .map(|_| m.read(1.0, (0.0, true_y), &mut r).y)
            .collect();
        assert!(ys.iter().all(|y| y.fract() == 0.0));
        let mean = ys.iter().sum::<f64>() / n as f64;
        let sd = (ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
        // Quantisation adds 1/12 count² of variance to the 4 count² of noise.
        let expected_sd = (4.0f64 + 1.0 / 12.0).sqrt();
        assert!((mean - m.counts(true_y)).abs() < 4.0 * expected_sd / (n as f64).sqrt());
        assert!((sd / expected_sd - 1.0).abs() < 0.03, "{sd}");
        let big = m.read(1.0, (1.0, -1.0), &mut r);
        assert_eq!((big.x, big.y), (m.saturation_counts, -m.saturation_counts));
        let a = m.read(1.0, (0.0, 0.0), &mut r).angle_rad;
        assert!(
            (a / m.angle_resolution_rad).fract().abs() < 1e-9
                || (a / m.angle_resolution_rad).fract().abs() > 1.0 - 1e-9
        );
        assert!((a - 1.0).abs() < 0.01);
    }
}
