//! WhiskerRatSLAM's 6-D pose cells against the thesis' worked examples (Fig 5.6, 5.10,
//! 5.11, 5.4) and the invariants of path integration.

use nalgebra::Vector3;
use rand::RngExt;
use whisker_slam::pose_grid::{PoseGrid, ShiftWeights};
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::posecells6d::{
    Cell6, PoseCellParams, PoseCells6, dense_convolve,
};

/// The thesis' worked examples use its printed linear shift weights (Fig 5.10–5.11).
fn params() -> PoseCellParams {
    PoseCellParams {
        shift: ShiftWeights::Linear,
        ..PoseCellParams::default()
    }
}

/// A confident packet: the default network settled at `at` for 200 updates.
fn settled(p: PoseCellParams, at: &Cell6) -> PoseCells6 {
    let mut cells = PoseCells6::new(p, at);
    for _ in 0..200 {
        cells.excite_inhibit();
    }
    cells
}

/// The decoded yaw travelled by a settled packet driven by `laps` laps of yaw rotation at
/// `step` cells per update (each update's decoded advance unwrapped), in cells.
fn yaw_travelled(p: PoseCellParams, step: f64, laps: usize) -> f64 {
    let mut cells = settled(p, &[2.0, 2.0, 2.0, 0.0, 0.0, 0.0]);
    let updates = (5.0 * laps as f64 / step).round() as usize;
    let mut prev = cells.best()[5];
    let mut travelled = 0.0;
    for _ in 0..updates {
        cells.update(
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, step * p.cell_angle(5)),
        );
        let now = cells.best()[5];
        travelled += (now - prev + 2.5).rem_euclid(5.0) - 2.5;
        prev = now;
    }
    travelled
}

fn activity(p: &PoseCells6, c: [i64; 6]) -> f64 {
    p.grid.cells[p.grid.index(&c)]
}

#[test]
fn fig_5_6_velocity_spreads_activity_to_n_nw_and_w_by_the_sector_areas_of_fig_5_10() {
    // v = [−0.5, 1] in the (x, y) view with magnitude 0.3 cell; orientation voxel 0
    // (identity), so the body velocity is the grid velocity.
    let s = 0.3 / 1.25f64.sqrt();
    let (vx, vy) = (-0.5 * s, 1.0 * s);
    let size = params().cell_size_m;
    for x in [2i64, 0] {
        let mut p = PoseCells6::new(params(), &[x as f64, 2.0, 2.0, 0.0, 0.0, 0.0]);
        p.path_integrate(&(Vector3::new(vx, vy, 0.0) * size), &Vector3::zeros());
        // Quadrant 2: remain (BR), N (TR), NW (TL), W (BL); at x = 0, W and NW wrap to x = 4.
        let (ax, ay) = (vx.abs(), vy.abs());
        let w = x - 1;
        for (cell, area) in [
            ([x, 2, 2, 0, 0, 0], (1.0 - ax) * (1.0 - ay)),
            ([x, 3, 2, 0, 0, 0], (1.0 - ax) * ay),
            ([w, 3, 2, 0, 0, 0], ax * ay),
            ([w, 2, 2, 0, 0, 0], ax * (1.0 - ay)),
        ] {
            assert!((activity(&p, cell) - area).abs() < 1e-15, "{cell:?}");
        }
        assert!(activity(&p, [w, 3, 2, 0, 0, 0]) < activity(&p, [w, 2, 2, 0, 0, 0]));
        assert!(activity(&p, [x, 3, 2, 0, 0, 0]) > activity(&p, [w, 2, 2, 0, 0, 0]));
        assert!((p.grid.sum() - 1.0).abs() < 1e-15);
    }
}

#[test]
fn translation_is_rotated_by_each_orientation_voxel() {
    // One cell forward (+x body) in yaw voxel 1 (72°) moves by (cos 72°, sin 72°) cells.
    let mut p = PoseCells6::new(params(), &[2.0, 2.0, 2.0, 0.0, 0.0, 1.0]);
    p.path_integrate(
        &Vector3::new(params().cell_size_m, 0.0, 0.0),
        &Vector3::zeros(),
    );
    let (c, s) = (72f64.to_radians().cos(), 72f64.to_radians().sin());
    for (cell, w) in [
        ([2, 2, 2, 0, 0, 1], (1.0 - c) * (1.0 - s)),
        ([3, 2, 2, 0, 0, 1], c * (1.0 - s)),
        ([2, 3, 2, 0, 0, 1], (1.0 - c) * s),
        ([3, 3, 2, 0, 0, 1], c * s),
    ] {
        assert!((activity(&p, cell) - w).abs() < 1e-12, "{cell:?}");
    }
    // Pitch voxel 1 (72°, nose down by convention R = Ry(72°)): forward goes to −z too.
    let mut p = PoseCells6::new(params(), &[2.0, 2.0, 2.0, 0.0, 1.0, 0.0]);
    p.path_integrate(
        &Vector3::new(params().cell_size_m, 0.0, 0.0),
        &Vector3::zeros(),
    );
    assert!((activity(&p, [3, 2, 1, 0, 1, 0]) - c * s).abs() < 1e-12);
}

#[test]
fn a_yaw_rate_of_158_degrees_per_second_shifts_2_and_3_cells_weighted_0_8_and_0_2() {
    let mut p = PoseCells6::new(params(), &[1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
    p.path_integrate(
        &Vector3::zeros(),
        &Vector3::new(0.0, 0.0, 158f64.to_radians()),
    );
    let frac = 158.0 / 72.0 - 2.0;
    assert!((activity(&p, [1, 1, 1, 0, 0, 2]) - (1.0 - frac)).abs() < 1e-12);
    assert!((activity(&p, [1, 1, 1, 0, 0, 3]) - frac).abs() < 1e-12);
    assert!(((1.0 - frac) - 0.8).abs() < 0.01);
}

#[test]
fn path_integration_conserves_mass_for_any_velocity_up_to_one_cell_per_axis() {
    let mut rng = substream(1, "test/posecells6d/mass");
    let mut p = PoseCells6::new(params(), &[0.0; 6]);
    for c in p.grid.cells.iter_mut() {
        *c = rng.random::<f64>();
    }
    let size = params().cell_size_m;
    for _ in 0..50 {
        // |v| ≤ 1 cell keeps every rotated component within one cell.
        let v: Vector3<f64> = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let v = v / v.norm().max(1.0) * size;
        let w = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ) * params().cell_angle(3);
        let before = p.grid.sum();
        p.path_integrate(&v, &w);
        assert!((p.grid.sum() - before).abs() < 1e-12 * before);
    }
}

/// Drives `laps` pentagons (4 updates forward at 0.25 cell each, then a 72° turn in yaw,
/// five times a lap); returns the best pose at each corner.
fn pentagon_laps(p: &mut PoseCells6, laps: usize) -> Vec<Cell6> {
    let size = p.params.cell_size_m;
    let mut corners = Vec::new();
    for _ in 0..5 * laps {
        for _ in 0..4 {
            p.update(&Vector3::new(0.25 * size, 0.0, 0.0), &Vector3::zeros());
        }
        p.update(
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, 72f64.to_radians()),
        );
        corners.push(p.best());
    }
    corners
}

#[test]
fn a_packet_driven_around_a_closed_loop_returns_to_its_start_cell() {
    // A pentagon: 4 updates forward at 0.25 cell each, then a 72° turn in yaw, five times.
    let start: Cell6 = [2.0, 2.0, 2.0, 0.0, 0.0, 0.0];
    let mut p = PoseCells6::new(params(), &start);
    for _ in 0..20 {
        p.excite_inhibit();
    }
    let visited = pentagon_laps(&mut p, 1);
    for _ in 0..5 {
        p.excite_inhibit();
    }
    let end = p.best();
    let rounded: Vec<i64> = end.iter().map(|c| c.round() as i64 % 5).collect();
    assert_eq!(rounded, vec![2, 2, 2, 0, 0, 0], "ended at {end:?}");
    // It did move: the packet left the start cell on the way.
    assert!(visited.iter().any(|b| p.distance(b, &start) > 0.9));
}

#[test]
fn the_stable_packet_of_fig_5_4_stays_put_over_1000_updates() {
    let centre: Cell6 = [2.0; 6];
    let mut p = PoseCells6::new(params(), &centre);
    for _ in 0..1000 {
        p.update(&Vector3::zeros(), &Vector3::zeros());
    }
    assert!(p.distance(&p.best(), &centre) < 1e-9);
    assert!((p.grid.sum() - 1.0).abs() < 1e-12);
    // A packet, not a flat sheet: zero far from the centre, and along every axis the
    // activity falls away from the centre on both sides, symmetrically.
    assert_eq!(activity(&p, [0, 0, 0, 0, 0, 0]), 0.0);
    for axis in 0..6 {
        let along = |k: i64| {
            let mut c = [2i64; 6];
            c[axis] = k;
            activity(&p, c)
        };
        assert!(along(2) > along(1) && along(1) > along(0), "axis {axis}");
        assert!((along(1) - along(3)).abs() < 1e-12 && (along(0) - along(4)).abs() < 1e-12);
    }
}

#[test]
fn separable_excitation_equals_the_dense_6d_kernel() {
    let mut rng = substream(2, "test/posecells6d/dense");
    let mut grid = PoseGrid::new(&[5, 4, 5, 3]);
    for c in grid.cells.iter_mut() {
        *c = rng.random::<f64>();
    }
    let kernel = whisker_slam::pose_grid::gaussian_kernel(3, 1.0);
    let dense = dense_convolve(&grid, &kernel);
    grid.convolve(&kernel);
    for (a, b) in grid.cells.iter().zip(&dense) {
        assert!((a - b).abs() < 1e-12);
    }
}

#[test]
fn phase_weights_integrate_a_yaw_lap_in_full_where_the_linear_weights_fall_short() {
    // A settled packet turned round one full lap of yaw (5 cells) in steps of 0.05, 0.1
    // and 0.2 cell. The linear weights advance the axis' population vector by
    // atan(f·sin 72° / (1 − f + f·cos 72°)) per step — 78 %, 81 % and 86 % of the
    // command — and the 3-cell decode round the peak reads a little less.
    let phase = PoseCellParams::corrected();
    assert_eq!(phase.shift, ShiftWeights::Phase);
    for step in [0.05, 0.1, 0.2] {
        let t = yaw_travelled(phase, step, 1);
        assert!((t - 5.0).abs() < 0.5, "phase, step {step}: {t} of 5 cells");
        let phi = 72f64.to_radians();
        let linear_gain = (step * phi.sin()).atan2(1.0 - step + step * phi.cos()) / (step * phi);
        let l = yaw_travelled(params(), step, 1);
        assert!(
            l / 5.0 < linear_gain + 0.02 && l < 4.5,
            "linear, step {step}: {l} of 5 cells, population-vector gain {linear_gain}"
        );
    }
}

#[test]
fn phase_weights_conserve_mass() {
    let mut rng = substream(4, "test/posecells6d/phase-mass");
    let mut p = PoseCells6::new(PoseCellParams::corrected(), &[0.0; 6]);
    for c in p.grid.cells.iter_mut() {
        *c = rng.random::<f64>();
    }
    let before = p.grid.sum();
    for _ in 0..20 {
        let v = Vector3::new(
            rng.random_range(-0.1..0.1),
            rng.random_range(-0.1..0.1),
            0.0,
        );
        let w = Vector3::new(
            0.0,
            rng.random_range(-1.0..1.0),
            rng.random_range(-2.0..2.0),
        );
        p.path_integrate(&v, &w);
    }
    assert!((p.grid.sum() - before).abs() < 1e-12 * before);
}

#[test]
fn translation_is_integrated_alike_on_every_lap_of_a_closed_orbit() {
    // The translation gain of the 5-cell grid is below 1 (module documentation: each
    // orientation voxel moves its block its own way and the packet spans ±72°), so it is
    // not tested against the command; what a revisit needs is that the same motion lands
    // on the same cells: a pentagon orbit (forward 0.25 cell four times, then 72° of
    // yaw), driven three laps; laps 2 and 3 pass each corner within 0.25 cell of lap 1.
    let mut cells = settled(PoseCellParams::corrected(), &[2.0, 2.0, 2.0, 0.0, 0.0, 0.0]);
    let corners = pentagon_laps(&mut cells, 3);
    for k in 5..15 {
        let d = cells.distance(&corners[k], &corners[k % 5]);
        assert!(
            d < 0.25,
            "corner {} of lap {}: {d} cells off",
            k % 5,
            k / 5 + 1
        );
    }
    // And the translation did move the packet (gain above zero): the corners differ in x-y.
    let spread = (1..5)
        .map(|k| cells.distance(&corners[k], &corners[0]))
        .fold(0.0, f64::max);
    assert!(spread > 0.5, "{spread}");
}

#[test]
fn one_injection_far_from_a_confident_packet_moves_it_little_and_consecutive_ones_move_it() {
    // Ω = ζ = 0.3 relative to the peak (`Params::corrected`), 144° away on roll, pitch
    // and yaw.
    let centre: Cell6 = [2.0, 2.0, 2.0, 2.0, 2.0, 2.0];
    let far: Cell6 = [2.0, 2.0, 2.0, 0.0, 0.0, 4.0];
    let confident = settled(PoseCellParams::corrected(), &centre);
    let after = |n: usize| {
        let mut p = confident.clone();
        for _ in 0..n {
            p.inject_packet(&far, 0.3);
            p.excite_inhibit();
        }
        p.best()
    };
    let one = after(1);
    assert!(confident.distance(&one, &centre) < 0.5, "{one:?}");
    let eight = after(8);
    assert!(
        confident.distance(&eight, &centre) > 1.0
            && confident.distance(&eight, &far) < confident.distance(&centre, &far) - 1.0,
        "{eight:?}"
    );
    // As printed (Ω added to one cell of a packet whose peak is ~0.0024), one match
    // alone moves it by more than a cell.
    let mut p = confident.clone();
    p.inject(&far, 0.3);
    p.excite_inhibit();
    assert!(confident.distance(&p.best(), &centre) > 1.0);
}
