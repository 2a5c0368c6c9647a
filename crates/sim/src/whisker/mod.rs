//! The actively whisked whisker (thesis §2.2.2, §2.3): the shaft as a discretised beam
//! ([`beam`]), the compliant follicle with its Hall-effect sensor ([`follicle`]), and
//! the whisker built in Rapier ([`body`]).

pub mod beam;
pub mod body;
pub mod characterize;
pub mod follicle;

pub use beam::BeamDesign;
pub use body::Whisker;
pub use follicle::FollicleDesign;
