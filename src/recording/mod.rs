//! The Rerun recordings (`.rrd`) of every command that simulates or runs SLAM, for
//! headless inspection: open one later with `rerun FILE.rrd`. The entity tree, one row per
//! entity (path, archetype, timeline, rate), is documented in `docs/recording.md`; its
//! entities are written by [`world`] (the scene), [`sensors`] (the 2 kHz streams),
//! [`slam`] (the SLAM state and the closed loop's decisions) and read back by [`decode`].
//!
//! Reproducibility: the recording id is made from the scenario (or command) and the seed,
//! the wall-clock `log_time` timeline is off, and nothing is batched on a timer: data is
//! written at [`Recording::checkpoint`]s the command places at fixed points of the
//! simulation (e.g. every whisk cycle), so that one seed gives the same decoded content
//! whatever the thread count. Rerun's row and chunk identifiers are random per write, so
//! two recordings of one seed hold the same data but not the same bytes.
//!
//! The file is written to a hidden temporary sibling and renamed into place by
//! [`Recording::finish`]; a recording dropped unfinished (an error) removes it.

pub mod blueprint;
pub mod decode;
pub mod sensors;
pub mod slam;
pub mod world;

use crate::error::{CliError, CliResult};
use crate::output;
use std::path::{Path, PathBuf};

/// Steps (SLAM updates, whisks) between checkpoints.
pub const STEPS_PER_CHECKPOINT: usize = 50;

/// The simulated-time timeline (seconds, stored as a duration).
pub const SIM_TIME: &str = "sim_time";

/// `--rrd FILE` / `--no-rrd`: where a command writes its recording.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RrdArgs {
    /// Write the Rerun recording to FILE [default: run.rrd in the output directory].
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
    /// Write no Rerun recording.
    #[arg(long, conflicts_with = "rrd")]
    pub no_rrd: bool,
    /// The recording id, when not the default `<scenario>-seed<seed>` (a batch trial's
    /// names its trial).
    #[arg(skip)]
    pub id: Option<String>,
}

impl RrdArgs {
    /// The recording's path: `--rrd`, else `run.rrd` in `dir` (the command's output
    /// directory, when it has one and `default_on`), else none.
    pub fn path(&self, dir: Option<&Path>, default_on: bool) -> Option<PathBuf> {
        if self.no_rrd {
            return None;
        }
        match (&self.rrd, dir) {
            (Some(p), _) => Some(p.clone()),
            (None, Some(d)) if default_on => Some(d.join("run.rrd")),
            _ => None,
        }
    }
}

/// A recording being written.
pub struct Recording {
    stream: rerun::RecordingStream,
    tmp: PathBuf,
    path: PathBuf,
    finished: bool,
    /// Contacts waiting for their other half (ground truth or estimate) of a cycle.
    pending: std::cell::RefCell<world::Pending>,
    /// Links of the arm logged (their axes are logged at the end).
    links: std::cell::Cell<usize>,
}

pub(crate) fn fail(path: &Path, e: impl std::fmt::Display) -> CliError {
    CliError::Failure(format!("cannot write recording {}: {e}", path.display()))
}

/// The recording id of `name` (a scenario's file stem, or a command) with `seed`.
pub fn id(name: &str, seed: u64) -> String {
    format!("{name}-seed{seed}")
}

impl Recording {
    /// Starts a recording to be saved at `path`, identified by `recording_id`, that opens
    /// on `layout` in the viewer.
    pub fn create(
        path: &Path,
        recording_id: &str,
        layout: rerun::blueprint::Blueprint,
    ) -> CliResult<Self> {
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            output::create_dir(parent)?;
        }
        let tmp = output::temporary(path);
        let stream = rerun::RecordingStreamBuilder::new("whisker")
            .recording_id(recording_id)
            .batcher_config(rerun::log::ChunkBatcherConfig::NEVER)
            .with_blueprint(layout)
            .save(&tmp)
            .map_err(|e| fail(path, e))?;
        stream.set_log_time_enabled(false);
        let rec = Self {
            stream,
            tmp,
            path: path.to_path_buf(),
            finished: false,
            pending: Default::default(),
            links: Default::default(),
        };
        rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())?;
        Ok(rec)
    }

    /// The recording `run.rrd` of a scenario run into `dir` (named after the file and the
    /// seed) unless `rrd` or the scenario switch it off; `--rrd` chooses another file.
    pub fn for_scenario(
        file: &Path,
        scenario: &crate::scenario::Scenario,
        dir: &Path,
        rrd: &RrdArgs,
        layout: rerun::blueprint::Blueprint,
    ) -> CliResult<Option<Self>> {
        let Some(path) = rrd.path(Some(dir), scenario.output.recording) else {
            return Ok(None);
        };
        let stem = file.file_stem().unwrap_or_default().to_string_lossy();
        let name = rrd.id.clone().unwrap_or_else(|| id(&stem, scenario.seed));
        Self::create(&path, &name, layout).map(Some)
    }

    /// Where the recording will be.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Sets the simulated time (s) of what is logged next, and no other timeline.
    pub fn at(&self, t: f64) {
        self.stream.reset_time();
        self.stream.set_duration_secs(SIM_TIME, t);
    }

    /// Adds a sequence timeline (e.g. `update`, `whisk`) to the time of what is logged
    /// next (after [`Self::at`], which clears it).
    pub fn at_step(&self, timeline: &'static str, k: u64) {
        self.stream.set_time_sequence(timeline, k as i64);
    }

    /// Runs `f` with the time set to `when`, then restores the time.
    pub(crate) fn at_timepoint<R>(&self, when: rerun::TimePoint, f: impl FnOnce() -> R) -> R {
        let now = self.stream.now();
        self.stream.reset_time();
        self.stream.set_timepoint(when);
        let r = f();
        self.stream.reset_time();
        self.stream.set_timepoint(now);
        r
    }

    /// The time of what is logged next.
    pub(crate) fn now(&self) -> rerun::TimePoint {
        self.stream.now()
    }

    /// Logs `what` at `entity` at the current time.
    pub fn log(
        &self,
        entity: impl Into<rerun::EntityPath>,
        what: &impl rerun::AsComponents,
    ) -> CliResult {
        self.stream
            .log(entity, what)
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs `what` at `entity` without time.
    pub fn log_static(
        &self,
        entity: impl Into<rerun::EntityPath>,
        what: &impl rerun::AsComponents,
    ) -> CliResult {
        self.stream
            .log_static(entity, what)
            .map_err(|e| fail(&self.path, e))
    }

    /// Sends whole columns (one chunk) at `entity`.
    pub fn send_columns(
        &self,
        entity: impl Into<rerun::EntityPath>,
        times: impl IntoIterator<Item = rerun::TimeColumn>,
        columns: impl IntoIterator<Item = rerun::SerializedComponentColumn>,
    ) -> CliResult {
        self.stream
            .send_columns(entity, times, columns)
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs a line of the run's event log (`events`, a text log) at the current time.
    pub fn event(&self, text: &str) -> CliResult {
        self.log(
            "events",
            &rerun::TextLog::new(text).with_level(rerun::TextLogLevel::INFO),
        )
    }

    /// Marks the end of step `k` (a SLAM update, a whisk) of a command: every
    /// [`STEPS_PER_CHECKPOINT`]-th is a checkpoint. (A chunk per entity per step would
    /// cost more in chunk headers than in data.)
    pub fn step_done(&self, k: usize) -> CliResult {
        if (k + 1).is_multiple_of(STEPS_PER_CHECKPOINT) {
            self.checkpoint()?;
        }
        Ok(())
    }

    /// Writes what has been logged so far (a fixed point of the simulation).
    pub fn checkpoint(&self) -> CliResult {
        self.stream
            .flush_blocking()
            .map_err(|e| fail(&self.path, e))
    }

    /// Completes the file and moves it into place.
    pub fn finish(mut self) -> CliResult {
        self.checkpoint()?;
        self.stream.disconnect();
        self.finished = true;
        output::commit(&self.tmp, &self.path)
    }
}

impl Drop for Recording {
    fn drop(&mut self) {
        if !self.finished {
            self.stream.disconnect();
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// An `[f32; 3]` of a point or vector in metres.
pub(crate) fn f32x3(v: &nalgebra::Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}
