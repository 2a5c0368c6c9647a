//! `whisker bench physics`: how fast the physics sensing mode runs.
//!
//! Cases: one whisker whisking freely, the 18-whisker array whisking freely, and the
//! array whisking against a box in front of it (every ring touches it), each with 1 and
//! 2 worker threads. Reported: the real-time factor (simulated seconds per wall-clock
//! second), the CPU cost per whisker (thread-seconds per simulated second per whisker),
//! and every case's speed relative to the single free whisker on one thread, measured in
//! the same run. Timing is a benchmark, never a test.

use crate::error::{CliError, CliResult};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use rapier3d_f64::prelude::SharedShape;
use serde_json::json;
use std::time::Instant;
use whisker_sim::sensing::physics::{EnvironmentPiece, PhysicsArray, WhiskerConfig};
use whisker_sim::whisker::array;
use whisker_sim::whisker::beam::Bending;

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
    /// Print a JSON list of {case, threads, real_time_factor, …}.
    #[arg(long)]
    pub json: bool,
}

/// The first `count` modules' configurations with the benchmark's settings.
fn configs(count: usize, o: &Options) -> Vec<WhiskerConfig> {
    array_configs(count, o.bending.into(), o.segments, o.substeps)
}

/// The first `count` modules' configurations: default whiskers, follicle, 1 Hz open-loop
/// whisking and sensors, with the given bending model, segments and substeps.
pub fn array_configs(
    count: usize,
    bending: Bending,
    segments: Option<usize>,
    substeps: usize,
) -> Vec<WhiskerConfig> {
    array::modules()
        .into_iter()
        .take(count)
        .map(|mut module| {
            module.beam.bending = bending;
            if let Some(n) = segments {
                module.beam.segments = n;
            }
            module
        })
        .map(|module| WhiskerConfig {
            substeps,
            ..WhiskerConfig::with_defaults(module)
        })
        .collect()
}

/// Wall-clock seconds to simulate `duration` of `whiskers` whiskers in `environment`.
fn time_case(
    whiskers: usize,
    environment: &[EnvironmentPiece],
    duration: f64,
    threads: usize,
    o: &Options,
) -> Result<f64, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| e.to_string())?;
    pool.install(|| {
        let dt = whisker_sim::sensing::physics::DT;
        let pose = Isometry3::identity();
        let mut array = PhysicsArray::new(configs(whiskers, o), environment, &pose, 0, dt);
        let steps = (duration / dt).round() as usize;
        let start = Instant::now();
        for _ in 0..steps {
            array.step(&pose);
        }
        Ok(start.elapsed().as_secs_f64())
    })
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
    // A 60 × 60 × 2 cm box whose face is 3 cm in front of the array: protracting
    // whiskers of every ring reach it.
    let wall: EnvironmentPiece = (
        SharedShape::cuboid(0.3, 0.3, 0.01),
        Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 0.04),
            UnitQuaternion::identity(),
        ),
    );
    let cases: [(&str, usize, Vec<EnvironmentPiece>); 3] = [
        ("1 whisker, free whisking", 1, vec![]),
        ("18 whiskers, free whisking", 18, vec![]),
        ("18 whiskers, whisking against a box", 18, vec![wall]),
    ];
    let mut rows = Vec::new();
    let mut baseline = None;
    for (name, whiskers, environment) in &cases {
        for threads in [1, 2] {
            let wall_s = time_case(*whiskers, environment, o.duration, threads, o)
                .map_err(CliError::Failure)?;
            let rtf = o.duration / wall_s;
            let cpu_per_whisker = threads as f64 * wall_s / o.duration / *whiskers as f64;
            let per_whisker_rate = rtf * *whiskers as f64;
            let base = *baseline.get_or_insert(per_whisker_rate);
            rows.push((
                name.to_string(),
                threads,
                rtf,
                cpu_per_whisker,
                per_whisker_rate / base,
            ));
            if !o.json {
                eprintln!("  {name:<38} {threads} thread(s): {rtf:.3}× real time");
            }
        }
    }
    if o.json {
        let list: Vec<_> = rows
            .iter()
            .map(|(case, threads, rtf, cpu, rel)| {
                json!({"case": case, "threads": threads, "real_time_factor": rtf, "cpu_s_per_sim_s_per_whisker": cpu, "whisker_rate_vs_baseline": rel})
            })
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&list).expect("plain JSON")
        );
    } else {
        println!(
            "physics sensing, {} s simulated per case at 2 kHz, {} segments per whisker, {:?} bending, {} substep(s)",
            o.duration,
            o.segments.unwrap_or(array::modules()[0].beam.segments),
            o.bending,
            o.substeps
        );
        println!(
            "{:<38} {:>7} {:>16} {:>22} {:>14}",
            "case", "threads", "real-time factor", "CPU s / sim s / whisker", "vs baseline"
        );
        for (case, threads, rtf, cpu, rel) in rows {
            println!("{case:<38} {threads:>7} {rtf:>16.3} {cpu:>22.3} {rel:>13.2}×");
        }
        println!(
            "baseline: 1 whisker, free whisking, 1 thread (whisker-seconds simulated per wall second)"
        );
    }
    Ok(())
}
