//! Peak finding with the semantics of Matlab's `findpeaks` (thesis §5.1.1.1.1: minimum
//! width 100 samples, minimum prominence 500 counts, at most one peak per whisk).
//!
//! - A peak is a sample higher than its left neighbour and not lower than its right one,
//!   where a plateau counts once, at its first sample, if the signal falls after it.
//! - Prominence: from the peak, go left and right until the signal rises above the peak
//!   (or ends); the reference is the higher of the two minima over those spans; the
//!   prominence is the peak height minus the reference.
//! - Width: at half prominence (reference + prominence/2), between the crossings of the
//!   signal on either side within those spans, interpolated linearly (in samples).
//! - Peaks under the minimum prominence or width are dropped; of the rest, the
//!   `max_peaks` most prominent are kept, in time order.

use serde::{Deserialize, Serialize};

/// `findpeaks` parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PeakParams {
    /// Minimum width at half prominence (samples).
    pub min_width: f64,
    /// Minimum prominence (signal units; counts for deflections).
    pub min_prominence: f64,
    /// At most this many peaks (the most prominent).
    pub max_peaks: usize,
}

impl Default for PeakParams {
    fn default() -> Self {
        Self {
            min_width: 100.0,
            min_prominence: 500.0,
            max_peaks: 1,
        }
    }
}

/// One peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Sample index.
    pub index: usize,
    /// Height.
    pub height: f64,
    /// Prominence.
    pub prominence: f64,
    /// Width at half prominence (samples).
    pub width: f64,
}

/// Local maxima of `x` (plateaus at their first sample).
fn local_maxima(x: &[f64]) -> Vec<usize> {
    let mut out = Vec::new();
    let n = x.len();
    let mut i = 1;
    while i + 1 < n {
        if x[i] > x[i - 1] {
            let mut j = i;
            while j + 1 < n && x[j + 1] == x[i] {
                j += 1;
            }
            if j + 1 < n && x[j + 1] < x[i] {
                out.push(i);
            }
            i = j + 1;
        } else {
            i += 1;
        }
    }
    out
}

/// Where a line from `a` (value `ya`) to `b` (value `yb`) crosses `level`.
fn crossing(a: usize, ya: f64, b: usize, yb: f64, level: f64) -> f64 {
    if ya == yb {
        return b as f64;
    }
    a as f64 + (level - ya) / (yb - ya) * (b as f64 - a as f64)
}

/// Prominence and width of the peak at `p`.
fn measure(x: &[f64], p: usize) -> (f64, f64) {
    let h = x[p];
    let mut l = p;
    let mut left_min = h;
    while l > 0 && x[l - 1] <= h {
        l -= 1;
        left_min = left_min.min(x[l]);
    }
    let mut r = p;
    let mut right_min = h;
    while r + 1 < x.len() && x[r + 1] <= h {
        r += 1;
        right_min = right_min.min(x[r]);
    }
    let reference = left_min.max(right_min);
    let prominence = h - reference;
    let level = reference + prominence / 2.0;
    let mut a = p;
    while a > l && x[a - 1] > level {
        a -= 1;
    }
    let left = if a > l {
        crossing(a - 1, x[a - 1], a, x[a], level)
    } else {
        l as f64
    };
    let mut b = p;
    while b < r && x[b + 1] > level {
        b += 1;
    }
    let right = if b < r {
        crossing(b, x[b], b + 1, x[b + 1], level)
    } else {
        r as f64
    };
    (prominence, right - left)
}

/// The peaks of `x` that pass `params`, in time order.
pub fn find_peaks(x: &[f64], params: &PeakParams) -> Vec<Peak> {
    let mut peaks: Vec<Peak> = local_maxima(x)
        .into_iter()
        .map(|i| {
            let (prominence, width) = measure(x, i);
            Peak {
                index: i,
                height: x[i],
                prominence,
                width,
            }
        })
        .filter(|p| p.prominence >= params.min_prominence && p.width >= params.min_width)
        .collect();
    peaks.sort_by(|a, b| {
        b.prominence
            .total_cmp(&a.prominence)
            .then(a.index.cmp(&b.index))
    });
    peaks.truncate(params.max_peaks);
    peaks.sort_by_key(|p| p.index);
    peaks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prominence_and_width_by_hand() {
        // Two peaks: nothing is higher than the right one (height 5), so its spans reach
        // both ends, minima 0 and 0 → prominence 5, half level 2.5; the signal crosses 2.5
        // at 4.25 (between 2 and 4) and at 7.75 (between 4 and 2): width 3.5.
        let x = [0.0, 3.0, 2.0, 1.0, 2.0, 4.0, 5.0, 4.0, 2.0, 0.0];
        let all = PeakParams {
            min_width: 0.0,
            min_prominence: 0.0,
            max_peaks: 10,
        };
        let peaks = find_peaks(&x, &all);
        assert_eq!(peaks.len(), 2);
        let (p1, p2) = (peaks[0], peaks[1]);
        assert_eq!((p1.index, p2.index), (1, 6));
        // Left peak: minima 0 (left) and 1 (right, until x rises above 3 at index 5).
        assert_eq!(p1.prominence, 2.0);
        assert_eq!(p2.prominence, 5.0);
        assert!((p2.width - (7.75 - 4.25)).abs() < 1e-12, "{}", p2.width);
        // Only the most prominent survives max_peaks = 1; the minimum prominence filters.
        let one = PeakParams {
            max_peaks: 1,
            ..all
        };
        assert_eq!(find_peaks(&x, &one)[0].index, 6);
        let tall = PeakParams {
            min_prominence: 3.0,
            ..all
        };
        assert_eq!(find_peaks(&x, &tall).len(), 1);
        // A plateau counts once, at its first sample.
        let plateau = [0.0, 1.0, 2.0, 2.0, 2.0, 1.0];
        assert_eq!(find_peaks(&plateau, &all)[0].index, 2);
    }
}
