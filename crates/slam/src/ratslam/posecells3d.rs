//! RatSLAM's planar pose cells (thesis §2.1.2, §3.2.1): a
//! periodic (x, y, θ) grid — 30 × 30 × 36 cells of 0.015 m and 10° by default (Table 3.1,
//! read with its values shifted one row down: pc_dim_xy 30, pc_cell_x_size 0.015) —
//! with, per update, local excitation (7 wide, variance 1) and inhibition (5 wide,
//! variance 2), global inhibition 2e-5, normalisation, then path integration: first the
//! rotation (the θ axis shifted by the floor/ceil pair of dθ over the cell angle), then
//! the translation — each θ layer shifted by (d·cos θ, d·sin θ)/cell size, separably (x,
//! then y: an exact bilinear sub-cell shift, mass conserved; the reference implementation
//! loses one torus-corner cell's spill per layer — not here), the order the thesis
//! prescribes (§3.1.2: rotate, then translate).
//!
//! Frames: cell (i, j, k) stands for x = i·cell size, y = j·cell size (both modulo the
//! grid) and heading θ = k·360°/n_θ measured from +x towards +y — the same frame the
//! experience map uses (the reference implementation transposes x and y between the
//! two). Path integration alone moves the activity by exactly its velocity. With the
//! attractor dynamics the packet does not quite: it spans several θ layers, whose
//! neighbours move at cos 10°, cos 20°… of the velocity, and the rectified difference of
//! Gaussians pins it to the lattice, so that one moving a fraction of a cell per update
//! is held back (or, near a whole cell, pulled on). Measured over 100 updates at headings
//! 0° / 45° (`cargo run --release -p whisker-slam --example packet_speed`): 0.871 /
//! 0.850 of v·t at 0.1 cell per update, 0.934 / 0.898 at 0.25, 0.990 / 0.954 at 0.5,
//! 1.010 / 0.988 at 0.75, 0.9925 / 0.998 at 1 — the speed the thesis chose the cell
//! size for (§3.2.1: 15 mm per 1.5 Hz update) and `whisker maze-slam` drives it at. The
//! experience map takes its positions from odometry, not from the packet (§2.1.2), so
//! the pinning only delays experience creation at slow speeds.

use crate::invalid::Invalid;
use crate::pose_grid::{Attractor, NetworkShape, PoseGrid, ShiftWeights, wrapped_distance};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Parameters of the planar pose cells.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlanarCellParams {
    /// Cells along x and y.
    pub dim_xy: usize,
    /// Cells around θ.
    pub dim_th: usize,
    /// Size of an x/y cell (m).
    pub cell_size_m: f64,
    /// Width of the excitation kernel (cells).
    pub excite_width: usize,
    /// Variance of the excitation kernel.
    pub excite_variance: f64,
    /// Width of the inhibition kernel (cells).
    pub inhibit_width: usize,
    /// Variance of the inhibition kernel.
    pub inhibit_variance: f64,
    /// Global inhibition.
    pub global_inhibition: f64,
}

impl Default for PlanarCellParams {
    fn default() -> Self {
        Self {
            dim_xy: 30,
            dim_th: 36,
            cell_size_m: 0.015,
            excite_width: 7,
            excite_variance: 1.0,
            inhibit_width: 5,
            inhibit_variance: 2.0,
            global_inhibition: 2e-5,
        }
    }
}

impl PlanarCellParams {
    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), Invalid> {
        self.shape().validate()
    }

    /// What the planar network shares with every pose-cell network.
    pub fn shape(&self) -> NetworkShape {
        NetworkShape {
            shortest_axis: self.dim_xy.min(self.dim_th),
            widths: [self.excite_width, self.inhibit_width],
            positives: [
                self.cell_size_m,
                self.excite_variance,
                self.inhibit_variance,
            ],
            global_inhibition: self.global_inhibition,
        }
    }

    /// The heading one θ cell stands for (rad).
    pub fn cell_angle(&self) -> f64 {
        TAU / self.dim_th as f64
    }
}

/// Planar pose-cell coordinates (fractional cells): x, y, θ.
pub type Cell3 = [f64; 3];

/// The planar pose-cell network.
#[derive(Debug, Clone)]
pub struct PoseCells3 {
    /// Its parameters.
    pub params: PlanarCellParams,
    /// The activities (x fastest, then y, then θ).
    pub grid: PoseGrid,
    attractor: Attractor,
}

impl PoseCells3 {
    /// A network with all activity in the cell nearest `start`.
    pub fn new(params: PlanarCellParams, start: &Cell3) -> Self {
        Self {
            params,
            grid: PoseGrid::packet(&[params.dim_xy, params.dim_xy, params.dim_th], start),
            attractor: params.shape().attractor(),
        }
    }

    /// Adds `amount` of activity to the cell nearest `at` (view-template injection).
    pub fn inject(&mut self, at: &Cell3, amount: f64) {
        self.grid.inject_nearest(at, amount);
    }

    /// The network's attractor dynamics (its kernels and global inhibition).
    pub fn attractor(&self) -> &Attractor {
        &self.attractor
    }

    /// Local excitation and inhibition, global inhibition, normalisation.
    pub fn excite_inhibit(&mut self) {
        self.attractor.apply(&mut self.grid);
    }

    /// Path integration of one update: turn by `dtheta` (rad), then move `distance` (m)
    /// along each layer's heading. Mass is conserved exactly (up to rounding).
    pub fn path_integrate(&mut self, distance: f64, dtheta: f64) {
        let (n, nt) = (self.params.dim_xy, self.params.dim_th);
        if dtheta != 0.0 {
            self.grid.shift_axis(2, dtheta / self.params.cell_angle());
        }
        if distance == 0.0 {
            return;
        }
        let block = n * n;
        let v = distance / self.params.cell_size_m;
        for k in 0..nt {
            let start = k * block;
            if self.grid.block_is_empty(start, block) {
                continue;
            }
            let th = k as f64 * self.params.cell_angle();
            let (dx, dy) = (v * th.cos(), v * th.sin());
            self.grid
                .shift_block(start, block, &[dx, dy], ShiftWeights::Linear);
        }
    }

    /// One update without view input: excitation/inhibition, then path integration.
    pub fn update(&mut self, distance: f64, dtheta: f64) {
        self.excite_inhibit();
        self.path_integrate(distance, dtheta);
    }

    /// The best pose: population-vector decode around the most active cell (window of the
    /// excitation width).
    pub fn best(&self) -> Cell3 {
        let b = self.grid.best(self.params.excite_width);
        [b[0], b[1], b[2]]
    }

    /// Distance between two cells (cells, Euclidean over x, y, θ, each the shorter way).
    pub fn distance(&self, a: &Cell3, b: &Cell3) -> f64 {
        let n = [self.params.dim_xy, self.params.dim_xy, self.params.dim_th];
        wrapped_distance(a, b, &n)
    }
}
