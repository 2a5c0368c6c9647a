//! # whisker-sim
//!
//! The physics testbed of whisker-slam: the arm loaded from URDF with forward and inverse
//! kinematics ([`kinematics`]), the arm's links as kinematic Rapier bodies ([`arm`]) and
//! the simulated world that holds them ([`world`]). It produces data in the sensor data
//! model of `whisker-slam`.

// A library says what it does through its caller (reports, `Reporter`), never on the
// console itself.
#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod arm;
pub mod environment;
pub mod kinematic_body;
pub mod kinematics;
pub mod sensing;
pub mod whisker;
pub mod world;
