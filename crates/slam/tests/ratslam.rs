//! Planar RatSLAM (thesis Ch 3): the pose-cell network's invariants, the head-direction
//! ring of Fig 5.3, relaxation of a loop with a known odometric error (closed form), and
//! Algorithm 1 and Eq 3.2 on hand-built logs.

use std::f64::consts::{FRAC_PI_2, PI};
use whisker_slam::pose::Pose2;
use whisker_slam::pose_grid::{PoseGrid, gaussian_kernel, population_index};
use whisker_slam::ratslam::experience_map::{Experience, ExperienceMap, ExperienceMapParams, Link};
use whisker_slam::ratslam::metrics::{consecutive, energy_metric, experience_metric};
use whisker_slam::ratslam::posecells3d::{PlanarCellParams, PoseCells3};

fn params() -> PlanarCellParams {
    PlanarCellParams {
        dim_xy: 21,
        ..PlanarCellParams::default()
    }
}

/// Circular centre of mass of one axis (fractional cells).
fn centre(cells: &PoseCells3, axis: usize) -> f64 {
    let dims = cells.grid.dims().to_vec();
    let mut marginal = vec![0.0; dims[axis]];
    for (i, a) in cells.grid.cells.iter().enumerate() {
        marginal[cells.grid.coords(i)[axis]] += a;
    }
    population_index(&marginal)
}

fn circular_gap(a: f64, b: f64, n: f64) -> f64 {
    let d = (a - b).rem_euclid(n);
    d.min(n - d)
}

#[test]
fn a_packet_with_no_input_keeps_its_centre_and_unit_mass() {
    let mut cells = PoseCells3::new(params(), &[10.0, 4.0, 35.0]);
    for _ in 0..1000 {
        cells.update(0.0, 0.0);
    }
    assert!((cells.grid.sum() - 1.0).abs() < 1e-12);
    let best = cells.best();
    for (b, (want, n)) in best.iter().zip([(10.0, 21.0), (4.0, 21.0), (35.0, 36.0)]) {
        assert!(circular_gap(*b, want, n) < 1e-9, "{best:?}");
    }
}

/// The linear mean of one axis' marginal for a packet narrower than the ring, unwrapped
/// around the cell opposite its circular mean (so that no mass straddles the cut).
fn unwrapped_mean(cells: &PoseCells3, axis: usize) -> f64 {
    let n = cells.grid.dims()[axis] as f64;
    let cut = centre(cells, axis) + n / 2.0;
    let (mut m, mut w) = (0.0, 0.0);
    for (i, a) in cells.grid.cells.iter().enumerate() {
        let c = cells.grid.coords(i)[axis] as f64;
        let x = c - ((c - cut) / n).ceil() * n + n;
        m += a * x;
        w += a;
    }
    (m / w).rem_euclid(n)
}

#[test]
fn path_integration_moves_the_mass_v_t_cells_across_the_wrap_and_conserves_it() {
    // Path integration (the update's step 5, before the next normalisation) of a one-cell
    // packet: 100 updates of 0.37 cell along the heading of its layer move its mean by
    // v·t = 37 cells along (cos θ, sin θ) — across the wrap of the 61-cell ring — within
    // 1e-6 cell (the issue asks 0.05 per 100 updates), the mass conserved to 1e-12. (The
    // grid is wide enough that the bilinear shifts' spreading, σ ≈ 5 cells after 100
    // sub-cell shifts, barely wraps onto itself: its tails move the unwrapped mean by
    // ~2e-8 cell.)
    let p = PlanarCellParams {
        dim_xy: 61,
        ..params()
    };
    for layer in [0usize, 1, 9, 22] {
        let mut cells = PoseCells3::new(p, &[50.0, 50.0, layer as f64]);
        let th = layer as f64 * p.cell_angle();
        for _ in 0..100 {
            cells.path_integrate(0.37 * p.cell_size_m, 0.0);
            assert!((cells.grid.sum() - 1.0).abs() < 1e-12);
        }
        for (axis, v) in [(0, th.cos()), (1, th.sin())] {
            let want = (50.0 + 37.0 * v).rem_euclid(61.0);
            let got = unwrapped_mean(&cells, axis);
            assert!(
                circular_gap(got, want, 61.0) < 1e-6,
                "layer {layer} axis {axis}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn full_updates_at_one_cell_per_update_move_the_packet_about_v_t_cells() {
    // With the attractor dynamics, a packet driven at one cell per update (the thesis'
    // choice of cell size, §3.2.1) along a θ layer's heading moves within 1 % of v·t
    // cells — across the wrap — and keeps unit mass. It lags by more than the 0.05 cell
    // per 100 updates the issue asks (99.25 cells in 100 updates at the defaults): the
    // packet spans several θ layers, and the neighbouring ones move at cos 10°, cos 20°…
    // of a cell — the expected advance of a heading belief that wide. Slower packets are
    // also pinned by the lattice (posecells3d's doc; `--example packet_speed`).
    let p = params();
    let mut cells = PoseCells3::new(p, &[15.0, 5.0, 0.0]);
    for _ in 0..20 {
        cells.update(0.0, 0.0);
    }
    let start = cells.best();
    for _ in 0..100 {
        cells.update(p.cell_size_m, 0.0);
    }
    let end = cells.best();
    assert!((cells.grid.sum() - 1.0).abs() < 1e-9);
    let moved = (end[0] - start[0]).rem_euclid(21.0);
    assert!(
        circular_gap(moved, 100.0 % 21.0, 21.0) < 1.0,
        "moved {moved}"
    );
    assert!(circular_gap(end[1], start[1], 21.0) < 0.05);
    // A turn of 90° in 9 updates of 10° (one θ cell each) turns the packet 9 cells.
    let before = cells.best()[2];
    for _ in 0..9 {
        cells.update(0.0, 10f64.to_radians());
    }
    let turned = (cells.best()[2] - before).rem_euclid(36.0);
    assert!((turned - 9.0).abs() < 0.05, "turned {turned}");
}

#[test]
fn a_head_direction_ring_reproduces_fig_5_3_with_the_wrap() {
    // One active cell at 0° on a 36-cell ring, excited by the 7-wide, variance-1 kernel:
    // activity (normalised by the maximum) exp(−k²/2) at k = −3…3 cells, the negative side
    // wrapping to 350°, 340°, 330°; at 120° (cell 12) the same shape, no wrap.
    for start in [0usize, 12] {
        let mut ring = PoseGrid::new(&[36]);
        ring.cells[start] = 1.0;
        ring.convolve(&gaussian_kernel(7, 1.0));
        let max = ring.cells.iter().copied().fold(0.0, f64::max);
        for (i, a) in ring.cells.iter().enumerate() {
            let k = ((i as i64 - start as i64 + 18).rem_euclid(36) - 18) as f64;
            let want = if k.abs() <= 3.0 {
                (-k * k / 2.0).exp()
            } else {
                0.0
            };
            assert!((a / max - want).abs() < 1e-12, "cell {i}");
        }
    }
}

/// A 4-node square loop, headings 0, whose closing link claims 0.4 m more travel in x
/// than the others undo.
fn square_with_error() -> ExperienceMap {
    let mut map = ExperienceMap::new(ExperienceMapParams::default());
    for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
        map.experiences.push(Experience {
            pose: Pose2 { x, y, th: 0.0 },
            template: 0,
            cell: [0.0; 3],
        });
    }
    // Displacements claimed: (1, 0), (0, 1), (−1, 0), (0.4, −1) — misclosure (0.4, 0).
    for (from, to, dx, dy) in [
        (0, 1, 1.0, 0.0),
        (1, 2, 0.0, 1.0),
        (2, 3, -1.0, 0.0),
        (3, 0, 0.4, -1.0),
    ] {
        map.links.push(Link {
            from,
            to,
            d: f64::hypot(dx, dy),
            heading: f64::atan2(dy, dx),
            facing: 0.0,
        });
    }
    map
}

#[test]
fn relaxation_spreads_a_loops_odometric_error_evenly() {
    // Least squares on a loop of equal links shares the misclosure equally: each link's
    // actual displacement differs from its claim by −(0.4, 0)/4 = (−0.1, 0).
    let mut map = square_with_error();
    let mean_before = map.experiences.iter().map(|e| e.pose.x).sum::<f64>();
    map.relax(200, 0.5);
    for l in &map.links {
        let (a, b) = (map.experiences[l.from].pose, map.experiences[l.to].pose);
        let claim = (l.d * l.heading.cos(), l.d * l.heading.sin());
        let residual = (b.x - a.x - claim.0, b.y - a.y - claim.1);
        assert!(
            (residual.0 + 0.1).abs() < 1e-9 && residual.1.abs() < 1e-9,
            "link {}→{}: {residual:?}",
            l.from,
            l.to
        );
        assert!(b.th.abs() < 1e-12);
    }
    // Symmetric moves keep the centroid.
    let mean_after = map.experiences.iter().map(|e| e.pose.x).sum::<f64>();
    assert!((mean_after - mean_before).abs() < 1e-9);
}

#[test]
fn relaxation_spreads_a_heading_error_evenly_too() {
    // Four links each claiming a 90° turn plus a 4° error at one: each ends 1° off.
    let mut map = ExperienceMap::new(ExperienceMapParams::default());
    for k in 0..4 {
        map.experiences.push(Experience {
            pose: Pose2 {
                x: 0.0,
                y: 0.0,
                th: k as f64 * FRAC_PI_2,
            },
            template: 0,
            cell: [0.0; 3],
        });
    }
    for k in 0..4 {
        let extra = if k == 3 { 4f64.to_radians() } else { 0.0 };
        map.links.push(Link {
            from: k,
            to: (k + 1) % 4,
            d: 0.0,
            heading: 0.0,
            facing: FRAC_PI_2 + extra,
        });
    }
    map.relax(200, 0.5);
    for l in &map.links {
        let turn = whisker_slam::pose::wrap(
            map.experiences[l.to].pose.th - map.experiences[l.from].pose.th,
        );
        let residual = whisker_slam::pose::wrap(turn - l.facing);
        assert!((residual + 1f64.to_radians()).abs() < 1e-9, "{residual}");
    }
}

fn line(n: usize) -> Vec<Pose2> {
    (0..n)
        .map(|k| Pose2 {
            x: 0.05 * k as f64,
            y: 0.0,
            th: 0.0,
        })
        .collect()
}

#[test]
fn algorithm_1_gives_the_hand_computed_rates() {
    // Base set: experiences 0, 1, 2 (indices 0–2). Then the log goes 3 (new), 0 (a
    // re-localisation onto the base set), 0 (staying on a re-localised experience counts
    // again), 4 (new), 1, 5 (new).
    let log = [0, 1, 2, 3, 0, 0, 4, 1, 5];
    // True poses: at index 4 the agent is back at the pose of index 0 (correct); at index 7
    // it is 0.5 m from where experience 1 was last seen (index 1): incorrect.
    let mut truth = line(9);
    truth[4] = truth[0];
    truth[5] = truth[0];
    truth[7] = Pose2 {
        x: truth[1].x + 0.5,
        y: 0.0,
        th: 0.0,
    };
    let m = experience_metric(&log, &truth, 2, 0.1, 25f64.to_radians());
    // Re-localisations at indices 4, 5, 7: η = 3 of 6 logged after the base set.
    assert_eq!(m.relocalisations, 3);
    assert!((m.arr - 0.5).abs() < 1e-15);
    // Correct: index 4 (within thresholds), index 5 (staying on it; the true pose also
    // matches index 4's); not index 7: η_c = 2, ARCR = 2/3.
    assert_eq!(m.correct, 2);
    assert!((m.arcr - 2.0 / 3.0).abs() < 1e-15);
    // A 30° heading difference at index 4 makes it (and the stay) incorrect.
    truth[4].th = 30f64.to_radians();
    truth[5].th = 30f64.to_radians();
    let m = experience_metric(&log, &truth, 2, 0.1, 25f64.to_radians());
    assert_eq!((m.relocalisations, m.correct), (3, 1));
    // Never re-localising: ARR 0, ARCR undefined.
    let m = experience_metric(&[0, 1, 2, 3, 4], &line(5), 1, 0.1, 0.5);
    assert_eq!(m.arr, 0.0);
    assert!(m.arcr.is_nan());
}

#[test]
fn composing_undoes_the_relative_pose() {
    // a ⊕ (b ⊖ a) = b, and a hand-computed composition: (1, 2, 90°) ⊕ (3, 0, 90°) is
    // 3 m along +y from (1, 2), facing 180°.
    let a = Pose2 {
        x: 1.0,
        y: 2.0,
        th: FRAC_PI_2,
    };
    let b = Pose2 {
        x: -0.4,
        y: 0.7,
        th: -2.9,
    };
    let back = a.compose(&a.relative(&b));
    assert!((back.x - b.x).abs() + (back.y - b.y).abs() + (back.th - b.th).abs() < 1e-12);
    let c = a.compose(&Pose2 {
        x: 3.0,
        y: 0.0,
        th: FRAC_PI_2,
    });
    assert!((c.x - 1.0).abs() < 1e-12 && (c.y - 5.0).abs() < 1e-12 && (c.th - PI).abs() < 1e-12);
}

#[test]
fn the_energy_metric_sums_squared_relative_errors() {
    let truth = line(4);
    // A perfect estimate, shifted and rotated as a whole: zero energy (relative relations).
    let moved: Vec<Pose2> = truth
        .iter()
        .map(|p| Pose2 {
            x: 1.0 - p.y,
            y: 2.0 + p.x,
            th: p.th + FRAC_PI_2,
        })
        .collect();
    let rel = consecutive(4);
    assert!(energy_metric(&moved, &truth, &rel).unwrap() < 1e-24);
    // One step 0.02 m too long and one turned 0.1 rad: (0.02² + 0.1² + the 0.1-rad turn's
    // displacement of the next relation, exact by hand below) / 3.
    let mut est = truth.clone();
    est[2].x += 0.02;
    est[3].x += 0.02;
    est[3].th = 0.1;
    // Relations: (0,1) exact; (1,2): δ = (0.07, 0, 0) vs (0.05, 0, 0) → 0.02² = 4e-4;
    // (2,3): δ = (0.05, 0, 0.1) vs (0.05, 0, 0) → error pose (0, 0, 0.1) → 0.01.
    let e = energy_metric(&est, &truth, &rel).unwrap();
    assert!((e - (4e-4 + 0.01) / 3.0).abs() < 1e-15, "{e}");
    assert!(energy_metric(&est, &truth, &[]).is_none());
    let _ = PI;
}

#[test]
fn a_second_lap_of_distinct_places_relocalises_onto_the_first() {
    use whisker_slam::ratslam::local_view::TactileImage;
    use whisker_slam::ratslam::{RatSlam, RatSlamParams};
    // A circular path of 40 places, each with its own tactile image, driven at one cell
    // per update with exact odometry, for three laps: the first builds the map; later
    // laps re-localise onto it, correctly.
    let params = RatSlamParams::default();
    let step = params.pose_cells.cell_size_m;
    let turn = std::f64::consts::TAU / 40.0;
    // Each place's image: whiskers touching (255) or not by the bits of a hash of k —
    // about 9 pixels differ between places, S ≈ 9·√255 ≫ the threshold.
    let image = |k: usize| {
        let bits = (k as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40;
        let mut img = TactileImage::default();
        for (j, p) in img.pixels.iter_mut().enumerate() {
            *p = if bits >> j & 1 == 1 { 255 } else { 0 };
        }
        img
    };
    let mut slam = RatSlam::new(params);
    let (mut log, mut truth) = (Vec::new(), Vec::new());
    let mut pose = Pose2::default();
    for k in 0..120 {
        let s = slam.step(&image(k % 40), step, if k == 0 { 0.0 } else { turn });
        if k > 0 {
            pose.th += turn;
            pose.x += step * pose.th.cos();
            pose.y += step * pose.th.sin();
        }
        log.push(s.experience);
        truth.push(pose);
    }
    let m = experience_metric(&log, &truth, 39, 0.1, 25f64.to_radians());
    println!("three laps of 40 distinct places: {m:?}");
    assert!(m.arr > 0.5, "{m:?}");
    assert!(m.arcr > 0.9, "{m:?}");
}

#[test]
fn bad_pose_cell_parameters_name_the_field() {
    assert!(PlanarCellParams::default().validate().is_ok());
    for (p, field) in [
        (
            PlanarCellParams {
                excite_width: 6,
                ..PlanarCellParams::default()
            },
            "excite_width",
        ),
        (
            PlanarCellParams {
                dim_th: 4,
                ..PlanarCellParams::default()
            },
            "excite_width",
        ),
        (
            PlanarCellParams {
                cell_size_m: 0.0,
                ..PlanarCellParams::default()
            },
            "cell_size_m",
        ),
        (
            PlanarCellParams {
                global_inhibition: f64::NAN,
                ..PlanarCellParams::default()
            },
            "global_inhibition",
        ),
    ] {
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
}

#[test]
fn a_gated_step_matches_its_template_but_never_injects() {
    use whisker_slam::ratslam::local_view::TactileImage;
    use whisker_slam::ratslam::{RatSlam, RatSlamParams};
    // A straight line of 20 places, each its own image, then place 0's image again 20
    // cells on: a false match. Ungated, its template injects at place 0's cell; gated,
    // the pose cells do exactly what the odometry alone does (excite, inhibit,
    // integrate), while the template is still matched.
    let params = RatSlamParams::default();
    let step = params.pose_cells.cell_size_m;
    let image = |k: usize| {
        let mut img = TactileImage::default();
        img.pixels[k % 18] = 255;
        img.pixels[(k / 18 + 7) % 18] = 200;
        img
    };
    let mut slam = RatSlam::new(params);
    for k in 0..20 {
        slam.step(&image(k), if k == 0 { 0.0 } else { step }, 0.0);
    }
    let mut odometry_only = slam.cells.clone();
    odometry_only.update(step, 0.0);
    let mut gated = slam.clone();
    let g = gated.step_gated(&image(0), step, 0.0, false);
    assert_eq!(g.template, 0, "the template is still matched");
    assert!(!g.new_template);
    assert_eq!(gated.cells.grid.cells, odometry_only.grid.cells);
    let mut ungated = slam.clone();
    ungated.step(&image(0), step, 0.0);
    let moved = ungated
        .cells
        .grid
        .cells
        .iter()
        .zip(&odometry_only.grid.cells)
        .any(|(a, b)| (a - b).abs() > 1e-9);
    assert!(moved, "an ungated false match injects");
}

#[test]
fn a_logged_path_is_placed_at_the_start_by_its_first_experience() {
    // Experience 0 faces +y at (1, 0); experience 1 lies 1 m ahead of it, facing −x.
    // Placed with experience 0 at (5, 5) facing +x, experience 1 is 1 m ahead along +x
    // and faces +y: (6, 5, π/2).
    let mut map = ExperienceMap::new(ExperienceMapParams::default());
    for (x, y, th) in [(1.0, 0.0, FRAC_PI_2), (1.0, 1.0, PI)] {
        map.experiences.push(Experience {
            pose: Pose2 { x, y, th },
            template: 0,
            cell: [0.0; 3],
        });
    }
    let start = Pose2 {
        x: 5.0,
        y: 5.0,
        th: 0.0,
    };
    let placed = map.placed(&[0, 1, 0], &start);
    assert_eq!(placed.len(), 3);
    for (p, want) in placed
        .iter()
        .zip([(5.0, 5.0, 0.0), (6.0, 5.0, FRAC_PI_2), (5.0, 5.0, 0.0)])
    {
        assert!(
            (p.x - want.0).abs() < 1e-12 && (p.y - want.1).abs() < 1e-12,
            "{p:?}"
        );
        assert!((p.th - want.2).abs() < 1e-12, "{p:?}");
    }
    assert!(map.placed(&[], &start).is_empty());
}
