//! Path integration on the grid (§3.1.2, §5.1.2.3.3.1, Fig 5.6–5.11): weighted periodic
//! shifts of every line along an axis, of the lines inside one block, and whole-cell
//! shifted copies (packet injection).

use super::{Evaluation, PoseGrid, ShiftWeights, active, dense};

impl PoseGrid {
    /// Shifts every line along `axis` by `amount` cells (fractional: floor and ceil
    /// shifts weighted 1 − frac and frac, Fig 5.11), wrapping; mass is conserved.
    pub fn shift_axis(&mut self, axis: usize, amount: f64) {
        self.shift_axis_with(axis, amount, ShiftWeights::Linear);
    }

    /// [`PoseGrid::shift_axis`] with the given fractional-shift `weights`.
    pub fn shift_axis_with(&mut self, axis: usize, amount: f64, weights: ShiftWeights) {
        let (n, stride) = (self.dims[axis], self.strides[axis]);
        let split = weights.split(amount, n);
        match self.evaluation {
            Evaluation::Dense => {
                dense::shift_lines(&mut self.cells, &mut self.scratch, n, stride, split)
            }
            Evaluation::Active => {
                active::scan(&self.cells, &self.dims, &mut self.masks);
                active::pass(
                    &mut self.cells,
                    &self.dims,
                    &self.strides,
                    axis,
                    &active::shift_taps(split, n),
                    &mut self.masks,
                    &mut self.workspace,
                );
            }
        }
    }

    /// Shifts the lines inside one block of `len` cells starting at `start` (a sub-grid
    /// whose axes are the first `amounts.len()` axes of the grid, `len` their product)
    /// along each of those axes in turn by its amount (cells; an axis whose amount is 0
    /// is left alone), with the given fractional-shift `weights`. Path integration of one
    /// orientation voxel or heading layer (§5.1.2.3.3.1, §3.1.2).
    pub fn shift_block(
        &mut self,
        start: usize,
        len: usize,
        amounts: &[f64],
        weights: ShiftWeights,
    ) {
        let axes = amounts.len();
        assert_eq!(
            len,
            self.dims[..axes].iter().product::<usize>(),
            "a block spans the first axes of the grid"
        );
        let cells = &mut self.cells[start..start + len];
        if self.evaluation == Evaluation::Active {
            active::scan(cells, &self.dims[..axes], &mut self.block_masks);
        }
        for (axis, &amount) in amounts.iter().enumerate() {
            if amount == 0.0 {
                continue;
            }
            let (n, stride) = (self.dims[axis], self.strides[axis]);
            let split = weights.split(amount, n);
            match self.evaluation {
                Evaluation::Dense => {
                    let scratch = &mut self.scratch[start..start + len];
                    dense::shift_lines(cells, scratch, n, stride, split);
                }
                Evaluation::Active => active::pass(
                    cells,
                    &self.dims[..axes],
                    &self.strides[..axes],
                    axis,
                    &active::shift_taps(split, n),
                    &mut self.block_masks,
                    &mut self.workspace,
                ),
            }
        }
    }

    /// Adds `factor` times a copy of the grid moved by the whole cells `offset` (wrapping,
    /// [`PoseGrid::shift_axis`] per axis): the activity's own shape, re-centred. Used to
    /// inject a packet-shaped bump.
    pub fn add_shifted_copy(&mut self, offset: &[i64], factor: f64) {
        if self.evaluation == Evaluation::Dense {
            return self.add_shifted_copy_dense(offset, factor);
        }
        // A whole-cell shift moves each cell unchanged (weights 1 and 0): the copy is
        // the grid with its indices moved.
        let moved: Vec<usize> = self
            .dims
            .iter()
            .zip(offset)
            .map(|(&n, &o)| o.rem_euclid(n as i64) as usize)
            .collect();
        let axes = self.dims.len();
        let layout = (&self.dims[..], &self.strides[..], &moved[..]);
        roll(&self.cells, &mut self.scratch, layout, axes, (0, 0));
        for (c, m) in self.cells.iter_mut().zip(&self.scratch) {
            *c += factor * m;
        }
    }
}

/// Copies the cells of the first `axes` axes from `from` (starting at `bases.0`) to `to`
/// (at `bases.1`), each axis rolled by its `moved` cells: `layout` is (dims, strides,
/// moved). A line of the first axis is two contiguous copies.
fn roll(
    from: &[f64],
    to: &mut [f64],
    layout: (&[usize], &[usize], &[usize]),
    axes: usize,
    (src, dst): (usize, usize),
) {
    let (dims, strides, moved) = layout;
    let a = axes - 1;
    let (n, k) = (dims[a], moved[a]);
    if a == 0 {
        to[dst + k..dst + n].copy_from_slice(&from[src..src + n - k]);
        to[dst..dst + k].copy_from_slice(&from[src + n - k..src + n]);
        return;
    }
    for c in 0..n {
        let bases = (src + c * strides[a], dst + (c + k) % n * strides[a]);
        roll(from, to, layout, a, bases);
    }
}
