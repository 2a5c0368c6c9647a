//! The best pose of a grid (§5.1.2.3.4, Fig 5.12): a window around the most active cell,
//! its activity summed onto each axis (Eq 5.11–5.12) and decoded by population vector.

use super::{Evaluation, PoseGrid, population_index};

impl PoseGrid {
    /// The best pose (§5.1.2.3.4): around the most active cell, a window of `window`
    /// cells per axis (at most the axis length); the window's activities summed onto each
    /// axis (Eq 5.11–5.12) and decoded by population vector, as fractional coordinates.
    pub fn best(&self, window: usize) -> Vec<f64> {
        let peak = self.coords(self.argmax());
        let spans: Vec<usize> = self.dims.iter().map(|&n| window.min(n)).collect();
        let marginals = match self.evaluation {
            Evaluation::Dense => self.marginals_dense(&peak, &spans),
            Evaluation::Active => self.marginals(&peak, &spans),
        };
        marginals.iter().map(|m| population_index(m)).collect()
    }

    /// The window's activities summed onto each axis, each sum taken in the order the
    /// dense reference visits the window (first axis fastest, from the peak's lower
    /// corner): the window is gathered in that order, then each axis' marginal is summed
    /// slab by slab.
    fn marginals(&self, peak: &[usize], spans: &[usize]) -> Vec<Vec<f64>> {
        let wrapped: Vec<Vec<usize>> = (0..self.dims.len())
            .map(|a| {
                let (n, half) = (self.dims[a], spans[a] / 2);
                (0..spans[a])
                    .map(|o| (peak[a] + n * spans[a] + o - half) % n)
                    .collect()
            })
            .collect();
        let mut window = Vec::with_capacity(spans.iter().product());
        self.gather(&wrapped, wrapped.len(), 0, &mut window);
        let mut marginals: Vec<Vec<f64>> = self.dims.iter().map(|&n| vec![0.0; n]).collect();
        let mut inner = 1;
        for (a, coords) in wrapped.iter().enumerate() {
            // One running sum per window coordinate, advanced side by side (each still
            // takes its cells in the visiting order).
            let span = coords.len();
            let sums = match span {
                3 => slab_sums::<3>(&window, inner).to_vec(),
                5 => slab_sums::<5>(&window, inner).to_vec(),
                7 => slab_sums::<7>(&window, inner).to_vec(),
                _ => {
                    let mut sums = vec![0.0; span];
                    add_slabs(&window, inner, &mut sums);
                    sums
                }
            };
            for (&c, sum) in coords.iter().zip(sums) {
                marginals[a][c] = sum;
            }
            inner *= span;
        }
        marginals
    }

    /// Appends to `window` the cells at the `wrapped` coordinates of the first `axes`
    /// axes, the first axis fastest, offset by `base`.
    fn gather(&self, wrapped: &[Vec<usize>], axes: usize, base: usize, window: &mut Vec<f64>) {
        let a = axes - 1;
        for &c in &wrapped[a] {
            let at = base + c * self.strides[a];
            if a == 0 {
                window.push(self.cells[at]);
            } else {
                self.gather(wrapped, a, at, window);
            }
        }
    }
}

/// The sums of a window's `S` slabs along one axis, with `S` known at compile time so
/// that the running sums stay in registers (the decode windows of 3, 5 and 7 cells).
fn slab_sums<const S: usize>(window: &[f64], inner: usize) -> [f64; S] {
    let mut sums = [0.0; S];
    add_slabs(window, inner, &mut sums);
    sums
}

/// Adds to `sums` the sums of a window's `sums.len()` slabs along one axis (slabs of
/// `inner` cells, repeated every `sums.len()·inner` cells), each taken in the window's
/// order.
#[inline(always)]
fn add_slabs(window: &[f64], inner: usize, sums: &mut [f64]) {
    let span = sums.len();
    for slab in window.chunks_exact(inner * span) {
        for p in 0..inner {
            for (o, sum) in sums.iter_mut().enumerate() {
                *sum += slab[o * inner + p];
            }
        }
    }
}
