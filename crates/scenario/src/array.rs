//! `[array]` of a scenario: the whisker array's design, whisking, follicle, sensors and
//! RCP, with per-ring and per-whisker overrides (documented in `scenarios/README.md`).

use crate::error::{Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use whisker_sim::sensing::physics::{DEFAULT_SUBSTEPS, WhiskerConfig};
use whisker_sim::whisker::array::{self, COLUMNS, RINGS};
use whisker_sim::whisker::beam::Bending;
use whisker_sim::whisker::control::{AmplitudeRcp, RcpThreshold, WhiskingPattern};
use whisker_sim::whisker::follicle::FollicleDesign;
use whisker_sim::whisker::sensor::SensorModel;
use whisker_sim::whisker::strategies::{SpreadReduction, WhiskingControl};

/// Shaft joint model, as written in scenarios.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum BendingConfig {
    /// Spherical joints (both planes).
    #[default]
    Spatial,
    /// Revolute joints (sweep plane only).
    SweepPlane,
}

/// RCP mode, as written in scenarios.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum RcpConfig {
    /// Open-loop whisking.
    #[default]
    Off,
    /// Threshold = `rcp_noise_multiple` × the free-whisking σ (§3.2.2).
    Noise,
    /// Threshold = the sensor's saturation (§4.1.1).
    Saturation,
}

/// Which RCP controller, as written in scenarios (`[array] rcp_control`).
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum RcpControl {
    /// Retract at the threshold by the cycle's end (§4.1.1; Ch 4–6).
    #[default]
    Retract,
    /// Scale the stroke by the mean deflection over the threshold, the initial angle kept
    /// (§3.2.2; Ch 3).
    Amplitude,
}

/// `[array.whisking]`: the contact-triggered whisking strategies beyond RCP (thesis
/// §2.3.1, `whisker_sim::whisker::strategies`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WhiskingConfig {
    /// Spread reduction: after a contact the stroke narrows and moves towards protraction.
    #[serde(default)]
    pub spread_reduction: bool,
    /// Fraction of the stroke's amplitude kept under spread reduction [0.5].
    pub range_fraction: Option<f64>,
    /// How far spread reduction moves the stroke's centre towards protraction (deg) [20].
    pub centre_shift_deg: Option<f64>,
    /// Whisk cycles without contact before the full stroke returns [2].
    pub release_cycles: Option<u32>,
    /// Contact-induced asymmetry: a contact stops its side's protraction.
    #[serde(default)]
    pub asymmetry: bool,
}

/// Whisker shaft parameters; every field optional (unset: the level above, then the
/// thesis' defaults).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaftConfig {
    /// Length (m).
    pub length_m: Option<f64>,
    /// Base diameter (m).
    pub base_diameter_m: Option<f64>,
    /// Tip diameter (m).
    pub tip_diameter_m: Option<f64>,
    /// Young's modulus (Pa).
    pub youngs_modulus_pa: Option<f64>,
    /// Density (kg/m³).
    pub density_kg_m3: Option<f64>,
    /// Damping ratio of the first mode.
    pub damping_ratio: Option<f64>,
}

/// One `[[array.rings]]` entry: whisking of a ring (rostral first).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingConfig {
    /// Fully retracted angle (deg).
    pub retracted_deg: Option<f64>,
    /// Fully protracted angle (deg).
    pub protracted_deg: Option<f64>,
    /// Whisking frequency (Hz).
    pub frequency_hz: Option<f64>,
    /// Phase (deg).
    pub phase_deg: Option<f64>,
    /// Shaft parameters of the ring's whiskers.
    #[serde(flatten)]
    pub shaft: ShaftConfig,
}

/// `[array.sensor]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorConfig {
    /// Deflection gain (counts per metre of magnet travel).
    pub gain_counts_per_m: Option<f64>,
    /// Saturation (counts).
    pub saturation_counts: Option<f64>,
    /// Deflection noise σ (counts).
    pub noise_counts: Option<f64>,
    /// Angle resolution (deg).
    pub angle_resolution_deg: Option<f64>,
    /// Angle noise σ (deg).
    pub angle_noise_deg: Option<f64>,
}

/// `[array]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArrayConfig {
    /// Segments per whisker.
    pub segments: Option<usize>,
    /// Shaft joint model.
    #[serde(default)]
    pub bending: BendingConfig,
    /// Rapier substeps per 0.5 ms step.
    pub substeps: Option<usize>,
    /// Follicle stiffness (N·m/rad); 0 clamps the shafts rigidly.
    pub follicle_stiffness_nm_per_rad: Option<f64>,
    /// RCP mode.
    #[serde(default)]
    pub rcp: RcpConfig,
    /// Which RCP controller (no effect with `rcp = "off"`).
    #[serde(default)]
    pub rcp_control: RcpControl,
    /// `rcp_control = "amplitude"`: the stroke's gain 1 − gain · P / (saturation −
    /// threshold) for a mean excess P [1].
    pub rcp_amplitude_gain: Option<f64>,
    /// Multiple of the free-whisking σ for `rcp = "noise"` (and for the contact
    /// threshold of the `[array.whisking]` strategies without RCP).
    pub rcp_noise_multiple: Option<f64>,
    /// Spread reduction and contact-induced asymmetry.
    #[serde(default)]
    pub whisking: WhiskingConfig,
    /// Shaft parameters of every whisker.
    #[serde(default)]
    pub shaft: ShaftConfig,
    /// Per-ring whisking and shaft parameters (0 to 3 entries, rostral first).
    #[serde(default)]
    pub rings: Vec<RingConfig>,
    /// Per-whisker shaft parameters, keyed by tactile-image pixel ("A1" … "F3").
    #[serde(default)]
    pub whiskers: BTreeMap<String, ShaftConfig>,
    /// Sensor model.
    #[serde(default)]
    pub sensor: SensorConfig,
}

fn field_error(file: &Path, field: &str, e: impl std::fmt::Display) -> Error {
    Error::field(file, field, e)
}

fn finite(file: &Path, field: &str, v: Option<f64>) -> Result<Option<f64>> {
    match v {
        Some(x) if !x.is_finite() => Err(field_error(
            file,
            field,
            format!("expected a finite number, got {x}"),
        )),
        other => Ok(other),
    }
}

impl ArrayConfig {
    /// How contacts are detected for RCP and the `[array.whisking]` strategies, if any
    /// is on: `rcp`'s threshold, or without RCP `rcp_noise_multiple` (20) × the
    /// free-whisking σ.
    pub fn contact_mode(&self) -> Option<RcpThreshold> {
        let noise = RcpThreshold::NoiseMultiple(self.rcp_noise_multiple.unwrap_or(20.0));
        match self.rcp {
            RcpConfig::Off if self.whisking.spread_reduction || self.whisking.asymmetry => {
                Some(noise)
            }
            RcpConfig::Off => None,
            RcpConfig::Noise => Some(noise),
            RcpConfig::Saturation => Some(RcpThreshold::Saturation),
        }
    }

    /// The whisking strategies (without contact thresholds), checked against `pattern`.
    pub fn control(
        &self,
        file: &Path,
        pattern: &WhiskingPattern,
        ring_field: &str,
    ) -> Result<WhiskingControl> {
        let w = &self.whisking;
        let spread_reduction = if w.spread_reduction {
            let d = SpreadReduction::default();
            let shift = finite(file, "array.whisking.centre_shift_deg", w.centre_shift_deg)?;
            let sr = SpreadReduction {
                range_fraction: finite(file, "array.whisking.range_fraction", w.range_fraction)?
                    .unwrap_or(d.range_fraction),
                centre_shift: shift.map_or(d.centre_shift, f64::to_radians),
                release_cycles: w.release_cycles.unwrap_or(d.release_cycles),
            };
            sr.check(pattern).map_err(|e| {
                field_error(
                    file,
                    &format!("array.whisking.{}", e.field),
                    format!("{} (the stroke of {ring_field})", e.message),
                )
            })?;
            Some(sr)
        } else {
            None
        };
        let saturation = self
            .sensor
            .saturation_counts
            .unwrap_or(SensorModel::default().saturation_counts);
        Ok(WhiskingControl {
            rcp: self.rcp != RcpConfig::Off,
            rcp_amplitude: (self.rcp_control == RcpControl::Amplitude).then(|| AmplitudeRcp {
                gain: self.rcp_amplitude_gain.unwrap_or(1.0),
                saturation,
            }),
            spread_reduction,
            asymmetry: w.asymmetry,
        })
    }

    /// The 18 whiskers' configurations (contact thresholds not yet calibrated), checking every
    /// value and naming the offending field. [`crate::Scenario`] checks them once
    /// when it is loaded and keeps them.
    pub fn whisker_configs(&self, file: &Path) -> Result<Vec<WhiskerConfig>> {
        let modules = array::modules();
        self.check_overrides(file, &modules)?;
        let follicle = self.follicle(file)?;
        if let Some(n) = self.substeps
            && !(1..=64).contains(&n)
        {
            return Err(field_error(
                file,
                "array.substeps",
                format!("expected 1 to 64, got {n}"),
            ));
        }
        let sensor = self.sensor_model(file)?;
        let mut out = Vec::with_capacity(modules.len());
        for mut module in modules {
            let ring = self.rings.get(module.ring).cloned().unwrap_or_default();
            let ring_field = format!("array.rings[{}]", module.ring);
            self.shaft(file, &mut module, &ring, &ring_field)?;
            let pattern = whisking_pattern(file, &ring, &ring_field)?;
            let control = self.control(file, &pattern, &ring_field)?;
            out.push(WhiskerConfig {
                module,
                follicle,
                pattern,
                contact_threshold: None,
                control,
                sensor,
                substeps: self.substeps.unwrap_or(DEFAULT_SUBSTEPS),
                solver: Default::default(),
                without: None,
                adaptive_steps: true,
            });
        }
        Ok(out)
    }

    /// At most three rings, per-whisker keys that name whiskers, a positive RCP multiple.
    fn check_overrides(&self, file: &Path, modules: &[array::Module]) -> Result {
        if self.rings.len() > RINGS.len() {
            return Err(field_error(
                file,
                "array.rings",
                format!(
                    "expected at most {} rings, got {}",
                    RINGS.len(),
                    self.rings.len()
                ),
            ));
        }
        for key in self.whiskers.keys() {
            if !modules.iter().any(|m| &m.pixel() == key) {
                return Err(field_error(
                    file,
                    &format!("array.whiskers.{key}"),
                    format!(
                        "no such whisker: expected a pixel label {}1 … {}3",
                        COLUMNS[0], COLUMNS[5]
                    ),
                ));
            }
        }
        if let Some(g) = finite(file, "array.rcp_amplitude_gain", self.rcp_amplitude_gain)? {
            if g <= 0.0 {
                return Err(field_error(
                    file,
                    "array.rcp_amplitude_gain",
                    format!("expected a positive number, got {g}"),
                ));
            }
            if self.rcp_control != RcpControl::Amplitude {
                return Err(field_error(
                    file,
                    "array.rcp_amplitude_gain",
                    "only with rcp_control = \"amplitude\"",
                ));
            }
        }
        if let Some(k) = finite(file, "array.rcp_noise_multiple", self.rcp_noise_multiple)?
            && k <= 0.0
        {
            return Err(field_error(
                file,
                "array.rcp_noise_multiple",
                format!("expected a positive number, got {k}"),
            ));
        }
        Ok(())
    }

    /// The follicle (§2.1.2): the default design, another stiffness, or none (0: clamped).
    fn follicle(&self, file: &Path) -> Result<Option<FollicleDesign>> {
        match finite(
            file,
            "array.follicle_stiffness_nm_per_rad",
            self.follicle_stiffness_nm_per_rad,
        )? {
            None => Ok(Some(FollicleDesign::default())),
            Some(0.0) => Ok(None),
            Some(k) => {
                let follicle = FollicleDesign {
                    stiffness: k,
                    ..FollicleDesign::default()
                };
                follicle
                    .validate()
                    .map_err(|e| field_error(file, "array.follicle_stiffness_nm_per_rad", e))?;
                Ok(Some(follicle))
            }
        }
    }

    /// The Hall-effect sensor model of `[array.sensor]` over the defaults.
    fn sensor_model(&self, file: &Path) -> Result<SensorModel> {
        let s = &self.sensor;
        let d = SensorModel::default();
        let sensor = SensorModel {
            gain_counts_per_m: finite(file, "array.sensor.gain_counts_per_m", s.gain_counts_per_m)?
                .unwrap_or(d.gain_counts_per_m),
            saturation_counts: finite(file, "array.sensor.saturation_counts", s.saturation_counts)?
                .unwrap_or(d.saturation_counts),
            noise_counts: finite(file, "array.sensor.noise_counts", s.noise_counts)?
                .unwrap_or(d.noise_counts),
            angle_resolution_rad: finite(
                file,
                "array.sensor.angle_resolution_deg",
                s.angle_resolution_deg,
            )?
            .map_or(d.angle_resolution_rad, f64::to_radians),
            angle_noise_rad: finite(file, "array.sensor.angle_noise_deg", s.angle_noise_deg)?
                .map_or(d.angle_noise_rad, f64::to_radians),
        };
        sensor
            .validate()
            .map_err(|e| field_error(file, "array.sensor", e))?;
        Ok(sensor)
    }

    /// The shaft of one whisker: `[array.shaft]`, then its ring's, then its own values over
    /// the thesis' defaults; segments and joint model; checked.
    fn shaft(
        &self,
        file: &Path,
        module: &mut array::Module,
        ring: &RingConfig,
        ring_field: &str,
    ) -> Result {
        let pixel = module.pixel();
        let none = ShaftConfig::default();
        let levels = [
            ("array.shaft".to_string(), &self.shaft),
            (ring_field.to_string(), &ring.shaft),
            (
                format!("array.whiskers.{pixel}"),
                self.whiskers.get(&pixel).unwrap_or(&none),
            ),
        ];
        let b = &mut module.beam;
        for (field, shaft) in &levels {
            let set = |target: &mut f64, name: &str, v: Option<f64>| -> Result {
                if let Some(x) = finite(file, &format!("{field}.{name}"), v)? {
                    *target = x;
                }
                Ok(())
            };
            set(&mut b.length, "length_m", shaft.length_m)?;
            set(
                &mut b.base_diameter,
                "base_diameter_m",
                shaft.base_diameter_m,
            )?;
            set(&mut b.tip_diameter, "tip_diameter_m", shaft.tip_diameter_m)?;
            set(
                &mut b.youngs_modulus,
                "youngs_modulus_pa",
                shaft.youngs_modulus_pa,
            )?;
            set(&mut b.density, "density_kg_m3", shaft.density_kg_m3)?;
            set(&mut b.damping_ratio, "damping_ratio", shaft.damping_ratio)?;
        }
        if let Some(n) = self.segments {
            b.segments = n;
        }
        b.bending = match self.bending {
            BendingConfig::Spatial => Bending::Spatial,
            BendingConfig::SweepPlane => Bending::SweepPlane,
        };
        b.check().map_err(|e| {
            // The design names its own field; the scenario's carries its unit.
            let name = match e.field.as_str() {
                "length" => "length_m",
                "base_diameter" => "base_diameter_m",
                "tip_diameter" => "tip_diameter_m",
                "youngs_modulus" => "youngs_modulus_pa",
                "density" => "density_kg_m3",
                other => other,
            };
            field_error(
                file,
                &format!("array.{name}"),
                format!("whisker {pixel}: {}", e.message),
            )
        })
    }
}

/// A ring's whisking pattern (§2.1.3) over the defaults, checked.
fn whisking_pattern(file: &Path, ring: &RingConfig, ring_field: &str) -> Result<WhiskingPattern> {
    let default = WhiskingPattern::default();
    let angle = |name: &str, v: Option<f64>, d: f64| -> Result<f64> {
        Ok(finite(file, &format!("{ring_field}.{name}"), v)?.map_or(d, f64::to_radians))
    };
    let pattern = WhiskingPattern {
        retracted: angle("retracted_deg", ring.retracted_deg, default.retracted)?,
        protracted: angle("protracted_deg", ring.protracted_deg, default.protracted)?,
        frequency: finite(
            file,
            &format!("{ring_field}.frequency_hz"),
            ring.frequency_hz,
        )?
        .unwrap_or(default.frequency),
        phase: angle("phase_deg", ring.phase_deg, default.phase)?,
    };
    if !(pattern.frequency > 0.0 && pattern.frequency <= 20.0) {
        return Err(field_error(
            file,
            &format!("{ring_field}.frequency_hz"),
            format!(
                "expected a frequency in (0, 20] Hz, got {}",
                pattern.frequency
            ),
        ));
    }
    if !(0.0 <= pattern.retracted
        && pattern.retracted < pattern.protracted
        && pattern.protracted <= std::f64::consts::PI)
    {
        return Err(field_error(
            file,
            ring_field,
            format!(
                "expected 0° ≤ retracted_deg < protracted_deg ≤ 180°, got {:.1}° and {:.1}°",
                pattern.retracted.to_degrees(),
                pattern.protracted.to_degrees()
            ),
        ));
    }
    Ok(pattern)
}
