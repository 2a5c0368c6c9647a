//! # whisker
//!
//! The experiments of the whisker-slam testbed as a library: the scenario format, runs of
//! the arm and the whiskers, the closed loop of Chapter 6, the object-SLAM, maze-SLAM and
//! radial-distance experiments, recording to Rerun, and benchmarks. The `whisker` binary
//! is a thin command line over it; tests and batch runs call it directly.

pub mod assets;
pub mod bench;
pub mod characterize;
pub mod check;
pub mod choice;
pub mod closed_loop;
pub mod dataset;
pub mod datasets;
pub mod error;
pub mod maze_slam;
pub mod object_slam;
pub mod output;
pub mod plan;
pub mod radial;
pub mod radial_model;
pub mod record;

pub mod run;
pub mod scenario;
pub mod sensing;
pub mod soak;
pub mod trials;
pub mod urdf;
