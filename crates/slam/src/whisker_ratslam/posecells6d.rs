//! WhiskerRatSLAM's 6-D grid of pose cells (thesis §5.1.2.1–§5.1.2.3): x, y, z, roll,
//! pitch, yaw, 5 cells per axis by default, every axis wrapping.
//!
//! One update (Alg 2): feature excitation (Eq 5.8–5.9, [`PoseCells6::inject`]), local
//! excitation and inhibition with separable 5-wide Gaussians of variance 1 and 2 and
//! global inhibition 2e-5 (Eq 5.10, Alg 3–5), normalisation, then path integration:
//!
//! - **translation** (§5.1.2.3.3.1): for each orientation voxel (α', β', γ') the
//!   body-frame velocity is rotated by that voxel's orientation, R = Rz(γ')·Ry(β')·Rx(α')
//!   (the workspace's roll-pitch-yaw convention), and the voxel's x-y-z block is shifted
//!   by it. The shift is separable — along x, then y, then z, each a floor/ceil pair
//!   weighted 1 − frac and frac — which in each planar view puts on the remain, side,
//!   side and diagonal cells exactly the sector areas of Fig 5.10, and applies each
//!   velocity component once;
//! - **rotation** (§5.1.2.3.3.2, Fig 5.11): the grid is shifted along the roll, pitch
//!   and yaw axes by the rotation vector's components over the cell angle (360°/n), each
//!   a floor/ceil pair. As in the thesis, the body rotation vector's components drive
//!   the Euler axes directly: exact for rotation about one axis, first order otherwise.
//!
//! **Shift weights** (`shift`, an addition to the thesis): Fig 5.10–5.11 weight a
//! fractional shift's floor and ceil by 1 − frac and frac. On a 5-cell axis the stable
//! packet is, per axis, a rectified first Fourier mode (the excitation and inhibition
//! kernels span the whole axis), and a linear-weighted shift advances that mode's phase —
//! the decoded pose — by only 78–88 % of the command at the fractions one whisk
//! commands, so a lap's rotation is integrated ~1 cell short. The `phase` weights
//! ([`ShiftWeights::Phase`], in [`PoseCellParams::corrected`]) advance it exactly;
//! `linear` is the thesis' rule and the default.
//!
//! **Translation gain** (a limit of the thesis' grid, not fixed): each orientation
//! voxel moves its block in its own direction, and the stable packet spreads over every
//! rotation axis (marginal 0.44 at its centre, 0.24 at ±72°, 0.04 at ±144°: a mean
//! cos(orientation offset) of 0.52 per axis), so the decoded position advances by only
//! ~0.3 of a commanded forward motion (measured 0.28–0.34 at 0.05–0.5 cell per update
//! with `phase` weights). It is the same on every lap, so revisits still land on their
//! first-lap cells, which `tests/posecells6d.rs` tests.
//!
//! Cell i of a rotation axis of n cells stands for the angle 360°·i/n (cell 0 is 0°);
//! cell i of a translation axis for the position i·`cell_size_m` (modulo n cells).

use crate::invalid::Invalid;
use crate::pose_grid::{Attractor, NetworkShape, PoseGrid, ShiftWeights, wrapped_distance};
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Parameters of the 6-D pose cells.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PoseCellParams {
    /// Cells per axis: x, y, z, roll, pitch, yaw.
    pub cells: [usize; 6],
    /// Size of a translation cell (m). The thesis does not state it; 0.12 m keeps its
    /// 11 cm exploration steps under one cell per update.
    pub cell_size_m: f64,
    /// Width of the excitation kernel (cells, odd; at most the shortest axis).
    pub excite_width: usize,
    /// Variance of the excitation kernel (cells²).
    pub excite_variance: f64,
    /// Width of the inhibition kernel (cells, odd).
    pub inhibit_width: usize,
    /// Variance of the inhibition kernel (cells²).
    pub inhibit_variance: f64,
    /// Global inhibition (Alg 5).
    pub global_inhibition: f64,
    /// Fractional-shift weights of path integration (module documentation): the thesis'
    /// `linear` (default) or `phase`.
    pub shift: ShiftWeights,
    /// Cells per axis around the most active cell read by the best-pose decode
    /// (§5.1.2.3.4: the peak cell and its neighbours; odd). The default 5 reads the whole
    /// axis of the thesis' grid: there the attractor keeps only an axis' first two
    /// Fourier modes (the inhibition removes the mean, the second mode is kept at 4 %),
    /// so no second packet survives an update to be blended, and a 3-cell window makes
    /// the decode jump by up to ~0.8 cell whenever the most active cell changes (a
    /// revisit then reads 0.9–1.3 cells off its first visit instead of 0.1–0.5).
    pub decode_window: usize,
}

impl Default for PoseCellParams {
    fn default() -> Self {
        Self {
            cells: [5; 6],
            cell_size_m: 0.12,
            excite_width: 5,
            excite_variance: 1.0,
            inhibit_width: 5,
            inhibit_variance: 2.0,
            global_inhibition: 2e-5,
            shift: ShiftWeights::Linear,
            decode_window: 5,
        }
    }
}

impl PoseCellParams {
    /// The thesis' grid with the corrections of `Params::corrected`: phase-exact shifts.
    pub fn corrected() -> Self {
        Self {
            shift: ShiftWeights::Phase,
            ..Self::default()
        }
    }

    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), Invalid> {
        if self.cells.iter().any(|&n| n < 3) {
            return Err(format!("cells {:?}: expected at least 3 per axis", self.cells).into());
        }
        let shortest = *self.cells.iter().min().unwrap_or(&0);
        if self.decode_window.is_multiple_of(2) || self.decode_window > shortest {
            return Err(format!(
                "decode_window {}: expected an odd width of at most {shortest} cells",
                self.decode_window
            )
            .into());
        }
        self.shape().validate()
    }

    /// What the 6-D network shares with every pose-cell network.
    pub fn shape(&self) -> NetworkShape {
        NetworkShape {
            shortest_axis: *self.cells.iter().min().unwrap_or(&0),
            widths: [self.excite_width, self.inhibit_width],
            positives: [
                self.cell_size_m,
                self.excite_variance,
                self.inhibit_variance,
            ],
            global_inhibition: self.global_inhibition,
        }
    }

    /// The angle one cell of rotation axis `axis` (3, 4 or 5) stands for (rad).
    pub fn cell_angle(&self, axis: usize) -> f64 {
        TAU / self.cells[axis] as f64
    }
}

/// Pose-cell coordinates (fractional cells): x, y, z, roll, pitch, yaw.
pub type Cell6 = [f64; 6];

/// The 6-D pose-cell network.
#[derive(Debug, Clone)]
pub struct PoseCells6 {
    /// Its parameters.
    pub params: PoseCellParams,
    /// The activities.
    pub grid: PoseGrid,
    attractor: Attractor,
}

impl PoseCells6 {
    /// A network with all activity in `start` (rounded to a cell).
    pub fn new(params: PoseCellParams, start: &Cell6) -> Self {
        Self {
            params,
            grid: PoseGrid::packet(&params.cells, start),
            attractor: params.shape().attractor(),
        }
    }

    /// Adds `amount` of activity to the cell nearest `at` (Eq 5.9 as printed).
    pub fn inject(&mut self, at: &Cell6, amount: f64) {
        self.grid.inject_nearest(at, amount);
    }

    /// Adds a copy of the current activity, moved so that its most active cell lands on
    /// the cell nearest `at` and scaled by `fraction`: a bump whose peak is `fraction` of
    /// the packet's peak (Eq 5.9 with Ω read relative to the peak, as in the thesis' 1-D
    /// example where activity is normalised to the maximum, §5.1.2.3.1).
    pub fn inject_packet(&mut self, at: &Cell6, fraction: f64) {
        let peak = self.grid.coords(self.grid.argmax());
        let offset: Vec<i64> = at
            .iter()
            .zip(&peak)
            .map(|(a, &p)| a.round() as i64 - p as i64)
            .collect();
        self.grid.add_shifted_copy(&offset, fraction);
    }

    /// The network's attractor dynamics (its kernels and global inhibition).
    pub fn attractor(&self) -> &Attractor {
        &self.attractor
    }

    /// Local excitation, local and global inhibition, normalisation (Alg 3–5).
    pub fn excite_inhibit(&mut self) {
        self.attractor.apply(&mut self.grid);
    }

    /// Path integration of one update's motion: `translation` (m) and `rotation` (a
    /// rotation vector, rad), both in the body frame.
    pub fn path_integrate(&mut self, translation: &Vector3<f64>, rotation: &Vector3<f64>) {
        let [nx, ny, nz, na, nb, ng] = self.params.cells;
        let block = nx * ny * nz;
        let v = translation / self.params.cell_size_m;
        if v.norm() > 0.0 {
            for g in 0..ng {
                for b in 0..nb {
                    for a in 0..na {
                        let q = self.voxel_rotation(a, b, g);
                        let w = q * v;
                        let start = ((g * nb + b) * na + a) * block;
                        if self.grid.block_is_empty(start, block) {
                            continue;
                        }
                        self.grid
                            .shift_block(start, block, w.as_slice(), self.params.shift);
                    }
                }
            }
        }
        for k in 0..3 {
            let amount = rotation[k] / self.params.cell_angle(3 + k);
            if amount != 0.0 {
                self.grid.shift_axis_with(3 + k, amount, self.params.shift);
            }
        }
    }

    /// The orientation an orientation voxel stands for.
    pub fn voxel_rotation(&self, a: usize, b: usize, g: usize) -> UnitQuaternion<f64> {
        UnitQuaternion::from_euler_angles(
            a as f64 * self.params.cell_angle(3),
            b as f64 * self.params.cell_angle(4),
            g as f64 * self.params.cell_angle(5),
        )
    }

    /// One update without feature input: excitation/inhibition, then path integration.
    pub fn update(&mut self, translation: &Vector3<f64>, rotation: &Vector3<f64>) {
        self.excite_inhibit();
        self.path_integrate(translation, rotation);
    }

    /// The best pose (§5.1.2.3.4): population-vector decode of the most active cell and
    /// its neighbours (`decode_window` cells per axis).
    pub fn best(&self) -> Cell6 {
        let b = self.grid.best(self.params.decode_window);
        [b[0], b[1], b[2], b[3], b[4], b[5]]
    }

    /// Distance between two pose-cell coordinates (cells, Euclidean over the six axes,
    /// each the shorter way round).
    pub fn distance(&self, a: &Cell6, b: &Cell6) -> f64 {
        wrapped_distance(a, b, &self.params.cells)
    }
}

/// A naive dense 6-D periodic convolution of `grid` with the full 6-D product of
/// `kernel` — every cell against every kernel offset. The baseline of
/// `whisker bench slam`; equal to [`PoseGrid::convolve`] up to rounding.
pub fn dense_convolve(grid: &PoseGrid, kernel: &[f64]) -> Vec<f64> {
    let dims = grid.dims().to_vec();
    let d = dims.len();
    let w = kernel.len();
    let h = (w / 2) as i64;
    let offsets = w.pow(d as u32);
    let mut out = vec![0.0; grid.cells.len()];
    let mut k = vec![0usize; d];
    let mut coords = vec![0i64; d];
    for (i, &a) in grid.cells.iter().enumerate() {
        let c = grid.coords(i);
        k.iter_mut().for_each(|x| *x = 0);
        for _ in 0..offsets {
            let mut weight = a;
            for axis in 0..d {
                weight *= kernel[k[axis]];
                coords[axis] = c[axis] as i64 + k[axis] as i64 - h;
            }
            out[grid.index(&coords)] += weight;
            for x in k.iter_mut() {
                *x += 1;
                if *x < w {
                    break;
                }
                *x = 0;
            }
        }
    }
    out
}
