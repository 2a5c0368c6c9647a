//! The pose-cell part of `whisker bench slam`: one update of each network split into its
//! phases and timed apart, in the dense reference evaluation and the active-set one
//! ([`Evaluation`]) in the same run, and the cost as a function of the active cells.
//!
//! An update, in the order of Alg 2 / §3.1.2: view or feature **injection** (at the
//! packet's last decoded cell, as a re-matched view or feature does, and at every other
//! hypothesis' site, which keeps several packets alive), local **excitation**, local
//! **inhibition**, **global** inhibition and normalisation, **path integration**, and the
//! **best-pose** decode. The planar network is RatSLAM's at 21 × 21 × 36 cells, moved one
//! cell forward and turned 10° per update; the 6-D network is WhiskerRatSLAM's at 5⁶ cells,
//! moved 0.3 cell forward with 5° of yaw and 2° of roll per update.

use nalgebra::Vector3;
use serde::Serialize;
use std::time::Instant;
use whisker_slam::pose_grid::{Attractor, Evaluation, PoseGrid};
use whisker_slam::ratslam::posecells3d::{PlanarCellParams, PoseCells3};
use whisker_slam::whisker_ratslam::posecells6d::{PoseCellParams, PoseCells6};

/// The phases of one update, in their order.
pub const PHASES: [&str; 6] = [
    "injection",
    "local excitation",
    "local inhibition",
    "global inhibition, normalisation",
    "path integration",
    "best-pose decode",
];

/// Updates run before the timing starts (the packets settle).
const WARMUP: usize = 20;

/// One network's update in one evaluation: the mean time of each phase.
#[derive(Debug, Clone, Serialize)]
pub struct Profile {
    /// `dense` or `active`.
    pub evaluation: &'static str,
    /// Packets kept alive by injection.
    pub packets: usize,
    /// Mean time of each phase of [`PHASES`] (ms).
    pub phases_ms: [f64; 6],
    /// Their sum: one update (ms).
    pub update_ms: f64,
    /// Mean number of non-zero cells after an update.
    pub active_cells: f64,
}

/// Sums of phase times over the timed updates.
#[derive(Default)]
struct Clock {
    sums: [f64; 6],
    active: f64,
}

impl Clock {
    fn time(&mut self, phase: usize, f: impl FnOnce()) {
        let start = Instant::now();
        f();
        self.sums[phase] += start.elapsed().as_secs_f64() * 1e3;
    }

    fn profile(&self, evaluation: Evaluation, packets: usize, updates: usize) -> Profile {
        let phases_ms = self.sums.map(|s| s / updates as f64);
        Profile {
            evaluation: match evaluation {
                Evaluation::Dense => "dense",
                Evaluation::Active => "active",
            },
            packets,
            phases_ms,
            update_ms: phases_ms.iter().sum(),
            active_cells: self.active / updates as f64,
        }
    }
}

/// Non-zero cells of a grid.
fn active_cells(grid: &PoseGrid) -> f64 {
    grid.cells.iter().filter(|&&c| c != 0.0).count() as f64
}

/// The planar network's sizes in the bench.
pub fn planar_params() -> PlanarCellParams {
    PlanarCellParams {
        dim_xy: 21,
        ..PlanarCellParams::default()
    }
}

/// The planar network's update profiled over `updates` updates with `packets` packets
/// (1 to 8: the first at the start, the others at fixed sites spread over the grid).
pub fn planar(evaluation: Evaluation, packets: usize, updates: usize) -> Profile {
    let params = planar_params();
    let sites = [
        [3.0, 16.0, 9.0],
        [17.0, 4.0, 27.0],
        [0.0, 0.0, 18.0],
        [14.0, 18.0, 33.0],
        [6.0, 6.0, 4.0],
        [19.0, 11.0, 22.0],
        [9.0, 1.0, 13.0],
    ];
    let sites = &sites[..packets.clamp(1, 8) - 1];
    let mut cells = PoseCells3::new(params, &[10.0, 10.0, 0.0]);
    cells.grid.set_evaluation(evaluation);
    let attractor = cells.attractor().clone();
    let best = cells.best();
    let mut net = (cells, best);
    let clock = run(
        &mut net,
        updates,
        |(cells, _)| &mut cells.grid,
        |(cells, best)| {
            cells.inject(best, 0.1);
            sites.iter().for_each(|s| cells.inject(s, 0.1));
        },
        &attractor,
        |(cells, _)| cells.path_integrate(params.cell_size_m, 10f64.to_radians()),
        |(cells, best)| *best = cells.best(),
    );
    clock.profile(evaluation, sites.len() + 1, updates)
}

/// The 6-D network's update profiled over `updates` updates with `packets` packets (1 to
/// 3; injected as copies of the packet, Eq 5.9 relative to the peak).
pub fn six_d(evaluation: Evaluation, packets: usize, updates: usize) -> Profile {
    let params = PoseCellParams::default();
    let sites = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [4.0, 1.0, 3.0, 0.0, 4.0, 1.0],
    ];
    let sites = &sites[..packets.clamp(1, 3) - 1];
    let mut cells = PoseCells6::new(params, &[2.0; 6]);
    cells.grid.set_evaluation(evaluation);
    let attractor = cells.attractor().clone();
    let (v, w) = (
        Vector3::new(0.3 * params.cell_size_m, 0.0, 0.0),
        Vector3::new(2f64.to_radians(), 0.0, 5f64.to_radians()),
    );
    let best = cells.best();
    let mut net = (cells, best);
    let clock = run(
        &mut net,
        updates,
        |(cells, _)| &mut cells.grid,
        |(cells, best)| {
            cells.inject_packet(best, 0.1);
            sites.iter().for_each(|s| cells.inject_packet(s, 0.3));
        },
        &attractor,
        |(cells, _)| cells.path_integrate(&v, &w),
        |(cells, best)| *best = cells.best(),
    );
    clock.profile(evaluation, sites.len() + 1, updates)
}

/// Runs [`WARMUP`] and then `updates` timed updates of a network `net`: its injection,
/// the `attractor`'s phases on its grid, its path integration and its decode.
fn run<N>(
    net: &mut N,
    updates: usize,
    grid: impl Fn(&mut N) -> &mut PoseGrid,
    inject: impl Fn(&mut N),
    attractor: &Attractor,
    integrate: impl Fn(&mut N),
    decode: impl Fn(&mut N),
) -> Clock {
    let mut clock = Clock::default();
    for u in 0..WARMUP + updates {
        if u == WARMUP {
            clock = Clock::default();
        }
        clock.time(0, || inject(net));
        clock.time(1, || attractor.excite(grid(net)));
        clock.time(2, || attractor.inhibit(grid(net)));
        clock.time(3, || attractor.inhibit_globally(grid(net)));
        clock.time(4, || integrate(net));
        clock.time(5, || decode(net));
        clock.active += active_cells(grid(net));
    }
    clock
}
