//! Polynomial regression (thesis §4.1.3, after Matlab's `polyfitn`): every monomial of the
//! standardised inputs up to a total degree, fitted by least squares; the degree is
//! chosen from 2–6 by 10-fold cross-validation (the thesis found 3) with the
//! one-standard-error rule: the lowest degree whose mean validation MSE is within one
//! standard error of the least. (The thesis takes the least mean; on noisy data a higher
//! degree then wins by noise alone — 0.09065 for 4 against 0.09085 for 3 on a cubic in
//! `tests/radial.rs`.)

use super::cross_validation::{CvScore, cv_mse, folds};
use super::standardise::Standardiser;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// A fitted polynomial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Polynomial {
    /// Total degree.
    pub degree: usize,
    /// Exponents of each monomial, one per input.
    pub terms: Vec<Vec<u32>>,
    /// Coefficient of each monomial (standardised target).
    pub coefficients: Vec<f64>,
    /// Input standardisation.
    pub inputs: Standardiser,
    /// Target standardisation.
    pub target: Standardiser,
}

/// All exponent vectors over `m` inputs of total degree ≤ `degree`.
fn monomials(m: usize, degree: usize) -> Vec<Vec<u32>> {
    let mut out = vec![vec![0u32; m]];
    for _ in 0..degree {
        let mut next = Vec::new();
        for t in &out {
            for j in 0..m {
                // Raise only at or after the last raised input: each monomial once.
                if t[j + 1..].iter().all(|&e| e == 0) {
                    let mut u = t.clone();
                    u[j] += 1;
                    next.push(u);
                }
            }
        }
        next.retain(|t| !out.contains(t));
        out.extend(next);
    }
    out.sort();
    out.dedup();
    out
}

fn row(terms: &[Vec<u32>], x: &[f64]) -> Vec<f64> {
    terms
        .iter()
        .map(|t| t.iter().zip(x).map(|(&e, v)| v.powi(e as i32)).product())
        .collect()
}

impl Polynomial {
    /// Least-squares fit of total degree `degree`.
    pub fn fit(x: &[Vec<f64>], y: &[f64], degree: usize) -> Self {
        let inputs = Standardiser::fit(x);
        let target = Standardiser::fit_column(y);
        let m = x.first().map_or(0, Vec::len);
        let terms = monomials(m, degree);
        let rows: Vec<Vec<f64>> = x.iter().map(|r| row(&terms, &inputs.apply(r))).collect();
        let a = DMatrix::from_fn(rows.len(), terms.len(), |i, j| rows[i][j]);
        let b = DVector::from_iterator(y.len(), y.iter().map(|&v| target.apply(&[v])[0]));
        let coefficients = a
            .svd(true, true)
            .solve(&b, 1e-12)
            .map(|c| c.iter().copied().collect())
            .unwrap_or_else(|_| vec![0.0; terms.len()]);
        Self {
            degree,
            terms,
            coefficients,
            inputs,
            target,
        }
    }

    /// The prediction for one input row.
    pub fn predict(&self, x: &[f64]) -> f64 {
        let r = row(&self.terms, &self.inputs.apply(x));
        let v: f64 = r.iter().zip(&self.coefficients).map(|(a, c)| a * c).sum();
        self.target.invert(0, v)
    }

    /// The degree among `degrees` chosen by `k`-fold cross-validation (seeded; the
    /// one-standard-error rule of the module documentation), then fitted to all the
    /// data; also returns each degree's score.
    pub fn fit_cv(
        x: &[Vec<f64>],
        y: &[f64],
        degrees: std::ops::RangeInclusive<usize>,
        k: usize,
        seed: u64,
    ) -> (Self, Vec<(usize, CvScore)>) {
        let f = folds(x.len(), k, seed, "radial/polynomial/folds");
        let scores: Vec<(usize, CvScore)> = degrees
            .map(|d| {
                (
                    d,
                    cv_mse(x, y, &f, |tx, ty| Self::fit(tx, ty, d), Self::predict),
                )
            })
            .collect();
        let least = scores
            .iter()
            .min_by(|a, b| a.1.mean.total_cmp(&b.1.mean))
            .map(|s| s.1);
        let best = scores
            .iter()
            .find(|s| least.is_some_and(|l| s.1.mean <= l.mean + l.se))
            .map_or(0, |s| s.0);
        (Self::fit(x, y, best), scores)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monomials_are_counted_by_the_binomial() {
        // C(m + d, d) monomials of total degree ≤ d in m variables.
        assert_eq!(monomials(1, 3).len(), 4);
        assert_eq!(monomials(2, 2).len(), 6);
        assert_eq!(monomials(5, 3).len(), 56);
    }
}
