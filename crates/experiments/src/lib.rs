//! # whisker-experiments
//!
//! The experiments of the whisker-slam testbed as a library: the scenario format and plans
//! ([`scenario`], [`plan`]), the sensing runs the experiments share ([`sensing`]: one
//! contact pipeline, one contacts-CSV writer), the experiments — the scripted [`run`], the
//! closed loop of Chapter 6 ([`closed_loop`]), [`maze_slam`] (Ch 3), [`object_slam`]
//! (Ch 5), [`radial`] distance (Ch 4), [`characterize`] — datasets (the format in
//! [`dataset`], each experiment's writer/reader beside it, dispatch and noise in
//! [`datasets`]), batch [`trials`], [`bench`]marks and [`soak`] tests.
//!
//! It prints nothing and knows neither clap nor Rerun: it takes plain settings, returns
//! typed `Serialize` reports (with a `Display` for the console), says what it does through
//! [`record::Reporter`] and records through [`record::Recorder`], which the
//! `whisker-recording` crate implements on Rerun. Errors are [`error::Error`]: bad input or
//! a failure; the `whisker` binary maps them to exit codes 2 and 1.

pub mod assets;
pub mod bench;
pub mod characterize;
pub mod check;
pub mod choice;
pub mod closed_loop;
pub mod console;
pub mod dataset;
pub mod datasets;
pub mod error;
pub mod maze_slam;
pub mod navigation;
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
pub mod surface;
pub mod trials;
pub mod urdf;
