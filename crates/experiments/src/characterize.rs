//! `whisker characterize`: a static point load on one held whisker, then its ring-down
//! (see `whisker_sim::whisker::characterize`).

use serde::Serialize;
use std::fmt;
use whisker_scenario::{Error, Result};
use whisker_sim::whisker::beam::Bending;
use whisker_sim::whisker::characterize::{Characterization, characterize, check_first_mode};
use whisker_sim::whisker::follicle::{MAX_STIFFNESS_NM_PER_RAD, MIN_STIFFNESS_NM_PER_RAD};
use whisker_sim::whisker::short;
use whisker_sim::whisker::{BeamDesign, FollicleDesign};

/// The largest static load (N): contact forces on whiskers are millinewtons, and 1 N
/// already bends the default 10 cm whisker through half its length; far beyond, the
/// load-point deflection stops growing with the force and then the simulation diverges.
pub const MAX_FORCE_N: f64 = 10.0;

/// The smallest static load (N): far below contact forces, still well above rounding
/// (a subnormal load left nothing to ring down).
pub const MIN_FORCE_N: f64 = 1e-6;

/// One whisker design and its load (SI units).
#[derive(Debug, Clone)]
pub struct Settings {
    /// The shaft.
    pub beam: BeamDesign,
    /// Rotational stiffness of the follicle (N·m/rad); 0 clamps the shaft rigidly.
    pub follicle_stiffness: f64,
    /// Static force, perpendicular to the shaft in the sweep plane (N).
    pub force: f64,
    /// Arc length of the load from the base (m) [default: 0.8 × length].
    pub at: Option<f64>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            beam: BeamDesign {
                length: 0.100,
                base_diameter: 2.0e-3,
                tip_diameter: 0.6e-3,
                youngs_modulus: 2.5e9,
                density: 1150.0,
                damping_ratio: 0.03,
                segments: BeamDesign::with_length(0.1).segments,
                bending: Bending::Spatial,
            },
            follicle_stiffness: FollicleDesign::default().stiffness,
            force: 0.005,
            at: None,
        }
    }
}

/// What a characterisation measured, with what it measured (`--json` prints it).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub length_m: f64,
    pub force_n: f64,
    pub at_m: f64,
    pub follicle_stiffness_nm_per_rad: f64,
    pub load_deflection_m: f64,
    pub tip_deflection_m: f64,
    pub base_moment_nm: f64,
    pub follicle_deflection_m: f64,
    pub first_frequency_hz: f64,
    pub damping_ratio: f64,
    pub ring_down_dt_s: f64,
    #[serde(skip)]
    beam: BeamDesign,
}

/// Loads and rings down the design of `s`.
pub fn run(s: &Settings) -> Result<Report> {
    let beam = s.beam;
    // The design names its bad field; the command line knows it as an option.
    beam.check().map_err(|e| {
        Error::Input(format!(
            "characterize: --{}: {}",
            e.field.replace('_', "-"),
            e.message
        ))
    })?;
    // The first mode depends on all of them.
    check_first_mode(&beam).map_err(|e| {
        Error::Input(format!(
            "characterize: --length, --base-diameter, --tip-diameter, --youngs-modulus, \
             --density: {e}"
        ))
    })?;
    let follicle = match s.follicle_stiffness {
        0.0 => None,
        k if (MIN_STIFFNESS_NM_PER_RAD..=MAX_STIFFNESS_NM_PER_RAD).contains(&k) => {
            Some(FollicleDesign {
                stiffness: k,
                ..FollicleDesign::default()
            })
        }
        k => {
            return Err(Error::Input(format!(
                "--follicle-stiffness: expected 0 (a rigid clamp) or a number from \
                 {MIN_STIFFNESS_NM_PER_RAD} to {MAX_STIFFNESS_NM_PER_RAD:e} N·m/rad, got {}",
                short(k)
            )));
        }
    };
    let at = s.at.unwrap_or(0.8 * beam.length);
    if !(at.is_finite() && at > 0.0 && at <= beam.length) {
        return Err(Error::Input(format!(
            "--at: expected an arc length in (0, {}] m, got {at}",
            beam.length
        )));
    }
    if !(MIN_FORCE_N..=MAX_FORCE_N).contains(&s.force.abs()) {
        return Err(Error::Input(format!(
            "--force: expected a load of {MIN_FORCE_N:e} to {MAX_FORCE_N} N (either sign), got {}",
            short(s.force)
        )));
    }
    // What the simulation cannot measure (a load that does not settle, a ring-down too
    // damped to show oscillations) is a property of the design: refused as input.
    let c: Characterization = characterize(beam, follicle, s.force, at).map_err(|e| {
        Error::Input(format!(
            "characterize: this design cannot be characterised: {e}"
        ))
    })?;
    Ok(Report {
        length_m: beam.length,
        force_n: s.force,
        at_m: at,
        follicle_stiffness_nm_per_rad: s.follicle_stiffness,
        load_deflection_m: c.load_deflection_m,
        tip_deflection_m: c.tip_deflection_m,
        base_moment_nm: c.base_moment_nm,
        follicle_deflection_m: c.follicle_deflection_m,
        first_frequency_hz: c.first_frequency_hz,
        damping_ratio: c.damping_ratio,
        ring_down_dt_s: c.dt_s,
        beam,
    })
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = &self.beam;
        writeln!(
            f,
            "whisker  L {:.1} mm, Ø {:.2} → {:.2} mm, E {:.2} GPa, ρ {} kg/m³, ζ {}, {} segments, mass {:.1} mg",
            b.length * 1e3,
            b.base_diameter * 1e3,
            b.tip_diameter * 1e3,
            b.youngs_modulus / 1e9,
            b.density,
            b.damping_ratio,
            b.segments,
            b.mass() * 1e6
        )?;
        let follicle = if self.follicle_stiffness_nm_per_rad != 0.0 {
            format!("follicle {} N·m/rad", self.follicle_stiffness_nm_per_rad)
        } else {
            "rigid clamp".to_string()
        };
        writeln!(
            f,
            "load     {} N at {:.1} mm ({follicle})",
            self.force_n,
            self.at_m * 1e3
        )?;
        writeln!(
            f,
            "load-point deflection  {:>12.4e} m",
            self.load_deflection_m
        )?;
        writeln!(
            f,
            "tip deflection         {:>12.4e} m",
            self.tip_deflection_m
        )?;
        writeln!(
            f,
            "base moment            {:>12.4e} N·m",
            self.base_moment_nm
        )?;
        writeln!(
            f,
            "follicle reading (y)   {:>12.4e} m",
            self.follicle_deflection_m
        )?;
        writeln!(
            f,
            "first frequency        {:>12.2} Hz",
            self.first_frequency_hz
        )?;
        writeln!(f, "damping ratio          {:>12.4}", self.damping_ratio)?;
        f.write_str(&whisker_scenario::console::legend(
            "what the lines mean",
            &[
                ("deflections", "static: the shaft's displacement under the point load, at the load and at the tip (Euler–Bernoulli for the tapered beam gives the reference; `cargo test` holds them within 1 %)"),
                ("base moment", "the bending moment the follicle carries (= force × distance for a rigid base)"),
                ("follicle reading", "the follicle displacement the Hall sensor reads (§2.2; its sign follows the load)"),
                ("first frequency", "the first bending mode from the free ring-down (cantilever theory within 5 %)"),
                ("damping ratio", "from the ring-down's logarithmic decrement; the beam's ζ is the target"),
            ],
        ))
    }
}
