//! `whisker bench …`: how fast the parts run, each against a baseline measured in the same
//! run. Timing is a benchmark, never a test.
//!
//! - [`physics`]: the real-time factor of physics sensing, by Rapier code path;
//! - [`sensing`]: whisk cycles per second of kinematic sensing against ray casts;
//! - [`slam`]: WhiskerRatSLAM's core against a naive dense convolution;
//! - [`recording`]: what the Rerun recording costs a run;
//! - [`trials`]: a batch on 1 against 2 worker threads.

pub mod physics;
pub mod pose_cells;
pub mod recording;
pub mod sensing;
pub mod slam;
pub mod trials;
