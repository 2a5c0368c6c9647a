//! # whisker-slam
//!
//! The algorithms of the whisker-slam testbed that would run unchanged on a real robot's
//! logs: the sensor data model, the signal front end, RatSLAM and WhiskerRatSLAM, object
//! maps, recognition and exploration (see docs/design.md and the thesis, Chapters 3–6).
//!
//! This crate depends on neither the simulator (`whisker-sim`), Rapier nor Rerun.
//!
//! Conventions shared by the whole workspace and defined here:
//! - [`pose`]: poses are nalgebra [`nalgebra::Isometry3<f64>`]; roll/pitch/yaw follow the
//!   URDF convention (R = Rz(yaw)·Ry(pitch)·Rx(roll)).
//! - [`rng`]: every random draw comes from a named sub-stream of a scenario seed.

// A library says what it does through its caller (reports, `Reporter`), never on the
// console itself.
#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod contact;
pub mod csv_records;
pub mod exploration;
pub mod features;
pub mod frontend;
pub mod invalid;
pub mod message;
pub mod navigation;
pub mod pose;
pub mod pose_grid;
pub mod radial;
pub mod ratslam;
pub mod recognition;
pub mod rng;
pub mod sensor;
pub mod stats;
pub mod whisker_ratslam;
