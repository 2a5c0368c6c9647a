//! The scenario's whisker array on its arm: what `whisker check` says of it, and the
//! chain that places it.

use crate::error::{Error, Result};
use crate::plan::Plan;
use crate::scenario::Scenario;
use std::fmt::Write as _;
use std::path::Path;
use whisker_sim::kinematics::Chain;
use whisker_sim::whisker::control::RcpThreshold;

/// A description of the array of `scenario` for `whisker check`: one line per whisker.
pub fn describe(scenario: &Scenario, file: &Path) -> Result<String> {
    let configs = scenario.whisker_configs(file)?;
    let a = &scenario.array;
    let rcp = match a.rcp_mode() {
        None => "off".to_string(),
        Some(RcpThreshold::Saturation) => "at saturation".to_string(),
        Some(RcpThreshold::NoiseMultiple(k)) => {
            format!("at {k} × the free-whisking σ (calibrated before the run)")
        }
    };
    let first = &configs[0];
    let mut s = format!(
        "array      18 whiskers, {} segments, {:?} bending, {} substep(s), follicle {}, RCP {rcp}\n",
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

/// The chain from the arm's base to the `whisker_array` link, which must be moved by the
/// same joints as the scenario's tip link.
pub fn array_chain(scenario: &Scenario, file: &Path, plan: &Plan) -> Result<Chain> {
    let chain = Chain::new(&plan.model, &plan.chain.base, "whisker_array").map_err(|e| {
        Error::field(
            file,
            "sensing",
            format!(
                "{:?} needs a whisker_array link in the URDF: {e}",
                scenario.sensing.name()
            ),
        )
    })?;
    if chain.joint_names != plan.chain.joint_names {
        return Err(Error::field(
            file,
            "arm.tip_link",
            "the whisker_array link must be moved by the same joints as the tip link",
        ));
    }
    Ok(chain)
}
