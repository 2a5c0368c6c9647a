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
//! Cell i of a rotation axis of n cells stands for the angle 360°·i/n (cell 0 is 0°);
//! cell i of a translation axis for the position i·`cell_size_m` (modulo n cells).

use crate::pose_grid::{Attractor, NetworkShape, PoseGrid, wrapped_distance};
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
        }
    }
}

impl PoseCellParams {
    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        if self.cells.iter().any(|&n| n < 3) {
            return Err(format!(
                "cells {:?}: expected at least 3 per axis",
                self.cells
            ));
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

    /// Adds `amount` of activity to the cell nearest `at` (Eq 5.9).
    pub fn inject(&mut self, at: &Cell6, amount: f64) {
        self.grid.inject_nearest(at, amount);
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
                        for (axis, amount) in w.iter().enumerate() {
                            if *amount != 0.0 {
                                self.grid.shift_block_axis(start, block, axis, *amount);
                            }
                        }
                    }
                }
            }
        }
        for k in 0..3 {
            let amount = rotation[k] / self.params.cell_angle(3 + k);
            if amount != 0.0 {
                self.grid.shift_axis(3 + k, amount);
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

    /// The best pose (§5.1.2.3.4): population-vector decode around the most active cell.
    pub fn best(&self) -> Cell6 {
        let b = self.grid.best(self.params.excite_width);
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
