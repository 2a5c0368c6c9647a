//! Contact thresholds of RCP and the whisking strategies, calibrated as the thesis did
//! (§3.2.2, §4.1.1).

use super::physics::{WhiskerConfig, WhiskerUnit};
use crate::whisker::control::RcpThreshold;
use crate::whisker::strategies::WhiskingControl;
use nalgebra::Isometry3;
use rayon::prelude::*;
use whisker_slam::rng;

/// The RCP threshold (counts) of a whisker, as the thesis calibrated it: for
/// [`RcpThreshold::NoiseMultiple`]`(k)`, k × the standard deviation of the y deflection
/// about its mean over one whisk cycle of free whisking (§3.2.2: whisking in the absence
/// of any obstacle, so it holds sensor noise and the shaft's own whisking dynamics),
/// simulated in an empty world with noise from the sub-stream
/// `"calibration/whisker/NN"`; for [`RcpThreshold::Saturation`], the sensor's maximum
/// detectable deflection (§4.1.1).
///
/// The free-whisking deflection grows with the square of the whisking frequency and with
/// the whisker's length: for the 160 mm whisker at 5 Hz its σ is about 190 counts, so
/// 20 σ exceeds the default saturation (2047) and RCP by that rule never fires. Callers
/// should check the result against the sensor's saturation.
pub fn calibrate_rcp(config: &WhiskerConfig, mode: RcpThreshold, seed: u64, dt: f64) -> f64 {
    match mode {
        RcpThreshold::Saturation => config.sensor.saturation_counts,
        RcpThreshold::NoiseMultiple(k) => {
            let free = WhiskerConfig {
                contact_threshold: None,
                control: WhiskingControl::default(),
                ..config.clone()
            };
            let mut unit = WhiskerUnit::new(free, &[], &Isometry3::identity(), seed, dt);
            unit.rng = rng::substream(
                seed,
                &format!("calibration/whisker/{:02}", config.module.index),
            );
            let n = (1.0 / (config.pattern.frequency * dt)).round() as usize;
            let y: Vec<f64> = (0..n)
                .map(|_| unit.step(&Isometry3::identity()).y)
                .collect();
            let mean = y.iter().sum::<f64>() / n as f64;
            let var = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1).max(1) as f64;
            k * var.sqrt()
        }
    }
}

/// Calibrates every whisker of `configs` by [`calibrate_rcp`] (in parallel) and sets its
/// `contact_threshold`.
pub fn calibrate_array_rcp(configs: &mut [WhiskerConfig], mode: RcpThreshold, seed: u64, dt: f64) {
    let thresholds: Vec<f64> = configs
        .par_iter()
        .map(|c| calibrate_rcp(c, mode, seed, dt))
        .collect();
    for (c, t) in configs.iter_mut().zip(thresholds) {
        c.contact_threshold = Some(t);
    }
}
