//! Chapter 6's algorithms on the map: least similar region (Eq 6.1–6.3) against a hand
//! computation, and its Dijkstra against brute force.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use rand::RngExt;
use std::f64::consts::FRAC_PI_2;
use whisker_slam::exploration::lsr::{self, ExperienceGraph, LsrParams};
use whisker_slam::features::sda::Sda;
use whisker_slam::features::similarity::Features;
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::object_map::{Link, ObjectMap};

fn features(pfh: [f64; 4], slope: f64) -> Features {
    Features {
        pfh: pfh.to_vec(),
        sda: Sda(vec![Some(slope); 18]),
    }
}

fn at(x: f64, y: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, y, 0.0),
        UnitQuaternion::from_euler_angles(0.0, 0.0, yaw),
    )
}

/// Box experiences 0–3 (0 —— 1 —— 3, 1 —— 2 —— 3) and an unlinked Mug experience 4.
fn hand_built() -> ObjectMap {
    let mut m = ObjectMap::default();
    let b = Some("box".to_string());
    m.add(
        features([1.0, 0.0, 0.0, 0.0], 1.0),
        [0.0; 6],
        &at(0.0, 0.0, 0.0),
        b.clone(),
    );
    m.add(
        features([0.5, 0.5, 0.0, 0.0], 1.0),
        [0.0; 6],
        &at(0.1, 0.0, 0.0),
        b.clone(),
    );
    m.add(
        features([0.0, 0.0, 1.0, 0.0], 0.0),
        [0.0; 6],
        &at(0.1, 0.1, FRAC_PI_2),
        b.clone(),
    );
    m.add(
        features([0.0, 0.0, 1.0, 0.0], 0.0),
        [0.0; 6],
        &at(0.2, 0.0, 0.0),
        b,
    );
    m.add(
        features([0.0, 0.0, 0.0, 1.0], 3.0),
        [0.0; 6],
        &at(0.5, 0.5, 0.0),
        Some("mug".into()),
    );
    for (a, b) in [(0, 1), (1, 2), (1, 3), (2, 3)] {
        let rel = m.pose(a).inverse() * m.pose(b);
        m.links.push(Link::new(a, b, &rel));
    }
    m
}

#[test]
fn lsr_picks_the_least_similar_reachable_region_by_the_cheapest_path() {
    let map = hand_built();
    let seen = features([1.0, 0.0, 0.0, 0.0], 1.0);
    // Rows by hand: χ²(seen, e1) = 0.25/1.5 + 0.25/0.5; e2, e3, e4: 1 + 1 = 2.
    // NMSE: e2, e3 (slopes 0 against 1): 1; e4 (3 against 1): 4.
    let rows = lsr::rows(&map, &seen, 0, |_| true);
    let order: Vec<usize> = rows.iter().map(|r| r.experience).collect();
    assert_eq!(order, vec![4, 2, 3, 1]);
    assert!((rows[0].chi2 - 2.0).abs() < 1e-12 && (rows[0].nmse - 4.0).abs() < 1e-12);
    assert!((rows[3].chi2 - (0.25 / 1.5 + 0.5)).abs() < 1e-12);
    // The Mug's region is least similar but not linked: the next group {2, 3} (a tie).
    // Degrees: e1 3, e2 2, e3 2. Costs (Eq 6.3, m and rad):
    //   0→1→3: (0.1 + 1/3) + (0.1 + 1/2)
    //   0→1→2: (0.1 + 1/3) + (0.1 + π/2 + 1/2)
    let plan = lsr::plan(&map, &seen, 0, |_| true, &LsrParams::default()).unwrap();
    assert_eq!(plan.target, 3);
    assert_eq!(plan.path, vec![0, 1, 3]);
    assert!((plan.cost - (0.2 + 1.0 / 3.0 + 0.5)).abs() < 1e-12);
    let g = ExperienceGraph::new(&map, &LsrParams::default());
    let to2 = g.costs(0)[&2];
    assert!((to2 - (0.2 + 1.0 / 3.0 + FRAC_PI_2 + 0.5)).abs() < 1e-12);
    assert!(!g.costs(0).contains_key(&4));
    // Only the Box likely: the same target; nothing likely: no plan.
    let box_only = lsr::plan(&map, &seen, 0, |o| o == Some("box"), &LsrParams::default());
    assert_eq!(box_only.unwrap().target, 3);
    assert!(lsr::plan(&map, &seen, 0, |_| false, &LsrParams::default()).is_none());
    // From the Mug nothing else is reachable.
    assert!(lsr::plan(&map, &seen, 4, |_| true, &LsrParams::default()).is_none());
    // Scaling rotation down to 0 makes the two targets differ only by 1/n_l and distance.
    let p = LsrParams {
        rotation_per_rad: 0.0,
        ..LsrParams::default()
    };
    let g = ExperienceGraph::new(&map, &p);
    assert!((g.costs(0)[&2] - (0.2 + 1.0 / 3.0 + 0.5)).abs() < 1e-12);
}

/// The cheapest simple path from `s` to `t` by enumerating every simple path.
fn brute_force(n: usize, edges: &[(usize, usize, f64)], s: usize, t: usize) -> Option<f64> {
    fn walk(
        at: usize,
        t: usize,
        cost: f64,
        seen: &mut Vec<bool>,
        edges: &[(usize, usize, f64)],
        best: &mut Option<f64>,
    ) {
        if at == t {
            *best = Some(best.map_or(cost, |b: f64| b.min(cost)));
            return;
        }
        for &(a, b, w) in edges {
            if a == at && !seen[b] {
                seen[b] = true;
                walk(b, t, cost + w, seen, edges, best);
                seen[b] = false;
            }
        }
    }
    let mut seen = vec![false; n];
    seen[s] = true;
    let mut best = None;
    walk(s, t, 0.0, &mut seen, edges, &mut best);
    best
}

#[test]
fn dijkstra_equals_brute_force_on_200_random_graphs() {
    let mut rng = substream(0, "test/lsr-brute-force");
    for _ in 0..200 {
        let n = rng.random_range(2..8usize);
        let m = rng.random_range(0..(n * n));
        let edges: Vec<(usize, usize, f64)> = (0..m)
            .map(|_| {
                (
                    rng.random_range(0..n),
                    rng.random_range(0..n),
                    rng.random_range(0.0..3.0),
                )
            })
            .filter(|(a, b, _)| a != b)
            .collect();
        let g = ExperienceGraph::from_edges(n, &edges);
        let costs = g.costs(0);
        for t in 1..n {
            let expected = brute_force(n, &edges, 0, t);
            match (expected, costs.get(&t)) {
                (None, None) => assert!(g.path(0, t).is_none()),
                (Some(e), Some(&c)) => {
                    assert!((e - c).abs() < 1e-12, "cost {c} vs brute force {e}");
                    let (pc, path) = g.path(0, t).unwrap();
                    assert!((pc - e).abs() < 1e-12);
                    assert_eq!((path[0], *path.last().unwrap()), (0, t));
                    // The path's own edges add up to its cost.
                    let sum: f64 = path
                        .windows(2)
                        .map(|w| {
                            edges
                                .iter()
                                .filter(|(a, b, _)| *a == w[0] && *b == w[1])
                                .map(|e| e.2)
                                .fold(f64::INFINITY, f64::min)
                        })
                        .sum();
                    assert!((sum - e).abs() < 1e-12);
                }
                (e, c) => panic!("reachability differs: brute force {e:?}, Dijkstra {c:?}"),
            }
        }
    }
}
