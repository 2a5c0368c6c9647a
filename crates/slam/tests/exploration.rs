//! Chapter 6's algorithms on the map: least similar region (Eq 6.1–6.3) against hand
//! computations — on one map and on two appended maps —, and its Dijkstra against brute
//! force.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use rand::RngExt;
use std::f64::consts::FRAC_PI_2;
use whisker_slam::exploration::lsr::{self, CostScale, ExperienceGraph, LsrParams, Scope};
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

/// The weights of Eq 6.3 in metres and radians (SI).
fn si() -> LsrParams {
    LsrParams {
        scale: CostScale::Weights,
        ..LsrParams::default()
    }
}

fn names(n: &[&str]) -> Vec<String> {
    n.iter().map(|s| s.to_string()).collect()
}

#[test]
fn lsr_picks_the_least_similar_reachable_region_by_the_cheapest_path() {
    let map = hand_built();
    let seen = features([1.0, 0.0, 0.0, 0.0], 1.0);
    let both = names(&["box", "mug"]);
    let scope = Scope {
        objects: &both,
        own_links: 4,
        starts: &[0],
    };
    // Rows by hand: χ²(seen, e1) = 0.25/1.5 + 0.25/0.5; e2, e3, e4: 1 + 1 = 2.
    // NMSE: e2, e3 (slopes 0 against 1): 1; e4 (3 against 1): 4.
    let rows = lsr::rows(&map, &seen, 0, &scope);
    let order: Vec<usize> = rows.iter().map(|r| r.experience).collect();
    assert_eq!(order, vec![4, 2, 3, 1]);
    assert!((rows[0].chi2 - 2.0).abs() < 1e-12 && (rows[0].nmse - 4.0).abs() < 1e-12);
    assert!((rows[3].chi2 - (0.25 / 1.5 + 0.5)).abs() < 1e-12);
    // The Mug's region is least similar but the Mug has no start node: the next group
    // {2, 3} (a tie). Degrees: e1 3, e2 2, e3 2. Costs (Eq 6.3, m and rad):
    //   0→1→3: (0.1 + 1/3) + (0.1 + 1/2)
    //   0→1→2: (0.1 + 1/3) + (0.1 + π/2 + 1/2)
    let plan = lsr::plan(&map, &seen, 0, &scope, &si()).unwrap();
    assert_eq!(plan.target, 3);
    assert_eq!(plan.path, vec![0, 1, 3]);
    assert!((plan.cost - (0.2 + 1.0 / 3.0 + 0.5)).abs() < 1e-12);
    assert_eq!((plan.tied, plan.skipped), (2, 1));
    let g = ExperienceGraph::new(&map, &scope, &si());
    let to2 = g.costs(0)[&2];
    assert!((to2 - (0.2 + 1.0 / 3.0 + FRAC_PI_2 + 0.5)).abs() < 1e-12);
    assert!(!g.costs(0).contains_key(&4));
    // Only the Box likely: the same target; nothing likely: no plan.
    let boxes = names(&["box"]);
    let box_only = Scope {
        objects: &boxes,
        ..scope
    };
    assert_eq!(
        lsr::plan(&map, &seen, 0, &box_only, &si()).unwrap().target,
        3
    );
    let none = Scope {
        objects: &[],
        ..scope
    };
    assert!(lsr::plan(&map, &seen, 0, &none, &si()).is_none());
    // From the Mug, nothing else is reachable.
    let mug = Scope {
        starts: &[4],
        ..scope
    };
    assert!(lsr::plan(&map, &seen, 4, &mug, &si()).is_none());
    // Scaling rotation down to 0 makes the two targets differ only by 1/n_l and distance.
    let p = LsrParams {
        rotation_per_rad: 0.0,
        ..si()
    };
    let g = ExperienceGraph::new(&map, &scope, &p);
    assert!((g.costs(0)[&2] - (0.2 + 1.0 / 3.0 + 0.5)).abs() < 1e-12);
}

/// A run on two appended maps (§5.2.2.2), worked by hand: the Box (experiences 0–4) and
/// the Box-Stack (5–8), loaded with links 0–1, 1–2, 2–4, 0–3, 3–4 and 5–6, 6–7, 7–8; then
/// the run's own experience 9 and links 9–4, 0–4 and 1–6 (the last joins the two maps).
/// The array last re-localised into Box experience 0 (now) and Box-Stack experience 5.
fn two_objects() -> ObjectMap {
    let mut m = ObjectMap::default();
    let (b, s) = (Some("box".to_string()), Some("box_stack".to_string()));
    let region = |pfh, slope, x, y, yaw, object: &Option<String>| {
        (features(pfh, slope), at(x, y, yaw), object.clone())
    };
    let regions = [
        region([1.0, 0.0, 0.0, 0.0], 1.0, 0.0, 0.0, 0.0, &b),
        region([0.5, 0.5, 0.0, 0.0], 1.0, 0.02, 0.0, 0.0, &b),
        region([0.0, 1.0, 0.0, 0.0], 1.0, 0.04, 0.0, 0.0, &b),
        region([0.0, 0.0, 1.0, 0.0], 0.0, 0.03, 0.04, 0.2, &b),
        region([0.0, 0.0, 0.0, 1.0], 3.0, 0.06, 0.0, 0.0, &b),
        region([0.5, 0.5, 0.0, 0.0], 1.0, 0.5, 0.0, 0.0, &s),
        region([0.0, 1.0, 0.0, 0.0], 1.0, 0.52, 0.0, 0.0, &s),
        region([0.0, 0.0, 1.0, 0.0], 0.0, 0.54, 0.0, 0.0, &s),
        region([0.0, 0.0, 0.0, 1.0], 3.0, 0.56, 0.0, 0.0, &s),
        region([0.0, 0.0, 0.0, 1.0], 5.0, 0.06, 0.02, 0.0, &None),
    ];
    for (f, pose, object) in regions {
        m.add(f, [0.0; 6], &pose, object);
    }
    for (a, b) in [
        (0, 1),
        (1, 2),
        (2, 4),
        (0, 3),
        (3, 4),
        (5, 6),
        (6, 7),
        (7, 8),
        (9, 4),
        (0, 4),
        (1, 6),
    ] {
        let rel = m.pose(a).inverse() * m.pose(b);
        m.links.push(Link::new(a, b, &rel));
    }
    m
}

#[test]
fn lsr_on_two_maps_targets_the_least_similar_region_of_the_maps_as_loaded() {
    let map = two_objects();
    let likely = names(&["box", "box_stack"]);
    let scope = Scope {
        objects: &likely,
        own_links: 8,
        starts: &[0, 5],
    };
    // The observation is Box experience 0's region. Rows (χ², NMSE) by hand, Eq 6.1–6.2:
    //   1, 5: 0.25/1.5 + 0.25/0.5 = 2/3, 0     2, 6: 1 + 1 = 2, 0
    //   3, 7: 2, (0 − 1)²/1 = 1                 4, 8: 2, (3 − 1)²/1 = 4
    //   9 (the run's, slope 5): 2, 16 — out of scope; 0 (current) and 5 (a start) left out.
    let seen = features([1.0, 0.0, 0.0, 0.0], 1.0);
    let rows = lsr::rows(&map, &seen, 0, &scope);
    let order: Vec<usize> = rows.iter().map(|r| r.experience).collect();
    assert_eq!(order, vec![4, 8, 3, 7, 2, 6, 1]);
    assert!((rows[0].chi2 - 2.0).abs() < 1e-12 && (rows[0].nmse - 4.0).abs() < 1e-12);
    // E_smin = {4, 8}, one in each map. The graph: the 8 loaded links only (the run's 9–4,
    // 0–4 and 1–6 left out). Per link, w_t (m) and w_r (rad):
    //   0–1, 1–2, 2–4, 5–6, 6–7, 7–8: 0.02, 0      0–3, 3–4: 0.05, 0.2
    // Degrees: 0–4 two each, 5 and 8 one, 6 and 7 two. Means over the 16 directed edges:
    //   w_t: (6 × 0.02 + 2 × 0.05) / 8 = 0.0275     w_r: 2 × 0.2 / 8 = 0.05
    //   1/n_l (of the node stepped onto): Box 5 links × (½ + ½) = 5; Box-Stack 5–6 and 7–8
    //   1 + ½ each, 6–7 ½ + ½: 4 — so 9/16.
    // In those units (each term over its mean):
    //   0→1→2→4: 3 × (0.02/0.0275 + 0 + ½ ÷ 9/16) = 3 × (8/11 + 8/9)
    //   0→3→4:   2 × (0.05/0.0275 + 0.2/0.05 + 8/9) = 2 × (20/11 + 4 + 8/9)
    //   5→6→7→8: 3 × 8/11 + 8/9 + 8/9 + 1 ÷ 9/16 = 24/11 + 32/9
    // so the target is Box experience 4 along 0→1→2→4, from the Box's start node.
    let plan = lsr::plan(&map, &seen, 0, &scope, &LsrParams::default()).unwrap();
    assert_eq!(plan.target, 4);
    assert_eq!(plan.path, vec![0, 1, 2, 4]);
    assert!((plan.cost - (24.0 / 11.0 + 24.0 / 9.0)).abs() < 1e-12);
    assert_eq!((plan.tied, plan.skipped), (2, 0));
    let g = ExperienceGraph::new(&map, &scope, &LsrParams::default());
    assert!((g.costs(5)[&8] - (24.0 / 11.0 + 32.0 / 9.0)).abs() < 1e-12);
    assert!((g.path(0, 3).unwrap().0 - (20.0 / 11.0 + 4.0 + 8.0 / 9.0)).abs() < 1e-12);
    // The maps stay apart: the run's link 1–6 does not join them.
    assert!(!g.costs(0).contains_key(&8) && !g.costs(5).contains_key(&4));
    // In metres and radians 1/n_l dominates and the two-hop path wins:
    //   0→3→4: 2 × (0.05 + 0.2 + ½) = 1.5 against 0→1→2→4: 3 × (0.02 + ½) = 1.56
    //   (and 5→6→7→8: 0.06 + ½ + ½ + 1 = 2.06).
    let plan = lsr::plan(&map, &seen, 0, &scope, &si()).unwrap();
    assert_eq!((plan.target, plan.path.clone()), (4, vec![0, 3, 4]));
    assert!((plan.cost - 1.5).abs() < 1e-12);
    // Only the Box-Stack likely: its own map's means — w_t 0.02, w_r 0 (the term drops),
    // 1/n_l (1½ + 1 + 1½)/6 = 2/3 — and 5→6→7→8 costs (1 + ¾) + (1 + ¾) + (1 + 3/2) = 6.
    let stack = names(&["box_stack"]);
    let only = Scope {
        objects: &stack,
        own_links: 8,
        starts: &[5],
    };
    let plan = lsr::plan(&map, &seen, 0, &only, &LsrParams::default()).unwrap();
    assert_eq!((plan.target, plan.path.clone()), (8, vec![5, 6, 7, 8]));
    assert!((plan.cost - 6.0).abs() < 1e-12);
    // Had the run's links counted, 0–4 would be a one-link path to the target.
    let with_runs = Scope {
        own_links: 11,
        ..scope
    };
    let plan = lsr::plan(&map, &seen, 0, &with_runs, &LsrParams::default()).unwrap();
    assert_eq!(plan.path, vec![0, 4]);
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
