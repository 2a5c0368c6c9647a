//! `whisker bench physics`: how fast the physics sensing mode runs.
//!
//! Cases: the 18-whisker array whisking freely, against the Box (the catalogue object at
//! the pose where the most whiskers touch it, as in `whisker soak`) and in the maze (the
//! most-touched point of a 50 mm grid 100 mm above the board, facing down), each on 1 and
//! 2 worker threads and by every code path measured side by side in the same run:
//!
//! - `released`: Rapier 0.36.1 as released (dense mass matrix, `MultibodyMassMatrix::Dense`)
//!   and the array stepped with a barrier per sample (`PhysicsArray::step`), one world step
//!   per sample (no speed-adaptive steps), the code path before issue #18;
//! - `exact`: the vendored patches 1–2 (`vendor/PATCHES.md`), bit-identical to `released`,
//!   and one task per whisker for the whole run (`PhysicsArray::run`); this and the paths
//!   below split a sample's step while a segment nears a surface fast
//!   (`whisker_sim::sensing::adaptive_step`), which costs the contact cases a little;
//! - `composite`: also patch 5 (the composite-rigid-body assembly of the same matrices,
//!   equal up to rounding);
//! - `once-per-step`: also patch 3 (the mass matrix factorised once per step; the default
//!   until #34);
//! - `explicit-coriolis`: also patch 4 (explicit gyroscopic and Coriolis terms);
//! - `articulated`: patches 3, 4 and 6–9 (the articulated-body factorisation, O(n) in the
//!   chain's DoFs, no dense matrix, explicit gyroscopic and Coriolis terms; the default,
//!   `SolverPath::Articulated`), the follicle's root driven onto the driver's pose instead
//!   of welded to it (`RootDrive::Driven`);
//! - `articulated −<lever>`: the default with one of its levers off
//!   (`SolverPath::levers`), so that each is measured on its own in the same run.
//!
//! `--repeat N` times every path of a case N times in turn and keeps each one's fastest
//! run (the least disturbed on a shared machine; the table's columns are from it).
//!
//! `articulated` is the default; `SolverPath` says why each earlier path was or was not.
//!
//! Then the scaling with segment count (8, 12, 16, 24) against the Box on 2 threads by
//! every path. Reported: the real-time factor (simulated seconds per wall-clock second),
//! the CPU cost per whisker (thread-seconds per simulated second per whisker, the peer's
//! unit: WHISKiT Physics needs about 7 for one whisker, docs/physics.md), and
//! each path's speed-up over `released` and over the default path. Timing is a benchmark, never a test.

use nalgebra::Isometry3;
use serde::Serialize;
use std::fmt;
use std::path::PathBuf;
use std::time::Instant;
use whisker_experiments::record::Context;
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::physics::{
    DT, EnvironmentPiece, Lever, PhysicsArray, SolverPath, StageTimes,
};
use whisker_sim::whisker::array;
use whisker_sim::whisker::beam::Bending;

/// CPU-seconds per simulated second for one whisker of WHISKiT Physics, the reference
/// simulator (docs/physics.md, "The peer").
const WHISKIT_CPU_S_PER_S: f64 = 7.0;

/// What `whisker bench physics` times.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Simulated time per case (s).
    pub duration: f64,
    /// Shaft joint model of every whisker.
    pub bending: Bending,
    /// Rapier substeps per 0.5 ms step.
    pub substeps: usize,
    /// Segments per whisker [default: the array's].
    pub segments: Option<usize>,
    /// The scenario whose `[maze]` is the maze case.
    pub maze: PathBuf,
    /// Skip the segment-count scaling (8/12/16/24).
    pub no_scaling: bool,
    /// Time only this code path [default: all].
    pub path: Option<SolverPath>,
    /// Instead: Rapier's stage timers for the array against the Box on 1 thread.
    pub stages: bool,
    /// Times every path of a case this many times, in turn (all paths once, then again),
    /// and keeps each one's fastest run: on a shared machine the slow runs are the
    /// disturbed ones, and taking turns spreads a slow spell over every path.
    pub repeat: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            duration: 0.5,
            bending: Bending::Spatial,
            substeps: whisker_sim::sensing::physics::DEFAULT_SUBSTEPS,
            segments: None,
            maze: PathBuf::from("scenarios/maze.toml"),
            no_scaling: false,
            path: None,
            stages: false,
            repeat: 1,
        }
    }
}

/// One timed case.
struct Case<'a> {
    name: &'a str,
    environment: &'a [EnvironmentPiece],
    pose: Isometry3<f64>,
    segments: Option<usize>,
}

/// Wall-clock seconds to simulate `duration` of the 18 whiskers of `case` by `path`, and
/// Rapier's stage timers summed over the whiskers.
fn time_case(
    case: &Case,
    (path, without): (SolverPath, Option<Lever>),
    threads: usize,
    o: &Settings,
) -> Result<(f64, StageTimes)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Failure(e.to_string()))?;
    pool.install(|| {
        let mut configs = whisker_sim::sensing::physics::standard_array(
            array::modules().len(),
            o.bending,
            case.segments.or(o.segments),
            o.substeps,
        );
        for c in &mut configs {
            c.solver = path;
            c.without = without;
            // The released path is the code before #18: one world step per sample too.
            c.adaptive_steps = path != SolverPath::Released;
        }
        let mut array = PhysicsArray::new(configs, case.environment, &case.pose, 0, DT);
        let steps = (o.duration / DT).round() as usize;
        let poses = vec![case.pose; steps];
        let start = Instant::now();
        // The released path also steps as before #18: a barrier per sample.
        match path {
            SolverPath::Released => {
                for pose in &poses {
                    array.step(pose);
                }
            }
            _ => {
                array.run(&poses);
            }
        }
        let wall = start.elapsed().as_secs_f64();
        let stages = array
            .units
            .iter()
            .fold(StageTimes::default(), |a, u| a.plus(u.stages));
        Ok((wall, stages))
    })
}

/// One measured row (`--json`: one object of the list).
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub case: String,
    pub whiskers: usize,
    pub segments: usize,
    pub threads: usize,
    /// The path, or `"<path> −<lever>"`: the default path with one lever off.
    pub path: String,
    pub real_time_factor: f64,
    pub cpu_s_per_sim_s_per_whisker: f64,
    pub speedup_vs_released: Option<f64>,
    /// The default path's wall time over this path's (same case and threads), when the
    /// default was timed.
    pub speedup_vs_default: Option<f64>,
    pub cpu_vs_whiskit: f64,
}

/// The table of `whisker bench physics`.
#[derive(Debug, Clone, Serialize)]
#[serde(transparent)]
pub struct Table {
    pub rows: Vec<Row>,
    #[serde(skip)]
    heading: String,
}

/// Where one path's steps spent their time (`--stages`).
#[derive(Debug, Clone, Serialize)]
pub struct Stages {
    pub path: &'static str,
    pub wall_s: f64,
    pub stages_s: std::collections::BTreeMap<&'static str, f64>,
    /// The stages in the order Rapier runs them, for the table.
    #[serde(skip)]
    order: Vec<(&'static str, f64)>,
    #[serde(skip)]
    heading: String,
}

/// What `whisker bench physics` measured.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Report {
    Table(Table),
    Stages(Vec<Stages>),
}

/// Times `case` by every path (or `--path`) on each of `threads`, noting progress.
fn measure(
    case: &Case,
    threads: &[usize],
    o: &Settings,
    rows: &mut Vec<Row>,
    ctx: Context,
) -> Result {
    let whiskers = array::modules().len();
    let segments = case
        .segments
        .or(o.segments)
        .unwrap_or(array::modules()[0].beam.segments);
    let variants = variants(o);
    for &t in threads {
        let mut walls: Vec<_> = variants.iter().map(|&v| (v, f64::INFINITY)).collect();
        for round in 1..=o.repeat {
            for (variant, best) in &mut walls {
                let (wall, _) = time_case(case, *variant, t, o)?;
                *best = best.min(wall);
                let turn = match o.repeat {
                    1 => String::new(),
                    n => format!(" (run {round} of {n})"),
                };
                ctx.note(&format!(
                    "  {:<26} {segments:>2} segments {t} thread(s) {:<9} {:.3}× real time{turn}",
                    case.name,
                    variant_name(*variant),
                    o.duration / wall,
                ));
            }
        }
        let first = rows.len();
        let released_wall = walls
            .iter()
            .find(|((p, _), _)| *p == SolverPath::Released)
            .map(|&(_, w)| w);
        for &((path, without), wall) in &walls {
            let cpu = t as f64 * wall / o.duration / whiskers as f64;
            rows.push(Row {
                case: case.name.to_string(),
                whiskers,
                segments,
                threads: t,
                path: variant_name((path, without)),
                real_time_factor: o.duration / wall,
                cpu_s_per_sim_s_per_whisker: cpu,
                speedup_vs_released: released_wall
                    .filter(|_| path != SolverPath::Released)
                    .map(|r| r / wall),
                speedup_vs_default: None,
                cpu_vs_whiskit: cpu / WHISKIT_CPU_S_PER_S,
            });
        }
        // Every path against the default, once all are timed.
        let default_wall = walls
            .iter()
            .find(|(p, _)| *p == (SolverPath::default(), None))
            .map(|&(_, w)| w);
        for (row, (_, wall)) in rows[first..].iter_mut().zip(&walls) {
            row.speedup_vs_default = default_wall.map(|d| d / wall);
        }
    }
    Ok(())
}

/// A path's name in the table, or `"<path> −<lever>"` for the default with a lever off.
fn variant_name((path, without): (SolverPath, Option<Lever>)) -> String {
    match without {
        Some(lever) => format!("{} −{}", path.name(), lever.name()),
        None => path.name().to_string(),
    }
}

/// What `measure` times: every path (or `--path`), and after the default the default with
/// each of its levers off in turn (#34: each lever measured on its own).
fn variants(o: &Settings) -> Vec<(SolverPath, Option<Lever>)> {
    let mut list = Vec::new();
    for path in SolverPath::ALL {
        if o.path.is_some_and(|p| p != path) {
            continue;
        }
        list.push((path, None));
        if path == SolverPath::default() {
            list.extend(path.levers().iter().map(|&l| (path, Some(l))));
        }
    }
    list
}

/// Runs `whisker bench physics`.
pub fn physics(o: &Settings, ctx: Context) -> Result<Report> {
    if !(1..=64).contains(&o.substeps) {
        return Err(Error::Input(format!(
            "--substeps: expected 1 to 64, got {}",
            o.substeps
        )));
    }
    if let Some(n) = o.segments
        && !(2..=200).contains(&n)
    {
        return Err(Error::Input(format!(
            "--segments: expected 2 to 200, got {n}"
        )));
    }
    if !(1..=100).contains(&o.repeat) {
        return Err(Error::Input(format!(
            "--repeat: expected 1 to 100, got {}",
            o.repeat
        )));
    }
    if !(o.duration.is_finite() && o.duration > 0.0) {
        return Err(Error::Input(format!(
            "--duration: expected a positive number of seconds, got {}",
            o.duration
        )));
    }
    let boxed = crate::soak::object_case("box")?;
    let maze = crate::soak::maze_case(&o.maze)?;
    let (box_pieces, maze_pieces) = (
        boxed.environment.physics_pieces(),
        maze.environment.physics_pieces(),
    );
    let cases = [
        Case {
            name: "free whisking",
            environment: &[],
            pose: Isometry3::identity(),
            segments: None,
        },
        Case {
            name: "against the Box",
            environment: &box_pieces,
            pose: boxed.pose,
            segments: None,
        },
        Case {
            name: "in the maze",
            environment: &maze_pieces,
            pose: maze.pose,
            segments: None,
        },
    ];
    if o.stages {
        return stages(&cases[1], o).map(Report::Stages);
    }
    let mut rows = Vec::new();
    for case in &cases {
        measure(case, &[1, 2], o, &mut rows, ctx)?;
    }
    if !o.no_scaling {
        for n in [8, 12, 16, 24] {
            let case = Case {
                name: "against the Box",
                segments: Some(n),
                ..cases[1]
            };
            measure(&case, &[2], o, &mut rows, ctx)?;
        }
    }
    let heading = format!(
        "physics sensing of the 18-whisker array, {} s simulated per case at 2 kHz{}, {:?} bending, {} substep(s); \
         {} whiskers touch the Box and {} the maze by the kinematic sweep",
        o.duration,
        match o.repeat {
            1 => String::new(),
            n => format!(" (each path's fastest of {n} runs taken in turn)"),
        },
        o.bending,
        o.substeps,
        boxed.touching.len(),
        maze.touching.len()
    );
    Ok(Report::Table(Table { rows, heading }))
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Report::Table(t) => t.fmt(f),
            Report::Stages(list) => list.iter().try_for_each(|s| s.fmt(f)),
        }
    }
}

impl fmt::Display for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.heading)?;
        writeln!(
            f,
            "{:<18} {:>8} {:>7} {:>32} {:>16} {:>24} {:>11} {:>13} {:>11}",
            "case",
            "segments",
            "threads",
            "path",
            "real-time factor",
            "CPU s / sim s / whisker",
            "vs WHISKiT",
            "speed-up",
            "vs default"
        )?;
        for r in &self.rows {
            writeln!(
                f,
                "{:<18} {:>8} {:>7} {:>32} {:>16.3} {:>24.3} {:>10.3}× {:>13} {:>11}",
                r.case,
                r.segments,
                r.threads,
                r.path,
                r.real_time_factor,
                r.cpu_s_per_sim_s_per_whisker,
                r.cpu_vs_whiskit,
                r.speedup_vs_released
                    .map_or(String::new(), |s| format!("{s:.2}×")),
                r.speedup_vs_default
                    .map_or(String::new(), |s| format!("{s:.2}×"))
            )?;
        }
        writeln!(
            f,
            "released: Rapier 0.36.1 as released, a barrier per sample; exact: vendor/PATCHES.md 1-2 (bit-identical); \
             composite: 1-2, 5 (the same matrices up to rounding); once-per-step: 1-3, 5 (the default until #34); \
             explicit-coriolis: 1-5 (both went non-finite in nudged Mug soaks with fixed steps); articulated: 3, 4, 6-9 (O(n) factorisation, explicit gyroscopic and Coriolis terms; the default); \
             articulated −<lever>: the default with one of its levers off (−reuse-step-kinematics: patch 8, bit-identical; −lazy-jacobians: patch 9, equal up to rounding; −explicit-coriolis: patch 4, the semi-implicit terms back; −load-balance: each whisker's steps in one task in rayon's split, not chunks dearest first; −driven-root: the follicle's root welded to the driver, 6 constraint rows a substep); \
             all but released one task per whisker and speed-adaptive steps. vs WHISKiT: CPU cost / its {WHISKIT_CPU_S_PER_S} CPU-s per simulated s per whisker \
             (below 1: cheaper). Speed-up: released wall time / the path's; vs default: the default path's wall time / this path's; same case and threads."
        )
    }
}

impl fmt::Display for Stages {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.heading)?;
        for (name, s) in &self.order {
            writeln!(
                f,
                "  {name:<36} {s:>8.3} s {:>6.1} %",
                100.0 * s / self.wall_s
            )?;
        }
        Ok(())
    }
}

/// `--stages`: where Rapier's steps spend their time, against the Box on 1 thread.
fn stages(case: &Case, o: &Settings) -> Result<Vec<Stages>> {
    let paths = match o.path {
        Some(p) => vec![p],
        None => vec![
            SolverPath::Released,
            SolverPath::Exact,
            SolverPath::Composite,
            SolverPath::OncePerStep,
            SolverPath::Articulated,
        ],
    };
    let mut list = Vec::new();
    for path in paths {
        let (wall, t) = time_case(case, (path, None), 1, o)?;
        if t.step == 0.0 {
            return Err(Error::Input(
                "--stages: this build has no stage timers; build with \
                 `cargo build --release --features profiler`"
                    .into(),
            ));
        }
        let order = vec![
            ("user changes (driver pose)", t.user_changes),
            ("body update", t.update),
            ("broad phase", t.broad_phase),
            ("narrow phase", t.narrow_phase),
            ("islands", t.islands),
            ("solver: assembly (first substep)", t.velocity_assembly),
            ("solver: substeps", t.velocity_resolution),
            (
                "solver: other",
                t.solver - t.velocity_assembly - t.velocity_resolution,
            ),
            ("CCD", t.ccd),
            ("whisker-slam outside Rapier's step", wall - t.step),
        ];
        list.push(Stages {
            path: path.name(),
            wall_s: wall,
            stages_s: order.iter().copied().collect(),
            heading: format!(
                "{}: 18 whiskers {} for {} s on 1 thread, {wall:.2} s wall",
                path.name(),
                case.name,
                o.duration
            ),
            order,
        });
    }
    Ok(list)
}
