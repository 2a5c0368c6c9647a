//! # whisker-scenario
//!
//! The scenario language of the whisker-slam testbed: what a scenario file says, read once
//! and checked once. A scenario is a TOML file (version 1, documented field by field in
//! `scenarios/README.md`), optionally written as changes to a `base` scenario and changed
//! again by `--set PATH=VALUE` ([`overrides`]); unknown fields are rejected and every error
//! names the file and the field ([`Error`]). A [`ScenarioFile`] is read once: its table as
//! run and the checked [`Scenario`], whose [`Experiment`] — the scripted run, the closed loop
//! or the office — is chosen then. From it come the arm's [`Plan`] (IK of every
//! waypoint, the joint trajectory) and the batch [`grid`] of its `[trials]`.
//!
//! Beside the language sit the pieces every command shares: [`files`] (output files written
//! atomically, nothing left behind by a failed command), [`console`] (the one shape of
//! every command's text), named [`choice`]s, and the radial-distance model a scenario's
//! front end names ([`radial_model`]).
//!
//! The experiments themselves are `whisker-experiments`; batches are `whisker-trials`.

// A library says what it does through its caller (reports, `Reporter`), never on the
// console itself.
#![deny(clippy::print_stdout, clippy::print_stderr)]

mod base;
mod environment;
mod error;
mod experiment;
mod file;
mod office;
mod paths;
mod scenario;
mod sensing;
mod strict;

pub mod array;
pub mod choice;
pub mod console;
pub mod explore;
pub mod files;
pub mod grid;
pub mod maze_slam;
pub mod navigate;
pub mod object_mode;
pub mod overrides;
pub mod plan;
pub mod radial_model;
pub mod stop;
pub mod trials;

pub use environment::{KinematicConfig, LoadedEnvironment, MazeConfig, ObjectConfig};
pub use error::{Error, Result};
pub use experiment::Experiment;
pub use file::ScenarioFile;
pub use office::OfficeConfig;
pub use plan::Plan;
pub use scenario::{
    ArmConfig, DEFAULT_JOINT_SPEED_RAD_S, MAX_HOLD_S, MAX_OBJECTS, MIN_JOINT_SPEED_RAD_S,
    OutputConfig, SAMPLE_PERIOD_RANGE_S, Scenario, Target, TrajectoryConfig, Waypoint,
};
pub use sensing::{DetectionLevels, FrontEndConfig, LevelRule, Sensing, SensingMode};
