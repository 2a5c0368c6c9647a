//! The scenario's whisker array on its arm: what `whisker check` says of it, and the
//! chain that places it.

use std::fmt::Write as _;
use whisker_scenario::ScenarioFile;
use whisker_scenario::plan::Plan;
use whisker_scenario::{DetectionLevels, Error, Result, Sensing};
use whisker_sim::kinematics::Chain;
use whisker_sim::sensing::noise::PointNoise;
use whisker_sim::whisker::control::{RcpThreshold, WhiskingPattern};
use whisker_sim::whisker::strategies::WhiskingControl;
use whisker_slam::whisker_ratslam::object_map::{MapSensing, SensedBy};

/// A description of the array of `scenario` for `whisker check`: one line per whisker.
pub fn describe(file: &ScenarioFile) -> Result<String> {
    let scenario = &file.scenario;
    let configs = file.whisker_configs()?;
    let a = &scenario.array;
    let contacts = match a.contact_mode() {
        None => String::new(),
        Some(RcpThreshold::Saturation) => ", contacts at saturation".to_string(),
        Some(RcpThreshold::NoiseMultiple(k)) => {
            format!(", contacts at {k} × the free-whisking σ (calibrated before the run)")
        }
    };
    let first = &configs[0];
    let control = strategies(&first.control, &first.pattern);
    let mut s = format!(
        "array      18 whiskers, {} segments, {:?} bending, {} substep(s), follicle {}, whisking {control}{contacts}\n",
        first.module.beam.segments,
        first.module.beam.bending,
        first.substeps,
        first
            .follicle
            .map_or("rigid".to_string(), |f| format!("{} N·m/rad", f.stiffness)),
    );
    for c in &configs {
        let b = &c.module.beam;
        let p = &c.pattern;
        let _ = writeln!(
            s,
            "  {}  L {:5.1} mm  Ø {:.2}→{:.2} mm  E {:.2} GPa  ρ {:.0}  ζ {:.3}  whisk {:.0}°–{:.0}° at {} Hz",
            c.module.pixel(),
            b.length * 1e3,
            b.base_diameter * 1e3,
            b.tip_diameter * 1e3,
            b.youngs_modulus / 1e9,
            b.density,
            b.damping_ratio,
            p.retracted.to_degrees(),
            p.protracted.to_degrees(),
            p.frequency
        );
    }
    Ok(s)
}

/// How a run of the scenario in `file` senses, as a map it builds records it: the mode and
/// one line — the array as [`describe`] gives it, then the kinematic noise or the physics
/// front end (detection levels of `[frontend.detection]`, radial-distance model).
pub fn map_sensing(file: &ScenarioFile) -> Result<MapSensing> {
    let scenario = &file.scenario;
    let text = describe(file)?;
    let first = text.lines().next().unwrap_or_default();
    let array = first.trim_start_matches("array").trim_start();
    Ok(match scenario.sensing {
        Sensing::Physics => {
            let d = &scenario.frontend.detection;
            let counts = match scenario.frontend.detection_levels() {
                DetectionLevels::NoiseMultiple(k) => {
                    format!("confirm and prominence {k} σ of each whisker's free whisking")
                }
                DetectionLevels::AsWritten => format!(
                    "confirm {} counts, prominence {} counts",
                    d.confirm_counts, d.peaks.min_prominence
                ),
            };
            let model = scenario
                .frontend
                .radial_model
                .as_ref()
                .map_or("svr10 (built in)".to_string(), |m| m.display().to_string());
            MapSensing {
                mode: SensedBy::Physics,
                array: format!(
                    "{array}; detection: {counts}, width {} samples, span {} samples (fitted to each RCP threshold); radial model {model}",
                    d.peaks.min_width, d.smoothing_span
                ),
            }
        }
        _ => {
            let k = &scenario.kinematic;
            let configs = file.whisker_configs()?;
            let control = strategies(&configs[0].control, &configs[0].pattern);
            let noise = match (k.noise, k.point_noise) {
                (false, _) => "no noise".to_string(),
                (true, how) => format!(
                    "noise: contact point σ {} of the whisker length {}, slope σ {}, detection probability {}",
                    k.point_noise_fraction,
                    match how {
                        PointNoise::AlongWhisker => "along the whisker",
                        PointNoise::PerCoordinate => "per coordinate",
                    },
                    k.slope_noise,
                    k.detection_probability
                ),
            };
            MapSensing {
                mode: SensedBy::Kinematic,
                array: format!(
                    "18 straight whiskers swept kinematically, whisking {control}; {noise}"
                ),
            }
        }
    })
}

/// The chain from the arm's base to the `whisker_array` link, which must be moved by the
/// same joints as the scenario's tip link.
pub fn array_chain(file: &ScenarioFile, plan: &Plan) -> Result<Chain> {
    let scenario = &file.scenario;
    let chain = Chain::new(&plan.model, &plan.chain.base, "whisker_array").map_err(|e| {
        Error::field(
            &file.path,
            "sensing",
            format!(
                "{:?} needs a whisker_array link in the URDF: {e}",
                scenario.sensing.name()
            ),
        )
    })?;
    if chain.joint_names != plan.chain.joint_names {
        return Err(Error::field(
            &file.path,
            "arm.tip_link",
            "the whisker_array link must be moved by the same joints as the tip link",
        ));
    }
    Ok(chain)
}

/// The whisking strategies in words, e.g. "RCP + spread reduction (50 % of the stroke,
/// +20° → 85°–135°, released after 2 quiet cycles)".
fn strategies(c: &WhiskingControl, pattern: &WhiskingPattern) -> String {
    let mut parts = Vec::new();
    if c.rcp {
        parts.push("RCP".to_string());
    }
    if let Some(sr) = c.spread_reduction {
        let (lo, hi) = sr.limits(pattern);
        parts.push(format!(
            "spread reduction ({:.0} % of the stroke, +{:.0}° → {:.0}°–{:.0}°, released after {} quiet cycle(s))",
            sr.range_fraction * 100.0,
            sr.centre_shift.to_degrees(),
            lo.to_degrees(),
            hi.to_degrees(),
            sr.release_cycles
        ));
    }
    if c.asymmetry {
        parts.push("contact-induced asymmetry (sides A–C / D–F)".to_string());
    }
    if parts.is_empty() {
        "open loop".into()
    } else {
        parts.join(" + ")
    }
}
