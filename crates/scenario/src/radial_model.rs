//! The radial-distance model files (thesis Ch 4): a serialised
//! `whisker_slam::radial::RadialEstimator`, as `whisker radial train` writes them
//! (`scenarios/README.md`), and the built-in default, svr10.

use crate::error::{Error, Result};
use std::path::Path;
use whisker_slam::radial::RadialEstimator;

/// The built-in default radial-distance model: svr10 (CP-CA-DV-DA-AV), the thesis'
/// choice (§4.2.1), trained by `whisker radial train` on the physics training set.
pub const DEFAULT_MODEL: &str = include_str!("../../../assets/models/svr10.json");

/// The radial-distance model file at `path`, or the built-in svr10.
pub fn load_or_default(path: Option<&Path>) -> Result<RadialEstimator> {
    match path {
        Some(p) => load(p),
        None => serde_json::from_str(DEFAULT_MODEL)
            .map_err(|e| Error::Failure(format!("the built-in svr10 model: {e}"))),
    }
}

/// Reads a model file (a serialised [`RadialEstimator`]) and checks its dimensions and
/// numbers ([`RadialEstimator::validate`]); errors name the file, and the line and column
/// (malformed JSON) or the field.
pub fn load(path: &Path) -> Result<RadialEstimator> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Input(format!("{}: cannot read the model: {e}", path.display())))?;
    let bad = |m: String| Error::Input(format!("{}: {m}", path.display()));
    // Two steps: JSON syntax errors have a place; errors of the model's shape (read
    // through the tagged enum) have none, and say which field or variant.
    let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        bad(format!(
            "line {}, column {}: not JSON: {e}",
            e.line(),
            e.column()
        ))
    })?;
    let model: RadialEstimator = serde_json::from_value(value)
        .map_err(|e| bad(format!("not a radial-distance model: {e}")))?;
    model
        .validate()
        .map_err(|(field, m)| bad(format!("field `{field}`: {m}")))?;
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_slam::frontend::features::Feature;

    #[test]
    fn the_built_in_model_is_svr10() {
        let model = load_or_default(None).unwrap();
        let RadialEstimator::Svr { features, model } = model else {
            panic!("the default model is not an SVR");
        };
        use Feature::*;
        assert_eq!(features, [Cp, Ca, Dv, Da, Av]);
        assert!(!model.support.is_empty());
        assert!(model.support.iter().all(|s| s.len() == 5));
        let model = load_or_default(None).unwrap();
        assert_eq!(model.validate(), Ok(()));
    }
}
