//! `whisker bench slam`: the cost of WhiskerRatSLAM's core operations (thesis Ch 5).
//!
//! - one 6-D pose-cell update at the default 5⁶ cells: local excitation, local and
//!   global inhibition, normalisation and path integration (translation per orientation
//!   voxel, rotation), from a settled packet; the mean over `--updates` updates;
//! - the baseline, measured in the same run: one naive dense 6-D convolution of the same
//!   grid with the full 5⁶-entry excitation kernel (every cell against every offset), the
//!   way Eq 5.10 reads, and the separable excitation pass that replaces it;
//! - one point feature histogram of an 18-contact whisk;
//! - one planar RatSLAM pose-cell update at 21 × 21 × 36 cells (Ch 3), one cell forward
//!   and 10° of turn per update.
//!
//! Timing is a benchmark, never a test.

use crate::error::{Error, Result};
use nalgebra::{Point3, Vector3};
use rand::RngExt;
use serde::Serialize;
use std::fmt;
use std::time::Instant;
use whisker_slam::features::pfh::{PfhParams, histogram};
use whisker_slam::pose_grid::gaussian_kernel;
use whisker_slam::ratslam::posecells3d::{PlanarCellParams, PoseCells3};
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::posecells6d::{PoseCellParams, PoseCells6, dense_convolve};

/// What `whisker bench slam` measured (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub posecell3d_cells: usize,
    pub posecell3d_update_ms: f64,
    pub posecell6d_cells: usize,
    pub posecell6d_update_ms: f64,
    pub naive_dense_ms: f64,
    pub separable_excitation_ms: f64,
    pub dense_over_separable: f64,
    pub pfh_18_contacts_ms: f64,
    pub pfh_bins: usize,
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

/// `whisker bench slam` over `updates` pose-cell updates.
pub fn slam(updates: usize) -> Result<Report> {
    if updates == 0 {
        return Err(Error::Input("--updates: expected at least 1".into()));
    }
    let params = PoseCellParams::default();
    let mut cells = PoseCells6::new(params, &[2.0; 6]);
    for _ in 0..20 {
        cells.excite_inhibit();
    }
    // A slow wander: 0.3 cell forward, 5° of yaw and 2° of roll per update.
    let (v, w) = (
        Vector3::new(0.3 * params.cell_size_m, 0.0, 0.0),
        Vector3::new(2f64.to_radians(), 0.0, 5f64.to_radians()),
    );
    let update_ms = time_ms(updates, || cells.update(&v, &w));
    let kernel = gaussian_kernel(params.excite_width, params.excite_variance);
    let mut dense_out = Vec::new();
    let dense_ms = time_ms(1, || dense_out = dense_convolve(&cells.grid, &kernel));
    let mut separable = cells.grid.clone();
    let separable_ms = time_ms(updates, || separable.convolve(&kernel));
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
    let pfh_ms = time_ms(updates, || {
        bins = histogram(&contacts, &Point3::origin(), &pfh).len();
    });
    let planar = PlanarCellParams {
        dim_xy: 21,
        ..PlanarCellParams::default()
    };
    let mut cells3 = PoseCells3::new(planar, &[10.0, 10.0, 0.0]);
    let posecell3d_ms = time_ms(updates, || {
        cells3.update(planar.cell_size_m, 10f64.to_radians())
    });
    Ok(Report {
        posecell3d_cells: cells3.grid.cells.len(),
        posecell3d_update_ms: posecell3d_ms,
        posecell6d_cells: cells.grid.cells.len(),
        posecell6d_update_ms: update_ms,
        naive_dense_ms: dense_ms,
        separable_excitation_ms: separable_ms,
        dense_over_separable: dense_ms / separable_ms,
        pfh_18_contacts_ms: pfh_ms,
        pfh_bins: bins,
        updates,
    })
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (dense_ms, separable_ms, update_ms) = (
            self.naive_dense_ms,
            self.separable_excitation_ms,
            self.posecell6d_update_ms,
        );
        writeln!(
            f,
            "WhiskerRatSLAM core, {} pose cells (5 per axis), {} updates",
            self.posecell6d_cells, self.updates
        )?;
        writeln!(f, "  {:<58} {:>12} {:>10}", "case", "ms", "ratio")?;
        writeln!(
            f,
            "  {:<58} {:>12.3} {:>10.1}",
            "baseline: naive dense 6-D excitation (5^6 kernel)", dense_ms, 1.0
        )?;
        writeln!(
            f,
            "  {:<58} {:>12.4} {:>10.1}",
            "separable excitation (six 1-D passes)",
            separable_ms,
            dense_ms / separable_ms
        )?;
        writeln!(
            f,
            "  {:<58} {:>12.4} {:>10.1}",
            "one 6-D pose-cell update (excite, inhibit, path integration)",
            update_ms,
            dense_ms / update_ms
        )?;
        writeln!(
            f,
            "  {:<58} {:>12.4}",
            format!(
                "point feature histogram, 18 contacts, {} bins",
                self.pfh_bins
            ),
            self.pfh_18_contacts_ms
        )?;
        writeln!(
            f,
            "  {:<58} {:>12.4}",
            format!(
                "one planar pose-cell update, {} cells (21x21x36)",
                self.posecell3d_cells
            ),
            self.posecell3d_update_ms
        )
    }
}
