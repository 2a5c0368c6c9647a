//! The detection levels of every physics path (the scripted run's front end, held whisks
//! of the closed loop, object walks and datasets, the maze's tactile images): the
//! scenario's `[frontend.detection]`, per whisker, fitted to its RCP threshold.
//!
//! With RCP (§3.2.2) a whisker retracts as soon as |y| reaches its threshold — with
//! `rcp = "noise"` 20 σ of free whisking, tens of counts — so a contact's peak stands
//! little above the threshold. The levels in counts (confirmation, peak prominence and
//! `contact_angle`'s |dy/dt| threshold) are then scaled down together so that the
//! confirmation is at most half the whisker's threshold; otherwise the default 500
//! counts are never reached and such whisks read empty (a third of the RCP
//! `contact_angle` images of the maze came out blank before this rule). Such a contact is
//! also brief — the whisker retracts as soon as it touches: 20–56 samples (10–28 ms) at
//! half the peak on `whisking_objects.toml` with `rcp = "noise"` at 1 Hz — so the span and
//! the least peak width (100 samples each by default) are cut to [`RCP_SAMPLES`]: with
//! them at 100, `whisker fidelity` found 26 % of the anticipated Box contacts at 20 σ RCP,
//! with 20, 90 % (8 poses, seed 0). With RCP at the sensor's saturation (2047 counts, the
//! radial models' training condition, §4.1.1) or without RCP the levels are the
//! scenario's as written.

use whisker_sim::sensing::physics::WhiskerConfig;
use whisker_slam::frontend::contact::FrontEndParams;

/// The longest smoothing span and least peak width (samples) under RCP with a threshold
/// below twice the confirmation: shorter than the shortest RCP contact measured (module
/// documentation).
pub const RCP_SAMPLES: usize = 20;

/// Each of `configs`' detection levels (RCP thresholds already calibrated) from the
/// scenario's `detection`.
pub fn levels(configs: &[WhiskerConfig], detection: &FrontEndParams) -> Vec<FrontEndParams> {
    configs
        .iter()
        .map(|c| {
            let mut p = *detection;
            if let (true, Some(t)) = (c.control.rcp, c.contact_threshold)
                && p.confirm_counts > 0.5 * t
            {
                let scale = 0.5 * t / p.confirm_counts;
                p.confirm_counts *= scale;
                p.peaks.min_prominence *= scale;
                p.contact_angle_rate *= scale;
                p.peaks.min_width = p.peaks.min_width.min(RCP_SAMPLES as f64);
                p.smoothing_span = p.smoothing_span.min(RCP_SAMPLES);
            }
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_sim::whisker::array;

    /// Without RCP, or with a threshold at least twice the confirmation, the levels are the
    /// scenario's; with a threshold of 60 counts the confirmation is 30 counts, the
    /// prominence and rate fall by the same factor (500 → 30: × 0.06) and the span and
    /// width to 20 samples.
    #[test]
    fn levels_fit_under_each_whiskers_rcp_threshold() {
        let d = FrontEndParams::default();
        let mut configs: Vec<WhiskerConfig> = array::modules()
            .into_iter()
            .take(3)
            .map(WhiskerConfig::with_defaults)
            .collect();
        configs[0].control.rcp = false;
        configs[0].contact_threshold = Some(60.0);
        configs[1].control.rcp = true;
        configs[1].contact_threshold = Some(2047.0);
        configs[2].control.rcp = true;
        configs[2].contact_threshold = Some(60.0);
        let l = levels(&configs, &d);
        assert_eq!((l[0], l[1]), (d, d));
        assert!((l[2].confirm_counts - 30.0).abs() < 1e-9);
        assert!((l[2].peaks.min_prominence - d.peaks.min_prominence * 0.06).abs() < 1e-9);
        assert!((l[2].contact_angle_rate - d.contact_angle_rate * 0.06).abs() < 1e-9);
        assert_eq!(l[2].peaks.min_width, 20.0);
        assert_eq!(l[2].smoothing_span, 20);
        assert_eq!(l[2].baseline_samples, d.baseline_samples);
    }
}
