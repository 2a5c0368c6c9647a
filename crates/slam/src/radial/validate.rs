//! The consistency of a radial-distance model read from a file (Ch 4's estimators as
//! `whisker radial train` writes them): every dimension agrees with the number of input
//! features and every number is finite, so that prediction never indexes past a vector,
//! silently drops inputs (zips of unequal lengths) or returns NaN.

use super::RadialEstimator;
use super::standardise::Standardiser;

/// A problem: (the field, what is wrong and what was expected).
pub type Problem = (String, String);

fn problem(field: &str, message: String) -> Problem {
    (field.to_string(), message)
}

fn finite(field: &str, values: &[f64]) -> Result<(), Problem> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(problem(
            &format!("{field}[{k}]"),
            "expected a finite number".into(),
        )),
        None => Ok(()),
    }
}

fn length(field: &str, len: usize, expected: usize, what: &str) -> Result<(), Problem> {
    if len == expected {
        Ok(())
    } else {
        Err(problem(
            field,
            format!("{len} values, expected {expected} ({what})"),
        ))
    }
}

/// A standardiser over `m` columns: means finite, deviations finite and positive.
fn standardiser(field: &str, s: &Standardiser, m: usize, what: &str) -> Result<(), Problem> {
    length(&format!("{field}.mean"), s.mean.len(), m, what)?;
    length(&format!("{field}.std"), s.std.len(), m, what)?;
    finite(&format!("{field}.mean"), &s.mean)?;
    finite(&format!("{field}.std"), &s.std)?;
    match s.std.iter().position(|&v| v <= 0.0) {
        Some(k) => Err(problem(
            &format!("{field}.std[{k}]"),
            "expected a positive number".into(),
        )),
        None => Ok(()),
    }
}

impl RadialEstimator {
    /// Checks the model's dimensions and numbers; the problem names the field (JSON
    /// path, e.g. `model.support[3]`).
    pub fn validate(&self) -> Result<(), Problem> {
        let (features, inputs, target) = match self {
            Self::Tip | Self::Random => return Ok(()),
            Self::Polynomial { features, model } => (features, &model.inputs, &model.target),
            Self::Mlp { features, model } => (features, &model.inputs, &model.target),
            Self::Svr { features, model } => (features, &model.inputs, &model.target),
        };
        let m = features.len();
        if m == 0 || (1..m).any(|i| features[..i].contains(&features[i])) {
            return Err(problem(
                "features",
                "expected one or more distinct features".into(),
            ));
        }
        let per_feature = "one per feature";
        standardiser("model.inputs", inputs, m, per_feature)?;
        standardiser("model.target", target, 1, "the one target")?;
        match self {
            Self::Polynomial { model, .. } => {
                let n = model.terms.len();
                length(
                    "model.coefficients",
                    model.coefficients.len(),
                    n,
                    "one per term",
                )?;
                finite("model.coefficients", &model.coefficients)?;
                for (k, t) in model.terms.iter().enumerate() {
                    let field = format!("model.terms[{k}]");
                    length(&field, t.len(), m, "an exponent per feature")?;
                    if t.iter().map(|&e| e as u64).sum::<u64>() > model.degree as u64 {
                        return Err(problem(&field, format!("degree above {}", model.degree)));
                    }
                }
            }
            Self::Mlp { model, .. } => {
                let mut width = m;
                for (l, (w, b)) in model.layers.iter().enumerate() {
                    let field = format!("model.layers[{l}]");
                    let last = l + 1 == model.layers.len();
                    let rows = if last {
                        1
                    } else {
                        model.hidden.get(l).copied().unwrap_or(0)
                    };
                    length(
                        &format!("{field}.weights"),
                        w.len(),
                        rows,
                        "the layer's width",
                    )?;
                    length(
                        &format!("{field}.biases"),
                        b.len(),
                        rows,
                        "the layer's width",
                    )?;
                    finite(&format!("{field}.biases"), b)?;
                    for (r, row) in w.iter().enumerate() {
                        let f = format!("{field}.weights[{r}]");
                        length(&f, row.len(), width, "the previous layer's width")?;
                        finite(&f, row)?;
                    }
                    width = rows;
                }
                length(
                    "model.layers",
                    model.layers.len(),
                    model.hidden.len() + 1,
                    "hidden + 1",
                )?;
            }
            Self::Svr { model, .. } => {
                let n = model.support.len();
                length(
                    "model.weights",
                    model.weights.len(),
                    n,
                    "one per support vector",
                )?;
                finite("model.weights", &model.weights)?;
                finite("model.bias", &[model.bias])?;
                let gamma = model.params.gamma;
                if !(gamma.is_finite() && gamma > 0.0) {
                    return Err(problem(
                        "model.params.gamma",
                        "expected a positive number".into(),
                    ));
                }
                for (k, s) in model.support.iter().enumerate() {
                    let f = format!("model.support[{k}]");
                    length(&f, s.len(), m, per_feature)?;
                    finite(&f, s)?;
                }
            }
            Self::Tip | Self::Random => {}
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frontend::features::Feature;
    use crate::radial::mlp::{Mlp, MlpTraining};
    use crate::radial::polynomial::Polynomial;
    use crate::radial::svr::{Svr, SvrParams};

    /// Models of each kind fitted to y = x0 + 2 x1 - x2 over three features.
    fn fitted() -> Vec<RadialEstimator> {
        let x: Vec<Vec<f64>> = (0..40)
            .map(|i| {
                let t = i as f64;
                vec![t.sin(), (0.7 * t).cos(), 0.01 * t]
            })
            .collect();
        let y: Vec<f64> = x.iter().map(|r| r[0] + 2.0 * r[1] - r[2]).collect();
        let features = vec![Feature::Cp, Feature::Ca, Feature::Dv];
        let training = MlpTraining {
            epochs: 20,
            ..Default::default()
        };
        let params = SvrParams {
            c: 1.0,
            eps: 0.1,
            gamma: 0.5,
        };
        vec![
            RadialEstimator::Polynomial {
                features: features.clone(),
                model: Polynomial::fit(&x, &y, 2),
            },
            RadialEstimator::Mlp {
                features: features.clone(),
                model: Mlp::fit(&x, &y, &[4, 3], &training),
            },
            RadialEstimator::Svr {
                features,
                model: Svr::fit(&x, &y, params).unwrap(),
            },
        ]
    }

    #[test]
    fn fitted_models_are_consistent_and_every_mismatch_is_named() {
        let models = fitted();
        for m in &models {
            assert_eq!(m.validate(), Ok(()), "{m:?}");
        }
        type Edit = fn(&mut RadialEstimator);
        let field = |m: &RadialEstimator| m.validate().unwrap_err().0;
        let edits: [(usize, Edit, &str); 9] = [
            (0, |m| features(m).push(Feature::Da), "model.inputs.mean"),
            (0, |m| features(m).push(Feature::Cp), "features"),
            (0, |m| poly(m).terms[2].push(0), "model.terms[2]"),
            (
                0,
                |m| poly(m).coefficients.pop().map(drop).unwrap(),
                "model.coefficients",
            ),
            (
                1,
                |m| mlp(m).layers[1].0[2].pop().map(drop).unwrap(),
                "model.layers[1].weights[2]",
            ),
            (
                1,
                |m| mlp(m).layers.pop().map(drop).unwrap(),
                "model.layers[1].weights",
            ),
            (
                1,
                |m| mlp(m).layers[0].1[0] = f64::NAN,
                "model.layers[0].biases[0]",
            ),
            (2, |m| svr(m).support[1].push(0.0), "model.support[1]"),
            (2, |m| svr(m).weights.push(0.0), "model.weights"),
        ];
        for (k, edit, expected) in edits {
            let mut m = models[k].clone();
            edit(&mut m);
            assert_eq!(field(&m), expected, "{m:?}");
        }
    }

    fn features(m: &mut RadialEstimator) -> &mut Vec<Feature> {
        match m {
            RadialEstimator::Polynomial { features, .. }
            | RadialEstimator::Mlp { features, .. }
            | RadialEstimator::Svr { features, .. } => features,
            _ => unreachable!(),
        }
    }

    fn poly(m: &mut RadialEstimator) -> &mut Polynomial {
        let RadialEstimator::Polynomial { model, .. } = m else {
            unreachable!()
        };
        model
    }

    fn mlp(m: &mut RadialEstimator) -> &mut Mlp {
        let RadialEstimator::Mlp { model, .. } = m else {
            unreachable!()
        };
        model
    }

    fn svr(m: &mut RadialEstimator) -> &mut Svr {
        let RadialEstimator::Svr { model, .. } = m else {
            unreachable!()
        };
        model
    }
}
