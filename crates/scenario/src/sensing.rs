//! How a scenario senses: `sensing = "none" | "physics" | "kinematic"`, the `--sensing`
//! choice of the commands that need contacts, and `[frontend]`, the signal front end of
//! physics sensing (thesis Ch 4).

use crate::error::{Error, Result};
use crate::paths::relative_to;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The default `[frontend] noise_multiple`: a contact is confirmed when its peak stands
/// 10 σ of the whisker's free whisking above the free-whisking mean. The thesis confirms
/// against "a set threshold" above that mean (§5.1.1.1.1) and sets the RCP contact threshold
/// at 20 σ of the same free-whisking signal (§3.2.2); half of it confirms an RCP contact,
/// which ends as it reaches 20 σ. At 1 Hz σ is 2.1 (60 mm), 3.2 (100 mm) and 9.0 counts
/// (160 mm whiskers; `whisker fidelity` prints them), and a free whisk's deterministic
/// excursion (the shaft's inertial bending) stays within about 3 σ.
pub const DEFAULT_NOISE_MULTIPLE: f64 = 10.0;

/// How the detection levels in counts (confirmation, peak prominence, the
/// `contact_angle` rate) are set.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum LevelRule {
    /// From each whisker's free-whisking σ: confirmation and prominence `noise_multiple`
    /// σ, the rate in the written proportion to the confirmation.
    #[default]
    Noise,
    /// `[frontend.detection]`'s counts as written.
    AsWritten,
}

/// How the detection levels are set, with the multiple of the noise rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DetectionLevels {
    /// `k` σ of each whisker's free whisking (calibrated before the run).
    NoiseMultiple(f64),
    /// As `[frontend.detection]` writes them.
    AsWritten,
}

/// `[frontend]`: the signal front end of `sensing = "physics"` (thesis Ch 4).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrontEndConfig {
    /// Radial-distance model (a `whisker radial train` output), relative to the scenario
    /// file; default: the built-in svr10.
    pub radial_model: Option<PathBuf>,
    /// `levels`: `"noise"` (default) or `"as-written"`.
    #[serde(default)]
    pub levels: LevelRule,
    /// `noise_multiple`: k of the noise rule ([`DEFAULT_NOISE_MULTIPLE`]).
    #[serde(default = "default_noise_multiple")]
    pub noise_multiple: f64,
    /// `[frontend.detection]`: contact-detection parameters.
    #[serde(default)]
    pub detection: whisker_slam::frontend::contact::FrontEndParams,
}

fn default_noise_multiple() -> f64 {
    DEFAULT_NOISE_MULTIPLE
}

impl Default for FrontEndConfig {
    fn default() -> Self {
        Self {
            radial_model: None,
            levels: LevelRule::default(),
            noise_multiple: DEFAULT_NOISE_MULTIPLE,
            detection: Default::default(),
        }
    }
}

impl FrontEndConfig {
    /// How the detection levels are set.
    pub fn detection_levels(&self) -> DetectionLevels {
        match self.levels {
            LevelRule::Noise => DetectionLevels::NoiseMultiple(self.noise_multiple),
            LevelRule::AsWritten => DetectionLevels::AsWritten,
        }
    }

    /// Checks the detection parameters; names the offending field.
    pub fn validate(&self, file: &Path) -> Result {
        let d = &self.detection;
        let p = &d.peaks;
        if !(self.noise_multiple.is_finite() && self.noise_multiple > 0.0) {
            return Err(Error::field(
                file,
                "frontend.noise_multiple",
                "expected a finite number > 0 (σ of free whisking)",
            ));
        }
        // Counts the noise rule replaces: written, they would be silently ignored.
        let written = whisker_slam::frontend::contact::FrontEndParams::default();
        let derived = [
            ("confirm_counts", d.confirm_counts, written.confirm_counts),
            (
                "peaks.min_prominence",
                p.min_prominence,
                written.peaks.min_prominence,
            ),
            (
                "contact_angle_rate",
                d.contact_angle_rate,
                written.contact_angle_rate,
            ),
        ];
        for (name, value, default) in derived {
            if self.levels == LevelRule::Noise && value != default {
                return Err(Error::field(
                    file,
                    &format!("frontend.detection.{name}"),
                    "with frontend.levels = \"noise\" (the default) the levels in counts come from \
                     each whisker's free-whisking σ; set frontend.levels = \"as-written\" to use \
                     this value",
                ));
            }
        }
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
