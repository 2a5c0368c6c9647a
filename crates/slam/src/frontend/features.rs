//! Contact features of one detected contact (thesis §4.1.2.4, Fig 4.6, Table 4.1) and the
//! surface slope (§5.1.1.1.3).
//!
//! The thesis names the features but not their formulas; here, on the smoothed signals:
//! - CP, contact period: offset − onset (s);
//! - CA, contact amplitude: peak y − the free-whisking mean (counts);
//! - DV, deflection velocity: the mean dy/dt from onset to peak (counts/s);
//! - DA, deflection acceleration: the largest d²y/dt² from onset to peak (counts/s²);
//! - AV, angular velocity: dθ/dt at onset (rad/s);
//! - AA, angular acceleration: d²θ/dt² at onset (rad/s²);
//! - WL, whisker length (m).

use super::smoothing::derivative;
use serde::{Deserialize, Serialize};

/// The contact features.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct ContactFeatures {
    /// Contact period (s).
    pub cp: f64,
    /// Contact amplitude (counts).
    pub ca: f64,
    /// Deflection velocity (counts/s).
    pub dv: f64,
    /// Deflection acceleration (counts/s²).
    pub da: f64,
    /// Angular velocity at onset (rad/s).
    pub av: f64,
    /// Angular acceleration at onset (rad/s²).
    pub aa: f64,
    /// Whisker length (m).
    pub wl: f64,
}

impl ContactFeatures {
    /// Measures the features from the smoothed deflection `y`, its derivative `dy`, the
    /// smoothed angle's derivative `da`, and the contact's samples.
    #[allow(clippy::too_many_arguments)]
    pub fn measure(
        y: &[f64],
        dy: &[f64],
        da: &[f64],
        onset: usize,
        peak: usize,
        offset: usize,
        baseline: f64,
        rate: f64,
        length_m: f64,
    ) -> Self {
        let rise = (peak.saturating_sub(onset)).max(1) as f64 / rate;
        let ddy = derivative(dy, rate);
        let dda = derivative(da, rate);
        Self {
            cp: offset.saturating_sub(onset) as f64 / rate,
            ca: y[peak] - baseline,
            dv: (y[peak] - y[onset]) / rise,
            da: ddy[onset..=peak.max(onset)]
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max),
            av: da[onset],
            aa: dda[onset],
            wl: length_m,
        }
    }

    /// The features named by a Table 4.1 label's list, e.g. "CP-CA-DV-DA-AV".
    pub fn select(&self, names: &[Feature]) -> Vec<f64> {
        names
            .iter()
            .map(|f| match f {
                Feature::Cp => self.cp,
                Feature::Ca => self.ca,
                Feature::Dv => self.dv,
                Feature::Da => self.da,
                Feature::Av => self.av,
                Feature::Aa => self.aa,
                Feature::Wl => self.wl,
            })
            .collect()
    }
}

/// A contact feature's name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Feature {
    /// Contact period.
    Cp,
    /// Contact amplitude.
    Ca,
    /// Deflection velocity.
    Dv,
    /// Deflection acceleration.
    Da,
    /// Angular velocity.
    Av,
    /// Angular acceleration.
    Aa,
    /// Whisker length.
    Wl,
}

/// Surface slope (§5.1.1.1.3, after Kim & Möller 2007): the gradient of the least-squares
/// line of y against x over the initial contact period (onset to peak). ±∞ when x does
/// not vary (the deflection lies in the sweep plane, as Eq 6.14's n_y/n_x with n_x = 0).
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len()) as f64;
    if n < 2.0 {
        return f64::NAN;
    }
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (sxy, sxx) = x.iter().zip(y).fold((0.0, 0.0), |(sxy, sxx), (a, b)| {
        (sxy + (a - mx) * (b - my), sxx + (a - mx) * (a - mx))
    });
    if sxx == 0.0 {
        if sxy == 0.0 {
            f64::NAN
        } else {
            f64::INFINITY.copysign(sxy)
        }
    } else {
        sxy / sxx
    }
}
