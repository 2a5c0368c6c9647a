//! Similarity of observations (thesis §5.1.1.1.4): χ² divergence of point feature
//! histograms (Eq 2.45), normalised mean square error of slope distribution arrays
//! (Eq 5.3–5.4), and the matching rule (Eq 5.5 and the thresholds that follow it).

use super::sda::Sda;
use serde::{Deserialize, Serialize};

/// χ²(q, v) = Σ (qᵢ − vᵢ)² / (qᵢ + vᵢ) (Eq 2.45), bins empty in both skipped.
pub fn chi2(q: &[f64], v: &[f64]) -> f64 {
    assert_eq!(q.len(), v.len(), "histograms of different sizes");
    q.iter()
        .zip(v)
        .filter(|(a, b)| *a + *b > 0.0)
        .map(|(a, b)| (a - b).powi(2) / (a + b))
        .sum()
}

/// MSE(x, y) = ‖x − y‖² / n (Eq 5.4).
pub fn mse(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len(), "arrays of different sizes");
    x.iter().zip(y).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / x.len().max(1) as f64
}

/// NMSE(x, y) = MSE(x, y) / MSE(x, 0) (Eq 5.3). When x is all zero: 0 if y is too,
/// otherwise +∞ (no scale to normalise by).
pub fn nmse(x: &[f64], y: &[f64]) -> f64 {
    let e = mse(x, y);
    let scale = mse(x, &vec![0.0; x.len()]);
    if scale > 0.0 {
        e / scale
    } else if e == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Which features identify a surface region (Table 5.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FeatureSet {
    /// Point feature histogram only.
    Pfh,
    /// Slope distribution array only.
    Sda,
    /// Both (the thesis' best).
    #[default]
    Both,
}

/// The matching rule: a stored region is a candidate when its χ² is under `t_pfh` and its
/// NMSE under `t_sda` (only the measures the feature set uses); the best candidate has the
/// smallest sum of the two (Eq 5.5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Matching {
    /// Features used.
    pub features: FeatureSet,
    /// χ² threshold T_pfh.
    pub t_pfh: f64,
    /// NMSE threshold T_sda.
    pub t_sda: f64,
}

impl Default for Matching {
    fn default() -> Self {
        Self {
            features: FeatureSet::Both,
            t_pfh: 0.5,
            t_sda: 0.5,
        }
    }
}

/// The features of one observation (one whisk).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Features {
    /// Point feature histogram.
    pub pfh: Vec<f64>,
    /// Slope distribution array.
    pub sda: Sda,
}

impl Matching {
    /// The score of `stored` against the observation `seen` (smaller is more similar), or
    /// None when a threshold rejects it.
    pub fn score(&self, seen: &Features, stored: &Features) -> Option<f64> {
        let use_pfh = self.features != FeatureSet::Sda;
        let use_sda = self.features != FeatureSet::Pfh;
        let mut sum = 0.0;
        if use_pfh {
            let c = chi2(&seen.pfh, &stored.pfh);
            if c >= self.t_pfh {
                return None;
            }
            sum += c;
        }
        if use_sda {
            let e = nmse(&seen.sda.filled(), &stored.sda.filled());
            if e >= self.t_sda {
                return None;
            }
            sum += e;
        }
        Some(sum)
    }

    /// The index and score of the best match of `seen` among `stored` (first on ties).
    pub fn best<'a>(
        &self,
        seen: &Features,
        stored: impl IntoIterator<Item = &'a Features>,
    ) -> Option<(usize, f64)> {
        stored
            .into_iter()
            .enumerate()
            .filter_map(|(i, f)| self.score(seen, f).map(|s| (i, s)))
            .fold(None, |best: Option<(usize, f64)>, (i, s)| match best {
                Some((_, b)) if b <= s => best,
                _ => Some((i, s)),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi2_by_hand() {
        // (0.5−0.25)²/0.75 + (0.5−0.25)²/0.75 + (0−0.5)²/0.5, the empty bin skipped.
        let q = [0.5, 0.5, 0.0, 0.0];
        let v = [0.25, 0.25, 0.5, 0.0];
        let expected = 0.0625 / 0.75 * 2.0 + 0.25 / 0.5;
        assert!((chi2(&q, &v) - expected).abs() < 1e-15);
        assert_eq!(chi2(&q, &q), 0.0);
        assert!((chi2(&q, &v) - chi2(&v, &q)).abs() < 1e-15);
    }

    #[test]
    fn nmse_by_hand() {
        // MSE(x, y) = (1 + 0 + 4) / 3; MSE(x, 0) = (1 + 4 + 9) / 3.
        let x = [1.0, 2.0, 3.0];
        let y = [2.0, 2.0, 1.0];
        assert!((nmse(&x, &y) - 5.0 / 14.0).abs() < 1e-15);
        assert_eq!(nmse(&x, &x), 0.0);
        assert_eq!(nmse(&[0.0; 3], &[0.0; 3]), 0.0);
        assert_eq!(nmse(&[0.0; 3], &x), f64::INFINITY);
    }

    #[test]
    fn matching_keeps_candidates_under_both_thresholds_and_picks_the_smallest_sum() {
        let f = |pfh: [f64; 2], sda: [f64; 2]| Features {
            pfh: pfh.to_vec(),
            sda: Sda(sda.iter().map(|&s| Some(s)).collect()),
        };
        let seen = f([1.0, 0.0], [1.0, 1.0]);
        let stored = [
            f([0.0, 1.0], [1.0, 1.0]), // χ² 2: rejected by T_pfh
            f([0.8, 0.2], [1.0, 0.0]), // χ² 0.04/1.8 + 0.04/0.2 = 0.222, NMSE 0.5: rejected by T_sda
            f([0.6, 0.4], [1.0, 1.2]), // χ² 0.16/1.6 + 0.16/0.4 = 0.5, NMSE 0.02: sum 0.52
            f([0.9, 0.1], [1.2, 1.2]), // χ² 0.01/1.9 + 0.01/0.1 = 0.10526, NMSE 0.04: sum 0.14526
        ];
        let m = Matching {
            features: FeatureSet::Both,
            t_pfh: 1.0,
            t_sda: 0.3,
        };
        let (i, s) = m.best(&seen, &stored).unwrap();
        assert_eq!(i, 3);
        assert!((s - (0.01 / 1.9 + 0.1 + 0.04)).abs() < 1e-12);
        // PFH alone: entry 1 is a candidate again (χ² 0.222), but 3 is closer (0.105).
        let pfh = Matching {
            features: FeatureSet::Pfh,
            ..m
        };
        assert_eq!(pfh.best(&seen, &stored).unwrap().0, 3);
        // SDA alone: entry 0 matches exactly.
        let sda = Matching {
            features: FeatureSet::Sda,
            ..m
        };
        assert_eq!(sda.best(&seen, &stored), Some((0, 0.0)));
        let strict = Matching { t_pfh: 0.1, ..m };
        assert_eq!(strict.best(&seen, &stored), None);
    }
}
