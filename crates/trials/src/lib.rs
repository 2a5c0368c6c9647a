//! # whisker-trials
//!
//! Batches of whisker-slam runs and the long measurements: the thesis' batches (§6.3: 10
//! seeds × 3 strategies, SPC on/off, IC thresholds; §3.3: the maze variants over seeds) as
//! one command (`whisker trials`), on worker threads, resumable, sharded for clusters, with
//! statistics and plots; the benchmarks (`whisker bench …`) and the soak tests
//! (`whisker soak`). Formats: scenarios/README.md, "Batch trials".
//!
//! The grid of a batch — which trials there are, their keys and shards — is the scenario's
//! (`whisker_scenario::grid`). A trial is one in-process `whisker run` on one thread, so
//! that N workers use N cores ([`batch`]); its row in `trials.csv` is its `summary.json`,
//! flattened ([`journal`]). Shards are merged by [`merge`] and submitted to Slurm by
//! [`slurm`]; [`report`] writes the statistics and [`plots`].

// A library says what it does through its caller (reports, `Reporter`), never on the
// console itself.
#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod batch;
pub mod bench;
pub mod journal;
pub mod lock;
pub mod merge;
mod plots;
pub mod report;
pub mod slurm;
pub mod soak;
