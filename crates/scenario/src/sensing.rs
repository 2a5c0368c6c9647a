//! How a scenario senses: `sensing = "none" | "physics" | "kinematic"`, the `--sensing`
//! choice of the commands that need contacts, and `[frontend]`, the signal front end of
//! physics sensing (thesis Ch 4).

use crate::error::{Error, Result};
use crate::paths::relative_to;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// `[frontend]`: the signal front end of `sensing = "physics"` (thesis Ch 4).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrontEndConfig {
    /// Radial-distance model (a `whisker radial train` output), relative to the scenario
    /// file; default: the built-in svr10.
    pub radial_model: Option<PathBuf>,
    /// `[frontend.detection]`: contact-detection parameters (thesis defaults).
    #[serde(default)]
    pub detection: whisker_slam::frontend::contact::FrontEndParams,
}

impl FrontEndConfig {
    /// Checks the detection parameters; names the offending field.
    pub fn validate(&self, file: &Path) -> Result {
        let d = &self.detection;
        let p = &d.peaks;
        let checks: [(&str, bool); 7] = [
            ("peaks.max_peaks", p.max_peaks >= 1),
            ("smoothing_span", d.smoothing_span >= 1),
            ("baseline_samples", d.baseline_samples >= 1),
            (
                "confirm_counts",
                d.confirm_counts.is_finite() && d.confirm_counts >= 0.0,
            ),
            (
                "contact_angle_rate",
                d.contact_angle_rate.is_finite() && d.contact_angle_rate > 0.0,
            ),
            (
                "peaks.min_width",
                p.min_width.is_finite() && p.min_width >= 0.0,
            ),
            (
                "peaks.min_prominence",
                p.min_prominence.is_finite() && p.min_prominence >= 0.0,
            ),
        ];
        for (name, ok) in checks {
            if !ok {
                return Err(Error::field(
                    file,
                    &format!("frontend.detection.{name}"),
                    "expected a finite number ≥ 0 (spans and counts ≥ 1, rates > 0)",
                ));
            }
        }
        self.model(file).map(|_| ())
    }

    /// The radial-distance model: `radial_model` (relative to the scenario `file`), or the
    /// built-in svr10.
    pub fn model(&self, file: &Path) -> Result<whisker_slam::radial::RadialEstimator> {
        match &self.radial_model {
            Some(m) => crate::radial_model::load(&relative_to(file, m))
                .map_err(|e| Error::field(file, "frontend.radial_model", e)),
            None => crate::radial_model::load_or_default(None),
        }
    }
}

/// Sensing mode of a scenario.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Sensing {
    /// No whisker simulation: the arm moves, nothing senses.
    #[default]
    None,
    /// Rapier simulates every whisker at 2 kHz (`whiskers.csv`, and the anticipated
    /// contacts as ground truth in `anticipated.csv`).
    Physics,
    /// Rigid whiskers swept once per whisk cycle, anticipated intersect with noise
    /// (§4.1.2.3, §6.1.3.1.2; `contacts.csv`).
    Kinematic,
}

impl Sensing {
    /// The name used in scenarios.
    pub fn name(self) -> &'static str {
        match self {
            Sensing::None => "none",
            Sensing::Physics => "physics",
            Sensing::Kinematic => "kinematic",
        }
    }
}

/// How whisker contacts are sensed by a command that needs them (`--sensing`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensingMode {
    /// The anticipated intersect with noise.
    Kinematic,
    /// Rapier whiskers, the front end and a radial-distance model.
    Physics,
}

impl crate::choice::Choice for SensingMode {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            SensingMode::Kinematic,
            "kinematic",
            "Anticipated intersect with noise",
        ),
        (
            SensingMode::Physics,
            "physics",
            "Rapier whiskers, the front end and a radial-distance model",
        ),
    ];
}
