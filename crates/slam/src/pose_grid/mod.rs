//! A periodic N-dimensional grid of pose cells and the operations RatSLAM (3-D, §2.1.2)
//! and WhiskerRatSLAM (6-D, §5.1.2.3) share: separable local excitation and inhibition
//! (Alg 3–4, Eq 5.10), global inhibition (Alg 5), normalisation, weighted periodic shifts
//! (path integration, Fig 5.6–5.11) and the population-vector decode of the best pose
//! (§5.1.2.3.4, Fig 5.12).
//!
//! Every axis wraps (the grid is a torus). Cells are stored with the first axis fastest.
//! Coordinates of cell i on an axis of n cells stand for the angle 2π·i/n, so the
//! population vector of an axis is a weighted sum of unit vectors at those angles.
//!
//! Two evaluations of the same operations ([`Evaluation`]): the active-set one
//! ([`active`], the default) works only where activity can be and reuses its buffers;
//! the dense one ([`dense`]) visits every cell and is the reference. They give the same
//! bits (`tests/pose_grid_active.rs`).

mod active;
mod decode;
mod dense;
mod shift;

use crate::invalid::Invalid;
use std::f64::consts::TAU;

/// How a [`PoseGrid`] evaluates its operations. Both give bit-identical activities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Evaluation {
    /// Only the lines, rows and columns the activity's per-axis support allows, with the
    /// taps and buffers kept ([`active`]).
    #[default]
    Active,
    /// Every cell of every line through every tap, taps rebuilt and the grid copied on
    /// each call: the reference and the baseline of `whisker bench slam` ([`dense`]).
    Dense,
}

/// A periodic grid of activities.
#[derive(Debug, Clone)]
pub struct PoseGrid {
    dims: Vec<usize>,
    strides: Vec<usize>,
    /// Activities, first axis fastest.
    pub cells: Vec<f64>,
    scratch: Vec<f64>,
    /// The activities after local excitation, kept for local inhibition (Alg 3–4).
    excited: Vec<f64>,
    evaluation: Evaluation,
    masks: active::Masks,
    block_masks: active::Masks,
    taps: Vec<(usize, f64)>,
    workspace: active::Workspace,
}

/// Two grids are equal when their axes and activities are.
impl PartialEq for PoseGrid {
    fn eq(&self, other: &Self) -> bool {
        self.dims == other.dims && self.cells == other.cells
    }
}

/// A normalised 1-D Gaussian kernel of odd `width` and `variance` (in cells²): the
/// separable factor of Eq 5.10, scaled so that its weights sum to 1.
pub fn gaussian_kernel(width: usize, variance: f64) -> Vec<f64> {
    let h = (width / 2) as f64;
    let w: Vec<f64> = (0..width)
        .map(|k| (-(k as f64 - h).powi(2) / (2.0 * variance)).exp())
        .collect();
    let s: f64 = w.iter().sum();
    w.into_iter().map(|x| x / s).collect()
}

/// Splits a shift of `amount` cells into (floor shift, its weight, ceil shift, its weight)
/// (Fig 5.11: 1 − frac and frac).
pub fn split_shift(amount: f64) -> (i64, f64, i64, f64) {
    let lo = amount.floor();
    let frac = amount - lo;
    (lo as i64, 1.0 - frac, lo as i64 + 1, frac)
}

/// How a fractional shift is shared between the floor and the ceil shift.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShiftWeights {
    /// 1 − frac and frac (Fig 5.10–5.11 as printed).
    #[default]
    Linear,
    /// Weights under which the population vector of the axis ([`population_index`])
    /// advances by exactly the commanded fraction of a cell, for any activity: on an axis
    /// of n cells (φ = 2π/n) the ceil weight is sin(frac·φ) / (sin(frac·φ) +
    /// sin((1 − frac)·φ)), the floor weight the rest (mass is conserved). The linear
    /// weights advance it by atan(f·sin φ / (1 − f + f·cos φ)) instead, which on a
    /// 5-cell axis is 78 % of the command at frac 0.05 and 86 % at 0.2 (exact only at
    /// 0, ½ and 1); on long axes the two coincide.
    Phase,
}

impl ShiftWeights {
    /// (floor shift, its weight, ceil shift, its weight) of a shift of `amount` cells on
    /// an axis of `n` cells.
    pub fn split(self, amount: f64, n: usize) -> (i64, f64, i64, f64) {
        let (lo, w_lo, hi, w_hi) = split_shift(amount);
        match self {
            ShiftWeights::Linear => (lo, w_lo, hi, w_hi),
            ShiftWeights::Phase => {
                let phi = TAU / n as f64;
                let (a, b) = ((w_hi * phi).sin(), (w_lo * phi).sin());
                let up = if a + b > 0.0 { a / (a + b) } else { w_hi };
                (lo, 1.0 - up, hi, up)
            }
        }
    }
}

/// The population-vector decode of one axis' activities (Fig 5.12): the angle of
/// Σ aᵢ·(cos 2πi/n, sin 2πi/n), wrapped to [0, 2π), as a fractional cell index in [0, n).
pub fn population_index(activity: &[f64]) -> f64 {
    let n = activity.len() as f64;
    let (c, s) = activity
        .iter()
        .enumerate()
        .fold((0.0, 0.0), |(c, s), (i, a)| {
            let t = TAU * i as f64 / n;
            (c + a * t.cos(), s + a * t.sin())
        });
    let angle = s.atan2(c).rem_euclid(TAU);
    (angle * n / TAU) % n
}

/// Euclidean distance between two fractional cell coordinates on a torus of axis
/// lengths `dims`, each axis the shorter way round (cells).
pub fn wrapped_distance(a: &[f64], b: &[f64], dims: &[usize]) -> f64 {
    a.iter()
        .zip(b)
        .zip(dims)
        .map(|((x, y), &n)| {
            let d = (x - y).rem_euclid(n as f64);
            d.min(n as f64 - d).powi(2)
        })
        .sum::<f64>()
        .sqrt()
}

/// The parameters every pose-cell network shares: checked, and made into its
/// [`Attractor`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetworkShape {
    /// Length of the shortest axis (cells).
    pub shortest_axis: usize,
    /// Excitation and inhibition kernel widths (cells).
    pub widths: [usize; 2],
    /// Cell size (m) and the two kernel variances (cells²).
    pub positives: [f64; 3],
    /// Global inhibition.
    pub global_inhibition: f64,
}

impl NetworkShape {
    /// Checks that every axis has at least 3 cells, the kernels are odd and no wider than
    /// the shortest axis (a wider window wraps onto itself), sizes and variances are
    /// positive and global inhibition ≥ 0; the message names the field.
    pub fn validate(&self) -> Result<(), Invalid> {
        let shortest = self.shortest_axis;
        if shortest < 3 {
            return Err(format!("{shortest} cells on an axis: expected at least 3").into());
        }
        for (name, w) in ["excite_width", "inhibit_width"]
            .into_iter()
            .zip(self.widths)
        {
            if w.is_multiple_of(2) || w > shortest {
                return Err(format!(
                    "{name} {w}: expected an odd width of at most {shortest} cells (a wider window wraps onto itself)"
                ).into());
            }
        }
        for (name, v) in ["cell_size_m", "excite_variance", "inhibit_variance"]
            .into_iter()
            .zip(self.positives)
        {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} {v}: expected a positive number").into());
            }
        }
        let g = self.global_inhibition;
        if !(g.is_finite() && g >= 0.0) {
            return Err(format!("global_inhibition {g}: expected a number ≥ 0").into());
        }
        Ok(())
    }

    /// The network's attractor dynamics: the excitation and inhibition kernels
    /// ([`gaussian_kernel`] of each width and variance) and the global inhibition.
    pub fn attractor(&self) -> Attractor {
        Attractor {
            excite: gaussian_kernel(self.widths[0], self.positives[1]),
            inhibit: gaussian_kernel(self.widths[1], self.positives[2]),
            global_inhibition: self.global_inhibition,
        }
    }
}

/// The attractor dynamics of a pose-cell network (Alg 3–5: excitation, inhibition, global
/// inhibition, normalisation), its kernels built once.
#[derive(Debug, Clone)]
pub struct Attractor {
    excite: Vec<f64>,
    inhibit: Vec<f64>,
    global_inhibition: f64,
}

impl Attractor {
    /// Excitation, inhibition, global inhibition and normalisation of `grid`
    /// ([`PoseGrid::excite_inhibit`]).
    pub fn apply(&self, grid: &mut PoseGrid) {
        grid.excite_inhibit(&self.excite, &self.inhibit, self.global_inhibition);
    }

    /// Local excitation alone (Alg 3, [`PoseGrid::excite`]): the first step of
    /// [`Attractor::apply`].
    pub fn excite(&self, grid: &mut PoseGrid) {
        grid.excite(&self.excite);
    }

    /// Local inhibition alone (Alg 4, the excited grid convolved with the inhibition
    /// kernel): the second step.
    pub fn inhibit(&self, grid: &mut PoseGrid) {
        grid.convolve(&self.inhibit);
    }

    /// The difference of the two, global inhibition and normalisation (Alg 5,
    /// [`PoseGrid::inhibit_globally`]): the last step.
    pub fn inhibit_globally(&self, grid: &mut PoseGrid) {
        grid.inhibit_globally(self.global_inhibition);
    }
}

impl PoseGrid {
    /// An all-zero grid of the given axis lengths.
    pub fn new(dims: &[usize]) -> Self {
        assert!(dims.iter().all(|&n| n > 0), "every axis needs a cell");
        let mut strides = Vec::with_capacity(dims.len());
        let mut s = 1;
        for &n in dims {
            strides.push(s);
            s *= n;
        }
        Self {
            dims: dims.to_vec(),
            strides,
            cells: vec![0.0; s],
            scratch: vec![0.0; s],
            excited: Vec::new(),
            evaluation: Evaluation::default(),
            masks: Vec::new(),
            block_masks: Vec::new(),
            taps: Vec::new(),
            workspace: active::Workspace::default(),
        }
    }

    /// How the grid evaluates its operations.
    pub fn evaluation(&self) -> Evaluation {
        self.evaluation
    }

    /// Sets how the grid evaluates its operations (the activities are unchanged).
    pub fn set_evaluation(&mut self, evaluation: Evaluation) {
        self.evaluation = evaluation;
    }

    /// Axis lengths.
    pub fn dims(&self) -> &[usize] {
        &self.dims
    }

    /// Flat index of integer coordinates (wrapped onto the grid).
    pub fn index(&self, coords: &[i64]) -> usize {
        coords
            .iter()
            .zip(&self.dims)
            .zip(&self.strides)
            .map(|((&c, &n), &s)| c.rem_euclid(n as i64) as usize * s)
            .sum()
    }

    /// Integer coordinates of a flat index.
    pub fn coords(&self, index: usize) -> Vec<usize> {
        self.dims
            .iter()
            .zip(&self.strides)
            .map(|(&n, &s)| (index / s) % n)
            .collect()
    }

    /// Total activity.
    pub fn sum(&self) -> f64 {
        self.cells.iter().sum()
    }

    /// Scales the activities to sum 1 (left alone when the sum is not positive).
    pub fn normalise(&mut self) {
        let s = self.sum();
        if s > 0.0 {
            for c in &mut self.cells {
                *c /= s;
            }
        }
    }

    /// Periodic convolution of every line along `axis` with an odd-width `kernel`: each
    /// cell spreads its activity to its neighbours with the kernel's weights (Alg 3).
    pub fn convolve_axis(&mut self, axis: usize, kernel: &[f64]) {
        match self.evaluation {
            Evaluation::Dense => self.convolve_axis_dense(axis, kernel),
            Evaluation::Active => {
                active::scan(&self.cells, &self.dims, &mut self.masks);
                self.convolve_axis_active(axis, kernel);
            }
        }
    }

    /// [`PoseGrid::convolve_axis`] on the current support (`self.masks`).
    fn convolve_axis_active(&mut self, axis: usize, kernel: &[f64]) {
        active::kernel_taps(kernel, self.dims[axis], &mut self.taps);
        active::pass(
            &mut self.cells,
            &self.dims,
            &self.strides,
            axis,
            &self.taps,
            &mut self.masks,
            &mut self.workspace,
        );
    }

    /// Periodic convolution along every axis with the same kernel (a separable N-D kernel).
    pub fn convolve(&mut self, kernel: &[f64]) {
        match self.evaluation {
            Evaluation::Dense => {
                (0..self.dims.len()).for_each(|axis| self.convolve_axis_dense(axis, kernel))
            }
            Evaluation::Active => {
                active::scan(&self.cells, &self.dims, &mut self.masks);
                (0..self.dims.len()).for_each(|axis| self.convolve_axis_active(axis, kernel));
            }
        }
    }

    /// Local excitation then local inhibition (Alg 3–4): p ← E − I with E = p ∗ excite
    /// and I = E ∗ inhibit; then global inhibition (Alg 5): cells at or above
    /// `global` lose `global`, the others go to 0; then normalisation to sum 1.
    pub fn excite_inhibit(&mut self, excite: &[f64], inhibit: &[f64], global: f64) {
        self.excite(excite);
        self.convolve(inhibit);
        self.inhibit_globally(global);
    }

    /// Local excitation (Alg 3): the grid convolved with `kernel`, the result kept for
    /// [`PoseGrid::inhibit_globally`].
    pub fn excite(&mut self, kernel: &[f64]) {
        self.convolve(kernel);
        match self.evaluation {
            Evaluation::Dense => self.excited = self.cells.clone(),
            Evaluation::Active => {
                self.excited.resize(self.cells.len(), 0.0);
                self.excited.copy_from_slice(&self.cells);
            }
        }
    }

    /// Given the grid after local inhibition (I = E ∗ inhibit), p ← E − I with E the
    /// activities [`PoseGrid::excite`] kept; global inhibition (Alg 5): cells at or above
    /// `global` lose `global`, the others go to 0; then normalisation to sum 1.
    pub fn inhibit_globally(&mut self, global: f64) {
        for (c, e) in self.cells.iter_mut().zip(&self.excited) {
            let p = e - *c;
            *c = if p >= global { p - global } else { 0.0 };
        }
        self.normalise();
    }

    /// A grid of the given axis lengths with all its activity (unit mass) in the cell
    /// nearest `at`: a network's starting packet.
    pub fn packet(dims: &[usize], at: &[f64]) -> Self {
        let mut grid = Self::new(dims);
        grid.inject_nearest(at, 1.0);
        grid
    }

    /// Adds `amount` of activity to the cell nearest the fractional coordinates `at`
    /// (wrapped).
    pub fn inject_nearest(&mut self, at: &[f64], amount: f64) {
        let coords: Vec<i64> = at.iter().map(|c| c.round() as i64).collect();
        let i = self.index(&coords);
        self.cells[i] += amount;
    }

    /// Whether the block of `len` cells from `start` holds no activity.
    pub fn block_is_empty(&self, start: usize, len: usize) -> bool {
        self.cells[start..start + len].iter().all(|&c| c == 0.0)
    }

    /// Index of the most active cell (the first on ties).
    pub fn argmax(&self) -> usize {
        self.cells
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (i, &a)| {
                if a > best.1 { (i, a) } else { best }
            })
            .0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn population_vector_worked_example() {
        // Fig 5.12: 1, 3.1 and 0.8 at 360°, 288° and 216° of a 5-cell ring decode to
        // 290.978°: cells 0, 4 and 3 stand for 0° (= 360°), 288° and 216°.
        let index = population_index(&[1.0, 0.0, 0.0, 0.8, 3.1]);
        let degrees = index * 72.0;
        assert!((degrees - 290.978).abs() < 1e-3, "{degrees}");
    }

    #[test]
    fn excitation_of_one_active_cell_reproduces_fig_5_3_with_the_wrap() {
        // A ring of 12 head-direction cells (30° apart), one active cell; excitation
        // spreads it over 5 cells with the normalised Gaussian of variance 1.
        let z = 1.0 + 2.0 * (-0.5f64).exp() + 2.0 * (-2.0f64).exp();
        let expect = [(-2.0f64).exp() / z, (-0.5f64).exp() / z, 1.0 / z];
        for (active, spread) in [(4, [2, 3, 4, 5, 6]), (0, [10, 11, 0, 1, 2])] {
            let mut ring = PoseGrid::new(&[12]);
            ring.cells[active] = 1.0;
            ring.convolve(&gaussian_kernel(5, 1.0));
            for (k, &cell) in spread.iter().enumerate() {
                let want = expect[2 - (k as i64 - 2).unsigned_abs() as usize];
                assert!((ring.cells[cell] - want).abs() < 1e-15);
            }
            let others: f64 = (0..12)
                .filter(|c| !spread.contains(c))
                .map(|c| ring.cells[c])
                .sum();
            assert_eq!(others, 0.0);
            assert!((ring.sum() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn yaw_rate_of_158_degrees_shifts_2_and_3_cells_weighted_0_8_and_0_2() {
        // Fig 5.11: 5 yaw cells of 72°, a whole yaw layer active, 158°/s for 1 s.
        let (lo, w_lo, hi, w_hi) = split_shift(158.0 / 72.0);
        assert_eq!((lo, hi), (2, 3));
        assert!((w_lo - 0.8).abs() < 0.01 && (w_hi - 0.2).abs() < 0.01);
        assert!((w_hi - (158.0 / 72.0 - 2.0)).abs() < 1e-15);
        let mut grid = PoseGrid::new(&[3, 5]);
        grid.cells[..3].fill(1.0 / 3.0);
        grid.shift_axis(1, 158.0 / 72.0);
        for x in 0..3 {
            assert!((grid.cells[grid.index(&[x, 2])] - w_lo / 3.0).abs() < 1e-15);
            assert!((grid.cells[grid.index(&[x, 3])] - w_hi / 3.0).abs() < 1e-15);
        }
        assert!((grid.sum() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn shifts_move_the_centre_of_mass_v_t_cells_across_the_wrap_and_keep_the_mass() {
        // A packet at cell 90 of a 100-cell ring driven 0.13 cell per update for 100
        // updates crosses the wrap; its mean, taken over the 100 cells centred on cell
        // 103 ≡ 3 (the binomial spread has σ ≈ 3.4 cells), is exactly 13 cells further on.
        let mut ring = PoseGrid::new(&[100]);
        for (c, a) in [(89, 0.25), (90, 0.5), (91, 0.25)] {
            ring.cells[c] = a;
        }
        for _ in 0..100 {
            ring.shift_axis(0, 0.13);
            assert!((ring.sum() - 1.0).abs() < 1e-12);
        }
        let mean: f64 = ring
            .cells
            .iter()
            .enumerate()
            .map(|(i, a)| a * ((i as f64 - 3.0 + 50.0).rem_euclid(100.0) - 50.0 + 13.0))
            .sum::<f64>();
        assert!((mean - 13.0).abs() < 1e-9, "moved {mean} cells");
    }

    #[test]
    fn a_stable_packet_stays_put() {
        let mut grid = PoseGrid::new(&[5, 5, 5]);
        let centre = grid.index(&[2, 2, 2]);
        grid.cells[centre] = 1.0;
        let (exc, inh) = (gaussian_kernel(5, 1.0), gaussian_kernel(5, 2.0));
        for _ in 0..1000 {
            grid.excite_inhibit(&exc, &inh, 2e-5);
            assert!((grid.sum() - 1.0).abs() < 1e-12);
        }
        for c in grid.best(5) {
            assert!((c - 2.0).abs() < 1e-9);
        }
        assert_eq!(grid.argmax(), centre);
    }
}
