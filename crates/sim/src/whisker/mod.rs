//! The actively whisked whisker (thesis §2.2.2, §2.3): the shaft as a discretised beam
//! ([`beam`]), the compliant follicle ([`follicle`]) and its sensors ([`sensor`]), the
//! whisker built in Rapier ([`body`]), the array's geometry ([`array`]), whisking
//! control with RCP ([`control`]), and characterisation of one design ([`characterize`]).

pub mod array;
pub mod beam;
pub mod body;
pub mod characterize;
pub mod control;
pub mod follicle;
pub mod sensor;

pub use beam::BeamDesign;
pub use body::Whisker;
pub use follicle::FollicleDesign;
