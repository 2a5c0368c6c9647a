//! `whisker bench physics`: how fast the physics sensing mode runs.
//!
//! Cases: the 18-whisker array whisking freely, against the Box (the catalogue object at
//! the pose where the most whiskers touch it, as in `whisker soak`) and in the maze (the
//! most-touched point of a 50 mm grid 100 mm above the board, facing down), each on 1 and
//! 2 worker threads and by four code paths measured side by side in the same run:
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
//! - `once-per-step`: also patch 3 (the mass matrix factorised once per step; the default,
//!   `SolverPath::OncePerStep`);
//! - `explicit-coriolis`: also patch 4 (explicit gyroscopic and Coriolis terms).
//!
//! `once-per-step` is the default; `SolverPath` says why `explicit-coriolis` is not.
//!
//! Then the scaling with segment count (8, 12, 16, 24) against the Box on 2 threads by
//! every path. Reported: the real-time factor (simulated seconds per wall-clock second),
//! the CPU cost per whisker (thread-seconds per simulated second per whisker, the peer's
//! unit: WHISKiT Physics needs about 7 for one whisker, `shared/notes/physics.md`), and
//! each path's speed-up over `released`. Timing is a benchmark, never a test.

use crate::error::{CliError, CliResult};
use clap::builder::TypedValueParser;
use nalgebra::Isometry3;
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;
use whisker_sim::sensing::physics::{DT, EnvironmentPiece, PhysicsArray, SolverPath, StageTimes};
use whisker_sim::whisker::array;

/// CPU-seconds per simulated second for one whisker of WHISKiT Physics, the reference
/// simulator (`shared/notes/physics.md`, "The peer to beat").
const WHISKIT_CPU_S_PER_S: f64 = 7.0;

/// Options of `whisker bench physics`.
#[derive(clap::Args, Debug)]
pub struct Options {
    /// Simulated time per case (s).
    #[arg(long, default_value_t = 0.5)]
    pub duration: f64,
    /// Shaft joint model of every whisker.
    #[arg(long, value_enum, default_value_t = crate::characterize::BendingArg::Spatial)]
    pub bending: crate::characterize::BendingArg,
    /// Rapier substeps per 0.5 ms step.
    #[arg(long, default_value_t = whisker_sim::sensing::physics::DEFAULT_SUBSTEPS)]
    pub substeps: usize,
    /// Segments per whisker [default: the array's].
    #[arg(long)]
    pub segments: Option<usize>,
    /// The scenario whose `[maze]` is the maze case.
    #[arg(long, default_value = "scenarios/maze.toml")]
    pub maze: PathBuf,
    /// Skip the segment-count scaling (8/12/16/24).
    #[arg(long)]
    pub no_scaling: bool,
    /// Time only this code path (e.g. under a profiler) [default: all].
    #[arg(long, value_parser = solver_path_parser())]
    pub path: Option<SolverPath>,
    /// Instead: Rapier's stage timers for the array against the Box on 1 thread (the
    /// released, exact, composite and once-per-step paths, or --path); needs `--features profiler`.
    #[arg(long)]
    pub stages: bool,
    /// Print a JSON list of {case, threads, path, real_time_factor, …}.
    #[arg(long)]
    pub json: bool,
}

/// Parses a code path by its name ([`SolverPath::name`]: `released`, `exact`, …) for
/// `--path` here and in `whisker soak`.
pub fn solver_path_parser() -> impl clap::builder::TypedValueParser<Value = SolverPath> {
    clap::builder::PossibleValuesParser::new(SolverPath::ALL.map(SolverPath::name)).map(|name| {
        *SolverPath::ALL
            .iter()
            .find(|p| p.name() == name)
            .expect("clap accepts only the paths' names")
    })
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
    path: SolverPath,
    threads: usize,
    o: &Options,
) -> Result<(f64, StageTimes), String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| e.to_string())?;
    pool.install(|| {
        let mut configs = whisker_sim::sensing::physics::standard_array(
            array::modules().len(),
            o.bending.into(),
            case.segments.or(o.segments),
            o.substeps,
        );
        for c in &mut configs {
            c.solver = path;
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

/// One measured row.
struct Row {
    case: String,
    segments: usize,
    threads: usize,
    path: SolverPath,
    rtf: f64,
    cpu: f64,
    speedup: Option<f64>,
}

/// Times `case` by every path (or `--path`) on each of `threads`, printing progress.
fn measure(case: &Case, threads: &[usize], o: &Options, rows: &mut Vec<Row>) -> CliResult {
    let whiskers = array::modules().len() as f64;
    let segments = case
        .segments
        .or(o.segments)
        .unwrap_or(array::modules()[0].beam.segments);
    for &t in threads {
        let mut released_wall = None;
        for path in SolverPath::ALL {
            if o.path.is_some_and(|p| p != path) {
                continue;
            }
            let (wall, _) = time_case(case, path, t, o).map_err(CliError::Failure)?;
            let rtf = o.duration / wall;
            let speedup = match path {
                SolverPath::Released => {
                    released_wall = Some(wall);
                    None
                }
                _ => released_wall.map(|r| r / wall),
            };
            if !o.json {
                eprintln!(
                    "  {:<26} {segments:>2} segments {t} thread(s) {:<9} {rtf:.3}× real time",
                    case.name,
                    path.name()
                );
            }
            rows.push(Row {
                case: case.name.to_string(),
                segments,
                threads: t,
                path,
                rtf,
                cpu: t as f64 * wall / o.duration / whiskers,
                speedup,
            });
        }
    }
    Ok(())
}

/// Runs `whisker bench physics`.
pub fn physics(o: &Options) -> CliResult {
    if !(1..=64).contains(&o.substeps) {
        return Err(CliError::Input(format!(
            "--substeps: expected 1 to 64, got {}",
            o.substeps
        )));
    }
    if let Some(n) = o.segments
        && !(2..=200).contains(&n)
    {
        return Err(CliError::Input(format!(
            "--segments: expected 2 to 200, got {n}"
        )));
    }
    if !(o.duration.is_finite() && o.duration > 0.0) {
        return Err(CliError::Input(format!(
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
        return stages(&cases[1], o);
    }
    let mut rows = Vec::new();
    for case in &cases {
        measure(case, &[1, 2], o, &mut rows)?;
    }
    if !o.no_scaling {
        for n in [8, 12, 16, 24] {
            let case = Case {
                name: "against the Box",
                segments: Some(n),
                ..cases[1]
            };
            measure(&case, &[2], o, &mut rows)?;
        }
    }
    print(&rows, &boxed.touching, &maze.touching, o);
    Ok(())
}

/// Prints the table (or the JSON list).
fn print(rows: &[Row], box_touching: &[usize], maze_touching: &[usize], o: &Options) {
    if o.json {
        let list: Vec<_> = rows
            .iter()
            .map(|r| {
                json!({
                    "case": r.case,
                    "whiskers": array::modules().len(),
                    "segments": r.segments,
                    "threads": r.threads,
                    "path": r.path.name(),
                    "real_time_factor": r.rtf,
                    "cpu_s_per_sim_s_per_whisker": r.cpu,
                    "speedup_vs_released": r.speedup,
                    "cpu_vs_whiskit": r.cpu / WHISKIT_CPU_S_PER_S,
                })
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&list).expect("plain JSON")
        );
        return;
    }
    println!(
        "physics sensing of the 18-whisker array, {} s simulated per case at 2 kHz, {:?} bending, {} substep(s); \
         {} whiskers touch the Box and {} the maze by the kinematic sweep",
        o.duration,
        o.bending,
        o.substeps,
        box_touching.len(),
        maze_touching.len()
    );
    println!(
        "{:<18} {:>8} {:>7} {:>17} {:>16} {:>24} {:>11} {:>13}",
        "case",
        "segments",
        "threads",
        "path",
        "real-time factor",
        "CPU s / sim s / whisker",
        "vs WHISKiT",
        "speed-up"
    );
    for r in rows {
        println!(
            "{:<18} {:>8} {:>7} {:>17} {:>16.3} {:>24.3} {:>10.3}× {:>13}",
            r.case,
            r.segments,
            r.threads,
            r.path.name(),
            r.rtf,
            r.cpu,
            r.cpu / WHISKIT_CPU_S_PER_S,
            r.speedup.map_or(String::new(), |s| format!("{s:.2}×"))
        );
    }
    println!(
        "released: Rapier 0.36.1 as released, a barrier per sample; exact: vendor/PATCHES.md 1-2 (bit-identical); \
         composite: 1-2, 5 (the same matrices up to rounding); once-per-step: 1-3, 5 (the default); \
         explicit-coriolis: 1-5 (both went non-finite in nudged Mug soaks with fixed steps); all four one task per whisker and speed-adaptive steps. vs WHISKiT: CPU cost / its {WHISKIT_CPU_S_PER_S} CPU-s per simulated s per whisker \
         (below 1: cheaper). Speed-up: released wall time / the path's, same case and threads."
    );
}

/// `--stages`: where Rapier's steps spend their time, against the Box on 1 thread.
fn stages(case: &Case, o: &Options) -> CliResult {
    let paths = match o.path {
        Some(p) => vec![p],
        None => vec![
            SolverPath::Released,
            SolverPath::Exact,
            SolverPath::Composite,
            SolverPath::OncePerStep,
        ],
    };
    let mut list = Vec::new();
    for path in paths {
        let (wall, t) = time_case(case, path, 1, o).map_err(CliError::Failure)?;
        if t.step == 0.0 {
            return Err(CliError::Input(
                "--stages: this build has no stage timers; build with \
                 `cargo build --release --features profiler`"
                    .into(),
            ));
        }
        let rows = [
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
        if o.json {
            let mut m = serde_json::Map::new();
            for (name, s) in rows {
                m.insert(name.into(), json!(s));
            }
            list.push(json!({"path": path.name(), "wall_s": wall, "stages_s": m}));
        } else {
            println!(
                "{}: 18 whiskers {} for {} s on 1 thread, {wall:.2} s wall",
                path.name(),
                case.name,
                o.duration
            );
            for (name, s) in rows {
                println!("  {name:<36} {s:>8.3} s {:>6.1} %", 100.0 * s / wall);
            }
        }
    }
    if o.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&list).expect("plain JSON")
        );
    }
    Ok(())
}
