//! `whisker soak`: long physics runs of the whole array whisking against every catalogue
//! object and the maze, checking that no whisker tunnels through a surface and nothing
//! turns NaN. A long experiment, not a test (the test suite runs a short version).
//!
//! Each case holds the array still at the pose (of the `bench sensing` candidates, or a
//! grid over the maze board 100 mm up, facing down) where the most whiskers touch the
//! environment by the kinematic sweep, and whisks open-loop at 1 Hz for `--duration`
//! simulated seconds. Every 10 ms it measures how deep any shaft's centre line lies
//! inside a solid ([`whisker_sim::sensing::physics::WhiskerUnit::shaft_depth`]) and
//! whether any body went non-finite. Exit code 1 if a case tunnels (centre line deeper
//! than the shaft's base radius, 1 mm) or breaks.

use nalgebra::{Isometry3, Vector3};
use rayon::prelude::*;
use serde::Serialize;
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;
use whisker_experiments::record::SensorColumns;
use whisker_experiments::record::{Context, Layout, Recorder};
use whisker_scenario::ScenarioFile;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::Environment;
use whisker_sim::environment::assets::{CATALOGUE, placed};
use whisker_sim::environment::solids::Solids;
use whisker_sim::sensing::physics::{DT, PhysicsArray, SolverPath};
use whisker_sim::sensing::viewpoints;
use whisker_sim::whisker::array;
use whisker_sim::whisker::beam::Bending;
use whisker_sim::whisker::control::ControlState;
use whisker_slam::sensor::Sample;

/// Depth of a shaft's centre line inside a solid that counts as tunnelling (m).
const TUNNEL_DEPTH: f64 = 1.0e-3;

/// The step of `--nudges`: the k-th extra run moves the array k × this along world x (m).
const NUDGE_M: f64 = 1.0e-9;

/// The longest `--duration` (s of simulated time per case).
pub const MAX_DURATION_S: f64 = 3600.0;

/// The most `--nudges`.
pub const MAX_NUDGES: usize = 100;

/// What `whisker soak` runs.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Simulated time per case (s).
    pub duration: f64,
    /// Catalogue objects to run [default: all].
    pub objects: Vec<String>,
    /// A scenario whose `[maze]` is run as one more case (e.g. scenarios/maze.toml).
    pub maze: Option<PathBuf>,
    /// Shaft joint model.
    pub bending: Bending,
    /// Also simulate the whiskers that the kinematic sweep says touch nothing (they whisk
    /// freely and cannot tunnel; by default they are left out to save time).
    pub all_whiskers: bool,
    /// Simulate only these whiskers (pixel labels): each whisker has a world of its own,
    /// so one alone follows exactly its course in the array.
    pub whiskers: Vec<String>,
    /// Rapier substeps per 0.5 ms step.
    pub substeps: usize,
    /// Rapier's multibody code path [default: the whiskers' default].
    pub path: Option<SolverPath>,
    /// One world step per 0.5 ms sample, as before speed-adaptive steps: for comparison.
    pub fixed_steps: bool,
    /// Also run each case N more times, the k-th with the array moved k nm along world x.
    pub nudges: usize,
    /// Write a recording to this file.
    pub rrd: Option<PathBuf>,
}

/// Where a case first tunnelled.
#[derive(Debug, Clone, Serialize)]
pub struct Tunnel {
    pub t_s: f64,
    pub whisker: String,
    pub depth_m: f64,
}

/// One run of a case (`--json`: one object of the list).
#[derive(Debug, Clone, Serialize)]
pub struct CaseReport {
    pub case: String,
    pub pieces: usize,
    pub triangles: usize,
    pub simulated_s: f64,
    pub whiskers_touching_by_sweep: usize,
    pub whiskers_simulated: usize,
    pub max_shaft_depth_m: f64,
    pub non_finite_or_quarantined: bool,
    pub tunnelled: bool,
    pub first_tunnelling: Option<Tunnel>,
    pub wall_s: f64,
    pub world_steps_per_sample: f64,
    pub passed: bool,
    pub nudge_m: f64,
}

impl fmt::Display for CaseReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<10} {:>2} whiskers touching  max centre-line depth {:>7.4} mm  {}  {:>6.0} s wall  {:.2} world steps/sample  {}",
            self.case,
            self.whiskers_touching_by_sweep,
            self.max_shaft_depth_m * 1e3,
            if self.non_finite_or_quarantined {
                "NON-FINITE"
            } else {
                "finite"
            },
            self.wall_s,
            self.world_steps_per_sample,
            if self.passed { "ok" } else { "FAILED" }
        )?;
        if let Some(t) = &self.first_tunnelling {
            writeln!(
                f,
                "           first tunnelling: whisker {} at {:.4} s, {:.3} mm deep",
                t.whisker,
                t.t_s,
                t.depth_m * 1e3
            )?;
        }
        Ok(())
    }
}

/// Spacing of the cases' frames in the recording, along y (m).
const CASE_SPACING_M: f64 = 1.5;

/// What a case puts in the recording: the frame and the streams of its whiskers.
struct CaseRecording<'a> {
    rec: &'a dyn Recorder,
    frame: String,
    columns: SensorColumns,
    /// Whether the controllers run open loop (then the RCP state is known: off).
    open_loop: bool,
}

impl<'a> CaseRecording<'a> {
    fn new(
        rec: &'a dyn Recorder,
        k: usize,
        name: &str,
        environment: &Environment,
        array: &PhysicsArray,
    ) -> Result<Self> {
        let frame = format!(
            "world/cases/{}",
            whisker_experiments::record::entity_name(name)
        );
        rec.frame(&frame, [0.0, CASE_SPACING_M * k as f64, 0.0])?;
        rec.environment_in(&format!("{frame}/environment"), environment)?;
        let labels: Vec<String> = array
            .units
            .iter()
            .map(|u| u.config.module.pixel())
            .collect();
        let columns = SensorColumns::new(
            rec,
            &format!("sensors/{}", whisker_experiments::record::entity_name(name)),
            &labels,
        )?;
        let open_loop = array
            .units
            .iter()
            .all(|u| u.config.control == Default::default());
        Ok(Self {
            rec,
            frame,
            columns,
            open_loop,
        })
    }

    /// Logs the samples of steps `k0 + 1 ..` (per whisker) and the shafts now.
    fn chunk(&mut self, k0: usize, samples: &[Vec<Sample>], array: &PhysicsArray) -> Result {
        let n = samples.first().map_or(0, Vec::len);
        let off = vec![ControlState::default(); samples.len()];
        let rcp = self.open_loop.then_some(off.as_slice());
        self.columns.push_streams(self.rec, 0.0, k0, samples, rcp)?;
        let shafts: Vec<Vec<[f64; 3]>> = array.units.iter().map(|u| u.shaft()).collect();
        self.rec.shafts_at(
            &format!("{}/whiskers", self.frame),
            (k0 + n) as f64 * DT,
            &shafts,
        )
    }

    fn finish(mut self) -> Result {
        self.columns.send(self.rec)?;
        self.rec.checkpoint()
    }
}

/// What a soak case's simulation saw: the deepest shaft inside a solid, whether a whisker
/// went non-finite or was quarantined, and when a shaft first went deeper than 1 mm.
#[derive(Default)]
struct Soaked {
    deepest: f64,
    broken: bool,
    first_tunnel: Option<Tunnel>,
}

/// The recording's layout: a tab per case, the camera on the first case (its environment
/// and the array's reach, the case's frame being the world's).
fn cases_layout(cases: &[(String, Case)]) -> Layout {
    Layout::Cases {
        cases: cases
            .iter()
            .map(|(n, _)| whisker_experiments::record::entity_name(n))
            .collect(),
        eye: cases.first().and_then(|(_, c)| {
            whisker_experiments::record::Eye::of(
                &c.environment,
                &whisker_experiments::record::Eye::reach(&c.pose),
            )
        }),
    }
}

/// Runs one case; says its line and returns its record.
/// `case` (named `name`, its solids `solids`) with the array at `pose` (the case's, or
/// nudged).
fn run_case(
    name: &str,
    case: &Case,
    solids: &Solids,
    pose: Isometry3<f64>,
    o: &Settings,
    recording: Option<(&dyn Recorder, usize)>,
    ctx: Context,
) -> Result<CaseReport> {
    let (environment, touching) = (&case.environment, case.touching.as_slice());
    let configs = whisker_sim::sensing::physics::standard_array(
        array::modules().len(),
        o.bending,
        None,
        o.substeps,
    )
    .into_iter()
    .filter(|c| o.all_whiskers || touching.contains(&c.module.index))
    .filter(|c| o.whiskers.is_empty() || o.whiskers.contains(&c.module.pixel()))
    .map(|mut c| {
        if let Some(path) = o.path {
            c.solver = path;
        }
        c.adaptive_steps = !o.fixed_steps;
        c
    })
    .collect();
    let mut array = PhysicsArray::new(configs, &environment.physics_pieces(), &pose, 0, DT);
    let record = match recording {
        Some((rec, k)) => Some(CaseRecording::new(rec, k, name, environment, &array)?),
        None => None,
    };
    let start = Instant::now();
    let soaked = simulate(name, &mut array, pose, solids, o, record, ctx)?;
    let wall = start.elapsed().as_secs_f64();
    // World steps per sample, summed over whiskers: 1 without speed-adaptive splits.
    let (samples, world) = array
        .units
        .iter()
        .map(|u| u.steps())
        .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    let report = CaseReport {
        case: name.to_string(),
        pieces: environment.pieces.len(),
        triangles: environment
            .pieces
            .iter()
            .map(|p| p.mesh.triangles.len())
            .sum::<usize>(),
        simulated_s: o.duration,
        whiskers_touching_by_sweep: touching.len(),
        whiskers_simulated: array.units.len(),
        max_shaft_depth_m: soaked.deepest,
        non_finite_or_quarantined: soaked.broken,
        tunnelled: soaked.deepest > TUNNEL_DEPTH,
        first_tunnelling: soaked.first_tunnel,
        wall_s: wall,
        world_steps_per_sample: world as f64 / samples.max(1) as f64,
        passed: !soaked.broken && soaked.deepest <= TUNNEL_DEPTH,
        nudge_m: 0.0,
    };
    ctx.say(&report.to_string());
    Ok(report)
}

/// Holds the array at `pose` for the case's duration, checking after every 20 steps how deep
/// the shafts are inside the solids; stops at a broken whisker.
fn simulate(
    name: &str,
    array: &mut PhysicsArray,
    pose: Isometry3<f64>,
    solids: &Solids,
    o: &Settings,
    mut record: Option<CaseRecording>,
    ctx: Context,
) -> Result<Soaked> {
    let steps = (o.duration / DT).round() as usize;
    let mut soaked = Soaked::default();
    // The array runs 20 steps per task between checks (`PhysicsArray::run`).
    let chunk = [pose; 20];
    let mut k = 0;
    while k < steps {
        let n = chunk.len().min(steps - k);
        let samples = array.run(&chunk[..n]);
        if let Some(r) = &mut record {
            r.chunk(k, &samples, array)?;
        }
        k += n;
        let per: Vec<(f64, bool)> = array
            .units
            .par_iter()
            .map(|u| (u.shaft_depth(solids), u.is_broken()))
            .collect();
        let (depth, bad) = per
            .iter()
            .fold((0.0f64, false), |a, b| (a.0.max(b.0), a.1 || b.1));
        if soaked.first_tunnel.is_none() && depth > TUNNEL_DEPTH {
            let w = per.iter().position(|p| p.0 == depth).unwrap_or(0);
            soaked.first_tunnel = Some(Tunnel {
                t_s: k as f64 * DT,
                whisker: array.units[w].config.module.pixel(),
                depth_m: depth,
            });
        }
        soaked.deepest = soaked.deepest.max(depth);
        soaked.broken |= bad;
        if soaked.broken {
            break;
        }
        // A bar on a terminal; off one (a log, a batch job) a line at each tenth.
        if k % 2000 == 0 || k >= steps {
            let what = format!("steps of {name} ({} s simulated)", o.duration);
            ctx.reporter.progress(&what, k as u64, steps as u64);
        }
    }
    if let Some(r) = record {
        r.finish()?;
    }
    Ok(soaked)
}

/// An environment and the array pose where the most whiskers touch it.
pub struct Case {
    /// The environment.
    pub environment: Environment,
    /// The array's pose.
    pub pose: Isometry3<f64>,
    /// Indices of the whiskers that touch it by the kinematic sweep.
    pub touching: Vec<usize>,
}

/// The catalogue object `name` at the `bench sensing` candidate pose where the most
/// whiskers touch it.
pub fn object_case(name: &str) -> Result<Case, Error> {
    let asset = CATALOGUE
        .iter()
        .find(|a| a.name == name)
        .ok_or_else(|| Error::Input(format!("no catalogue object {name:?}")))?;
    let (environment, shape) = placed(asset).map_err(|e| Error::Failure(e.to_string()))?;
    let (pose, touching) =
        viewpoints::busiest(&environment, &shape, asset.size).ok_or_else(|| {
            Error::Failure(format!(
                "{}: no candidate pose where the whiskers reach it without starting inside",
                asset.name
            ))
        })?;
    Ok(Case {
        environment,
        pose,
        touching,
    })
}

/// The `[maze]` of the scenario at `path`, the array 100 mm above the board facing down, at
/// the point of a 50 mm grid where the most whiskers touch the walls.
pub fn maze_case(path: &Path) -> Result<Case, Error> {
    let file = ScenarioFile::load(path)?;
    let scenario = &file.scenario;
    let maze = scenario
        .maze
        .as_ref()
        .ok_or_else(|| file.error("maze", "expected a [maze] section"))?;
    let environment = file.environment()?.environment;
    let frame =
        whisker_slam::pose::from_xyz_rpy(maze.position_m, maze.rpy_deg.map(f64::to_radians));
    let down = Isometry3::rotation(Vector3::x() * std::f64::consts::PI);
    let mut grid = Vec::new();
    for i in 0..28 {
        for j in 0..20 {
            let (x, y) = (0.025 + 0.05 * i as f64, 0.025 + 0.05 * j as f64);
            if x < maze.board_m[0] && y < maze.board_m[1] {
                grid.push(frame * Isometry3::translation(x, y, 0.10) * down);
            }
        }
    }
    let (pose, touching) =
        viewpoints::most_touching(&environment, &grid).unwrap_or((grid[0], Vec::new()));
    Ok(Case {
        environment,
        pose,
        touching,
    })
}

/// `whisker soak`.
/// `whisker soak`: every case's runs, failed ones included (see [`CaseReport::passed`]).
pub fn soak(o: &Settings, ctx: Context) -> Result<Vec<CaseReport>> {
    if !(o.duration > 0.0 && o.duration <= MAX_DURATION_S) {
        return Err(Error::Input(format!(
            "--duration {}: expected a positive number of seconds up to {MAX_DURATION_S} \
             (simulated per case; an hour of one whisker's physics takes hours)",
            o.duration
        )));
    }
    if o.nudges > MAX_NUDGES {
        return Err(Error::Input(format!(
            "--nudges {}: expected 0 to {MAX_NUDGES} (each is one more whole run of every case)",
            o.nudges
        )));
    }
    if !(1..=64).contains(&o.substeps) {
        return Err(Error::Input(format!(
            "--substeps {}: expected 1 to 64 (as `array.substeps`)",
            o.substeps
        )));
    }
    let labels = array::labels();
    if let Some(w) = o.whiskers.iter().find(|w| !labels.contains(w)) {
        return Err(Error::Input(format!(
            "--whiskers: no whisker {w:?}: expected labels of {} … {}",
            labels[0],
            labels[labels.len() - 1]
        )));
    }
    let mut cases: Vec<(String, Case)> = Vec::new();
    for name in &o.objects {
        if !CATALOGUE.iter().any(|a| a.name == name) {
            return Err(Error::Input(format!(
                "--objects: no catalogue object {name:?}"
            )));
        }
    }
    for asset in &CATALOGUE {
        if o.objects.is_empty() || o.objects.iter().any(|n| n == asset.name) {
            cases.push((asset.name.to_string(), object_case(asset.name)?));
        }
    }
    if let Some(file) = &o.maze {
        cases.push(("maze".into(), maze_case(file)?));
    }
    let recording = match &o.rrd {
        Some(path) => Some(ctx.recordings.create(
            path,
            &whisker_experiments::record::id("soak", 0),
            cases_layout(&cases),
        )?),
        None => None,
    };
    let mut records = Vec::new();
    for (k, (name, case)) in cases.iter().enumerate() {
        let solids = Solids::new(&case.environment)
            .map_err(|e| Error::Failure(format!("soak: {name}: {e}")))?;
        let mut failed = 0;
        for nudge in 0..=o.nudges {
            let label = match nudge {
                0 => name.clone(),
                n => format!("{name}+{n}nm"),
            };
            let shift = nudge as f64 * NUDGE_M;
            let pose = Isometry3::translation(shift, 0.0, 0.0) * case.pose;
            let mut r = run_case(
                &label,
                case,
                &solids,
                pose,
                o,
                recording.as_deref().filter(|_| nudge == 0).map(|r| (r, k)),
                ctx,
            )?;
            r.nudge_m = shift;
            failed += usize::from(!r.passed);
            records.push(r);
        }
        if o.nudges > 0 {
            ctx.say(&format!(
                "{name}: {failed} of {} runs tunnelled or broke",
                o.nudges + 1
            ));
        }
    }
    if let Some(rec) = recording {
        rec.finish()?;
    }
    ctx.say(&whisker_scenario::console::legend(
        "what the columns mean",
        &[
            ("whiskers touching", "whiskers the kinematic sweep says reach the object (those simulated unless --all-whiskers)"),
            ("centre-line depth", "the deepest any shaft's centre line went inside a solid, mm; below its radius (≤ 1 mm) is contact, deeper is tunnelling"),
            ("finite", "no position or velocity became NaN or infinite and no whisker was quarantined"),
            ("world steps/sample", "Rapier steps per 0.5 ms sample (adaptive substepping; 1 = none needed)"),
            ("ok / FAILED", "passed = finite and no tunnelling"),
        ],
    ));
    Ok(records)
}
