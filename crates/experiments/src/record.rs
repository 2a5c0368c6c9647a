//! What the experiments record for inspection, and where they say what they do.
//!
//! An experiment emits what it has — the scene (environment, arm, array, shafts, contacts,
//! goals), the 2 kHz sensor streams, the SLAM state (tactile images, pose cells, maps),
//! scalars and events — through a [`Recorder`], at entity paths that name what each thing
//! is (`world/contacts/true`, `slam/<run>/map`; `docs/recording.md`). How it is drawn and
//! stored is the recorder's business: the `whisker-recording` crate writes Rerun files;
//! an experiment does not know Rerun. Recordings are made by a [`Recordings`] factory and
//! messages go to a [`Reporter`], both handed in by the caller in a [`Context`].
//!
//! Reproducibility: nothing is batched on a timer; data is written at the checkpoints an
//! experiment places at fixed points of the simulation ([`Recorder::checkpoint`],
//! [`Recorder::step_done`]), so that one seed gives the same content whatever the thread
//! count.

use nalgebra::Isometry3;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};
use whisker_sim::environment::{Environment, Mesh};
use whisker_sim::whisker::control::ControlState;
use whisker_slam::pose_grid::PoseGrid;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::sensor::Sample;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// Steps (SLAM updates, whisks) between checkpoints.
pub const STEPS_PER_CHECKPOINT: usize = 50;

/// The simulated-time timeline (seconds).
pub const SIM_TIME: &str = "sim_time";

/// Values per row of a whisker's stream (`sensors/<label>`).
pub const SENSOR_VALUES: usize = 6;
/// The series of a whisker's stream, in row order: the whisk angle (degrees), the x and y
/// deflections (ADC counts) and the whisking strategies' state (§2.3.1; NaN when not
/// known): `rcp` 1 while the controller retracts early (§3.2.2), `spread_reduction` 1
/// while the stroke is narrowed, `asymmetry_hold` 1 while its side holds protraction.
pub const SENSOR_SERIES: [&str; SENSOR_VALUES] = [
    "angle_deg",
    "x_counts",
    "y_counts",
    "rcp",
    "spread_reduction",
    "asymmetry_hold",
];
/// Samples buffered before they are sent (one simulated second at 2 kHz).
const SENSOR_BATCH: usize = 2000;

/// One contact: the whisker (module index 0–17) and the point (world, m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    pub whisker: usize,
    pub point: [f64; 3],
}

/// Which contacts: the ground truth or the estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum ContactKind {
    /// `<prefix>/true`: the anticipated intersect of the rigid sweep, no noise.
    True,
    /// `<prefix>/estimated`: what the sensing reported (front end + radial model, or the
    /// kinematic contact with its noise).
    Estimated,
}

/// One experience graph: positions (map frame, m) and links.
pub struct Graph<'a> {
    /// Each experience's position (x, y) in the map, m.
    pub positions: Vec<[f64; 2]>,
    /// Each link (from, to).
    pub links: Vec<(usize, usize)>,
    /// The current experience.
    pub current: Option<usize>,
    /// The experience the strategy is heading for.
    pub target: Option<usize>,
    /// Each experience's object (appended maps), for the label.
    pub objects: Option<&'a [Option<String>]>,
}

/// Experiences of a map logged in full at most about this often: every update while the
/// map is small, then every k-th with k growing with the map (bounding the file).
const GRAPH_BUDGET: usize = 100;

/// Decides which updates log the whole map ([`GRAPH_BUDGET`]): the first, then every
/// (1 + n / budget)-th for a map of n experiences, and the last.
#[derive(Debug, Default)]
pub struct GraphSchedule {
    updates: usize,
}

impl GraphSchedule {
    /// Whether to log the map of `experiences` at this update (always when `last`).
    pub fn due(&mut self, experiences: usize, last: bool) -> bool {
        let every = 1 + experiences / GRAPH_BUDGET;
        let due = last || self.updates.is_multiple_of(every);
        self.updates += 1;
        due
    }
}

/// Half the angle (degrees) of the cone [`Eye::framing`] fits a scene's bounding sphere in.
const FRAMED_HALF_ANGLE: f64 = 22.0;

/// Where a 3-D view's camera opens: its position and the point it looks at (world, m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eye {
    pub position: [f64; 3],
    pub target: [f64; 3],
}

impl Eye {
    /// A camera framing the box `lo`..`hi` (world, m, z up) whole: looking at its centre
    /// from the front left (−x, −y) and above, at about 40° of elevation, far enough that
    /// the box's bounding sphere fits a 44° cone (the viewer's vertical field of view is
    /// 55°, narrower across in a view taller than wide).
    pub fn framing(lo: [f64; 3], hi: [f64; 3]) -> Self {
        let c = [0, 1, 2].map(|i| (lo[i] + hi[i]) / 2.0);
        let radius = ((0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt() / 2.0).max(0.05);
        let distance = radius / FRAMED_HALF_ANGLE.to_radians().sin();
        let dir = [-0.55, -0.75, 0.9];
        let norm = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
        Self {
            position: [0, 1, 2].map(|i| c[i] + dir[i] / norm * distance),
            target: c,
        }
    }

    /// The array's reach about its pose `array` (world): the six points at the longest
    /// whisker's length plus its ring's radius along ± each of the array's axes; to frame
    /// with [`Eye::of`].
    pub fn reach(array: &Isometry3<f64>) -> Vec<[f64; 3]> {
        let reach = whisker_sim::whisker::array::RINGS
            .iter()
            .map(|(length, radius, _)| length + radius)
            .fold(0.0, f64::max);
        (0..3)
            .flat_map(|i| [-reach, reach].map(|r| (i, r)))
            .map(|(i, r)| {
                (array * nalgebra::Point3::from(nalgebra::Vector3::ith(i, r)))
                    .coords
                    .into()
            })
            .collect()
    }

    /// [`Eye::framing`] of [`bounds`]`(environment, points)`; none when there is nothing.
    pub fn of(environment: &Environment, points: &[[f64; 3]]) -> Option<Self> {
        bounds(environment, points).map(|(lo, hi)| Self::framing(lo, hi))
    }
}

/// The axis-aligned bounds (lowest, highest corner; world, m) of the pieces of
/// `environment` (their meshes' vertices in the world) and `points`; none when there is
/// nothing.
pub fn bounds(environment: &Environment, points: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let world = environment.pieces.iter().flat_map(|p| {
        p.mesh
            .vertices
            .iter()
            .map(move |v| (p.pose * v).coords.into())
    });
    let all: Vec<[f64; 3]> = world.chain(points.iter().copied()).collect();
    if all.is_empty() {
        return None;
    }
    let lo = [0, 1, 2].map(|i| all.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1, 2].map(|i| all.iter().map(|p| p[i]).fold(f64::NEG_INFINITY, f64::max));
    Some((lo, hi))
}

/// Cases given a tab of their own in a [`Layout::Cases`] (a data set may have hundreds; the
/// rest stay in the viewer's streams tree, to drag into a plot).
pub const CASE_TABS: usize = 30;

/// The layout a recording opens on in a viewer.
#[derive(Debug, Clone, PartialEq)]
pub enum Layout {
    /// `whisker run` without a closed loop: the scene (camera at `eye`), and with physics
    /// whiskers their streams.
    Run { physics: bool, eye: Option<Eye> },
    /// `whisker soak` and `radial generate`: the cases' scenes side by side (the camera at
    /// `eye`, framing the first), and a tab per case (`sensors/<case>`, the first
    /// [`CASE_TABS`] of `cases`) with its whiskers' streams.
    Cases {
        cases: Vec<String>,
        eye: Option<Eye>,
    },
    /// A closed loop (Ch 6): the scene (camera at `eye`), confidence, the object map, pose
    /// cells, events, on the whisk timeline.
    ClosedLoop { eye: Option<Eye> },
    /// A SLAM command over several runs (`maze-slam`, `object-slam`): per run its input
    /// image (when `images`), pose cells and map, on timeline `timeline`; the scene's
    /// camera at `eye`.
    SlamRuns {
        runs: Vec<String>,
        images: bool,
        timeline: &'static str,
        eye: Option<Eye>,
    },
}

/// A recording being written. Every method logs at the time set last by [`Self::at`] (and
/// [`Self::at_step`]), except the static ones. `Sync`, so that a run holding one can move
/// between threads (the Python package steps closed loops on several).
pub trait Recorder: Sync {
    /// Sets the simulated time (s) of what is logged next, and no other timeline.
    fn at(&self, t: f64);
    /// Adds a sequence timeline (`update`, `whisk`) to the time of what is logged next
    /// (after [`Self::at`], which clears it).
    fn at_step(&self, timeline: &'static str, k: u64);
    /// Writes what has been logged so far (a fixed point of the simulation).
    fn checkpoint(&self) -> Result;
    /// Completes the recording and moves it into place.
    fn finish(self: Box<Self>) -> Result;

    /// A line of the event log (`events`).
    fn event(&self, text: &str) -> Result;
    /// A static frame at `entity`, translated by `translation` (m) from its parent.
    fn frame(&self, entity: &str, translation: [f64; 3]) -> Result;
    /// A static triangle mesh at `entity` (its own frame) in `colour`.
    fn mesh(&self, entity: &str, mesh: &Mesh, colour: [u8; 3]) -> Result;
    /// The environment's pieces as static meshes at `<prefix>/<piece>`.
    fn environment_in(&self, prefix: &str, environment: &Environment) -> Result;
    /// The tip positions at the waypoints (`world/waypoints`, static).
    fn waypoints(&self, tips: &[Isometry3<f64>]) -> Result;
    /// The arm at time `t`: its link frames along the chain from the root, a line through
    /// their origins and the tip frame (`world/arm/…`).
    fn arm(&self, t: f64, links: &[Isometry3<f64>], tip: &Isometry3<f64>) -> Result;
    /// The arm as [`Recorder::arm`] at whisk `whisk` (also on the `whisk` timeline), with
    /// the tip's `recent` path (`world/arm/tip_path`, the last whisks': a trail, not the
    /// whole run scribbled over the scene).
    fn arm_at_whisk(
        &self,
        t: f64,
        whisk: u64,
        arm: (&[Isometry3<f64>], &Isometry3<f64>),
        recent: &[Isometry3<f64>],
    ) -> Result;
    /// The axes of the tip, link and array frames (static).
    fn frame_axes(&self) -> Result;
    /// A frame's pose at `entity`.
    fn pose(&self, entity: &str, pose: &Isometry3<f64>) -> Result;
    /// The whole tip path (`world/arm/tip_path`, static) and the axes of the frames.
    fn tip_path(&self, path: &[Isometry3<f64>]) -> Result;
    /// Whisker shafts at `entity` at time `t`, each base to tip (world).
    fn shafts_at(&self, entity: &str, t: f64, shafts: &[Vec<[f64; 3]>]) -> Result;
    /// The contacts of whisk cycle `cycle` of one kind at `<prefix>/true` or
    /// `<prefix>/estimated`; once both kinds of a cycle are in, the error between them.
    fn contacts_in(
        &self,
        prefix: &str,
        kind: ContactKind,
        cycle: u64,
        contacts: &[Contact],
    ) -> Result;
    /// One point at `entity` (world, m) of `radius` (m), in `colour` if given.
    fn marker(&self, entity: &str, point: [f64; 3], radius: f64, colour: Option<[u8; 3]>)
    -> Result;
    /// A whole path (world) as a static line at `entity`.
    fn trajectory(&self, entity: &str, points: &[[f64; 3]], colour: [u8; 3]) -> Result;
    /// A re-localisation: a point at the true pose (at `entity`) and a line of the event
    /// log.
    fn relocalisation(&self, entity: &str, at: &Isometry3<f64>, text: &str) -> Result;
    /// A closed loop's goal of kind `kind` (`face:<k>`, `spc`, `step:<e>`).
    fn goal(&self, pose: &Isometry3<f64>, kind: &str) -> Result;
    /// A tactile image (6 × 3, intensities 0–255) at `entity`.
    fn tactile_image(&self, entity: &str, image: &TactileImage) -> Result;
    /// The pose-cell activity of `grid` (planar or 6-D) at `entity`.
    fn pose_cells(&self, entity: &str, grid: &PoseGrid) -> Result;
    /// An experience graph under `entity`, in map space.
    fn graph(&self, entity: &str, graph: &Graph) -> Result;
    /// Points of a 2-D view (map space, m) at `entity`, their labels shown.
    fn labelled_2d(
        &self,
        entity: &str,
        points: &[[f64; 2]],
        labels: &[String],
        colour: [u8; 3],
    ) -> Result;
    /// One scalar at `entity`.
    fn scalar(&self, entity: &str, value: f64) -> Result;
    /// Names the series of a whisker's stream at `entity` ([`SENSOR_SERIES`], static).
    fn sensor_series(&self, entity: &str) -> Result;
    /// Rows of a whisker's stream at `entity`: `values` holds [`SENSOR_VALUES`] values per
    /// time of `times` (s).
    fn sensor_columns(&self, entity: &str, times: &[f64], values: Vec<f64>) -> Result;

    /// Marks the end of step `k` (a SLAM update, a whisk): every
    /// [`STEPS_PER_CHECKPOINT`]-th is a checkpoint.
    fn step_done(&self, k: usize) -> Result {
        if (k + 1).is_multiple_of(STEPS_PER_CHECKPOINT) {
            self.checkpoint()?;
        }
        Ok(())
    }
    /// The environment at `world/environment`.
    fn environment(&self, environment: &Environment) -> Result {
        self.environment_in("world/environment", environment)
    }
    /// The array frame at time `t` (`world/array`).
    fn array(&self, t: f64, pose: &Isometry3<f64>) -> Result {
        self.at(t);
        self.pose("world/array", pose)
    }
    /// The 18 shafts at time `t` (`world/whiskers`).
    fn shafts(&self, t: f64, shafts: &[Vec<[f64; 3]>]) -> Result {
        self.shafts_at("world/whiskers", t, shafts)
    }
    /// The contacts of whisk cycle `cycle` (starting at `t`) at `world/contacts/…`.
    fn contacts(&self, kind: ContactKind, cycle: u64, t: f64, contacts: &[Contact]) -> Result {
        self.at(t);
        self.contacts_in("world/contacts", kind, cycle, contacts)
    }
    /// A WhiskerRatSLAM object map under `entity` ([`Self::graph`]), `current` and the
    /// strategy's `target` highlighted; appended maps' experiences labelled with their
    /// object.
    fn object_map(
        &self,
        entity: &str,
        map: &ObjectMap,
        current: Option<usize>,
        target: Option<usize>,
    ) -> Result {
        let objects: Vec<Option<String>> =
            map.experiences.iter().map(|e| e.object.clone()).collect();
        self.graph(
            entity,
            &Graph {
                positions: map
                    .experiences
                    .iter()
                    .map(|e| [e.position_m[0], e.position_m[1]])
                    .collect(),
                links: map.links.iter().map(|l| (l.from, l.to)).collect(),
                current,
                target,
                objects: Some(&objects),
            },
        )
    }
}

/// Makes recordings: the CLI's writes Rerun files (`whisker-recording`).
pub trait Recordings: Sync {
    /// Starts a recording to be saved at `path`, identified by `id`, opening on `layout`.
    fn create(&self, path: &Path, id: &str, layout: Layout) -> Result<Box<dyn Recorder>>;
}

/// Records nothing: a request for a recording is an error (for library users and tests
/// that do not record; `Target::off` asks for none).
pub struct NoRecordings;

impl Recordings for NoRecordings {
    fn create(&self, path: &Path, _: &str, _: Layout) -> Result<Box<dyn Recorder>> {
        Err(Error::Failure(format!(
            "cannot write recording {}: this program records nothing",
            path.display()
        )))
    }
}

/// Hears what an experiment says while it runs: `say` what it is and does (the CLI's
/// stdout, a trial's `stdout.txt`), `note` progress and warnings (stderr).
pub trait Reporter: Sync {
    /// A line of the experiment's account.
    fn say(&self, line: &str);
    /// A line of progress or a warning.
    fn note(&self, line: &str);
    /// A passing status, replaced by the next one (an empty one clears it).
    fn status(&self, _text: &str) {}
    /// Progress of a long step: `done` of `total` `what` (e.g. "whisks"); the console
    /// shows a bar with a time estimate and clears it when `done` reaches `total`.
    fn progress(&self, _what: &str, _done: u64, _total: u64) {}
}

/// Hears nothing.
pub struct Silent;

impl Reporter for Silent {
    fn say(&self, _: &str) {}
    fn note(&self, _: &str) {}
}

/// What an experiment needs from its caller besides its settings: where recordings are
/// made and who hears what it says.
#[derive(Clone, Copy)]
pub struct Context<'a> {
    pub recordings: &'a dyn Recordings,
    pub reporter: &'a dyn Reporter,
}

impl Context<'_> {
    /// Says every line of `text` ([`Reporter::say`]).
    pub fn say(&self, text: &str) {
        text.lines().for_each(|l| self.reporter.say(l));
    }

    /// Reports progress ([`Reporter::progress`]).
    pub fn progress(&self, what: &str, done: u64, total: u64) {
        self.reporter.progress(what, done, total);
    }

    /// Notes every line of `text` ([`Reporter::note`]).
    pub fn note(&self, text: &str) {
        text.lines().for_each(|l| self.reporter.note(l));
    }

    /// The recording `run.rrd` of a scenario run into `dir` (named after the scenario's
    /// `file` and `seed`, or `target.id`) unless `target` or the scenario (`on`: its
    /// `output.recording`) switch it off; `target.rrd` chooses another file.
    pub fn scenario_recording(
        &self,
        file: &Path,
        seed: u64,
        on: bool,
        dir: &Path,
        target: &Target,
        layout: Layout,
    ) -> Result<Option<Box<dyn Recorder>>> {
        let Some(path) = target.path(Some(dir), on) else {
            return Ok(None);
        };
        let stem = file.file_stem().unwrap_or_default().to_string_lossy();
        let name = target.id.clone().unwrap_or_else(|| id(&stem, seed));
        self.recordings.create(&path, &name, layout).map(Some)
    }
}

impl Context<'static> {
    /// No recordings, no messages.
    pub const QUIET: Self = Self {
        recordings: &NoRecordings,
        reporter: &Silent,
    };
}

/// Where a command writes its recording (`--rrd FILE` / `--no-rrd`).
#[derive(Debug, Clone, Default)]
pub struct Target {
    /// The recording's file [default: run.rrd in the output directory].
    pub rrd: Option<PathBuf>,
    /// No recording.
    pub no_rrd: bool,
    /// The recording id, when not the default `<scenario>-seed<seed>` (a batch trial's
    /// names its trial).
    pub id: Option<String>,
}

impl Target {
    /// No recording.
    pub fn off() -> Self {
        Self {
            no_rrd: true,
            ..Self::default()
        }
    }

    /// The recording's path: `rrd`, else `run.rrd` in `dir` (the command's output
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

/// The recording id of `name` (a scenario's file stem, or a command) with `seed`.
pub fn id(name: &str, seed: u64) -> String {
    format!("{name}-seed{seed}")
}

/// An entity path segment from a name: letters and digits kept, the rest `_`.
pub fn entity_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

/// The whiskers' 2 kHz streams not yet in the recording (`<prefix>/<label>`): per whisker
/// one row per sample of [`SENSOR_VALUES`] values, sent in columns, a chunk per whisker
/// per simulated second, not a call per sample. The values are those of `whiskers.csv`
/// (the angle there in radians).
#[derive(Debug, Default)]
pub struct SensorColumns {
    times: Vec<f64>,
    /// Per whisker (module order), SENSOR_VALUES values per sample.
    values: Vec<Vec<f64>>,
    /// Each whisker's entity path.
    entities: Vec<String>,
}

impl SensorColumns {
    /// Columns for the whiskers labelled `labels` at `<prefix>/<label>` (`prefix`:
    /// `sensors`, or `sensors/<case>`), their series named on `rec`.
    pub fn new(rec: &dyn Recorder, prefix: &str, labels: &[String]) -> Result<Self> {
        let entities: Vec<String> = labels.iter().map(|l| format!("{prefix}/{l}")).collect();
        for e in &entities {
            rec.sensor_series(e)?;
        }
        Ok(Self {
            times: Vec::with_capacity(SENSOR_BATCH),
            values: vec![Vec::with_capacity(SENSOR_BATCH * SENSOR_VALUES); labels.len()],
            entities,
        })
    }

    /// Takes every whisker's sample of time `t` (s) and its strategies' state (NaN in
    /// the recording when not known); sends a full batch.
    pub fn push(
        &mut self,
        rec: &dyn Recorder,
        t: f64,
        samples: &[Sample],
        states: Option<&[ControlState]>,
    ) -> Result {
        self.times.push(t);
        let flag = |b: bool| f64::from(u8::from(b));
        for (w, (v, s)) in self.values.iter_mut().zip(samples).enumerate() {
            let [r, n, h] = states.map_or([f64::NAN; 3], |c| {
                [flag(c[w].rcp), flag(c[w].narrowed), flag(c[w].held)]
            });
            v.extend([s.angle_rad.to_degrees(), s.x, s.y, r, n, h]);
        }
        if self.times.len() >= SENSOR_BATCH {
            self.send(rec)?;
        }
        Ok(())
    }

    /// Takes whole streams: `streams[w]` holds whisker w's samples of steps `first + 1`,
    /// `first + 2` … (step k at `start` + k × 0.5 ms; as many steps as the shortest
    /// stream), with the strategies' states when known ([`Self::push`]).
    pub fn push_streams(
        &mut self,
        rec: &dyn Recorder,
        start: f64,
        first: usize,
        streams: &[Vec<Sample>],
        rcp: Option<&[ControlState]>,
    ) -> Result {
        let dt = 1.0 / whisker_slam::sensor::SAMPLE_RATE_HZ;
        let n = streams.iter().map(Vec::len).min().unwrap_or(0);
        for i in 0..n {
            let row: Vec<Sample> = streams.iter().map(|s| s[i]).collect();
            self.push(rec, start + (first + i + 1) as f64 * dt, &row, rcp)?;
        }
        Ok(())
    }

    /// Sends what is buffered (one chunk per whisker).
    pub fn send(&mut self, rec: &dyn Recorder) -> Result {
        if self.times.is_empty() {
            return Ok(());
        }
        for (entity, values) in self.entities.iter().zip(&mut self.values) {
            rec.sensor_columns(entity, &self.times, std::mem::take(values))?;
            values.reserve(SENSOR_BATCH * SENSOR_VALUES);
        }
        self.times.clear();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::Eye;

    #[test]
    fn the_camera_looks_at_the_middle_of_the_box_from_outside_it() {
        let (lo, hi) = ([0.45, -0.1, 0.0], [0.65, 0.1, 0.35]);
        let e = Eye::framing(lo, hi);
        assert_eq!(e.target, [0.55, 0.0, 0.175]);
        // From the front left and above, far enough that every corner is within 22° of
        // the line of sight.
        let d: Vec<f64> = (0..3).map(|i| e.position[i] - e.target[i]).collect();
        assert!(d[0] < 0.0 && d[1] < 0.0 && d[2] > 0.0);
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut widest: f64 = 0.0;
        for corner in 0..8 {
            let p = [0, 1, 2].map(|i| if corner >> i & 1 == 1 { hi[i] } else { lo[i] });
            let to_corner: Vec<f64> = (0..3).map(|i| p[i] - e.position[i]).collect();
            let cos =
                -(0..3).map(|i| to_corner[i] * d[i]).sum::<f64>() / (norm(&to_corner) * norm(&d));
            widest = widest.max(cos.acos().to_degrees());
        }
        assert!(widest <= 22.0 && widest > 15.0, "{widest}°");
        for i in 0..3 {
            assert!(!(lo[i]..=hi[i]).contains(&e.position[i]) || i == 2);
        }
    }
}
