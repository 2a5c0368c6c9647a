//! Noise of the simulated whisker-contact features (thesis §6.1.3.1.2).
//!
//! The anticipated contact point is displaced by N(0, r_η) with r_η = 25 % of the
//! whisker's length — along the whisker ([`PointNoise::AlongWhisker`]: the thesis' contact
//! points come from Ch 4's radial-distance process, whose error lies along the shaft), or
//! in each of x, y and z ([`PointNoise::PerCoordinate`], ~√3 × as far in 3-D); the slope
//! gets N(0, s_η), s_η = 0.33; a contact is registered with probability 98 %. All are
//! configurable; the draws come from the caller's stream (one named sub-stream per
//! whisker), always in the order detection, point (one draw along the whisker, or x, y,
//! z), slope.

use nalgebra::Vector3;
use rand::RngExt;
use serde::{Deserialize, Serialize};
use whisker_slam::invalid::Invalid;
use whisker_slam::rng::gauss;

/// Which way the contact point's noise displaces it (§6.1.3.1.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PointNoise {
    /// N(0, r_η) on each of x, y and z (this project's reading until issue #35).
    PerCoordinate,
    /// N(0, r_η) along the whisker's shaft: the radial distance's error (the default).
    #[default]
    AlongWhisker,
}

/// The contact-feature noise model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactNoise {
    /// Standard deviation of each contact-point coordinate, as a fraction of the
    /// whisker's length (§6.1.3.1.2: 0.25).
    pub point_fraction: f64,
    /// Standard deviation of the slope (§6.1.3.1.2: 0.33).
    pub slope_sigma: f64,
    /// Probability that a contact is registered (§6.1.3.1.2: 0.98).
    pub detection_probability: f64,
    /// Which way the point's noise displaces it.
    pub point_model: PointNoise,
}

impl Default for ContactNoise {
    /// The thesis' values.
    fn default() -> Self {
        Self {
            point_fraction: 0.25,
            slope_sigma: 0.33,
            detection_probability: 0.98,
            point_model: PointNoise::AlongWhisker,
        }
    }
}

impl ContactNoise {
    /// No noise: every contact registered, exactly.
    pub const NONE: ContactNoise = ContactNoise {
        point_fraction: 0.0,
        slope_sigma: 0.0,
        detection_probability: 1.0,
        point_model: PointNoise::AlongWhisker,
    };

    /// Checks the values; names the first bad field.
    pub fn validate(&self) -> Result<(), Invalid> {
        // σ beyond these bounds says nothing more (a point scattered over ten whisker
        // lengths, a slope over ±100) and, near the f64 limit, drew infinite values that
        // the dataset reader then refused.
        for (name, v, max) in [
            ("point_fraction", self.point_fraction, 10.0),
            ("slope_sigma", self.slope_sigma, 100.0),
        ] {
            if !(v >= 0.0 && v <= max) {
                return Err(Invalid::field(
                    name,
                    format!(
                        "{}: expected a number from 0 to {max}",
                        whisker_slam::message::short(v)
                    ),
                ));
            }
        }
        let p = self.detection_probability;
        if !(0.0..=1.0).contains(&p) {
            return Err(Invalid::field(
                "detection_probability",
                format!("{p}: expected a probability in [0, 1]"),
            ));
        }
        Ok(())
    }

    /// Applies the model to one contact of a whisker of length `length` whose shaft runs
    /// along the unit `shaft` (in the frame of the point): None if the contact is not
    /// registered, else the noisy point's offset (added to the point) and slope.
    pub fn draw(
        &self,
        length: f64,
        shaft: &Vector3<f64>,
        slope: f64,
        rng: &mut impl rand::Rng,
    ) -> Option<([f64; 3], f64)> {
        if self.detection_probability < 1.0 && !rng.random_bool(self.detection_probability) {
            return None;
        }
        let s = self.point_fraction * length;
        let offset = match self.point_model {
            PointNoise::PerCoordinate => [gauss(s, rng), gauss(s, rng), gauss(s, rng)],
            PointNoise::AlongWhisker => (shaft * gauss(s, rng)).into(),
        };
        Some((offset, slope + gauss(self.slope_sigma, rng)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_slam::rng::substream;

    /// 20,000 draws for a 100 mm whisker: along the whisker every offset is parallel to the
    /// shaft with σ = 25 mm along it; per coordinate each of x, y, z has σ = 25 mm, so the
    /// 3-D RMS is √3 × as large. The slope's σ is 0.33 in both.
    #[test]
    fn the_point_noise_lies_along_the_shaft_or_on_each_coordinate() {
        let shaft = Vector3::new(1.0, 2.0, -2.0) / 3.0;
        let n = 20_000;
        for model in [PointNoise::AlongWhisker, PointNoise::PerCoordinate] {
            let noise = ContactNoise {
                point_model: model,
                detection_probability: 1.0,
                ..ContactNoise::default()
            };
            let mut rng = substream(7, "test/noise");
            let (mut along, mut across, mut squares, mut slope) = (0.0, 0.0, 0.0, 0.0);
            for _ in 0..n {
                let (o, s) = noise.draw(0.1, &shaft, 0.0, &mut rng).unwrap();
                let o = Vector3::from(o);
                let a = o.dot(&shaft);
                along += a * a;
                across += (o - shaft * a).norm_squared();
                squares += o.norm_squared();
                slope += s * s;
            }
            let rms = |x: f64| (x / n as f64).sqrt();
            assert!(
                (rms(slope) - 0.33).abs() < 0.01,
                "{model:?}: {}",
                rms(slope)
            );
            match model {
                PointNoise::AlongWhisker => {
                    assert!((rms(along) - 0.025).abs() < 0.0005, "{}", rms(along));
                    assert!(rms(across) < 1e-12, "{}", rms(across));
                }
                PointNoise::PerCoordinate => {
                    let expected = 0.025 * 3f64.sqrt();
                    assert!((rms(squares) - expected).abs() < 0.001, "{}", rms(squares));
                    assert!((rms(along) - 0.025).abs() < 0.0005, "{}", rms(along));
                }
            }
        }
    }
}
