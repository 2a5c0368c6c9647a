//! Principal component analysis with whitening (thesis §4.1.2.4.1, Fig 4.6): the features
//! are standardised (unit standard deviation), then the eigenvectors of their covariance,
//! by decreasing eigenvalue, are the components; a component's loadings are its
//! coefficients on the features.

use super::standardise::Standardiser;
use nalgebra::{DMatrix, SymmetricEigen};

/// A fitted PCA.
#[derive(Debug, Clone, PartialEq)]
pub struct Pca {
    /// Eigenvalues (variance explained), decreasing.
    pub variances: Vec<f64>,
    /// Unit loading vectors, in the same order (sign: largest coefficient positive).
    pub components: Vec<Vec<f64>>,
    /// The standardisation applied first.
    pub standardiser: Standardiser,
}

impl Pca {
    /// PCA of the rows of `x`.
    pub fn fit(x: &[Vec<f64>]) -> Self {
        let standardiser = Standardiser::fit(x);
        let m = x.first().map_or(0, Vec::len);
        let n = x.len().max(1) as f64;
        let z: Vec<Vec<f64>> = x.iter().map(|r| standardiser.apply(r)).collect();
        let cov = DMatrix::from_fn(m, m, |i, j| z.iter().map(|r| r[i] * r[j]).sum::<f64>() / n);
        let eig = SymmetricEigen::new(cov);
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
        let components = order
            .iter()
            .map(|&k| {
                let v: Vec<f64> = eig.eigenvectors.column(k).iter().copied().collect();
                let big = v
                    .iter()
                    .copied()
                    .fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
                v.iter().map(|c| c * big.signum()).collect()
            })
            .collect();
        Self {
            variances: order.iter().map(|&k| eig.eigenvalues[k]).collect(),
            components,
            standardiser,
        }
    }

    /// Whitened scores of a row on the first `k` components (unit variance each).
    pub fn whiten(&self, row: &[f64], k: usize) -> Vec<f64> {
        let z = self.standardiser.apply(row);
        self.components
            .iter()
            .zip(&self.variances)
            .take(k)
            .map(|(c, v)| c.iter().zip(&z).map(|(a, b)| a * b).sum::<f64>() / v.sqrt().max(1e-300))
            .collect()
    }
}
