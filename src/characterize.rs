//! `whisker characterize`: a static point load on one held whisker, then its ring-down
//! (see `whisker_sim::whisker::characterize`).

use crate::error::{CliError, CliResult};
use serde_json::json;
use whisker_sim::whisker::beam::Bending;
use whisker_sim::whisker::characterize::characterize;
use whisker_sim::whisker::{BeamDesign, FollicleDesign};

/// Command-line options of `whisker characterize` (SI units).
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct Options {
    /// Whisker length (m).
    #[arg(long, default_value_t = 0.100)]
    pub length: f64,
    /// Base diameter (m).
    #[arg(long, default_value_t = 2.0e-3)]
    pub base_diameter: f64,
    /// Tip diameter (m).
    #[arg(long, default_value_t = 0.6e-3)]
    pub tip_diameter: f64,
    /// Young's modulus (Pa).
    #[arg(long, default_value_t = 2.5e9)]
    pub youngs_modulus: f64,
    /// Density (kg/m³).
    #[arg(long, default_value_t = 1150.0)]
    pub density: f64,
    /// Damping ratio of the first bending mode.
    #[arg(long, default_value_t = 0.03)]
    pub damping_ratio: f64,
    /// Number of rigid segments.
    #[arg(long, default_value_t = BeamDesign::with_length(0.1).segments)]
    pub segments: usize,
    /// Shaft joint model: spatial (spherical joints) or sweep-plane (revolute joints).
    #[arg(long, value_enum, default_value_t = BendingArg::Spatial)]
    pub bending: BendingArg,
    /// Rotational stiffness of the follicle (N·m/rad); 0 clamps the shaft rigidly.
    #[arg(long, default_value_t = FollicleDesign::default().stiffness)]
    pub follicle_stiffness: f64,
    /// Static force, perpendicular to the shaft in the sweep plane (N).
    #[arg(long, default_value_t = 0.005)]
    pub force: f64,
    /// Arc length of the load from the base (m) [default: 0.8 × length].
    #[arg(long)]
    pub at: Option<f64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `--bending` values.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum BendingArg {
    /// Spherical joints: the shaft bends in both planes.
    Spatial,
    /// Revolute joints: the shaft bends in the sweep plane only (faster).
    SweepPlane,
}

impl From<BendingArg> for Bending {
    fn from(b: BendingArg) -> Self {
        match b {
            BendingArg::Spatial => Bending::Spatial,
            BendingArg::SweepPlane => Bending::SweepPlane,
        }
    }
}

/// Runs `whisker characterize`.
pub fn run(o: &Options) -> CliResult {
    let beam = BeamDesign {
        length: o.length,
        base_diameter: o.base_diameter,
        tip_diameter: o.tip_diameter,
        youngs_modulus: o.youngs_modulus,
        density: o.density,
        damping_ratio: o.damping_ratio,
        segments: o.segments,
        bending: o.bending.into(),
    };
    beam.validate()
        .map_err(|e| CliError::Input(format!("characterize: {e}")))?;
    let follicle = match o.follicle_stiffness {
        0.0 => None,
        k if k.is_finite() && k > 0.0 => Some(FollicleDesign {
            stiffness: k,
            ..FollicleDesign::default()
        }),
        k => {
            return Err(CliError::Input(format!(
                "--follicle-stiffness: expected a number ≥ 0, got {k}"
            )));
        }
    };
    let at = o.at.unwrap_or(0.8 * o.length);
    if !(at.is_finite() && at > 0.0 && at <= o.length) {
        return Err(CliError::Input(format!(
            "--at: expected an arc length in (0, {}] m, got {at}",
            o.length
        )));
    }
    if !o.force.is_finite() || o.force == 0.0 {
        return Err(CliError::Input(format!(
            "--force: expected a non-zero finite number of newtons, got {}",
            o.force
        )));
    }
    let c = characterize(beam, follicle, o.force, at).map_err(CliError::Failure)?;
    if o.json {
        let out = json!({
            "length_m": o.length,
            "force_n": o.force,
            "at_m": at,
            "follicle_stiffness_nm_per_rad": o.follicle_stiffness,
            "load_deflection_m": c.load_deflection_m,
            "tip_deflection_m": c.tip_deflection_m,
            "base_moment_nm": c.base_moment_nm,
            "follicle_deflection_m": c.follicle_deflection_m,
            "first_frequency_hz": c.first_frequency_hz,
            "damping_ratio": c.damping_ratio,
            "ring_down_dt_s": c.dt_s,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&out).expect("plain JSON")
        );
    } else {
        println!(
            "whisker  L {:.1} mm, Ø {:.2} → {:.2} mm, E {:.2} GPa, ρ {} kg/m³, ζ {}, {} segments, mass {:.1} mg",
            o.length * 1e3,
            o.base_diameter * 1e3,
            o.tip_diameter * 1e3,
            o.youngs_modulus / 1e9,
            o.density,
            o.damping_ratio,
            o.segments,
            beam.mass() * 1e6
        );
        let follicle = if follicle.is_some() {
            format!("follicle {} N·m/rad", o.follicle_stiffness)
        } else {
            "rigid clamp".to_string()
        };
        println!("load     {} N at {:.1} mm ({follicle})", o.force, at * 1e3);
        println!("load-point deflection  {:>12.4e} m", c.load_deflection_m);
        println!("tip deflection         {:>12.4e} m", c.tip_deflection_m);
        println!("base moment            {:>12.4e} N·m", c.base_moment_nm);
        println!(
            "follicle reading (y)   {:>12.4e} m",
            c.follicle_deflection_m
        );
        println!("first frequency        {:>12.2} Hz", c.first_frequency_hz);
        println!("damping ratio          {:>12.4}", c.damping_ratio);
    }
    Ok(())
}
