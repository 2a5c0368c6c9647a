//! `whisker bench slam`: the cost of WhiskerRatSLAM's and RatSLAM's core operations
//! (thesis Ch 3, Ch 5).
//!
//! - the baseline, measured in the same run: one naive dense 6-D convolution of a settled
//!   5⁶ grid with the full 5⁶-entry excitation kernel (every cell against every offset),
//!   the way Eq 5.10 reads, and the separable excitation pass that replaces it, in the
//!   dense reference evaluation and the active-set one;
//! - one point feature histogram of an 18-contact whisk;
//! - one update of each pose-cell network by phase, dense reference and active set side
//!   by side ([`pose_cells`]), and the cost of an update against the number of active
//!   cells (several packets kept alive by injection).
//!
//! Timing is a benchmark, never a test.

use super::pose_cells::{self, PHASES, Profile};
use nalgebra::Point3;
use rand::RngExt;
use serde::Serialize;
use std::fmt;
use std::time::Instant;
use whisker_scenario::{Error, Result};
use whisker_slam::features::pfh::{PfhParams, histogram};
use whisker_slam::pose_grid::{Evaluation, gaussian_kernel};
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::posecells6d::{PoseCellParams, PoseCells6, dense_convolve};

/// One network's update in both evaluations, measured in the same run.
#[derive(Debug, Clone, Serialize)]
pub struct Pair {
    pub dense: Profile,
    pub active: Profile,
    /// dense / active update time.
    pub dense_over_active: f64,
}

impl Pair {
    fn measure(updates: usize, f: impl Fn(Evaluation, usize) -> Profile) -> Self {
        let (dense, active) = (
            f(Evaluation::Dense, updates),
            f(Evaluation::Active, updates),
        );
        Self {
            dense_over_active: dense.update_ms / active.update_ms,
            dense,
            active,
        }
    }
}

/// What `whisker bench slam` measured (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub posecell3d_cells: usize,
    /// One planar update, active set, one packet (ms).
    pub posecell3d_update_ms: f64,
    pub posecell6d_cells: usize,
    /// One 6-D update, active set, one packet (ms).
    pub posecell6d_update_ms: f64,
    pub naive_dense_ms: f64,
    /// The separable excitation, dense reference (ms).
    pub separable_excitation_ms: f64,
    /// The separable excitation, active set (ms).
    pub separable_excitation_active_ms: f64,
    pub dense_over_separable: f64,
    pub pfh_18_contacts_ms: f64,
    pub pfh_bins: usize,
    /// The planar update with 1, 2, 4 and 8 packets.
    pub planar: Vec<Pair>,
    /// The 6-D update with 1, 2 and 3 packets.
    pub six_d: Vec<Pair>,
    #[serde(skip)]
    updates: usize,
}

/// Mean wall time of `f` over `n` calls (ms).
fn time_ms(n: usize, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..n {
        f();
    }
    start.elapsed().as_secs_f64() * 1e3 / n as f64
}

/// `whisker bench slam` over `updates` pose-cell updates per case.
pub fn slam(updates: usize) -> Result<Report> {
    if updates == 0 {
        return Err(Error::Input("--updates: expected at least 1".into()));
    }
    let params = PoseCellParams::default();
    let mut cells = PoseCells6::new(params, &[2.0; 6]);
    for _ in 0..20 {
        cells.excite_inhibit();
    }
    let kernel = gaussian_kernel(params.excite_width, params.excite_variance);
    let mut dense_out = Vec::new();
    let dense_ms = time_ms(1, || dense_out = dense_convolve(&cells.grid, &kernel));
    let mut separable = [0.0; 2];
    for (ms, evaluation) in separable
        .iter_mut()
        .zip([Evaluation::Dense, Evaluation::Active])
    {
        let mut grid = cells.grid.clone();
        grid.set_evaluation(evaluation);
        *ms = time_ms(updates, || grid.convolve(&kernel));
    }
    let (pfh_ms, pfh_bins) = pfh(updates);
    let planar: Vec<Pair> = [1, 2, 4, 8]
        .map(|k| Pair::measure(updates, |e, u| pose_cells::planar(e, k, u)))
        .into();
    let six_d: Vec<Pair> = [1, 2, 3]
        .map(|k| Pair::measure(updates, |e, u| pose_cells::six_d(e, k, u)))
        .into();
    let planar_params = pose_cells::planar_params();
    Ok(Report {
        posecell3d_cells: planar_params.dim_xy.pow(2) * planar_params.dim_th,
        posecell3d_update_ms: planar[0].active.update_ms,
        posecell6d_cells: cells.grid.cells.len(),
        posecell6d_update_ms: six_d[0].active.update_ms,
        naive_dense_ms: dense_ms,
        separable_excitation_ms: separable[0],
        separable_excitation_active_ms: separable[1],
        dense_over_separable: dense_ms / separable[0],
        pfh_18_contacts_ms: pfh_ms,
        pfh_bins,
        planar,
        six_d,
        updates,
    })
}

/// One point feature histogram of 18 random contacts: (ms, bins).
fn pfh(updates: usize) -> (f64, usize) {
    let mut rng = substream(0, "bench/slam/contacts");
    let contacts: Vec<Point3<f64>> = (0..18)
        .map(|_| {
            Point3::new(
                rng.random_range(-0.08..0.08),
                rng.random_range(-0.08..0.08),
                rng.random_range(0.05..0.15),
            )
        })
        .collect();
    let pfh = PfhParams::default();
    let mut bins = 0;
    let ms = time_ms(updates, || {
        bins = histogram(&contacts, &Point3::origin(), &pfh).len();
    });
    (ms, bins)
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let dense_ms = self.naive_dense_ms;
        writeln!(
            f,
            "WhiskerRatSLAM core, {} pose cells (5 per axis), {} updates per case",
            self.posecell6d_cells, self.updates
        )?;
        writeln!(f, "  {:<58} {:>12} {:>10}", "case", "ms", "ratio")?;
        let rows = [
            (
                "baseline: naive dense 6-D excitation (5^6 kernel)",
                dense_ms,
            ),
            (
                "separable excitation, dense reference (six 1-D passes)",
                self.separable_excitation_ms,
            ),
            (
                "separable excitation, active set",
                self.separable_excitation_active_ms,
            ),
        ];
        for (case, ms) in rows {
            writeln!(f, "  {case:<58} {ms:>12.4} {:>10.1}", dense_ms / ms)?;
        }
        writeln!(
            f,
            "  {:<58} {:>12.4}",
            format!(
                "point feature histogram, 18 contacts, {} bins",
                self.pfh_bins
            ),
            self.pfh_18_contacts_ms
        )?;
        let (p, s) = (&self.planar[0], &self.six_d[0]);
        writeln!(
            f,
            "\nOne pose-cell update by phase, one packet (ms; ratio = dense reference / active set)"
        )?;
        writeln!(
            f,
            "  {:<34} {:>25} {:>25}",
            "",
            format!("planar, {} cells", self.posecell3d_cells),
            format!("6-D, {} cells", self.posecell6d_cells)
        )?;
        let head = format!("{:>8} {:>8} {:>7}", "dense", "active", "ratio");
        writeln!(f, "  {:<34} {head} {head}", "phase")?;
        let cols = |d: f64, a: f64| format!("{d:>8.4} {a:>8.4} {:>7.1}", d / a);
        for (i, phase) in PHASES.iter().enumerate() {
            let (pd, pa) = (p.dense.phases_ms[i], p.active.phases_ms[i]);
            let (sd, sa) = (s.dense.phases_ms[i], s.active.phases_ms[i]);
            writeln!(f, "  {phase:<34} {} {}", cols(pd, pa), cols(sd, sa))?;
        }
        let (pd, pa, sd, sa) = (
            p.dense.update_ms,
            p.active.update_ms,
            s.dense.update_ms,
            s.active.update_ms,
        );
        writeln!(
            f,
            "  {:<34} {} {}",
            "one update",
            cols(pd, pa),
            cols(sd, sa)
        )?;
        writeln!(
            f,
            "\nOne update against the active cells (packets kept alive by injection)"
        )?;
        writeln!(
            f,
            "  {:<8} {:>8} {:>13} {:>10} {:>10} {:>13}",
            "network", "packets", "active cells", "dense ms", "active ms", "dense/active"
        )?;
        let networks = [("planar", &self.planar), ("6-D", &self.six_d)];
        for (name, pairs) in networks {
            for pair in pairs.iter() {
                writeln!(
                    f,
                    "  {name:<8} {:>8} {:>13.0} {:>10.4} {:>10.4} {:>13.1}",
                    pair.active.packets,
                    pair.active.active_cells,
                    pair.dense.update_ms,
                    pair.active.update_ms,
                    pair.dense_over_active
                )?;
            }
        }
        Ok(())
    }
}
