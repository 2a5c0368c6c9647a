//! The rank tests against published worked examples (the examples of R's `wilcox.test`
//! and `kruskal.test` manual pages, from Hollander & Wolfe 1973, and the `mtcars` data
//! of Henderson & Velleman 1981 as R's tutorials test it), exact against asymptotic
//! p-values where both apply, and the exact counts against brute-force enumeration.

use whisker_slam::stats::rank_tests::{
    doubled_midranks, holm, kruskal_wallis, mann_whitney, normal_upper,
};

/// Hollander & Wolfe (1973) p. 69: permeability constants of the human chorioamnion at
/// term (x) and at 12–26 weeks (y). Published: W = 35, one-sided exact p = 0.1272
/// (so two-sided 0.2544).
#[test]
fn mann_whitney_hollander_wolfe_no_ties() {
    let x = [0.80, 0.83, 1.89, 1.04, 1.45, 1.38, 1.91, 1.64, 0.73, 1.46];
    let y = [1.15, 0.88, 0.90, 0.74, 1.21];
    let t = mann_whitney(&x, &y).unwrap();
    assert_eq!(t.u, 35.0);
    let exact = t.p_exact.unwrap();
    assert!((exact / 2.0 - 0.1272).abs() < 5e-5, "{exact}");
    // The same data the other way round: U' = n₁n₂ − U, the same two-sided p.
    let r = mann_whitney(&y, &x).unwrap();
    assert_eq!(r.u, 15.0);
    assert!((r.p_exact.unwrap() - exact).abs() < 1e-12);
}

/// Motor Trend 1974 (`mtcars`): miles per gallon of 19 automatic against 13 manual
/// cars, with ties (10.4, 15.2, 19.2, 21.0, 21.4, 22.8, 30.4 appear twice). Published
/// (R, normal approximation with tie and continuity correction): W = 42, p = 0.001871.
#[test]
fn mann_whitney_mtcars_with_ties() {
    let (auto, manual) = mtcars_by_transmission();
    assert_eq!((auto.len(), manual.len()), (19, 13));
    let t = mann_whitney(&auto, &manual).unwrap();
    assert_eq!(t.u, 42.0);
    assert!(
        (t.p_asymptotic - 0.001871).abs() < 5e-7,
        "{}",
        t.p_asymptotic
    );
    // The exact conditional p-value exists (32 values) and is of the same order.
    let exact = t.p_exact.unwrap();
    assert!(exact > 0.0005 && exact < 0.004, "{exact}");
}

/// Hollander & Wolfe (1973) p. 116: mucociliary efficiency in normal subjects, with
/// obstructive airway disease, with asbestosis. Published: H = 0.77143, df 2, p = 0.68.
#[test]
fn kruskal_wallis_hollander_wolfe() {
    let x = [2.9, 3.0, 2.5, 2.6, 3.2];
    let y = [3.8, 2.7, 4.0, 2.4];
    let z = [2.8, 3.4, 3.7, 2.2, 2.0];
    let t = kruskal_wallis(&[&x, &y, &z]).unwrap();
    assert!((t.h - 0.77143).abs() < 5e-6, "{}", t.h);
    assert_eq!(t.df, 2);
    assert!((t.p_asymptotic - 0.68).abs() < 0.005, "{}", t.p_asymptotic);
    // 14!/(5!4!5!) = 252252 assignments: counted exactly. Published exact tables give
    // P(H ≥ 0.7714) for sizes (5, 4, 5) well above 0.5.
    let exact = t.p_exact.unwrap();
    assert!(exact > 0.6 && exact < 0.75, "{exact}");
}

/// `mtcars` miles per gallon by number of cylinders (4, 6, 8), with ties. Published
/// (R): H = 25.746, df 2, p = 2.566e-06.
#[test]
fn kruskal_wallis_mtcars_with_ties() {
    let groups: Vec<Vec<f64>> = [4, 6, 8]
        .iter()
        .map(|&c| {
            MPG.iter()
                .zip(CYL)
                .filter(|&(_, k)| k == c)
                .map(|(&m, _)| m)
                .collect()
        })
        .collect();
    let refs: Vec<&[f64]> = groups.iter().map(Vec::as_slice).collect();
    let t = kruskal_wallis(&refs).unwrap();
    assert!((t.h - 25.746).abs() < 5e-4, "{}", t.h);
    assert!(
        (t.p_asymptotic - 2.566e-6).abs() < 5e-10,
        "{}",
        t.p_asymptotic
    );
    assert!(
        t.p_exact.is_none(),
        "32 values in 3 groups are too many to enumerate"
    );
}

/// With two groups Kruskal–Wallis is the square of Mann–Whitney's z without the
/// continuity correction: H = z², and the exact p-values are the same test.
#[test]
fn kruskal_wallis_of_two_groups_is_mann_whitney() {
    let x = [1.1, 2.5, 2.5, 4.0, 7.2, 3.3];
    let y = [0.4, 2.5, 1.0, 0.9, 3.3];
    let k = kruskal_wallis(&[&x, &y]).unwrap();
    let m = mann_whitney(&x, &y).unwrap();
    let (n1, n2) = (6.0, 5.0);
    let n: f64 = n1 + n2;
    let (ranks, ties) = doubled_midranks(&[x.as_slice(), &y].concat());
    let tie: f64 = ties.iter().map(|&t| (t * t * t - t) as f64).sum();
    let sigma = (n1 * n2 / 12.0 * ((n + 1.0) - tie / (n * (n - 1.0)))).sqrt();
    let z = (m.u - n1 * n2 / 2.0) / sigma;
    assert!((k.h - z * z).abs() < 1e-9, "{} vs {}", k.h, z * z);
    assert!((k.p_exact.unwrap() - m.p_exact.unwrap()).abs() < 1e-12);
    assert_eq!(ranks.iter().sum::<u64>(), 11 * 12);
}

/// Exact and asymptotic p-values agree for groups of 20 (no ties), where the normal
/// approximation is good, across a range of separations.
#[test]
fn exact_and_asymptotic_agree_for_larger_samples() {
    for shift in [0.0, 3.0, 6.0, 9.0, 14.0] {
        let x: Vec<f64> = (0..20).map(|i| i as f64 * 1.37 % 20.0).collect();
        let y: Vec<f64> = (0..20).map(|i| i as f64 * 0.91 + shift + 0.005).collect();
        let t = mann_whitney(&x, &y).unwrap();
        let (e, a) = (t.p_exact.unwrap(), t.p_asymptotic);
        assert!(
            (e - a).abs() < 0.006,
            "shift {shift}: exact {e} asymptotic {a}"
        );
    }
    // Kruskal–Wallis, three groups of 4 (34650 assignments), distinct values.
    let g = [
        [1.0, 5.0, 9.0, 12.5],
        [2.0, 6.0, 10.0, 11.0],
        [3.0, 4.0, 7.0, 8.0],
    ];
    let t = kruskal_wallis(&[&g[0], &g[1], &g[2]]).unwrap();
    let (e, a) = (t.p_exact.unwrap(), t.p_asymptotic);
    assert!((e - a).abs() < 0.05, "exact {e} asymptotic {a}");
}

/// The exact counts against brute force: every C(9, 4) split of values with ties.
#[test]
fn exact_mann_whitney_matches_brute_force_enumeration() {
    let x = [1.0, 3.0, 3.0, 5.0];
    let y = [2.0, 3.0, 5.0, 5.0, 8.0];
    let pooled: Vec<f64> = x.iter().chain(&y).copied().collect();
    let (ranks, _) = doubled_midranks(&pooled);
    let observed: u64 = ranks[..4].iter().sum();
    let (mut below, mut above, mut total) = (0u32, 0u32, 0u32);
    for mask in 0u32..(1 << 9) {
        if mask.count_ones() != 4 {
            continue;
        }
        let s: u64 = (0..9)
            .filter(|i| mask >> i & 1 == 1)
            .map(|i| ranks[i])
            .sum();
        total += 1;
        below += u32::from(s <= observed);
        above += u32::from(s >= observed);
    }
    let want = (2.0 * below.min(above) as f64 / total as f64).min(1.0);
    let t = mann_whitney(&x, &y).unwrap();
    assert!((t.p_exact.unwrap() - want).abs() < 1e-12);
    assert_eq!(total, 126);
}

/// Holm by hand: p = (0.01, 0.04, 0.03, 0.005) sorted 0.005, 0.01, 0.03, 0.04 →
/// 0.02, 0.03, 0.06, max(0.06, 0.04) = 0.06.
#[test]
fn holm_by_hand() {
    let adj = holm(&[0.01, 0.04, 0.03, 0.005]);
    let want = [0.03, 0.06, 0.06, 0.02];
    for (a, w) in adj.iter().zip(want) {
        assert!((a - w).abs() < 1e-12, "{adj:?}");
    }
    assert_eq!(holm(&[0.6, 0.9]), vec![1.0, 1.0]);
}

#[test]
fn normal_tail_by_table() {
    assert!((normal_upper(1.959964) - 0.025).abs() < 1e-7);
    assert!((normal_upper(0.0) - 0.5).abs() < 1e-15);
}

const MPG: [f64; 32] = [
    21.0, 21.0, 22.8, 21.4, 18.7, 18.1, 14.3, 24.4, 22.8, 19.2, 17.8, 16.4, 17.3, 15.2, 10.4, 10.4,
    14.7, 32.4, 30.4, 33.9, 21.5, 15.5, 15.2, 13.3, 19.2, 27.3, 26.0, 30.4, 15.8, 19.7, 15.0, 21.4,
];
const AM: [u8; 32] = [
    1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1,
];
const CYL: [u8; 32] = [
    6, 6, 4, 6, 8, 6, 8, 4, 4, 6, 6, 8, 8, 8, 8, 8, 8, 4, 4, 4, 4, 8, 8, 8, 8, 4, 4, 4, 8, 6, 8, 4,
];

fn mtcars_by_transmission() -> (Vec<f64>, Vec<f64>) {
    let pick = |a| {
        MPG.iter()
            .zip(AM)
            .filter(|&(_, k)| k == a)
            .map(|(&m, _)| m)
            .collect()
    };
    (pick(0), pick(1))
}
