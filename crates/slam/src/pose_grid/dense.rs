//! The dense reference evaluation of the pose-grid operations ([`Evaluation::Dense`]):
//! every line of the grid through every tap, as Alg 3–5 and Fig 5.10–5.11 read, with the
//! taps rebuilt and the grid copied on each call. It is the reference the active-set
//! evaluation ([`super::active`]) is tested against, and the baseline of
//! `whisker bench slam`.
//!
//! [`Evaluation::Dense`]: super::Evaluation::Dense

use super::PoseGrid;

impl PoseGrid {
    /// Periodic convolution of every line along `axis` with an odd-width `kernel`: each
    /// cell spreads its activity to its neighbours with the kernel's weights (Alg 3).
    pub(super) fn convolve_axis_dense(&mut self, axis: usize, kernel: &[f64]) {
        let (n, stride) = (self.dims[axis], self.strides[axis]);
        let h = kernel.len() / 2;
        // For output cell j of a line: Σ_k kernel[k]·in[(j − k + h) mod n].
        let taps: Vec<Vec<(usize, f64)>> = (0..n)
            .map(|j| {
                kernel
                    .iter()
                    .enumerate()
                    .map(|(k, &w)| ((j + n * kernel.len() + h - k) % n, w))
                    .collect()
            })
            .collect();
        for_each_line(self.cells.len(), n, stride, |base| {
            for (j, t) in taps.iter().enumerate() {
                self.scratch[base + j * stride] = t
                    .iter()
                    .map(|&(i, w)| w * self.cells[base + i * stride])
                    .sum();
            }
        });
        std::mem::swap(&mut self.cells, &mut self.scratch);
    }

    /// Adds `factor` times a copy of the grid moved by the whole cells `offset`, through
    /// a copy of the grid shifted axis by axis.
    pub(super) fn add_shifted_copy_dense(&mut self, offset: &[i64], factor: f64) {
        let mut moved = self.clone();
        for (axis, &o) in offset.iter().enumerate() {
            if o != 0 {
                let (n, stride) = (moved.dims[axis], moved.strides[axis]);
                let split = super::split_shift(o as f64);
                shift_lines(&mut moved.cells, &mut moved.scratch, n, stride, split);
            }
        }
        for (c, m) in self.cells.iter_mut().zip(&moved.cells) {
            *c += factor * m;
        }
    }

    /// The best pose's marginals, the window's cells found by wrapped coordinates one by
    /// one.
    pub(super) fn marginals_dense(&self, peak: &[usize], spans: &[usize]) -> Vec<Vec<f64>> {
        let d = self.dims.len();
        let mut marginals: Vec<Vec<f64>> = self.dims.iter().map(|&n| vec![0.0; n]).collect();
        let total: usize = spans.iter().product();
        let mut offset = vec![0usize; d];
        let mut coords = vec![0i64; d];
        for _ in 0..total {
            for a in 0..d {
                coords[a] = peak[a] as i64 + offset[a] as i64 - (spans[a] / 2) as i64;
            }
            let v = self.cells[self.index(&coords)];
            for a in 0..d {
                marginals[a][coords[a].rem_euclid(self.dims[a] as i64) as usize] += v;
            }
            for a in 0..d {
                offset[a] += 1;
                if offset[a] < spans[a] {
                    break;
                }
                offset[a] = 0;
            }
        }
        marginals
    }
}

/// Calls `f` with the first index of every line of `n` cells `stride` apart in a grid of
/// `len` cells.
fn for_each_line(len: usize, n: usize, stride: usize, mut f: impl FnMut(usize)) {
    for outer in (0..len).step_by(n * stride) {
        for inner in 0..stride {
            f(outer + inner);
        }
    }
}

/// Shifts, in `cells` (lines of `n` cells `stride` apart), every line by the split shift
/// (floor, its weight, ceil, its weight), using `scratch` (same length) as the output
/// buffer.
pub(super) fn shift_lines(
    cells: &mut [f64],
    scratch: &mut [f64],
    n: usize,
    stride: usize,
    (lo, w_lo, _, w_hi): (i64, f64, i64, f64),
) {
    // Output cell j takes w_lo of cell j − lo and w_hi of cell j − lo − 1.
    let from = |j: usize, s: i64| (j as i64 - s).rem_euclid(n as i64) as usize;
    for_each_line(cells.len(), n, stride, |base| {
        for j in 0..n {
            scratch[base + j * stride] = w_lo * cells[base + from(j, lo) * stride]
                + w_hi * cells[base + from(j, lo + 1) * stride];
        }
    });
    cells.copy_from_slice(scratch);
}
