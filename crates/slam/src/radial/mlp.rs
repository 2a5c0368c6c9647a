//! A multilayer perceptron for regression (thesis §4.1.3: at most 2 hidden layers, the
//! size searched): tanh hidden units, a linear output, standardised inputs and target,
//! weights drawn from a seeded sub-stream (Xavier-uniform), full-batch Adam on the mean
//! squared error.

use super::cross_validation::{cv_mse, folds};
use super::standardise::Standardiser;
use crate::rng::substream;
use nalgebra::{DMatrix, DVector};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Training settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MlpTraining {
    /// Adam steps (full batch).
    pub epochs: usize,
    /// Adam learning rate.
    pub learning_rate: f64,
    /// Seed of the initial weights.
    pub seed: u64,
}

impl Default for MlpTraining {
    fn default() -> Self {
        Self {
            epochs: 3000,
            learning_rate: 0.01,
            seed: 0,
        }
    }
}

/// A trained network.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mlp {
    /// Hidden layer sizes.
    pub hidden: Vec<usize>,
    /// Weight matrices (rows: outputs) and biases, input layer first.
    pub layers: Vec<(Vec<Vec<f64>>, Vec<f64>)>,
    /// Input standardisation.
    pub inputs: Standardiser,
    /// Target standardisation.
    pub target: Standardiser,
}

struct Net {
    w: Vec<DMatrix<f64>>,
    b: Vec<DVector<f64>>,
}

impl Net {
    /// Activations of every layer for a batch (columns are samples).
    fn forward(&self, x: &DMatrix<f64>) -> Vec<DMatrix<f64>> {
        let mut acts = vec![x.clone()];
        for (l, (w, b)) in self.w.iter().zip(&self.b).enumerate() {
            let mut z = w * acts.last().expect("input");
            for mut c in z.column_iter_mut() {
                c += b;
            }
            if l + 1 < self.w.len() {
                z.apply(|v| *v = v.tanh());
            }
            acts.push(z);
        }
        acts
    }
}

impl Mlp {
    /// Trains a network with `hidden` layer sizes on rows `x` and targets `y`.
    pub fn fit(x: &[Vec<f64>], y: &[f64], hidden: &[usize], training: &MlpTraining) -> Self {
        let inputs = Standardiser::fit(x);
        let target = Standardiser::fit_column(y);
        let n = x.len();
        let m = x.first().map_or(0, Vec::len);
        let xs = DMatrix::from_fn(m, n, |i, j| inputs.apply(&x[j])[i]);
        let ys = DMatrix::from_fn(1, n, |_, j| target.apply(&[y[j]])[0]);
        let mut sizes = vec![m];
        sizes.extend_from_slice(hidden);
        sizes.push(1);
        let mut rng = substream(training.seed, "radial/mlp/init");
        let mut net = Net {
            w: Vec::new(),
            b: Vec::new(),
        };
        for pair in sizes.windows(2) {
            let limit = (6.0 / (pair[0] + pair[1]) as f64).sqrt();
            net.w.push(DMatrix::from_fn(pair[1], pair[0], |_, _| {
                rng.random_range(-limit..limit)
            }));
            net.b.push(DVector::zeros(pair[1]));
        }
        let (b1, b2, eps) = (0.9f64, 0.999f64, 1e-8);
        let mut mw: Vec<DMatrix<f64>> = net.w.iter().map(|w| w * 0.0).collect();
        let mut vw = mw.clone();
        let mut mb: Vec<DVector<f64>> = net.b.iter().map(|b| b * 0.0).collect();
        let mut vb = mb.clone();
        for step in 1..=training.epochs {
            let acts = net.forward(&xs);
            // Gradient of the mean squared error, back through the layers.
            let mut delta = (acts.last().expect("output") - &ys) * (2.0 / n as f64);
            for l in (0..net.w.len()).rev() {
                let gw = &delta * acts[l].transpose();
                let gb = delta.column_sum();
                if l > 0 {
                    let mut back = net.w[l].transpose() * &delta;
                    back.zip_apply(&acts[l], |d, a| *d *= 1.0 - a * a);
                    delta = back;
                }
                let (c1, c2) = (1.0 - b1.powi(step as i32), 1.0 - b2.powi(step as i32));
                mw[l] = &mw[l] * b1 + &gw * (1.0 - b1);
                vw[l] = &vw[l] * b2 + gw.map(|g| g * g) * (1.0 - b2);
                mb[l] = &mb[l] * b1 + &gb * (1.0 - b1);
                vb[l] = &vb[l] * b2 + gb.map(|g| g * g) * (1.0 - b2);
                let lr = training.learning_rate;
                net.w[l] -= mw[l].zip_map(&vw[l], |m, v| lr * (m / c1) / ((v / c2).sqrt() + eps));
                net.b[l] -= mb[l].zip_map(&vb[l], |m, v| lr * (m / c1) / ((v / c2).sqrt() + eps));
            }
        }
        let layers = net
            .w
            .iter()
            .zip(&net.b)
            .map(|(w, b)| {
                (
                    w.row_iter().map(|r| r.iter().copied().collect()).collect(),
                    b.iter().copied().collect(),
                )
            })
            .collect();
        Self {
            hidden: hidden.to_vec(),
            layers,
            inputs,
            target,
        }
    }

    /// The prediction for one input row.
    pub fn predict(&self, x: &[f64]) -> f64 {
        let mut a = self.inputs.apply(x);
        for (l, (w, b)) in self.layers.iter().enumerate() {
            let mut z: Vec<f64> = w
                .iter()
                .zip(b)
                .map(|(row, bi)| row.iter().zip(&a).map(|(wi, ai)| wi * ai).sum::<f64>() + bi)
                .collect();
            if l + 1 < self.layers.len() {
                z.iter_mut().for_each(|v| *v = v.tanh());
            }
            a = z;
        }
        self.target.invert(0, a[0])
    }

    /// The hidden sizes among `candidates` with the least `k`-fold validation MSE, then
    /// trained on all the data; also returns each candidate's CV MSE.
    pub fn fit_search(
        x: &[Vec<f64>],
        y: &[f64],
        candidates: &[Vec<usize>],
        k: usize,
        training: &MlpTraining,
    ) -> (Self, Vec<(Vec<usize>, f64)>) {
        let f = folds(x.len(), k, training.seed, "radial/mlp/folds");
        let scores: Vec<(Vec<usize>, f64)> = candidates
            .iter()
            .map(|h| {
                let e = cv_mse(
                    x,
                    y,
                    &f,
                    |tx, ty| Self::fit(tx, ty, h, training),
                    Self::predict,
                );
                (h.clone(), e.mean)
            })
            .collect();
        let best = scores
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|s| s.0.clone())
            .unwrap_or_default();
        (Self::fit(x, y, &best, training), scores)
    }
}
