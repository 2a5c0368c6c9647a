//! The active-set evaluation of the pose grid (the default) against the dense reference:
//! the same bits on random activity with holes, on packets across the grid's edges and on
//! several packets at once, through every operation and through both networks' updates;
//! and against an independent naive N-D convolution.

use nalgebra::Vector3;
use rand::RngExt;
use whisker_slam::pose_grid::{Evaluation, PoseGrid, ShiftWeights, gaussian_kernel};
use whisker_slam::ratslam::posecells3d::{PlanarCellParams, PoseCells3};
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::posecells6d::{PoseCellParams, PoseCells6, dense_convolve};

/// The grid's activities as bit patterns (equal only if every bit is).
fn bits(grid: &PoseGrid) -> Vec<u64> {
    grid.cells.iter().map(|c| c.to_bits()).collect()
}

/// The same grid evaluated densely.
fn dense(grid: &PoseGrid) -> PoseGrid {
    let mut d = grid.clone();
    d.set_evaluation(Evaluation::Dense);
    d
}

/// Checks that `op` gives the same bits on the active grid and its dense twin.
fn same(active: &mut PoseGrid, reference: &mut PoseGrid, what: &str, op: impl Fn(&mut PoseGrid)) {
    op(active);
    op(reference);
    assert_eq!(active.evaluation(), Evaluation::Active);
    assert_eq!(reference.evaluation(), Evaluation::Dense);
    let (a, r) = (bits(active), bits(reference));
    let differ = a.iter().zip(&r).filter(|(x, y)| x != y).count();
    assert_eq!(
        differ, 0,
        "{what}: {differ} cells differ from the dense reference"
    );
}

/// A grid of `dims` holding, in a random box per axis (possibly across the edge) of
/// random size, random activity with about `holes` of its cells zero.
fn random_grid(dims: &[usize], holes: f64, name: &str) -> PoseGrid {
    let mut rng = substream(11, name);
    let mut grid = PoseGrid::new(dims);
    let boxes: Vec<(usize, usize)> = dims
        .iter()
        .map(|&n| (rng.random_range(0..n), rng.random_range(1..=n)))
        .collect();
    for i in 0..grid.cells.len() {
        let c = grid.coords(i);
        let inside = c
            .iter()
            .zip(&boxes)
            .zip(dims)
            .all(|((&x, &(start, len)), &n)| (x + n - start) % n < len);
        if inside && rng.random::<f64>() >= holes {
            grid.cells[i] = rng.random::<f64>();
        }
    }
    grid.normalise();
    grid
}

#[test]
fn every_operation_gives_the_dense_bits_on_random_activity_with_holes() {
    let shapes: [&[usize]; 5] = [&[21, 21, 36], &[5; 6], &[7, 3, 9], &[12], &[4, 9, 5, 3]];
    for (s, dims) in shapes.iter().enumerate() {
        for (t, holes) in [0.0, 0.5, 0.95].into_iter().enumerate() {
            let name = format!("test/pose_grid_active/{s}/{t}");
            let mut a = random_grid(dims, holes, &name);
            let mut r = dense(&a);
            let w = dims.iter().min().copied().unwrap_or(3).min(5) | 1;
            let (exc, inh) = (gaussian_kernel(w, 1.0), gaussian_kernel(w.min(3), 2.0));
            same(&mut a, &mut r, "convolve", |g| g.convolve(&exc));
            same(&mut a, &mut r, "excite_inhibit", |g| {
                g.excite_inhibit(&exc, &inh, 2e-5)
            });
            for axis in 0..dims.len() {
                for amount in [0.3, -1.7, 2.0, 0.0] {
                    same(&mut a, &mut r, "shift_axis", |g| {
                        g.shift_axis_with(axis, amount, ShiftWeights::Phase)
                    });
                }
            }
            let offset: Vec<i64> = dims.iter().map(|&n| n as i64 / 2 + 1).collect();
            same(&mut a, &mut r, "add_shifted_copy", |g| {
                g.add_shifted_copy(&offset, 0.3)
            });
            if dims.len() >= 2 {
                let len = dims[0] * dims[1];
                let start = len * (dims.len() > 2) as usize;
                same(&mut a, &mut r, "shift_block", |g| {
                    g.shift_block(start, len, &[0.6, -2.2], ShiftWeights::Linear)
                });
            }
            assert_eq!(a.best(3), r.best(3), "{dims:?}: best pose");
        }
    }
}

#[test]
fn planar_packets_across_the_edges_and_several_at_once_give_the_dense_bits() {
    // A packet at the corner of the torus (every axis wraps), driven round while view
    // injections put up to three more packets elsewhere, some across other edges.
    let params = PlanarCellParams {
        dim_xy: 21,
        ..PlanarCellParams::default()
    };
    let mut a = PoseCells3::new(params, &[20.4, 0.3, 35.6]);
    let mut r = a.clone();
    r.grid.set_evaluation(Evaluation::Dense);
    let injections = [
        (30, [10.0, 0.0, 18.0]),
        (60, [0.0, 20.0, 3.0]),
        (90, [7.0, 14.0, 35.0]),
    ];
    let mut most = 0;
    for step in 0..150 {
        for (at, cell) in injections {
            if step >= at && step < at + 20 {
                a.inject(&cell, 0.1);
                r.inject(&cell, 0.1);
            }
        }
        let (d, th) = (params.cell_size_m * 0.7, (7.0 + step as f64).to_radians());
        a.update(d, th);
        r.update(d, th);
        assert_eq!(bits(&a.grid), bits(&r.grid), "update {step}");
        assert_eq!(a.best(), r.best(), "update {step}");
        most = most.max(a.grid.cells.iter().filter(|&&c| c > 0.0).count());
    }
    // The injections did make several packets: more cells active than one packet holds.
    assert!(most > 300, "at most {most} active cells");
}

#[test]
fn whisker_ratslam_updates_with_packet_injections_give_the_dense_bits() {
    for params in [PoseCellParams::default(), PoseCellParams::corrected()] {
        let mut a = PoseCells6::new(params, &[4.0, 0.0, 2.0, 4.0, 1.0, 0.0]);
        let mut r = a.clone();
        r.grid.set_evaluation(Evaluation::Dense);
        let (v, w) = (
            Vector3::new(0.04, -0.02, 0.01),
            Vector3::new(0.05, -0.1, 0.3),
        );
        for step in 0..25 {
            if step % 5 == 4 {
                let far = [1.0, 3.0, 0.0, 2.0, 4.0, 3.0];
                a.inject_packet(&far, 0.3);
                r.inject_packet(&far, 0.3);
                a.inject(&far, 0.05);
                r.inject(&far, 0.05);
            }
            a.update(&v, &w);
            r.update(&v, &w);
            assert_eq!(bits(&a.grid), bits(&r.grid), "update {step}");
            assert_eq!(a.best(), r.best(), "update {step}");
        }
    }
}

#[test]
fn active_convolution_of_packets_across_the_edges_equals_the_naive_kernel() {
    // An independent computation: every cell against every offset of the full 3-D kernel.
    let mut grid = PoseGrid::new(&[21, 21, 36]);
    for (at, mass) in [([0, 20, 35], 0.5), ([10, 10, 0], 0.3), ([20, 5, 17], 0.2)] {
        let i = grid.index(&at);
        grid.cells[i] = mass;
    }
    let kernel = gaussian_kernel(7, 1.0);
    let naive = dense_convolve(&grid, &kernel);
    grid.convolve(&kernel);
    for (i, (a, b)) in grid.cells.iter().zip(&naive).enumerate() {
        assert!(
            (a - b).abs() < 1e-15,
            "cell {:?}: {a} vs {b}",
            grid.coords(i)
        );
    }
    // Each packet reaches 7 cells per axis and no further.
    assert_eq!(grid.cells.iter().filter(|&&c| c > 0.0).count(), 3 * 343);
}
