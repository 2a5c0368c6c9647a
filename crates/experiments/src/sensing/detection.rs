//! The detection levels of every physics path (the scripted run's front end, held whisks
//! of the closed loop, object walks and datasets, the maze's tactile images): the
//! scenario's `[frontend.detection]`, per whisker, its levels in counts set by
//! `[frontend] levels` and fitted to the whisker's RCP threshold.
//!
//! **From the noise** (`levels = "noise"`, the default): the thesis confirms a contact when
//! its peak stands "a set threshold" above the free-whisking mean (§5.1.1.1.1) and sets the
//! RCP threshold at 20 σ of free whisking (§3.2.2). Here the confirmation and the peak
//! prominence are k σ of each whisker's own free whisking (k =
//! [`whisker_scenario::DEFAULT_NOISE_MULTIPLE`] = 10 unless `noise_multiple` says), σ
//! measured as RCP's is (one free cycle on the sub-stream `calibration/whisker/NN` of the
//! seed), and the `contact_angle` |dy/dt| threshold keeps its written proportion to the
//! confirmation (5000 counts/s to 500 counts). At 1 Hz that is 21, 32 and 90 counts for the
//! 60, 100 and 160 mm whiskers, where `levels = "as-written"` keeps the written 500 counts
//! (250 σ of the sensor's noise): with those, `whisker fidelity` missed the contacts of a
//! compliant tip sliding off an edge (10–560 counts) and weak grazes.
//!
//! **Under RCP** (§3.2.2) a whisker retracts as soon as |y| reaches its threshold — with
//! `rcp = "noise"` 20 σ of free whisking, tens of counts — so a contact's peak stands
//! little above the threshold. The levels in counts are then scaled down together so that
//! the confirmation is at most half the whisker's threshold; otherwise written levels of
//! 500 counts are never reached and such whisks read empty (a third of the RCP
//! `contact_angle` images of the maze came out blank before this rule). Such a contact is
//! also brief — the whisker retracts as soon as it touches: 20–56 samples (10–28 ms) at
//! half the peak on `whisking_objects.toml` with `rcp = "noise"` at 1 Hz — so, with the
//! threshold below four confirmations, the span and the least peak width (100 samples
//! each by default) are cut to [`RCP_SAMPLES`]: with
//! them at 100, `whisker fidelity` found 26 % of the anticipated Box contacts at 20 σ RCP,
//! with 20, 90 % (8 poses, seed 0). With RCP at the sensor's saturation (2047 counts, the
//! radial models' training condition, §4.1.1) or without RCP the levels stand as the
//! rule sets them.

use rayon::prelude::*;
use whisker_scenario::{DetectionLevels, Scenario};
use whisker_sim::sensing::calibration::calibrate_rcp;
use whisker_sim::sensing::physics::{DT, WhiskerConfig};
use whisker_sim::whisker::control::RcpThreshold;
use whisker_slam::frontend::contact::FrontEndParams;

/// The longest smoothing span and least peak width (samples) under RCP with a threshold
/// below twice the confirmation: shorter than the shortest RCP contact measured (module
/// documentation).
pub const RCP_SAMPLES: usize = 20;

/// What a physics path detects with: `[frontend.detection]` as written, the rule that sets
/// its levels in counts (`[frontend] levels`, `noise_multiple`), and the seed whose
/// `calibration/whisker/NN` sub-streams the free-whisking σ is measured on.
#[derive(Debug, Clone, Copy)]
pub struct Detection {
    pub written: FrontEndParams,
    pub rule: DetectionLevels,
    pub seed: u64,
}

impl Detection {
    /// The scenario's.
    pub fn of_scenario(scenario: &Scenario) -> Self {
        Self {
            written: scenario.frontend.detection,
            rule: scenario.frontend.detection_levels(),
            seed: scenario.seed,
        }
    }

    /// The same, its σ measured on the sub-streams of `seed` (the maze's, which
    /// calibrates RCP on a key of its own).
    pub fn at(self, seed: u64) -> Self {
        Self { seed, ..self }
    }

    /// The defaults (levels from the noise, [`whisker_scenario::DEFAULT_NOISE_MULTIPLE`]
    /// σ) calibrated on `seed`.
    pub fn default_at(seed: u64) -> Self {
        let f = whisker_scenario::FrontEndConfig::default();
        Self {
            written: f.detection,
            rule: f.detection_levels(),
            seed,
        }
    }

    /// `written` as written (how datasets that predate the noise rule were detected).
    pub fn as_written(written: FrontEndParams) -> Self {
        Self {
            written,
            rule: DetectionLevels::AsWritten,
            seed: 0,
        }
    }

    /// Each of `configs`' detection levels (RCP thresholds already calibrated): by the
    /// rule, then fitted under RCP ([`fit_to_rcp`]).
    pub fn levels(&self, configs: &[WhiskerConfig]) -> Vec<FrontEndParams> {
        configs
            .par_iter()
            .map(|c| {
                let mut p = self.written;
                if let DetectionLevels::NoiseMultiple(k) = self.rule {
                    let sigma = calibrate_rcp(c, RcpThreshold::NoiseMultiple(1.0), self.seed, DT);
                    let scale = k * sigma / p.confirm_counts.max(f64::MIN_POSITIVE);
                    p.contact_angle_rate *= scale;
                    p.confirm_counts = k * sigma;
                    p.peaks.min_prominence = k * sigma;
                }
                fit_to_rcp(c, p)
            })
            .collect()
    }
}

/// `p` fitted to `c`'s RCP threshold t: with the confirmation above half of t the levels
/// in counts are scaled together to a confirmation of t/2; with t below four
/// confirmations (the whisker retracts soon after a contact is confirmed: the noise
/// rule's 10 σ against RCP's 20 σ, or written levels scaled down) the span and least
/// width are cut to [`RCP_SAMPLES`].
fn fit_to_rcp(c: &WhiskerConfig, mut p: FrontEndParams) -> FrontEndParams {
    if let (true, Some(t)) = (c.control.rcp, c.contact_threshold) {
        if p.confirm_counts > 0.5 * t {
            let scale = 0.5 * t / p.confirm_counts;
            p.confirm_counts *= scale;
            p.peaks.min_prominence *= scale;
            p.contact_angle_rate *= scale;
        }
        if t < 4.0 * p.confirm_counts {
            p.peaks.min_width = p.peaks.min_width.min(RCP_SAMPLES as f64);
            p.smoothing_span = p.smoothing_span.min(RCP_SAMPLES);
        }
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_sim::whisker::array;

    fn configs(n: usize) -> Vec<WhiskerConfig> {
        array::modules()
            .into_iter()
            .take(n)
            .map(WhiskerConfig::with_defaults)
            .collect()
    }

    /// As written: without RCP, or with a threshold at least twice the confirmation, the
    /// levels are the scenario's; with a threshold of 60 counts the confirmation is 30
    /// counts, the prominence and rate fall by the same factor (500 → 30: × 0.06) and the
    /// span and width to 20 samples.
    #[test]
    fn levels_fit_under_each_whiskers_rcp_threshold() {
        let d = FrontEndParams::default();
        let mut configs = configs(3);
        configs[0].control.rcp = false;
        configs[0].contact_threshold = Some(60.0);
        configs[1].control.rcp = true;
        configs[1].contact_threshold = Some(2047.0);
        configs[2].control.rcp = true;
        configs[2].contact_threshold = Some(60.0);
        let l = Detection::as_written(d).levels(&configs);
        assert_eq!((l[0], l[1]), (d, d));
        assert!((l[2].confirm_counts - 30.0).abs() < 1e-9);
        assert!((l[2].peaks.min_prominence - d.peaks.min_prominence * 0.06).abs() < 1e-9);
        assert!((l[2].contact_angle_rate - d.contact_angle_rate * 0.06).abs() < 1e-9);
        assert_eq!(l[2].peaks.min_width, 20.0);
        assert_eq!(l[2].smoothing_span, 20);
        assert_eq!(l[2].baseline_samples, d.baseline_samples);
    }

    /// From the noise: the levels are k σ of each whisker's free whisking (k = 10 gives
    /// twice k = 5's), the rate keeps its written proportion, the long whisker's levels are
    /// above the short one's (it bends more as it whisks), and under RCP at 20 σ of the same
    /// free whisking the confirmation is exactly half the threshold and the span is cut.
    #[test]
    fn noise_levels_are_k_sigma_of_free_whisking() {
        let d = FrontEndParams::default();
        let all = configs(18);
        let short_long = vec![all[0].clone(), all[17].clone()];
        let at = |k: f64, configs: &[WhiskerConfig]| {
            Detection {
                written: d,
                rule: DetectionLevels::NoiseMultiple(k),
                seed: 3,
            }
            .levels(configs)
        };
        let (ten, five) = (at(10.0, &short_long), at(5.0, &short_long));
        for (a, b) in ten.iter().zip(&five) {
            assert!((a.confirm_counts - 2.0 * b.confirm_counts).abs() < 1e-9);
            assert_eq!(a.confirm_counts, a.peaks.min_prominence);
            let rate = d.contact_angle_rate / d.confirm_counts;
            assert!((a.contact_angle_rate - rate * a.confirm_counts).abs() < 1e-6);
            assert_eq!(a.smoothing_span, d.smoothing_span);
        }
        let sigma = |c: &WhiskerConfig| calibrate_rcp(c, RcpThreshold::NoiseMultiple(1.0), 3, DT);
        assert!((ten[0].confirm_counts - 10.0 * sigma(&short_long[0])).abs() < 1e-9);
        assert!(
            ten[1].confirm_counts > 2.0 * ten[0].confirm_counts,
            "{ten:?}"
        );
        let mut rcp = short_long.clone();
        for c in &mut rcp {
            c.control.rcp = true;
            c.contact_threshold = Some(calibrate_rcp(c, RcpThreshold::NoiseMultiple(20.0), 3, DT));
        }
        for (l, c) in at(10.0, &rcp).iter().zip(&rcp) {
            let t = c.contact_threshold.unwrap();
            assert!((l.confirm_counts - 0.5 * t).abs() < 1e-9 * t);
            assert_eq!(l.smoothing_span, RCP_SAMPLES);
        }
    }
}
