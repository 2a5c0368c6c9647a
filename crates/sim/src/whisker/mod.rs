//! The actively whisked whisker (thesis §2.2.2, §2.3): the shaft as a discretised beam
//! ([`beam`]), the compliant follicle ([`follicle`]) and its sensors ([`sensor`]), the
//! whisker built in Rapier ([`body`]), the array's geometry ([`array`]), whisking
//! control with RCP ([`control`]) and the array's contact-triggered strategies
//! ([`strategies`]), characterisation of one design ([`characterize`]) and
//! the Rapier code path that steps the chain ([`solver`]).

pub mod array;
pub mod beam;
pub mod body;
pub mod characterize;
pub mod control;
pub mod follicle;
pub mod sensor;
pub mod solver;
pub mod strategies;

pub use beam::BeamDesign;
pub use body::{RootDrive, Whisker};
pub use follicle::FollicleDesign;

/// Checks that every `(name, value)` is a positive finite number; the error names the
/// first that is not (`prefix` is prepended to the name).
pub use whisker_slam::message::short;

pub(crate) fn require_positive(prefix: &str, values: &[(&str, f64)]) -> Result<(), Invalid> {
    match values.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
        Some((name, v)) => Err(format!("{prefix}{name} must be a positive number, got {v}").into()),
        None => Ok(()),
    }
}
use whisker_slam::invalid::Invalid;
