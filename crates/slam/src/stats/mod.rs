//! Small statistics shared by the algorithms and the experiments: the median, the one
//! percentile definition of the project ([`prctile`]: MATLAB's, as the thesis' figures were
//! MATLAB's), the figures of notched box plots ([`boxplot`]) and rank tests between groups
//! of trials ([`rank_tests`]).

pub mod boxplot;
pub mod rank_tests;

/// The `pct`-th percentile (0–100) of `sorted` (ascending, not empty) by MATLAB's
/// `prctile`: the i-th smallest of n values sits at percentile 100 (i − ½)/n, linear in
/// between, the extremes beyond.
pub fn prctile(sorted: &[f64], pct: f64) -> f64 {
    let n = sorted.len() as f64;
    // Position (0-based, fractional) of the percentile among the order statistics.
    let pos = pct / 100.0 * n - 0.5;
    if pos <= 0.0 {
        return sorted[0];
    }
    if pos >= n - 1.0 {
        return sorted[sorted.len() - 1];
    }
    let i = pos.floor() as usize;
    let f = pos - i as f64;
    sorted[i] + f * (sorted[i + 1] - sorted[i])
}

/// The `pct`-th percentile (0–100) of a list by [`prctile`] (NaN when empty).
pub fn percentile(mut v: Vec<f64>, pct: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    prctile(&v, pct)
}

/// The median of a list (the mean of the middle two for an even count; NaN when empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_by_hand() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(vec![]).is_nan());
    }
}
