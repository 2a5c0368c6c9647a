//! Standardisation of features and targets (zero mean, unit standard deviation), which
//! every regressor applies first: the contact features differ by orders of magnitude.

use serde::{Deserialize, Serialize};

/// Per-column means and standard deviations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Standardiser {
    /// Column means.
    pub mean: Vec<f64>,
    /// Column standard deviations (1 where a column is constant).
    pub std: Vec<f64>,
}

impl Standardiser {
    /// Fitted to the rows of `x`.
    pub fn fit(x: &[Vec<f64>]) -> Self {
        let m = x.first().map_or(0, Vec::len);
        let n = x.len().max(1) as f64;
        let mean: Vec<f64> = (0..m)
            .map(|j| x.iter().map(|r| r[j]).sum::<f64>() / n)
            .collect();
        let std = (0..m)
            .map(|j| {
                let v = x.iter().map(|r| (r[j] - mean[j]).powi(2)).sum::<f64>() / n;
                if v > 0.0 { v.sqrt() } else { 1.0 }
            })
            .collect();
        Self { mean, std }
    }

    /// Fitted to one column of values.
    pub fn fit_column(y: &[f64]) -> Self {
        let rows: Vec<Vec<f64>> = y.iter().map(|&v| vec![v]).collect();
        Self::fit(&rows)
    }

    /// A row standardised.
    pub fn apply(&self, row: &[f64]) -> Vec<f64> {
        row.iter()
            .zip(self.mean.iter().zip(&self.std))
            .map(|(v, (m, s))| (v - m) / s)
            .collect()
    }

    /// A standardised value of column `j` back in the original units.
    pub fn invert(&self, j: usize, v: f64) -> f64 {
        v * self.std[j] + self.mean[j]
    }
}
