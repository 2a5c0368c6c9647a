//! The Rerun recordings (`.rrd`) of every command that simulates or runs SLAM, for
//! headless inspection: open one later with `rerun FILE.rrd`. [`Rerun`] makes them: it
//! implements the experiments' recording interface (`whisker_experiments::record`). The
//! entity tree, one row per entity (path, archetype, timeline, rate), is documented in
//! `docs/recording.md`; its entities are written by [`world`] (the scene), [`sensors`] (the
//! 2 kHz streams), [`slam`] (the SLAM state and the closed loop's decisions) and read back
//! by [`decode`].
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

// A library says what it does through its caller (reports, `Reporter`), never on the
// console itself.
#![deny(clippy::print_stdout, clippy::print_stderr)]

mod blueprint;
pub mod decode;
mod sensors;
mod slam;
mod world;

use std::path::{Path, PathBuf};
use whisker_scenario::files;
use whisker_scenario::{Error, Result};

use nalgebra::Isometry3;
pub use whisker_experiments::record::SIM_TIME;
use whisker_experiments::record::{Contact, ContactKind, Graph, Layout, Recorder, Recordings};
use whisker_sim::environment::{Environment, Mesh};
use whisker_slam::pose_grid::PoseGrid;
use whisker_slam::ratslam::local_view::TactileImage;

/// Makes Rerun recordings.
pub struct Rerun;

impl Recordings for Rerun {
    fn create(&self, path: &Path, id: &str, layout: Layout) -> Result<Box<dyn Recorder>> {
        Ok(Box::new(Recording::create(
            path,
            id,
            blueprint::of(&layout),
        )?))
    }
}

/// A recording being written.
pub struct Recording {
    stream: rerun::RecordingStream,
    tmp: PathBuf,
    path: PathBuf,
    finished: bool,
    /// Contacts waiting for their other half (ground truth or estimate) of a cycle.
    pending: std::sync::Mutex<world::Pending>,
    /// Links of the arm logged (their axes are logged at the end).
    links: std::sync::atomic::AtomicUsize,
}

pub(crate) fn fail(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Failure(format!("cannot write recording {}: {e}", path.display()))
}

impl Recording {
    /// Starts a recording to be saved at `path`, identified by `recording_id`, that opens
    /// on `layout` in the viewer.
    pub fn create(path: &Path, recording_id: &str, layout: blueprint::Viewer) -> Result<Self> {
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            files::create_dir(parent)?;
        }
        let tmp = files::temporary(path);
        let stream = rerun::RecordingStreamBuilder::new("whisker")
            .recording_id(recording_id)
            .batcher_config(rerun::log::ChunkBatcherConfig::NEVER)
            .save(&tmp)
            .map_err(|e| fail(path, e))?;
        stream.set_log_time_enabled(false);
        // Named in the viewer's list of recordings by its id (the name alone: the
        // builder's properties would add the wall-clock start time, and the same seed
        // would no longer give the same content).
        stream
            .send_recording_name(recording_id)
            .map_err(|e| fail(path, e))?;
        send_viewer(&stream, layout).map_err(|e| fail(path, e))?;
        let rec = Self {
            stream,
            tmp,
            path: path.to_path_buf(),
            finished: false,
            pending: Default::default(),
            links: Default::default(),
        };
        rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())?;
        rec.log_static(
            "legend",
            &rerun::TextDocument::new(blueprint::LEGEND)
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        Ok(rec)
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
    ) -> Result {
        self.stream
            .log(entity, what)
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs `what` at `entity` without time.
    pub fn log_static(
        &self,
        entity: impl Into<rerun::EntityPath>,
        what: &impl rerun::AsComponents,
    ) -> Result {
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
    ) -> Result {
        self.stream
            .send_columns(entity, times, columns)
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs a line of the run's event log (`events`, a text log) at the current time.
    pub fn event(&self, text: &str) -> Result {
        self.log(
            "events",
            &rerun::TextLog::new(text).with_level(rerun::TextLogLevel::INFO),
        )
    }

    /// Writes what has been logged so far (a fixed point of the simulation).
    pub fn checkpoint(&self) -> Result {
        self.stream
            .flush_blocking()
            .map_err(|e| fail(&self.path, e))
    }

    /// Completes the file and moves it into place.
    pub fn finish_file(mut self) -> Result {
        self.checkpoint()?;
        self.stream.disconnect();
        self.finished = true;
        files::commit(&self.tmp, &self.path)
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

/// Sends `viewer` into `stream` as its active blueprint: the blueprint's own messages and
/// its views' properties in the same blueprint store, then the activation.
fn send_viewer(
    stream: &rerun::RecordingStream,
    viewer: blueprint::Viewer,
) -> rerun::RecordingStreamResult<()> {
    use rerun::log::LogMsg;
    let (memory, storage) = rerun::RecordingStreamBuilder::new("whisker").memory()?;
    viewer.blueprint.send(
        &memory,
        rerun::blueprint::BlueprintActivation {
            make_active: true,
            make_default: true,
        },
    )?;
    let mut messages = Vec::new();
    let mut activation = None;
    for m in storage.take() {
        match m {
            LogMsg::BlueprintActivationCommand(c) => activation = Some(c),
            m if m.store_id().kind() == rerun::StoreKind::Blueprint => messages.push(m),
            _ => {}
        }
    }
    let Some(activation) = activation else {
        return Ok(());
    };
    let (properties, stored) = rerun::RecordingStreamBuilder::new("whisker")
        .recording_id(activation.blueprint_id.recording_id().clone())
        .blueprint()
        .memory()?;
    properties.set_time_sequence("blueprint", 0);
    for (path, batches) in viewer.properties {
        properties.log_serialized_batches(path, false, batches)?;
    }
    messages.extend(
        stored
            .take()
            .into_iter()
            .filter(|m| matches!(m, LogMsg::ArrowMsg(..))),
    );
    stream.send_blueprint(messages, activation);
    Ok(())
}

/// An `[f32; 3]` of a point or vector in metres.
pub(crate) fn f32x3(v: &nalgebra::Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The experiments' recording interface on Rerun: each method logs the archetypes
/// `docs/recording.md` lists for its entities.
impl Recorder for Recording {
    fn at(&self, t: f64) {
        Recording::at(self, t)
    }
    fn at_step(&self, timeline: &'static str, k: u64) {
        Recording::at_step(self, timeline, k)
    }
    fn checkpoint(&self) -> Result {
        Recording::checkpoint(self)
    }
    fn finish(self: Box<Self>) -> Result {
        self.finish_file()
    }
    fn event(&self, text: &str) -> Result {
        Recording::event(self, text)
    }
    fn frame(&self, entity: &str, translation: [f64; 3]) -> Result {
        self.log_static(
            entity,
            &rerun::Transform3D::from_translation(translation.map(|v| v as f32)),
        )
    }
    fn mesh(&self, entity: &str, mesh: &Mesh, colour: [u8; 3]) -> Result {
        let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| f32x3(&v.coords)).collect();
        let [r, g, b] = colour;
        self.log_static(
            entity,
            &rerun::Mesh3D::new(positions)
                .with_triangle_indices(mesh.triangles.iter().copied())
                .with_albedo_factor(rerun::Rgba32::from_unmultiplied_rgba(r, g, b, 255)),
        )
    }
    fn environment_in(&self, prefix: &str, environment: &Environment) -> Result {
        Recording::environment_in(self, prefix, environment)
    }
    fn waypoints(&self, tips: &[Isometry3<f64>]) -> Result {
        Recording::waypoints(self, tips)
    }
    fn arm(&self, t: f64, links: &[Isometry3<f64>], tip: &Isometry3<f64>) -> Result {
        Recording::arm(self, t, links, tip)
    }
    fn pose(&self, entity: &str, pose: &Isometry3<f64>) -> Result {
        self.log(entity, &world::transform(pose))
    }
    fn tip_path(&self, path: &[Isometry3<f64>]) -> Result {
        Recording::tip_path(self, path)
    }
    fn arm_at_whisk(
        &self,
        t: f64,
        whisk: u64,
        (links, tip): (&[Isometry3<f64>], &Isometry3<f64>),
        recent: &[Isometry3<f64>],
    ) -> Result {
        self.at(t);
        self.at_step("whisk", whisk);
        Recording::arm_now(self, links, tip)?;
        let strip: Vec<[f32; 3]> = recent.iter().map(world::point).collect();
        self.log(
            "world/arm/tip_path",
            &rerun::LineStrips3D::new([strip]).with_radii([rerun::Radius::new_ui_points(1.5)]),
        )
    }
    fn frame_axes(&self) -> Result {
        Recording::frame_axes(self)
    }
    fn shafts_at(&self, entity: &str, t: f64, shafts: &[Vec<[f64; 3]>]) -> Result {
        Recording::shafts_at(self, entity, t, shafts)
    }
    fn contacts_in(
        &self,
        prefix: &str,
        kind: ContactKind,
        cycle: u64,
        contacts: &[Contact],
    ) -> Result {
        Recording::contacts_in(self, prefix, kind, cycle, contacts)
    }
    fn marker(
        &self,
        entity: &str,
        point: [f64; 3],
        radius: f64,
        colour: Option<[u8; 3]>,
    ) -> Result {
        let points = rerun::Points3D::new([point.map(|v| v as f32)]).with_radii([radius as f32]);
        match colour {
            Some([r, g, b]) => self.log(
                entity,
                &points.with_colors([rerun::Color::from_rgb(r, g, b)]),
            ),
            None => self.log(entity, &points),
        }
    }
    fn trajectory(&self, entity: &str, points: &[[f64; 3]], colour: [u8; 3]) -> Result {
        Recording::trajectory(self, entity, points, colour)
    }
    fn relocalisation(&self, entity: &str, at: &Isometry3<f64>, text: &str) -> Result {
        Recording::relocalisation(self, entity, at, text)
    }
    fn goal(&self, pose: &Isometry3<f64>, kind: &str) -> Result {
        Recording::goal(self, pose, kind)
    }
    fn tactile_image(&self, entity: &str, image: &TactileImage) -> Result {
        Recording::tactile_image(self, entity, image)
    }
    fn pose_cells(&self, entity: &str, grid: &PoseGrid) -> Result {
        Recording::pose_cells(self, entity, grid)
    }
    fn graph(&self, entity: &str, graph: &Graph) -> Result {
        Recording::graph(self, entity, graph)
    }
    fn labelled_2d(
        &self,
        entity: &str,
        points: &[[f64; 2]],
        labels: &[String],
        [r, g, b]: [u8; 3],
    ) -> Result {
        let point = |p: &[f64; 2]| [p[0] as f32, p[1] as f32];
        self.log(
            entity,
            &rerun::Points2D::new(points.iter().map(point))
                .with_labels(labels.iter().map(String::as_str))
                .with_colors([rerun::Color::from_rgb(r, g, b)])
                .with_radii([rerun::Radius::new_ui_points(6.0)])
                .with_show_labels(true),
        )
    }
    fn scalar(&self, entity: &str, value: f64) -> Result {
        Recording::scalar(self, entity, value)
    }
    fn sensor_series(&self, entity: &str) -> Result {
        Recording::sensor_series(self, entity)
    }
    fn sensor_columns(&self, entity: &str, times: &[f64], values: Vec<f64>) -> Result {
        Recording::sensor_columns(self, entity, times, values)
    }
}
