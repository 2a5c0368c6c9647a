//! Sensing modes: how whisker readings are produced from a world.
//!
//! - [`physics`]: Rapier simulates every whisker's compliant beam, follicle and motor.

pub mod physics;
