//! The figures of a notched box plot, as MATLAB's `boxplot` draws them (the thesis'
//! Figs 6.6–6.10 were MATLAB's): quartiles by [`super::prctile`],
//! whiskers to the most extreme values within 1.5 IQR of the box, and the notch
//! median ± 1.57 IQR/√n (McGill, Tukey and Larsen 1978): two medians whose notches do
//! not overlap differ at roughly the 5 % level.

use super::prctile;

/// One box of a notched box plot, with the group's mean.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxStats {
    /// Number of values.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Median (the 50th percentile).
    pub median: f64,
    /// First quartile.
    pub q1: f64,
    /// Third quartile.
    pub q3: f64,
    /// Lower end of the notch: median − 1.57 IQR/√n.
    pub notch_low: f64,
    /// Upper end of the notch.
    pub notch_high: f64,
    /// Lower whisker: the smallest value ≥ q1 − 1.5 IQR.
    pub whisker_low: f64,
    /// Upper whisker: the largest value ≤ q3 + 1.5 IQR.
    pub whisker_high: f64,
    /// Values beyond the whiskers.
    pub outliers: Vec<f64>,
}

impl BoxStats {
    /// The box of `values` (NaNs ignored); `None` when no value is left.
    pub fn of(values: &[f64]) -> Option<Self> {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let (q1, median, q3) = (prctile(&v, 25.0), prctile(&v, 50.0), prctile(&v, 75.0));
        let iqr = q3 - q1;
        let half_notch = 1.57 * iqr / (n as f64).sqrt();
        let (low_fence, high_fence) = (q1 - 1.5 * iqr, q3 + 1.5 * iqr);
        let inside = || {
            v.iter()
                .copied()
                .filter(|&x| x >= low_fence && x <= high_fence)
        };
        Some(Self {
            n,
            mean: v.iter().sum::<f64>() / n as f64,
            median,
            q1,
            q3,
            notch_low: median - half_notch,
            notch_high: median + half_notch,
            whisker_low: inside().fold(f64::INFINITY, f64::min),
            whisker_high: inside().fold(f64::NEG_INFINITY, f64::max),
            outliers: v
                .iter()
                .copied()
                .filter(|&x| x < low_fence || x > high_fence)
                .collect(),
        })
    }

    /// The interquartile range.
    pub fn iqr(&self) -> f64 {
        self.q3 - self.q1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MATLAB's documented definition on 1..=10: the 25th percentile sits exactly on the
    /// 3rd value ((3 − ½)/10 = 25 %), the 75th on the 8th, the median halfway between the
    /// 5th and 6th; the notch is 5.5 ± 1.57 · 5/√10.
    #[test]
    fn quartiles_and_notch_of_one_to_ten_by_hand() {
        let v: Vec<f64> = (1..=10).map(f64::from).collect();
        let b = BoxStats::of(&v).unwrap();
        assert_eq!((b.q1, b.median, b.q3), (3.0, 5.5, 8.0));
        let half = 1.57 * 5.0 / 10f64.sqrt();
        assert!((b.notch_low - (5.5 - half)).abs() < 1e-12);
        assert!((b.notch_high - (5.5 + half)).abs() < 1e-12);
        assert_eq!((b.whisker_low, b.whisker_high), (1.0, 10.0));
        assert!(b.outliers.is_empty());
        assert_eq!(b.mean, 5.5);
    }

    /// Interpolation and the ends: for [1, 2, 4, 8] the 30th percentile is at position
    /// 0.3·4 − 0.5 = 0.7 → 1 + 0.7·1; below 12.5 % and above 87.5 % the extremes.
    #[test]
    fn prctile_interpolates_and_clamps() {
        let v = [1.0, 2.0, 4.0, 8.0];
        assert!((prctile(&v, 30.0) - 1.7).abs() < 1e-12);
        assert_eq!(prctile(&v, 10.0), 1.0);
        assert_eq!(prctile(&v, 95.0), 8.0);
        assert_eq!(prctile(&v, 50.0), 3.0);
    }

    /// An outlier beyond q3 + 1.5 IQR leaves the whisker at the largest value inside.
    #[test]
    fn outliers_lie_beyond_the_whiskers() {
        let b = BoxStats::of(&[1.0, 2.0, 3.0, 4.0, 5.0, 100.0, f64::NAN]).unwrap();
        assert_eq!(b.n, 6);
        assert_eq!(b.outliers, vec![100.0]);
        assert_eq!(b.whisker_high, 5.0);
    }
}
