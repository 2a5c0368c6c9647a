//! Support vector regression with a Gaussian (RBF) kernel (thesis §4.1.3: the best of its
//! regressors), trained by smartcore's SMO on standardised inputs and target; C, ε and γ
//! searched over a grid by k-fold cross-validation.
//!
//! A trained model keeps its support vectors, their weights and the bias, so that it can
//! be saved and applied without smartcore: f(x) = b + Σ wᵢ·exp(−γ‖x − xᵢ‖²).

use super::cross_validation::{cv_mse, folds};
use super::standardise::Standardiser;
use serde::{Deserialize, Serialize};

/// Why an SVR could not be trained.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    /// smartcore refused the data or failed to fit (its message).
    #[error("{0}")]
    Smartcore(String),
    /// smartcore's fitted model did not read back as expected.
    #[error("reading the fitted SVR: {0}")]
    Fitted(serde_json::Error),
    /// No hyper-parameters to search.
    #[error("empty grid")]
    EmptyGrid,
}
use smartcore::linalg::basic::matrix::DenseMatrix;
use smartcore::svm::Kernels;
use smartcore::svm::svr::{SVR, SVRParameters};

/// SVR hyper-parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SvrParams {
    /// Box constraint C.
    pub c: f64,
    /// Width of the ε-insensitive tube (standardised target units).
    pub eps: f64,
    /// RBF kernel coefficient γ (standardised input units).
    pub gamma: f64,
}

/// A trained SVR.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Svr {
    /// Hyper-parameters.
    pub params: SvrParams,
    /// Support vectors (standardised inputs).
    pub support: Vec<Vec<f64>>,
    /// Their weights.
    pub weights: Vec<f64>,
    /// Bias.
    pub bias: f64,
    /// Input standardisation.
    pub inputs: Standardiser,
    /// Target standardisation.
    pub target: Standardiser,
}

/// The parts of smartcore's fitted model that prediction needs (read through its serde
/// form: the fields are private).
#[derive(Deserialize)]
struct Fitted {
    instances: Option<Vec<Vec<f64>>>,
    w: Option<Vec<f64>>,
    b: f64,
}

impl Svr {
    /// Trains on rows `x` and targets `y`; Err names smartcore's complaint.
    pub fn fit(x: &[Vec<f64>], y: &[f64], params: SvrParams) -> Result<Self, TrainError> {
        let inputs = Standardiser::fit(x);
        let target = Standardiser::fit_column(y);
        let rows: Vec<Vec<f64>> = x.iter().map(|r| inputs.apply(r)).collect();
        let ys: Vec<f64> = y.iter().map(|&v| target.apply(&[v])[0]).collect();
        let matrix =
            DenseMatrix::from_2d_vec(&rows).map_err(|e| TrainError::Smartcore(e.to_string()))?;
        let p = SVRParameters::default()
            .with_c(params.c)
            .with_eps(params.eps)
            .with_kernel(Kernels::rbf().with_gamma(params.gamma));
        let model = SVR::fit(&matrix, &ys, &p).map_err(|e| TrainError::Smartcore(e.to_string()))?;
        let fitted: Fitted = serde_json::to_value(&model)
            .and_then(serde_json::from_value)
            .map_err(TrainError::Fitted)?;
        Ok(Self {
            params,
            support: fitted.instances.unwrap_or_default(),
            weights: fitted.w.unwrap_or_default(),
            bias: fitted.b,
            inputs,
            target,
        })
    }

    /// The prediction for one input row.
    pub fn predict(&self, x: &[f64]) -> f64 {
        let z = self.inputs.apply(x);
        let f = self
            .support
            .iter()
            .zip(&self.weights)
            .fold(self.bias, |f, (s, w)| {
                let d2: f64 = s.iter().zip(&z).map(|(a, b)| (a - b).powi(2)).sum();
                f + w * (-self.params.gamma * d2).exp()
            });
        self.target.invert(0, f)
    }

    /// The grid point with the least `k`-fold validation MSE, then trained on all data;
    /// also returns each grid point's CV MSE.
    pub fn fit_search(
        x: &[Vec<f64>],
        y: &[f64],
        grid: &[SvrParams],
        k: usize,
        seed: u64,
    ) -> Result<(Self, Vec<(SvrParams, f64)>), TrainError> {
        let f = folds(x.len(), k, seed, "radial/svr/folds");
        let scores: Vec<(SvrParams, f64)> = grid
            .iter()
            .map(|&p| {
                let e = cv_mse(
                    x,
                    y,
                    &f,
                    |tx, ty| Self::fit(tx, ty, p),
                    |m, v| m.as_ref().map_or(f64::INFINITY, |m| m.predict(v)),
                );
                (p, e.mean)
            })
            .collect();
        let best = scores
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|s| s.0)
            .ok_or(TrainError::EmptyGrid)?;
        Ok((Self::fit(x, y, best)?, scores))
    }

    /// A default search grid: C ∈ {1, 10, 100}, ε ∈ {0.01, 0.1}, γ ∈ {0.1, 0.5, 2} / inputs.
    pub fn default_grid(inputs: usize) -> Vec<SvrParams> {
        let mut g = Vec::new();
        for c in [1.0, 10.0, 100.0] {
            for eps in [0.01, 0.1] {
                for gamma in [0.1, 0.5, 2.0] {
                    g.push(SvrParams {
                        c,
                        eps,
                        gamma: gamma / inputs.max(1) as f64,
                    });
                }
            }
        }
        g
    }
}
