//! # whisker-experiments
//!
//! The experiments of the whisker-slam testbed as a library, on the scenarios of
//! `whisker-scenario`: the sensing runs the experiments share ([`sensing`]: one contact
//! pipeline, one contacts-CSV writer), the experiments — the scripted [`run`], the closed
//! loop of Chapter 6 ([`closed_loop`]), [`maze_slam`] (Ch 3), [`object_slam`] (Ch 5),
//! [`navigation`] (Fig 5.1), [`radial`] distance (Ch 4), [`characterize`], the front end's
//! [`fidelity`] to the anticipated contacts — and datasets
//! (the format in [`dataset_format`], each experiment's writer/reader beside it; writing,
//! noising and replaying one by its manifest in [`dataset_runs`]). Batches, benchmarks and soak tests are `whisker-trials`.
//!
//! It prints nothing and knows neither clap nor Rerun: it takes plain settings, returns
//! typed `Serialize` reports (with a `Display` for the console), says what it does through
//! [`record::Reporter`] and records through [`record::Recorder`], which the
//! `whisker-recording` crate implements on Rerun. Errors are `whisker_scenario::Error`: bad input or
//! a failure; the `whisker` binary maps them to exit codes 2 and 1.

// A library says what it does through its caller (reports, `Reporter`), never on the
// console itself.
#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod assets;
pub mod characterize;
pub mod check;
pub mod closed_loop;
pub mod dataset_format;
pub mod dataset_runs;
pub mod maze_slam;
pub mod navigation;
pub mod object_slam;
pub mod radial;
pub mod record;
pub mod ros2_bag;
pub mod run;
mod sensing;
mod surface;
pub mod urdf;

/// `whisker fidelity`: the physics front end against the anticipated contacts.
pub use sensing::fidelity;
