//! `whisker radial eval`: the validation of thesis §4.2.1 (Figs 4.8–4.9). For every
//! trained model found in `--models` (Table 4.1 labels), the tip assumption and a uniform
//! random guess, over the validation contacts whose ground truth lies at ≤ 0.7 L (the
//! thesis' restriction against the bias towards tip contacts):
//! - the normalised radial-distance error δr = (d_m − d_gt)/L (Eq 4.1), median and
//!   standard deviation;
//! - the distance from the contact point localised with the estimate (Eq 5.1–5.2) to the
//!   nearest face of the object, median and standard deviation (mm);
//! - two-sample Kolmogorov–Smirnov p-values of each distribution against the tip's and the
//!   random guess's.

use super::{Label, feature_names, read_set};
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::shape::SharedShape;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;
use whisker_scenario::radial_model::load as load_model;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::assets::{CATALOGUE, generate};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::radial::dataset::RadialSample;
use whisker_slam::radial::kolmogorov_smirnov::two_sample;
use whisker_slam::stats::median;

/// What `whisker radial eval` validates.
#[derive(Debug, Clone)]
pub struct EvalSettings {
    /// The validation set (CSV of `whisker radial generate --set validation`).
    pub data: PathBuf,
    /// Directory of trained models (`<label>.json`, from `whisker radial train`).
    pub models: PathBuf,
    /// Seed of the random guess.
    pub seed: u64,
    /// Ground-truth limit as a fraction of the whisker length.
    pub max_fraction: f64,
}

/// One estimator's validation.
#[derive(Debug, Clone, Serialize)]
pub struct EvalRow {
    pub model: String,
    pub features: String,
    pub contacts: usize,
    pub radial_error_median: f64,
    pub radial_error_std: f64,
    pub face_distance_median_mm: f64,
    pub face_distance_std_mm: f64,
    pub radial_error_p_vs_tip: f64,
    pub radial_error_p_vs_random: f64,
    pub face_distance_p_vs_tip: f64,
    pub face_distance_p_vs_random: f64,
}

/// What `whisker radial eval` found.
#[derive(Debug, Clone, Serialize)]
pub struct EvalReport {
    pub data: PathBuf,
    pub contacts_total: usize,
    pub contacts_used: usize,
    pub max_fraction: f64,
    pub models: Vec<EvalRow>,
}

/// One estimator's distributions.
struct Scored {
    name: String,
    features: String,
    errors: Vec<f64>,
    distances_mm: Vec<f64>,
}

fn std(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt()
}

fn score(
    name: &str,
    model: &RadialEstimator,
    set: &[RadialSample],
    objects: &BTreeMap<String, SharedShape>,
    seed: u64,
) -> Scored {
    let mut rng = whisker_slam::rng::substream(seed, &format!("radial/eval/{name}"));
    let mut errors = Vec::with_capacity(set.len());
    let mut distances_mm = Vec::new();
    for s in set {
        let r = model.estimate(&s.features, &mut rng);
        errors.push((r - s.truth_radial_m) / s.features.wl);
        if let Some(shape) = objects.get(&s.object) {
            let p = s.point_at(r);
            let v = PVector::new(p.x, p.y, p.z);
            let d = (shape.project_local_point(v, false).point - v).length();
            distances_mm.push(1000.0 * d);
        }
    }
    let features = match model {
        RadialEstimator::Tip | RadialEstimator::Random => "-".into(),
        RadialEstimator::Polynomial { features, .. }
        | RadialEstimator::Mlp { features, .. }
        | RadialEstimator::Svr { features, .. } => feature_names(features),
    };
    Scored {
        name: name.into(),
        features,
        errors,
        distances_mm,
    }
}

/// Runs `whisker radial eval`.
pub fn run(o: &EvalSettings) -> Result<EvalReport> {
    if !(o.max_fraction > 0.0 && o.max_fraction <= 1.0) {
        return Err(Error::Input(format!(
            "--max-fraction: expected 0 < f ≤ 1, got {}",
            o.max_fraction
        )));
    }
    let all = read_set(&o.data)?;
    let set: Vec<RadialSample> = all
        .iter()
        .filter(|s| s.truth_radial_m <= o.max_fraction * s.features.wl)
        .cloned()
        .collect();
    if set.is_empty() {
        return Err(Error::Input(format!(
            "{}: no contact with ground truth ≤ {} L (--max-fraction): expected a larger fraction",
            o.data.display(),
            whisker_slam::message::short(o.max_fraction)
        )));
    }
    let mut objects = BTreeMap::new();
    for s in &set {
        if let Some(asset) = CATALOGUE.iter().find(|a| a.name == s.object)
            && !objects.contains_key(&s.object)
        {
            let shape = whisker_sim::environment::solids::shape(&generate(asset))
                .map_err(|e| Error::Failure(format!("{}: {e}", asset.name)))?;
            objects.insert(s.object.clone(), shape);
        }
    }
    let mut scored = vec![
        score("tip", &RadialEstimator::Tip, &set, &objects, o.seed),
        score("random", &RadialEstimator::Random, &set, &objects, o.seed),
    ];
    for label in Label::all() {
        let path = o.models.join(format!("{}.json", label.name));
        if path.exists() {
            scored.push(score(
                &label.name,
                &load_model(&path)?,
                &set,
                &objects,
                o.seed,
            ));
        }
    }
    if scored.len() == 2 {
        return Err(Error::Input(format!(
            "{}: no model files (nn1.json … svr12.json; see `whisker radial train`)",
            o.models.display()
        )));
    }
    let p = |a: &[f64], b: &[f64]| two_sample(a, b).map_or(f64::NAN, |t| t.p);
    let models = scored
        .iter()
        .map(|s| EvalRow {
            model: s.name.clone(),
            features: s.features.clone(),
            contacts: s.errors.len(),
            radial_error_median: median(s.errors.clone()),
            radial_error_std: std(&s.errors),
            face_distance_median_mm: median(s.distances_mm.clone()),
            face_distance_std_mm: std(&s.distances_mm),
            radial_error_p_vs_tip: p(&s.errors, &scored[0].errors),
            radial_error_p_vs_random: p(&s.errors, &scored[1].errors),
            face_distance_p_vs_tip: p(&s.distances_mm, &scored[0].distances_mm),
            face_distance_p_vs_random: p(&s.distances_mm, &scored[1].distances_mm),
        })
        .collect();
    Ok(EvalReport {
        data: o.data.clone(),
        contacts_total: all.len(),
        contacts_used: set.len(),
        max_fraction: o.max_fraction,
        models,
    })
}

impl fmt::Display for EvalReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}: {} of {} contacts with ground truth ≤ {} L",
            self.data.display(),
            self.contacts_used,
            self.contacts_total,
            self.max_fraction
        )?;
        writeln!(
            f,
            "{:<7} {:<20} | {:>8} {:>7} {:>9} {:>9} | {:>8} {:>7} {:>9} {:>9}",
            "model",
            "features",
            "δr med",
            "δr std",
            "p(tip)",
            "p(random)",
            "d med",
            "d std",
            "p(tip)",
            "p(random)"
        )?;
        writeln!(
            f,
            "{:<28} | {:^36} | {:^36}",
            "", "radial error (Eq 4.1)", "distance to face (mm)"
        )?;
        for r in &self.models {
            writeln!(
                f,
                "{:<7} {:<20} | {:>+8.3} {:>7.3} {:>9.2e} {:>9.2e} | {:>8.2} {:>7.2} {:>9.2e} {:>9.2e}",
                r.model,
                r.features,
                r.radial_error_median,
                r.radial_error_std,
                r.radial_error_p_vs_tip,
                r.radial_error_p_vs_random,
                r.face_distance_median_mm,
                r.face_distance_std_mm,
                r.face_distance_p_vs_tip,
                r.face_distance_p_vs_random,
            )?;
        }
        f.write_str(&whisker_scenario::console::legend(
            "columns",
            &[
                ("model", "a Table 4.1 regressor (svr = support vector regression, poly = polynomial, mlp = perceptron; the number is its feature set), tip = assume the contact at the tip, random = a uniform guess"),
                ("δr", "normalised radial error (d_estimate − d_true)/L (Eq 4.1): median and SD; 0 is perfect, tip is biased positive (Fig 4.8)"),
                ("d", "distance from the contact point placed with the estimate (Eq 5.1–5.2) to the object's nearest face, mm; lower is better (Fig 4.9)"),
                ("p(tip), p(random)", "two-sample Kolmogorov–Smirnov p-values against the tip's and the random guess's distributions; small = significantly different"),
            ],
        ))
    }
}
