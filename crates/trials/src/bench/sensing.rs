//! `whisker bench sensing`: how fast kinematic sensing (the anticipated intersect,
//! `whisker_sim::sensing::kinematic`) sweeps the full array near an object.
//!
//! The object (a catalogue asset) stands at the origin; the array visits a fixed set of
//! poses 2–8 cm out from the object's surface, facing it (from the `bench/sensing` sub-stream of seed
//! 0). A whisk cycle is one 40°–140° sweep of all 18 whiskers in 1° steps. Reported:
//! whisk cycles per second on one thread and on two, and the same sweeps done the naive
//! way — 101 parry ray casts per whisker per cycle against the object's BVH — measured
//! in the same run as the baseline. Timing is a benchmark, never a test.

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::query::Ray;
use rayon::prelude::*;
use serde::Serialize;
use std::fmt;
use std::time::Instant;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::assets::{CATALOGUE, generate};
use whisker_sim::sensing::kinematic::{RigidWhisker, SweepTarget};
use whisker_sim::sensing::viewpoints;
use whisker_sim::whisker::array;

/// What `whisker bench sensing` times.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Catalogue object the array sweeps.
    pub object: String,
    /// Whisk cycles timed per case.
    pub cycles: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            object: "kettle".into(),
            cycles: 20_000,
        }
    }
}

/// What it measured (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub object: &'static str,
    pub triangles: usize,
    pub poses: usize,
    pub contacts_per_cycle: f64,
    pub whisk_cycles_per_s: f64,
    pub whisk_cycles_per_s_2_threads: f64,
    pub baseline_ray_casts_whisk_cycles_per_s: f64,
    pub speedup_over_ray_casts: f64,
}

/// Times `cycles` whisk cycles of `sweep` over the poses on `threads` threads; returns
/// (cycles per second, contacts per cycle).
fn time_case(
    threads: usize,
    cycles: usize,
    poses: &[Isometry3<f64>],
    sweep: &(dyn Fn(&Isometry3<f64>) -> usize + Sync),
) -> Result<(f64, f64)> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Failure(format!("cannot start {threads} threads: {e}")))?;
    let start = Instant::now();
    let contacts: usize = pool.install(|| {
        (0..cycles)
            .into_par_iter()
            .with_min_len(64)
            .map(|i| sweep(&poses[i % poses.len()]))
            .sum()
    });
    let seconds = start.elapsed().as_secs_f64();
    Ok((cycles as f64 / seconds, contacts as f64 / cycles as f64))
}

/// `whisker bench sensing`.
pub fn sensing(o: &Settings) -> Result<Report> {
    let asset = CATALOGUE
        .iter()
        .find(|a| a.name == o.object)
        .ok_or_else(|| {
            let names: Vec<&str> = CATALOGUE.iter().map(|a| a.name).collect();
            Error::Input(format!(
                "--object {:?}: expected one of {}",
                o.object,
                names.join(", ")
            ))
        })?;
    if o.cycles == 0 {
        return Err(Error::Input("--cycles: expected at least 1".into()));
    }
    let mesh = generate(asset);
    let triangles = mesh.triangles.len();
    let shape = whisker_sim::environment::solids::shape(&mesh)
        .map_err(|e| Error::Failure(format!("{}: {e}", asset.name)))?;
    let target = SweepTarget::new(mesh);
    let whiskers: Vec<RigidWhisker> = array::modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, 3.0e-3))
        .collect();
    let poses = viewpoints::facing(&shape, asset.size, 256, "bench/sensing");
    let exact = |pose: &Isometry3<f64>| {
        whiskers
            .iter()
            .filter(|w| target.sweep(w, pose).is_some())
            .count()
    };
    let naive = |pose: &Isometry3<f64>| {
        whiskers
            .iter()
            .filter(|w| {
                let reach = w.base_offset + w.module.beam.length;
                (0..=w.steps()).any(|k| {
                    let f = pose * w.module.whisker_pose(w.angle(k));
                    let (p, d) = (f.translation.vector, f.rotation * Vector3::z());
                    let ray = Ray::new(PVector::new(p.x, p.y, p.z), PVector::new(d.x, d.y, d.z));
                    shape.cast_local_ray(&ray, reach, false).is_some()
                })
            })
            .count()
    };
    let baseline_cycles = (o.cycles / 10).max(1);
    let (naive_1, _) = time_case(1, baseline_cycles, &poses, &naive)?;
    let (exact_1, contacts) = time_case(1, o.cycles, &poses, &exact)?;
    let (exact_2, _) = time_case(2, o.cycles, &poses, &exact)?;
    Ok(Report {
        object: asset.name,
        triangles,
        poses: poses.len(),
        contacts_per_cycle: contacts,
        whisk_cycles_per_s: exact_1,
        whisk_cycles_per_s_2_threads: exact_2,
        baseline_ray_casts_whisk_cycles_per_s: naive_1,
        speedup_over_ray_casts: exact_1 / naive_1,
    })
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (naive_1, exact_1, exact_2) = (
            self.baseline_ray_casts_whisk_cycles_per_s,
            self.whisk_cycles_per_s,
            self.whisk_cycles_per_s_2_threads,
        );
        writeln!(
            f,
            "kinematic sensing, 18 whiskers, 40°–140° in 1° steps, near {} ({} triangles), {} poses, {:.1} contacts per cycle",
            self.object, self.triangles, self.poses, self.contacts_per_cycle
        )?;
        writeln!(f, "  {:<40} {:>14} {:>10}", "case", "cycles/s", "ratio")?;
        writeln!(
            f,
            "  {:<40} {:>14.0} {:>10.2}",
            "baseline: per-step ray casts, 1 thread", naive_1, 1.0
        )?;
        writeln!(
            f,
            "  {:<40} {:>14.0} {:>10.2}",
            "sweep-plane slicing, 1 thread",
            exact_1,
            exact_1 / naive_1
        )?;
        writeln!(
            f,
            "  {:<40} {:>14.0} {:>10.2}",
            "sweep-plane slicing, 2 threads",
            exact_2,
            exact_2 / naive_1
        )
    }
}
