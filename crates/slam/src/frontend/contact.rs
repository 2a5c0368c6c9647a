//! Contact detection in one whisker's whisk cycle (thesis §5.1.1.1.1, §4.1.2.4, §3.1.1).
//!
//! 1. The angle and both deflections are smoothed by a moving average (span 100).
//! 2. The contact peak is the one `findpeaks` peak of the smoothed y deflection (minimum
//!    width 100 samples, minimum prominence 500 counts).
//! 3. Onset: back from the peak to the nearest sample where the derivative of the
//!    smoothed y changes sign; offset: forward from the peak likewise. The search starts
//!    where the smoothed y crosses half the peak's height above the baseline: a flat or
//!    rounded top (a saturated sensor, a contact held through protraction) has
//!    derivative sign changes at the peak itself.
//! 4. Confirmation: the peak must stand `confirm_counts` above the free-whisking
//!    baseline, the mean raw y of the whisk's last 100 samples.
//! 5. Refinement (added here): a centred moving average starts rising half a span (25 ms)
//!    before the signal does, so the backtracked onset is early by about that much. The
//!    onset is refined on the raw y by fitting a hinge — flat, then a straight rise —
//!    over the span around it, and taking the hinge's corner; the offset likewise with a
//!    mirrored hinge. `refine = false` keeps the thesis' backtracked samples.
//!
//! Contact angles: `max_angle`, the largest whisk angle of the cycle; `contact_angle`,
//! the angle when |dy/dt| of the smoothed y first crosses a threshold within the contact
//! (§3.1.1); and the
//! angle at the onset, which localisation uses (§5.1.1.1.2).

use super::features::{ContactFeatures, slope};
use super::peaks::{PeakParams, find_peaks};
use super::smoothing::{derivative, moving_average};
use crate::sensor::Sample;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Front-end parameters (the thesis' values by default).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrontEndParams {
    /// Moving-average span (samples).
    pub smoothing_span: usize,
    /// Peak finding on the smoothed y deflection.
    pub peaks: PeakParams,
    /// Samples at the end of the whisk taken as free whisking.
    pub baseline_samples: usize,
    /// Least height of the peak above the free-whisking mean (counts).
    pub confirm_counts: f64,
    /// |dy/dt| threshold of `contact_angle` (counts/s).
    pub contact_angle_rate: f64,
    /// Refine onset and offset on the raw signal (module documentation, step 5).
    pub refine: bool,
}

impl Default for FrontEndParams {
    fn default() -> Self {
        Self {
            smoothing_span: 100,
            peaks: PeakParams::default(),
            baseline_samples: 100,
            confirm_counts: 500.0,
            contact_angle_rate: 5000.0,
            refine: true,
        }
    }
}

/// A detected contact in one whisk cycle of one whisker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEvent {
    /// Onset sample.
    pub onset: usize,
    /// Peak sample (of the smoothed y).
    pub peak: usize,
    /// Offset sample.
    pub offset: usize,
    /// Whisk angle at onset (rad; smoothed).
    pub onset_angle: f64,
    /// `max_angle` (rad): the largest smoothed whisk angle of the cycle.
    pub max_angle: f64,
    /// `contact_angle` (rad), if |dy/dt| crossed its threshold.
    pub contact_angle: Option<f64>,
    /// Contact features.
    pub features: ContactFeatures,
    /// Surface slope: gradient of y against x from onset to peak (§5.1.1.1.3).
    pub slope: f64,
}

/// The corner of the best hinge fitted to `y` over `lo..=hi`: flat (level c) up to the
/// corner t0, then c + m·u + q·u² with u = t − t0 — or, `mirrored`, u = t0 − t (a fall
/// to the corner, then flat). The quadratic term absorbs the curvature of a contact
/// signal that follows the whisk angle, which a straight hinge would turn into a bias.
fn hinge(y: &[f64], lo: usize, hi: usize, mirrored: bool) -> usize {
    let mut best = (f64::INFINITY, lo);
    let rel = |t: usize, t0: usize| {
        if mirrored {
            t0.saturating_sub(t) as f64
        } else {
            t.saturating_sub(t0) as f64
        }
    };
    for t0 in lo..=hi {
        let mut ata = Matrix3::<f64>::zeros();
        let mut aty = Vector3::<f64>::zeros();
        for (t, &v) in y.iter().enumerate().take(hi + 1).skip(lo) {
            let u = rel(t, t0);
            let row = Vector3::new(1.0, u, u * u);
            ata += row * row.transpose();
            aty += row * v;
        }
        let Some(coef) = ata.try_inverse().map(|inv| inv * aty) else {
            continue;
        };
        let sse: f64 = (lo..=hi)
            .map(|t| {
                let u = rel(t, t0);
                (y[t] - coef[0] - coef[1] * u - coef[2] * u * u).powi(2)
            })
            .sum();
        if sse < best.0 {
            best = (sse, t0);
        }
    }
    best.1
}

/// Detects the contact of one whisk cycle of one whisker (`samples` at `rate` Hz; the
/// whisker's length `length_m` becomes the WL feature). None: no confirmed contact.
pub fn detect(
    samples: &[Sample],
    rate: f64,
    length_m: f64,
    params: &FrontEndParams,
) -> Option<ContactEvent> {
    let n = samples.len();
    if n < 3 {
        return None;
    }
    let raw_y: Vec<f64> = samples.iter().map(|s| s.y).collect();
    let raw_x: Vec<f64> = samples.iter().map(|s| s.x).collect();
    let raw_a: Vec<f64> = samples.iter().map(|s| s.angle_rad).collect();
    let span = params.smoothing_span;
    let (y, x, a) = (
        moving_average(&raw_y, span),
        moving_average(&raw_x, span),
        moving_average(&raw_a, span),
    );
    let peak = find_peaks(&y, &params.peaks).first()?.index;
    let tail = params.baseline_samples.clamp(1, n);
    let baseline = raw_y[n - tail..].iter().sum::<f64>() / tail as f64;
    if y[peak] - baseline <= params.confirm_counts {
        return None;
    }
    let dy = derivative(&y, rate);
    // Backtrack from the half-height crossings: a flat or rounded top (saturation, a
    // contact held through protraction) makes the derivative change sign at the peak.
    let half = baseline + (y[peak] - baseline) / 2.0;
    let mut onset = (0..peak).rev().find(|&i| y[i] < half).unwrap_or(0);
    while onset > 0 && dy[onset - 1] > 0.0 {
        onset -= 1;
    }
    let mut offset = (peak..n).find(|&i| y[i] < half).unwrap_or(n - 1);
    while offset + 1 < n && dy[offset + 1] < 0.0 {
        offset += 1;
    }
    if params.refine {
        let h = span / 2;
        onset = hinge(
            &raw_y,
            onset.saturating_sub(h),
            (onset + 2 * h).min(peak),
            false,
        );
        offset = hinge(
            &raw_y,
            offset.saturating_sub(2 * h).max(peak),
            (offset + h).min(n - 1),
            true,
        );
    }
    let da = derivative(&a, rate);
    // Searched over the contact only — from half a smoothing span before the onset (the
    // moving average spreads the rise that far back) to the peak — so that a fast swing
    // of free whisking elsewhere in the cycle is not taken for it.
    let from = onset.saturating_sub(params.smoothing_span / 2).min(peak);
    let contact_angle = dy[from..=peak]
        .iter()
        .position(|d| d.abs() > params.contact_angle_rate)
        .map(|i| a[from + i]);
    let features =
        ContactFeatures::measure(&y, &dy, &da, onset, peak, offset, baseline, rate, length_m);
    Some(ContactEvent {
        onset,
        peak,
        offset,
        onset_angle: a[onset],
        max_angle: a.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        contact_angle,
        features,
        slope: slope(&x[onset..=peak], &y[onset..=peak]),
    })
}
