//! K-fold cross-validation (thesis §4.1.3: K = 10) with a seeded shuffle.

use crate::rng::substream;
use rand::seq::SliceRandom;

/// The `k` folds of `n` samples: (training indices, validation indices) per fold; the
/// samples are shuffled by the sub-stream `stream` of `seed` and dealt round-robin.
pub fn folds(n: usize, k: usize, seed: u64, stream: &str) -> Vec<(Vec<usize>, Vec<usize>)> {
    let mut order: Vec<usize> = (0..n).collect();
    order.shuffle(&mut substream(seed, stream));
    (0..k)
        .map(|f| {
            let (mut train, mut valid) = (Vec::new(), Vec::new());
            for (j, &i) in order.iter().enumerate() {
                if j % k == f {
                    valid.push(i)
                } else {
                    train.push(i)
                }
            }
            (train, valid)
        })
        .collect()
}

/// Mean squared error of predictions.
pub fn mse(predicted: &[f64], actual: &[f64]) -> f64 {
    predicted
        .iter()
        .zip(actual)
        .map(|(p, a)| (p - a).powi(2))
        .sum::<f64>()
        / actual.len().max(1) as f64
}

/// Coefficient of determination R² of predictions.
pub fn r2(predicted: &[f64], actual: &[f64]) -> f64 {
    let mean = actual.iter().sum::<f64>() / actual.len().max(1) as f64;
    let total: f64 = actual.iter().map(|a| (a - mean).powi(2)).sum();
    1.0 - mse(predicted, actual) * actual.len() as f64 / total
}

/// Validation error of a model over the folds.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CvScore {
    /// Mean validation MSE over the folds.
    pub mean: f64,
    /// Standard error of that mean (fold-to-fold standard deviation / √k).
    pub se: f64,
}

/// Validation MSE over the folds of a model fitted by `fit` and applied by `predict`.
pub fn cv_mse<M>(
    x: &[Vec<f64>],
    y: &[f64],
    folds: &[(Vec<usize>, Vec<usize>)],
    fit: impl Fn(&[Vec<f64>], &[f64]) -> M,
    predict: impl Fn(&M, &[f64]) -> f64,
) -> CvScore {
    let pick = |idx: &[usize]| -> (Vec<Vec<f64>>, Vec<f64>) {
        (
            idx.iter().map(|&i| x[i].clone()).collect(),
            idx.iter().map(|&i| y[i]).collect(),
        )
    };
    let errors: Vec<f64> = folds
        .iter()
        .map(|(train, valid)| {
            let (tx, ty) = pick(train);
            let model = fit(&tx, &ty);
            let (vx, vy) = pick(valid);
            let p: Vec<f64> = vx.iter().map(|v| predict(&model, v)).collect();
            mse(&p, &vy)
        })
        .collect();
    let k = errors.len().max(1) as f64;
    let mean = errors.iter().sum::<f64>() / k;
    let var = errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (k - 1.0).max(1.0);
    CvScore {
        mean,
        se: (var / k).sqrt(),
    }
}
