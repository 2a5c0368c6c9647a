//! `whisker radial train`: the twelve regressors of thesis Table 4.1 (nn1–4, poly5–8,
//! svr9–12: CP-CA-DV-DA with and without AV and WL) trained on a training set
//! (`whisker radial generate --set training`), each saved as `<label>.json`, a serialised
//! [`RadialEstimator`] — the file scenarios load (`[frontend] radial_model`), format in
//! `scenarios/README.md`. It also prints the whitened PCA loadings of all seven features
//! (Fig 4.6).
//!
//! Hyper-parameters are chosen by 10-fold cross-validation (§4.1.3): polynomial order
//! 2–6 (one-standard-error rule); MLP hidden layers — one or two, of ⌈N_h/2⌉ or N_h units
//! with N_h = (N_in + √N_p)/L (Gnana Sheela & Deepa's bound the thesis used); SVR C, ε and
//! γ over [`Svr::default_grid`].

use super::{Label, read_set};
use rayon::prelude::*;
use serde::Serialize;
use std::fmt;
use std::path::PathBuf;
use std::time::Instant;
use whisker_scenario::files::{create_dir, write_atomic};
use whisker_scenario::{Error, Result};
use whisker_slam::frontend::features::Feature;
use whisker_slam::radial::RadialEstimator;
use whisker_slam::radial::cross_validation::{mse, r2};
use whisker_slam::radial::mlp::{Mlp, MlpTraining};
use whisker_slam::radial::pca::Pca;
use whisker_slam::radial::polynomial::Polynomial;
use whisker_slam::radial::svr::Svr;

/// What `whisker radial train` trains.
#[derive(Debug, Clone)]
pub struct TrainSettings {
    /// The training set (CSV of `whisker radial generate`).
    pub data: PathBuf,
    /// Directory the models are written to.
    pub out: PathBuf,
    /// Models to train (labels of Table 4.1) [default: all twelve].
    pub models: Vec<String>,
    /// Seed of the cross-validation folds and the MLP weights.
    pub seed: u64,
}

/// One trained model's fit on the training set.
#[derive(Debug, Clone, Serialize)]
pub struct Trained {
    pub model: String,
    pub features: String,
    pub r2_train: f64,
    pub rmse_mm: f64,
    /// The hyper-parameters cross-validation chose.
    pub chosen: String,
}

/// What `whisker radial train` did.
#[derive(Debug, Clone, Serialize)]
pub struct TrainReport {
    /// The first three principal components of the whitened features (Fig 4.6): the
    /// share of variance and the loadings on CP CA DV DA AV AA WL.
    pub pca: Vec<(f64, Vec<f64>)>,
    pub models: Vec<Trained>,
    pub contacts: usize,
    pub out: PathBuf,
    pub seconds: f64,
}

/// Folds of the cross-validation (§4.1.3).
const FOLDS: usize = 10;

fn train(label: &Label, x: &[Vec<f64>], y: &[f64], seed: u64) -> Result<(RadialEstimator, String)> {
    let features = label.features.clone();
    Ok(match label.family {
        "poly" => {
            let (model, _) = Polynomial::fit_cv(x, y, 2..=6, FOLDS, seed);
            let note = format!("order {}", model.degree);
            (RadialEstimator::Polynomial { features, model }, note)
        }
        "nn" => {
            let n_in = features.len() as f64;
            let bound = |layers: f64| ((n_in + (x.len() as f64).sqrt()) / layers).round() as usize;
            let (one, two) = (bound(1.0).max(2), bound(2.0).max(2));
            let candidates = vec![
                vec![one.div_ceil(2)],
                vec![one],
                vec![two.div_ceil(2); 2],
                vec![two; 2],
            ];
            let training = MlpTraining {
                seed,
                ..MlpTraining::default()
            };
            let (model, _) = Mlp::fit_search(x, y, &candidates, FOLDS, &training);
            let note = format!("hidden {:?}", model.hidden);
            (RadialEstimator::Mlp { features, model }, note)
        }
        _ => {
            let grid = Svr::default_grid(features.len());
            let (model, _) = Svr::fit_search(x, y, &grid, FOLDS, seed)
                .map_err(|e| Error::Failure(format!("{}: SVR training failed: {e}", label.name)))?;
            let p = model.params;
            let note = format!(
                "C {} ε {} γ {:.3}, {} support vectors",
                p.c,
                p.eps,
                p.gamma,
                model.support.len()
            );
            (RadialEstimator::Svr { features, model }, note)
        }
    })
}

/// Runs `whisker radial train`.
pub fn run(o: &TrainSettings) -> Result<TrainReport> {
    let set = read_set(&o.data)?;
    if set.len() < 2 * FOLDS {
        return Err(Error::Input(format!(
            "{}: {} contacts; training needs at least {}",
            o.data.display(),
            set.len(),
            2 * FOLDS
        )));
    }
    let labels = Label::parse_list(&o.models)?;
    create_dir(&o.out)?;
    let all = [
        Feature::Cp,
        Feature::Ca,
        Feature::Dv,
        Feature::Da,
        Feature::Av,
        Feature::Aa,
        Feature::Wl,
    ];
    let pca = Pca::fit(
        &set.iter()
            .map(|s| s.features.select(&all))
            .collect::<Vec<_>>(),
    );
    let total: f64 = pca.variances.iter().sum();
    let pca = pca
        .components
        .iter()
        .zip(&pca.variances)
        .take(3)
        .map(|(c, v)| (100.0 * v / total, c.to_vec()))
        .collect();
    let y: Vec<f64> = set.iter().map(|s| s.truth_radial_m).collect();
    let start = Instant::now();
    let trained: Vec<Result<(RadialEstimator, String)>> = labels
        .par_iter()
        .map(|label| {
            let x: Vec<Vec<f64>> = set
                .iter()
                .map(|s| s.features.select(&label.features))
                .collect();
            train(label, &x, &y, o.seed)
        })
        .collect();
    let mut rng = whisker_slam::rng::substream(o.seed, "radial/train/report");
    let mut models = Vec::new();
    for (label, t) in labels.iter().zip(trained) {
        let (model, note) = t?;
        let name = &label.name;
        let p: Vec<f64> = set
            .iter()
            .map(|s| model.estimate(&s.features, &mut rng))
            .collect();
        models.push(Trained {
            model: name.clone(),
            features: label.feature_names(),
            r2_train: r2(&p, &y),
            rmse_mm: 1000.0 * mse(&p, &y).sqrt(),
            chosen: note,
        });
        let json = serde_json::to_string_pretty(&model)
            .map_err(|e| Error::Failure(format!("{name}: {e}")))?;
        write_atomic(&o.out.join(format!("{name}.json")), json.as_bytes())?;
    }
    Ok(TrainReport {
        pca,
        models,
        contacts: set.len(),
        out: o.out.clone(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

impl fmt::Display for TrainReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "PCA of the whitened features (Fig 4.6), loadings on CP CA DV DA AV AA WL:"
        )?;
        for (k, (share, c)) in self.pca.iter().enumerate() {
            let loadings: Vec<String> = c.iter().map(|v| format!("{v:+.2}")).collect();
            writeln!(
                f,
                "  PC{} ({share:4.1} % of variance): {}",
                k + 1,
                loadings.join(" ")
            )?;
        }
        f.write_str(&whisker_scenario::console::legend(
            "PCA",
            &[("PC1…", "principal components of the whitened contact features (§2.7, Fig 4.6): CP CA = contact period and amplitude, DV DA = deflection velocity and acceleration, AV AA = angular velocity and acceleration, WL = whisker length")],
        ))?;
        writeln!(
            f,
            "{:<7} {:<20} {:>9} {:>11}  chosen",
            "model", "features", "R² train", "RMSE (mm)"
        )?;
        for m in &self.models {
            writeln!(
                f,
                "{:<7} {:<20} {:>9.4} {:>11.2}  {}",
                m.model, m.features, m.r2_train, m.rmse_mm, m.chosen
            )?;
        }
        f.write_str(&whisker_scenario::console::legend(
            "columns",
            &[
                ("model, features", "the Table 4.1 regressors and the contact features each uses"),
                ("R² train", "coefficient of determination on the training set (1 = perfect fit; judge on `radial eval`, not this)"),
                ("RMSE", "root-mean-square radial-distance error on the training set, mm"),
                ("chosen", "the hyper-parameters cross-validation picked"),
            ],
        ))?;
        writeln!(
            f,
            "{} models from {} contacts written to {} ({:.0} s)",
            self.models.len(),
            self.contacts,
            self.out.display(),
            self.seconds
        )
    }
}
