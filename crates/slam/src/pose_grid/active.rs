//! The active-set evaluation of the pose-grid operations ([`Evaluation::Active`], the
//! default): the work of a pass goes only where activity can be.
//!
//! **The support.** Per axis, the coordinates at which some cell is non-zero
//! ([`scan`]); a cell can be active only if each of its coordinates is set on its axis.
//! This product of per-axis sets is a bounding box generalised to the wrap (a packet
//! across the grid's edge sets both ends of an axis) and to several packets (each adds
//! its coordinates). OpenRatSLAM keeps a list of active cells instead; per-axis sets keep
//! the separable passes over contiguous memory.
//!
//! **A pass** ([`pass`]) along an axis of n cells is out[j] = Σₜ wₜ·in[(j + dₜ) mod n]
//! on every line: a kernel of Alg 3–4 (dₜ = h − k, wₜ = kernel[k]) or the floor/ceil pair
//! of a fractional shift (Fig 5.10–5.11). It visits only the lines whose other
//! coordinates are in the support, computes only the output rows some tap reaches from an
//! active row, reads only active rows, and along a row only the runs of columns the
//! faster axes' support allows. The axis' support then becomes those output rows.
//!
//! **Equal to the dense reference bit for bit.** The taps are summed in the reference's
//! order, from −0.0 as `Iterator::sum` does; a skipped tap reads a cell that is exactly
//! zero, and adding w·0 = +0 to a sum that already holds a term changes nothing. On the
//! 5⁶ WhiskerRatSLAM grid the settled packet sets every coordinate of every axis (its
//! kernels span each axis), so there the evaluation is the dense one with the taps
//! precomputed and no copies; on the planar grid it is a few hundred cells of 15,876.
//!
//! [`Evaluation::Active`]: super::Evaluation::Active

/// Per axis, whether activity may be found at each coordinate.
pub type Masks = Vec<Vec<bool>>;

/// The support of `cells` (laid out first axis fastest, axis lengths `dims`): per axis,
/// the coordinates at which some cell is non-zero (NaN counts as activity). The slowest
/// axis is read off its contiguous slabs, which are then OR-ed onto one another to give
/// the occupancy of the remaining axes, and so on down to the fastest.
pub fn scan(cells: &[f64], dims: &[usize], masks: &mut Masks) {
    masks.resize_with(dims.len(), Vec::new);
    let mut occupied: Vec<bool> = cells.iter().map(|&c| c != 0.0).collect();
    for (axis, &n) in dims.iter().enumerate().rev() {
        let rest = occupied.len() / n;
        let mask = &mut masks[axis];
        mask.clear();
        mask.extend(occupied.chunks_exact(rest).map(|slab| slab.contains(&true)));
        if axis > 0 {
            let (first, others) = occupied.split_at_mut(rest);
            for slab in others.chunks_exact(rest) {
                for (f, &o) in first.iter_mut().zip(slab) {
                    *f |= o;
                }
            }
            occupied.truncate(rest);
        }
    }
}

/// Buffers a pass reuses from call to call.
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    /// Output rows of the block being computed.
    out: Vec<f64>,
    /// Runs (start, length) of supported columns within a row.
    runs: Vec<(usize, usize)>,
    /// First cells of the supported blocks (one line of rows each).
    bases: Vec<usize>,
    /// Output rows of the axis.
    rows: Vec<bool>,
    /// For a stride-1 axis, the supported lines' cells, column by column.
    columns: Vec<f64>,
    swap_usize: Vec<usize>,
    swap_runs: Vec<(usize, usize)>,
}

/// One periodic pass along `axis` of the grid in `cells` (axis lengths `dims`, strides
/// `strides`, first axis fastest): out[j] = Σₜ wₜ·in[(j + dₜ) mod n] on every line, the
/// taps (dₜ mod n, wₜ) summed in their order, where `masks` allow activity (module
/// documentation); the axis' mask becomes the output rows.
pub fn pass(
    cells: &mut [f64],
    dims: &[usize],
    strides: &[usize],
    axis: usize,
    taps: &[(usize, f64)],
    masks: &mut Masks,
    ws: &mut Workspace,
) {
    let (n, s) = (dims[axis], strides[axis]);
    ws.rows.clear();
    ws.rows
        .extend((0..n).map(|j| taps.iter().any(|&(d, _)| masks[axis][(j + d) % n])));
    supported_runs(dims, strides, axis, masks, ws);
    supported_bases(dims, strides, axis, masks, ws);
    let input = &masks[axis];
    let len = n * s;
    ws.out.resize(len, 0.0);
    if s == 1 {
        lines_pass(cells, n, taps, ws);
        masks[axis].clone_from(&ws.rows);
        return;
    }
    let fixed = match (n, s, ws.runs.as_slice()) {
        (5, 5, [(0, 5)]) => Some(fixed_block::<5, 5> as FixedBlock),
        (5, 25, [(0, 25)]) => Some(fixed_block::<5, 25> as FixedBlock),
        _ => None,
    };
    for &base in &ws.bases {
        let block = &mut cells[base..base + len];
        if let Some(fixed) = fixed {
            fixed(block, taps);
        } else {
            block_pass(block, s, taps, input, &ws.rows, &ws.runs, &mut ws.out);
        }
    }
    masks[axis].clone_from(&ws.rows);
}

/// A pass over one whole block, its sizes known when compiled.
type FixedBlock = fn(&mut [f64], &[(usize, f64)]);

/// A pass over one whole block of `N` rows of `S` cells, every row and column: the dense
/// computation, with the row length known when compiled so that the short rows of the
/// thesis' 5-cell axes (S = 1, 5, 25) are unrolled. Used where the support covers whole
/// rows; rows outside it compute to +0, as in the reference.
fn fixed_block<const N: usize, const S: usize>(block: &mut [f64], taps: &[(usize, f64)]) {
    let mut x = [[0.0f64; S]; N];
    for (row, cells) in x.iter_mut().zip(block.chunks_exact(S)) {
        row.copy_from_slice(cells);
    }
    for (j, out) in block.chunks_exact_mut(S).enumerate() {
        let mut o = [-0.0f64; S];
        for &(d, w) in taps {
            let r = &x[(j + d) % N];
            for (o, r) in o.iter_mut().zip(r) {
                *o += w * r;
            }
        }
        out.copy_from_slice(&o);
    }
}

/// A pass along an axis of stride 1 (its lines contiguous, one per supported base): the
/// lines' cells gathered column by column (column c holds cell c of every line), each
/// output column summed tap by tap over all lines at once, and scattered back.
fn lines_pass(cells: &mut [f64], n: usize, taps: &[(usize, f64)], ws: &mut Workspace) {
    let lines = ws.bases.len();
    ws.columns.resize(n * lines, 0.0);
    ws.out.resize(n * lines, 0.0);
    for (b, &base) in ws.bases.iter().enumerate() {
        for (c, &x) in cells[base..base + n].iter().enumerate() {
            ws.columns[c * lines + b] = x;
        }
    }
    for j in (0..n).filter(|&j| ws.rows[j]) {
        let out = &mut ws.out[j * lines..][..lines];
        out.fill(-0.0);
        for &(d, w) in taps {
            let column = &ws.columns[(j + d) % n * lines..][..lines];
            for (o, x) in out.iter_mut().zip(column) {
                *o += w * x;
            }
        }
    }
    for (b, &base) in ws.bases.iter().enumerate() {
        for (j, c) in cells[base..base + n].iter_mut().enumerate() {
            *c = if ws.rows[j] {
                ws.out[j * lines + b]
            } else {
                0.0
            };
        }
    }
}

/// A pass over one block of `n` rows of `s` cells (the line's cells are `s` apart):
/// row by row, tap by tap, over the supported runs of columns.
fn block_pass(
    block: &mut [f64],
    s: usize,
    taps: &[(usize, f64)],
    input: &[bool],
    rows: &[bool],
    runs: &[(usize, usize)],
    out: &mut [f64],
) {
    let n = rows.len();
    for j in (0..n).filter(|&j| rows[j]) {
        for &(start, len) in runs {
            out[j * s + start..][..len].fill(-0.0);
        }
        for &(d, w) in taps {
            let r = (j + d) % n;
            if !input[r] {
                continue;
            }
            for &(start, len) in runs {
                let o = &mut out[j * s + start..][..len];
                let x = &block[r * s + start..][..len];
                for (o, x) in o.iter_mut().zip(x) {
                    *o += w * x;
                }
            }
        }
    }
    for j in 0..n {
        if rows[j] || input[j] {
            for &(start, len) in runs {
                let c = &mut block[j * s + start..][..len];
                if rows[j] {
                    c.copy_from_slice(&out[j * s + start..][..len]);
                } else {
                    c.fill(0.0);
                }
            }
        }
    }
}

/// The runs of columns of a row of `axis` (the cells of the faster axes) that the masks
/// support, adjacent runs merged: one run of the whole row when those axes are full.
fn supported_runs(
    dims: &[usize],
    strides: &[usize],
    axis: usize,
    masks: &Masks,
    ws: &mut Workspace,
) {
    ws.runs.clear();
    ws.runs.push((0, 1));
    for b in 0..axis {
        ws.swap_runs.clear();
        for c in (0..dims[b]).filter(|&c| masks[b][c]) {
            for &(start, len) in &ws.runs {
                let run = (start + c * strides[b], len);
                match ws.swap_runs.last_mut() {
                    Some(last) if last.0 + last.1 == run.0 => last.1 += len,
                    _ => ws.swap_runs.push(run),
                }
            }
        }
        std::mem::swap(&mut ws.runs, &mut ws.swap_runs);
    }
}

/// The first cells of the blocks (one per combination of the slower axes' coordinates)
/// that the masks support.
fn supported_bases(
    dims: &[usize],
    strides: &[usize],
    axis: usize,
    masks: &Masks,
    ws: &mut Workspace,
) {
    ws.bases.clear();
    ws.bases.push(0);
    for b in axis + 1..dims.len() {
        ws.swap_usize.clear();
        for c in (0..dims[b]).filter(|&c| masks[b][c]) {
            ws.swap_usize
                .extend(ws.bases.iter().map(|&base| base + c * strides[b]));
        }
        std::mem::swap(&mut ws.bases, &mut ws.swap_usize);
    }
}

/// The taps of a kernel of odd width on an axis of `n` cells: output j takes
/// kernel[k]·in[j − k + h], in the order of k (Alg 3).
pub fn kernel_taps(kernel: &[f64], n: usize, taps: &mut Vec<(usize, f64)>) {
    let h = kernel.len() / 2;
    taps.clear();
    taps.extend(
        kernel
            .iter()
            .enumerate()
            .map(|(k, &w)| ((h + n * kernel.len() - k) % n, w)),
    );
}

/// The taps of a split shift (floor, its weight, ceil, its weight) on an axis of `n`
/// cells: output j takes w_lo of cell j − lo and w_hi of cell j − lo − 1.
pub fn shift_taps((lo, w_lo, _, w_hi): (i64, f64, i64, f64), n: usize) -> [(usize, f64); 2] {
    let n = n as i64;
    [
        ((-lo).rem_euclid(n) as usize, w_lo),
        ((-lo - 1).rem_euclid(n) as usize, w_hi),
    ]
}
