//! Radial distance to contact (thesis Chapter 4): estimators behind one interface — the
//! tip assumption, a uniform random guess, polynomial regression, a multilayer
//! perceptron and RBF support vector regression — over the contact features of
//! Table 4.1, with PCA, cross-validation and standardisation.

pub mod cross_validation;
pub mod dataset;
pub mod kolmogorov_smirnov;
pub mod mlp;
pub mod pca;
pub mod polynomial;
pub mod standardise;
pub mod svr;
pub mod validate;

use crate::frontend::features::{ContactFeatures, Feature};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// A radial-distance estimator (m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RadialEstimator {
    /// The contact is at the tip: r = whisker length.
    Tip,
    /// Uniform on [0, whisker length] (a baseline).
    Random,
    /// Polynomial regression on `features`.
    Polynomial {
        /// Inputs, in order.
        features: Vec<Feature>,
        /// The model.
        model: polynomial::Polynomial,
    },
    /// Multilayer perceptron on `features`.
    Mlp {
        /// Inputs, in order.
        features: Vec<Feature>,
        /// The model.
        model: mlp::Mlp,
    },
    /// RBF support vector regression on `features`.
    Svr {
        /// Inputs, in order.
        features: Vec<Feature>,
        /// The model.
        model: svr::Svr,
    },
}

impl RadialEstimator {
    /// The radial distance of a contact (m), clamped to [0, whisker length]; `rng` is
    /// drawn from only by [`RadialEstimator::Random`].
    pub fn estimate(&self, f: &ContactFeatures, rng: &mut impl rand::Rng) -> f64 {
        let r = match self {
            Self::Tip => f.wl,
            Self::Random => rng.random_range(0.0..=f.wl.max(0.0)),
            Self::Polynomial { features, model } => model.predict(&f.select(features)),
            Self::Mlp { features, model } => model.predict(&f.select(features)),
            Self::Svr { features, model } => model.predict(&f.select(features)),
        };
        r.clamp(0.0, f.wl.max(0.0))
    }
}

/// The feature sets of Table 4.1: with and without AV and WL.
pub fn table_4_1_features(label: usize) -> Vec<Feature> {
    use Feature::*;
    let mut f = vec![Cp, Ca, Dv, Da];
    let (av, wl) = match (label - 1) % 4 {
        0 => (true, true),
        1 => (true, false),
        2 => (false, true),
        _ => (false, false),
    };
    if av {
        f.push(Av);
    }
    if wl {
        f.push(Wl);
    }
    f
}
