//! The two-sample Kolmogorov–Smirnov test (thesis §4.2.1: are a model's error
//! distributions different from the tip assumption's and the random guess's?).
//!
//! D = sup |F₁(x) − F₂(x)| over the two empirical distribution functions; the p-value is
//! the asymptotic Kolmogorov distribution Q(λ) = 2 Σ_{k≥1} (−1)^{k−1} e^{−2k²λ²} at
//! λ = (√nₑ + 0.12 + 0.11/√nₑ)·D with nₑ = n₁n₂/(n₁ + n₂) (Stephens' small-sample
//! correction, as in Numerical Recipes §14.3).

/// The result of a two-sample test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KsTest {
    /// The statistic D.
    pub d: f64,
    /// The p-value (probability of a D this large if both samples come from one
    /// distribution).
    pub p: f64,
}

/// Q(λ), the Kolmogorov distribution's survival function.
pub fn kolmogorov_q(lambda: f64) -> f64 {
    if lambda < 1e-3 {
        return 1.0;
    }
    let mut sum = 0.0;
    let mut sign = 1.0;
    for k in 1..=200 {
        let term = sign * (-2.0 * (k * k) as f64 * lambda * lambda).exp();
        sum += term;
        if term.abs() < 1e-16 * sum.abs().max(1e-300) {
            break;
        }
        sign = -sign;
    }
    (2.0 * sum).clamp(0.0, 1.0)
}

/// The two-sample test of `a` against `b` (NaNs are ignored); None if either is empty.
pub fn two_sample(a: &[f64], b: &[f64]) -> Option<KsTest> {
    let sorted = |v: &[f64]| {
        let mut s: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
        s.sort_by(f64::total_cmp);
        s
    };
    let (a, b) = (sorted(a), sorted(b));
    if a.is_empty() || b.is_empty() {
        return None;
    }
    let (n1, n2) = (a.len() as f64, b.len() as f64);
    let (mut i, mut j, mut d) = (0usize, 0usize, 0.0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / n1 - j as f64 / n2).abs());
    }
    let ne = n1 * n2 / (n1 + n2);
    let lambda = (ne.sqrt() + 0.12 + 0.11 / ne.sqrt()) * d;
    Some(KsTest {
        d,
        p: kolmogorov_q(lambda),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kolmogorov_distribution_has_its_tabulated_critical_values() {
        // Critical values of the limiting distribution: Q(1.3581) = 0.05, Q(1.6276) = 0.01,
        // Q(1.2238) = 0.10 (Smirnov 1948).
        for (lambda, alpha) in [(1.35810, 0.05), (1.62762, 0.01), (1.22385, 0.10)] {
            assert!((kolmogorov_q(lambda) - alpha).abs() < 2e-5, "{lambda}");
        }
        assert_eq!(kolmogorov_q(0.0), 1.0);
        assert!(kolmogorov_q(5.0) < 1e-20);
    }

    #[test]
    fn d_is_the_largest_gap_between_the_empirical_distributions() {
        // a = {1, 2, 3, 4}, b = {3.5, 5, 6}: after 3, F_a = 3/4 and F_b = 0 → D = 0.75.
        let t = two_sample(&[4.0, 2.0, 1.0, 3.0], &[6.0, 3.5, 5.0]).unwrap();
        assert!((t.d - 0.75).abs() < 1e-15);
        // Identical samples: D = 0, p = 1; disjoint ones: D = 1.
        let s: Vec<f64> = (0..50).map(|k| k as f64).collect();
        let same = two_sample(&s, &s).unwrap();
        assert_eq!((same.d, same.p), (0.0, 1.0));
        let shifted: Vec<f64> = s.iter().map(|x| x + 100.0).collect();
        let far = two_sample(&s, &shifted).unwrap();
        assert_eq!(far.d, 1.0);
        assert!(far.p < 1e-15);
        // Ties across the samples are stepped together.
        let tie = two_sample(&[1.0, 2.0], &[2.0, 3.0]).unwrap();
        assert!((tie.d - 0.5).abs() < 1e-15);
        assert!(two_sample(&[], &s).is_none());
    }

    #[test]
    fn samples_of_one_distribution_are_rarely_rejected() {
        // Two interleaved halves of one uniform grid: D ≤ 1/n, p near 1.
        let a: Vec<f64> = (0..200).map(|k| (2 * k) as f64).collect();
        let b: Vec<f64> = (0..200).map(|k| (2 * k + 1) as f64).collect();
        let t = two_sample(&a, &b).unwrap();
        assert!(t.d <= 1.0 / 200.0 + 1e-15 && t.p > 0.99, "{t:?}");
    }
}
