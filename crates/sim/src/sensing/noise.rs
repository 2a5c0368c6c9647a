//! Noise of the simulated whisker-contact features (thesis §6.1.3.1.2).
//!
//! The anticipated contact point is displaced by N(0, r_η) in each of x, y and z with
//! r_η = 25 % of the whisker's length; the slope gets N(0, s_η), s_η = 0.33; a contact
//! is registered with probability 98 %. All three are configurable; the draws come from
//! the caller's stream (one named sub-stream per whisker), always in the order detection,
//! point x, y, z, slope.

use rand::RngExt;
use whisker_slam::rng::gauss;

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
}

impl Default for ContactNoise {
    /// The thesis' values.
    fn default() -> Self {
        Self {
            point_fraction: 0.25,
            slope_sigma: 0.33,
            detection_probability: 0.98,
        }
    }
}

impl ContactNoise {
    /// No noise: every contact registered, exactly.
    pub const NONE: ContactNoise = ContactNoise {
        point_fraction: 0.0,
        slope_sigma: 0.0,
        detection_probability: 1.0,
    };

    /// Checks the values; names the first bad field.
    pub fn validate(&self) -> Result<(), (String, String)> {
        // σ beyond these bounds says nothing more (a point scattered over ten whisker
        // lengths, a slope over ±100) and, near the f64 limit, drew infinite values that
        // the dataset reader then refused.
        for (name, v, max) in [
            ("point_fraction", self.point_fraction, 10.0),
            ("slope_sigma", self.slope_sigma, 100.0),
        ] {
            if !(v >= 0.0 && v <= max) {
                return Err((
                    name.into(),
                    format!(
                        "{}: expected a number from 0 to {max}",
                        whisker_slam::message::short(v)
                    ),
                ));
            }
        }
        let p = self.detection_probability;
        if !(0.0..=1.0).contains(&p) {
            return Err((
                "detection_probability".into(),
                format!("{p}: expected a probability in [0, 1]"),
            ));
        }
        Ok(())
    }

    /// Applies the model to one contact of a whisker of length `length`: None if the
    /// contact is not registered, else the noisy point offset (added to the point) and
    /// slope.
    pub fn draw(
        &self,
        length: f64,
        slope: f64,
        rng: &mut impl rand::Rng,
    ) -> Option<([f64; 3], f64)> {
        if self.detection_probability < 1.0 && !rng.random_bool(self.detection_probability) {
            return None;
        }
        let s = self.point_fraction * length;
        let offset = [gauss(s, rng), gauss(s, rng), gauss(s, rng)];
        Some((offset, slope + gauss(self.slope_sigma, rng)))
    }
}
