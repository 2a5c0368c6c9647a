//! `whisker characterize`.

use super::{choice, print_json};
use whisker_experiments::characterize::{self, Settings};
use whisker_scenario::Result;
use whisker_sim::whisker::BeamDesign;
use whisker_sim::whisker::beam::Bending;

/// Characterise one whisker design: static point load, then ring-down (SI units).
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Whisker length (m).
    #[arg(long, default_value_t = Settings::default().beam.length)]
    pub length: f64,
    /// Base diameter (m).
    #[arg(long, default_value_t = Settings::default().beam.base_diameter)]
    pub base_diameter: f64,
    /// Tip diameter (m).
    #[arg(long, default_value_t = Settings::default().beam.tip_diameter)]
    pub tip_diameter: f64,
    /// Young's modulus (Pa).
    #[arg(long, default_value_t = Settings::default().beam.youngs_modulus)]
    pub youngs_modulus: f64,
    /// Density (kg/m³).
    #[arg(long, default_value_t = Settings::default().beam.density)]
    pub density: f64,
    /// Damping ratio of the first bending mode.
    #[arg(long, default_value_t = Settings::default().beam.damping_ratio)]
    pub damping_ratio: f64,
    /// Number of rigid segments.
    #[arg(long, default_value_t = Settings::default().beam.segments)]
    pub segments: usize,
    /// Shaft joint model.
    #[arg(long, value_parser = choice::<Bending>(), default_value = "spatial")]
    pub bending: Bending,
    /// Rotational stiffness of the follicle (N·m/rad); 0 clamps the shaft rigidly.
    #[arg(long, default_value_t = Settings::default().follicle_stiffness)]
    pub follicle_stiffness: f64,
    /// Static force, perpendicular to the shaft in the sweep plane (N).
    #[arg(long, default_value_t = Settings::default().force)]
    pub force: f64,
    /// Arc length of the load from the base (m) [default: 0.8 × length].
    #[arg(long)]
    pub at: Option<f64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs it.
pub fn run(a: &Args) -> Result {
    let settings = Settings {
        beam: BeamDesign {
            length: a.length,
            base_diameter: a.base_diameter,
            tip_diameter: a.tip_diameter,
            youngs_modulus: a.youngs_modulus,
            density: a.density,
            damping_ratio: a.damping_ratio,
            segments: a.segments,
            bending: a.bending,
        },
        follicle_stiffness: a.follicle_stiffness,
        force: a.force,
        at: a.at,
    };
    let report = characterize::run(&settings)?;
    if a.json {
        print_json(&report, true);
    } else {
        print!("{report}");
    }
    Ok(())
}
