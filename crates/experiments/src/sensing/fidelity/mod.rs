//! `whisker fidelity`: how faithfully the physics front end reproduces the anticipated
//! contacts of kinematic sensing (issue #61). The same array poses near a catalogue object
//! are sensed twice — by the rigid sweep's anticipated intersections (§4.1.2.3, the truth
//! of kinematic sensing) and by physics whiskers held still for one whisk, their streams
//! through the signal front end and the radial-distance model ([`super::held`]) — in each
//! whisking mode: open loop, RCP at the sensor's saturation (§4.1.1, the radial models'
//! training condition), RCP at 20 σ of free whisking (§3.2.2), and spread reduction
//! (§2.3.1) with its 20 σ contact threshold.
//!
//! Per object and mode: recall (anticipated contacts the front end detects on the same
//! whisker) and precision (detections with an anticipated contact), and over the matched
//! contacts the median and 90th percentile of the onset angle error, the radial-distance
//! error (the model's estimate against the anticipated distance along the shaft, Table
//! 4.1), the contact-point error and the slope error (§5.1.1.1.3 against the contacted
//! triangle's slope, Eq 6.12–6.14). Poses: [`viewpoints::facing`] of sub-stream
//! `fidelity/<object>` of seed 0, the array face 2–8 cm from the surface; sensor noise
//! from sub-streams `fidelity/<object>/<mode>/<pose>` of `seed`. The tables and files:
//! [`output`]; the picture of a tip contact: [`figure`].

pub mod figure;
pub mod output;

pub use output::run;

use super::held::PhysicsSensing;
use crate::record::Reporter;
use crate::sensing::detection::Detection;
use figure::{Example, example, pick_examples};
use nalgebra::Isometry3;
use rayon::prelude::*;
use serde::Serialize;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::assets::{CATALOGUE, placed};
use whisker_sim::sensing::calibration::calibrate_array_rcp;
use whisker_sim::sensing::kinematic::SweepTarget;
use whisker_sim::sensing::physics::{DT, WhiskerConfig};
use whisker_sim::sensing::viewpoints;
use whisker_sim::whisker::array;
use whisker_sim::whisker::control::RcpThreshold;
use whisker_sim::whisker::strategies::SpreadReduction;
use whisker_slam::frontend::contact::FrontEndParams;
use whisker_slam::radial::RadialEstimator;
use whisker_slam::stats::percentile;

/// A whisking mode of the comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Open-loop whisking.
    OpenLoop,
    /// RCP at the sensor's saturation (§4.1.1).
    RcpSaturation,
    /// RCP at 20 σ of free whisking (§3.2.2).
    RcpNoise,
    /// Spread reduction, contact at 20 σ of free whisking (§2.3.1).
    SpreadReduction,
}

impl Mode {
    /// Every mode, in report order.
    pub const ALL: [Mode; 4] = [
        Mode::OpenLoop,
        Mode::RcpSaturation,
        Mode::RcpNoise,
        Mode::SpreadReduction,
    ];

    /// The mode's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Mode::OpenLoop => "open-loop",
            Mode::RcpSaturation => "rcp-saturation",
            Mode::RcpNoise => "rcp-noise",
            Mode::SpreadReduction => "spread-reduction",
        }
    }

    /// The default array whisking in this mode, contact thresholds calibrated (sub-streams
    /// `calibration/whisker/NN` of `seed`).
    fn configs(self, seed: u64) -> Vec<WhiskerConfig> {
        let mut configs: Vec<WhiskerConfig> = array::modules()
            .into_iter()
            .map(WhiskerConfig::with_defaults)
            .collect();
        let threshold = match self {
            Mode::OpenLoop => None,
            Mode::RcpSaturation => Some(RcpThreshold::Saturation),
            Mode::RcpNoise | Mode::SpreadReduction => Some(RcpThreshold::NoiseMultiple(20.0)),
        };
        for c in &mut configs {
            c.control.rcp = matches!(self, Mode::RcpSaturation | Mode::RcpNoise);
            if self == Mode::SpreadReduction {
                c.control.spread_reduction = Some(SpreadReduction::default());
            }
        }
        if let Some(t) = threshold {
            calibrate_array_rcp(&mut configs, t, seed, DT);
        }
        configs
    }
}

/// What the comparison covers.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Catalogue objects by name.
    pub objects: Vec<String>,
    /// Array poses per object.
    pub poses: usize,
    /// Seed of the sensor noise.
    pub seed: u64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            objects: ["box", "box_stack", "mug", "kettle"]
                .map(String::from)
                .to_vec(),
            poses: 24,
            seed: 0,
        }
    }
}

/// One contact of the comparison: anticipated, detected, or both.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub object: String,
    pub mode: Mode,
    pub pose: usize,
    /// Tactile-image label.
    pub whisker: String,
    pub anticipated: bool,
    pub detected: bool,
    /// Detected − anticipated onset angle (deg).
    pub onset_error_deg: Option<f64>,
    /// Model estimate − anticipated distance along the shaft (mm).
    pub radial_error_mm: Option<f64>,
    /// Distance between the detected and the anticipated contact points (mm).
    pub point_error_mm: Option<f64>,
    /// Detected − anticipated slope.
    pub slope_error: Option<f64>,
    /// The anticipated contact's whisk angle (deg) and distance along the shaft as a
    /// fraction of the whisker's length.
    pub anticipated_angle_deg: Option<f64>,
    pub anticipated_fraction: Option<f64>,
    /// The largest |y| deflection of the whisker's whisk (counts): what detection saw.
    pub peak_counts: f64,
    /// Why an anticipated contact was missed ([`Miss`]), if it was.
    pub miss: Option<Miss>,
}

/// The classes of anticipated contacts the front end misses, each with its physical
/// reading (docs/physics-results.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Miss {
    /// Anticipated within 10° of full retraction: the shaft already presses on the object
    /// as the whisk begins, so the stream has no rising edge to find an onset on.
    Start,
    /// Anticipated within 2.5° of full protraction: the stroke ends as the shaft arrives,
    /// bending it by a few tens of counts at most.
    End,
    /// Anticipated on the last 5 % of the shaft: the tip meets the surface and slides off
    /// it, loading the follicle little.
    Tip,
    /// Elsewhere, with a peak deflection below the confirmation level.
    Weak,
    /// None of these.
    Other,
}

impl Miss {
    fn of(angle: f64, fraction: f64, peak: f64, pattern: (f64, f64), confirm: f64) -> Self {
        let (retracted, protracted) = pattern;
        if angle <= retracted + 10f64.to_radians() {
            Miss::Start
        } else if angle >= protracted - 2.5f64.to_radians() {
            Miss::End
        } else if fraction >= 0.95 {
            Miss::Tip
        } else if peak < confirm {
            Miss::Weak
        } else {
            Miss::Other
        }
    }
}

/// The figures of one object in one mode.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub object: String,
    pub mode: Mode,
    pub anticipated: usize,
    pub detected: usize,
    pub matched: usize,
    pub recall: f64,
    pub precision: f64,
    /// The missed anticipated contacts by class.
    pub misses: std::collections::BTreeMap<Miss, usize>,
    /// Median and 90th percentile of |error| over the matched contacts.
    pub onset_deg: [f64; 2],
    pub radial_mm: [f64; 2],
    pub point_mm: [f64; 2],
    pub slope: [f64; 2],
}

/// The detection levels of one whisker length in one mode (the default rule:
/// [`Detection::default_at`]).
#[derive(Debug, Clone, Serialize)]
pub struct Levels {
    pub mode: Mode,
    pub length_mm: f64,
    pub confirm_counts: f64,
    pub smoothing_span: usize,
}

/// The comparison's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fidelity {
    pub poses: usize,
    pub seed: u64,
    /// Each mode's levels, per whisker length.
    pub levels: Vec<Levels>,
    pub summaries: Vec<Summary>,
    #[serde(skip)]
    pub rows: Vec<Row>,
    /// The whisks of `tip.svg` ([`figure`]).
    #[serde(skip)]
    pub examples: Vec<Example>,
}

/// Senses every object of `s` in every mode both ways and compares.
pub fn compare(s: &Settings, model: &RadialEstimator, reporter: &dyn Reporter) -> Result<Fidelity> {
    let mut rows = Vec::new();
    let mut summaries = Vec::new();
    let mut levels = Vec::new();
    let mut examples = Vec::new();
    // Each mode's array and levels, calibrated once for every object.
    let arrays: Vec<(Mode, Vec<WhiskerConfig>, Vec<FrontEndParams>)> = Mode::ALL
        .into_iter()
        .map(|mode| {
            let configs = mode.configs(s.seed);
            let params = Detection::default_at(s.seed).levels(&configs);
            (mode, configs, params)
        })
        .collect();
    for (mode, configs, params) in &arrays {
        let mode = *mode;
        for (c, p) in configs.iter().zip(params) {
            let length_mm = 1e3 * c.module.beam.length;
            if !levels
                .iter()
                .any(|l: &Levels| l.mode == mode && l.length_mm == length_mm)
            {
                levels.push(Levels {
                    mode,
                    length_mm,
                    confirm_counts: p.confirm_counts,
                    smoothing_span: p.smoothing_span,
                });
            }
        }
    }
    for name in &s.objects {
        let asset = CATALOGUE.iter().find(|a| a.name == name).ok_or_else(|| {
            let known: Vec<&str> = CATALOGUE.iter().map(|a| a.name).collect();
            Error::Input(format!(
                "--objects: no catalogue object {name:?} (expected one of {})",
                known.join(", ")
            ))
        })?;
        let (environment, shape) =
            placed(asset).map_err(|e| Error::Failure(format!("{name}: {e}")))?;
        let target = SweepTarget::of(&environment);
        let poses = viewpoints::facing(&shape, asset.size, s.poses, &format!("fidelity/{name}"));
        for (mode, configs, params) in &arrays {
            let mode = *mode;
            let sensing = PhysicsSensing::with_params(
                vec![(shape.clone(), Isometry3::identity())],
                model.clone(),
                configs.clone(),
                params.clone(),
            );
            let stream = format!("fidelity/{name}/{}", mode.name());
            let these: Vec<Row> = poses
                .par_iter()
                .enumerate()
                .flat_map_iter(|(k, pose)| {
                    compare_pose(&sensing, &target, (k, pose), s.seed, &stream)
                        .into_iter()
                        .map(move |mut r| {
                            r.object = name.clone();
                            r.mode = mode;
                            r
                        })
                })
                .collect();
            if name == "box" && mode == Mode::RcpSaturation {
                let pattern = sensing.pattern(0);
                let stroke = (
                    pattern.retracted.to_degrees(),
                    pattern.protracted.to_degrees(),
                );
                examples = pick_examples(&these, stroke)
                    .into_iter()
                    .filter_map(|(label, r)| {
                        let i = sensing
                            .rigid()
                            .iter()
                            .position(|w| w.module.pixel() == r.whisker)?;
                        let at = (r.pose, &poses[r.pose]);
                        example(&sensing, &target, at, (s.seed, &stream), (i, label))
                    })
                    .collect();
            }
            let summary = summarise(name, mode, &these);
            reporter.note(&format!(
                "  {name:<10} {:<16} recall {:5.1} %  precision {:5.1} %  ({} anticipated, {} detected)",
                mode.name(),
                100.0 * summary.recall,
                100.0 * summary.precision,
                summary.anticipated,
                summary.detected
            ));
            summaries.push(summary);
            rows.extend(these);
        }
    }
    Ok(Fidelity {
        poses: s.poses,
        seed: s.seed,
        levels,
        summaries,
        rows,
        examples,
    })
}

/// The rows of one pose: every whisker with an anticipated or a detected contact.
fn compare_pose(
    sensing: &PhysicsSensing,
    target: &SweepTarget,
    (k, pose): (usize, &Isometry3<f64>),
    seed: u64,
    stream: &str,
) -> Vec<Row> {
    let stream = format!("{stream}/{k}");
    let (cycle, streams) = sensing.whisk_streams(target, k, pose, seed, &stream);
    sensing
        .rigid()
        .iter()
        .enumerate()
        .filter_map(|(i, w)| {
            let hit = target.sweep(w, pose);
            let found = cycle.contacts.iter().find(|c| c.whisker == i);
            if hit.is_none() && found.is_none() {
                return None;
            }
            let both = hit.zip(found);
            let peak = streams[i].iter().map(|r| r.y.abs()).fold(0.0, f64::max);
            let fraction = hit.map_or(0.0, |h| h.radial_distance / w.module.beam.length);
            let pattern = sensing.pattern(i);
            Some(Row {
                object: String::new(),
                mode: Mode::OpenLoop,
                pose: k,
                whisker: w.module.pixel(),
                anticipated: hit.is_some(),
                detected: found.is_some(),
                onset_error_deg: both.map(|(h, c)| (c.angle_rad - h.angle).to_degrees()),
                radial_error_mm: both.map(|(h, c)| 1e3 * (c.radial_distance - h.radial_distance)),
                point_error_mm: both.map(|(h, c)| 1e3 * (pose * c.point - h.point).norm()),
                slope_error: both.and_then(|(h, c)| {
                    let s = h.slope();
                    s.is_finite().then_some(c.slope - s)
                }),
                anticipated_angle_deg: hit.map(|h| h.angle.to_degrees()),
                anticipated_fraction: hit.map(|_| fraction),
                peak_counts: peak,
                miss: match (hit, found) {
                    (Some(h), None) => Some(Miss::of(
                        h.angle,
                        fraction,
                        peak,
                        (pattern.retracted, pattern.protracted),
                        sensing.levels()[i].confirm_counts,
                    )),
                    _ => None,
                },
            })
        })
        .collect()
}

fn spread(values: impl Iterator<Item = f64>) -> [f64; 2] {
    let v: Vec<f64> = values.map(f64::abs).collect();
    [percentile(v.clone(), 50.0), percentile(v, 90.0)]
}

fn summarise(object: &str, mode: Mode, rows: &[Row]) -> Summary {
    let anticipated = rows.iter().filter(|r| r.anticipated).count();
    let detected = rows.iter().filter(|r| r.detected).count();
    let matched: Vec<&Row> = rows
        .iter()
        .filter(|r| r.anticipated && r.detected)
        .collect();
    let ratio = |a: usize, b: usize| {
        if b == 0 {
            f64::NAN
        } else {
            a as f64 / b as f64
        }
    };
    Summary {
        object: object.to_string(),
        mode,
        anticipated,
        detected,
        matched: matched.len(),
        misses: rows.iter().filter_map(|r| r.miss).fold(
            std::collections::BTreeMap::new(),
            |mut m, c| {
                *m.entry(c).or_insert(0) += 1;
                m
            },
        ),
        recall: ratio(matched.len(), anticipated),
        precision: ratio(matched.len(), detected),
        onset_deg: spread(matched.iter().filter_map(|r| r.onset_error_deg)),
        radial_mm: spread(matched.iter().filter_map(|r| r.radial_error_mm)),
        point_mm: spread(matched.iter().filter_map(|r| r.point_error_mm)),
        slope: spread(matched.iter().filter_map(|r| r.slope_error)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On two Box poses: every row is anticipated or detected; the summary's counts and
    /// ratios equal a recount of the rows; with RCP at saturation the front end finds at
    /// least 80 % of the anticipated contacts and nothing the sweep does not anticipate
    /// (precision 1), at onset angles within 5° (median) of the anticipated ones.
    #[test]
    fn the_summary_recounts_its_rows_and_rcp_at_saturation_follows_the_sweep() {
        let s = Settings {
            objects: vec!["box".into()],
            poses: 2,
            seed: 3,
        };
        let model = whisker_scenario::radial_model::load_or_default(None).unwrap();
        let f = compare(&s, &model, &crate::record::Silent).unwrap();
        assert_eq!(f.summaries.len(), Mode::ALL.len());
        for m in &f.summaries {
            let rows: Vec<&Row> = f.rows.iter().filter(|r| r.mode == m.mode).collect();
            assert!(rows.iter().all(|r| r.anticipated || r.detected));
            let a = rows.iter().filter(|r| r.anticipated).count();
            let d = rows.iter().filter(|r| r.detected).count();
            let both = rows.iter().filter(|r| r.anticipated && r.detected).count();
            assert_eq!((m.anticipated, m.detected, m.matched), (a, d, both));
            assert_eq!(m.recall, both as f64 / a as f64);
            assert_eq!(m.misses.values().sum::<usize>(), a - both);
        }
        let sat = f
            .summaries
            .iter()
            .find(|m| m.mode == Mode::RcpSaturation)
            .unwrap();
        assert!(sat.anticipated >= 5, "{sat:?}");
        assert!(sat.recall >= 0.8 && sat.precision == 1.0, "{sat:?}");
        assert!(sat.onset_deg[0] < 5.0, "{sat:?}");
        // The figure's whisks are anticipated contacts: each whisker's samples span the
        // stroke and the anticipated onset lies inside it.
        for e in &f.examples {
            let (lo, hi) = e
                .samples
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, s| {
                    (a.0.min(s.0), a.1.max(s.0))
                });
            assert!(
                lo < e.anticipated_deg && e.anticipated_deg < hi,
                "{}",
                e.title
            );
            assert!(e.confirm > 0.0);
        }
    }
}
