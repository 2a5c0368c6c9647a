//! Rank tests for comparing groups of trials. The thesis compares its strategies by
//! notched box plots (§6.3, Figs 6.6–6.10); these give the p-values beside them:
//! Mann–Whitney U for two groups, Kruskal–Wallis H for more, Holm's step-down
//! correction for the pairwise comparisons that follow.
//!
//! Ties get midranks. Each test reports the large-sample p-value (normal with tie and
//! continuity correction for U, as R's `wilcox.test`; χ² with k − 1 degrees of freedom
//! after the tie correction for H, as R's `kruskal.test`) and, where the permutation
//! distribution is small enough to count, the exact p-value: the probability, over every
//! equally likely assignment of the pooled values to the groups, of a statistic at least
//! as extreme. With ties this is the exact conditional test on the midranks.

use statrs::function::{erf::erfc, gamma::gamma_ur};

/// At most this many pooled values for the exact Mann–Whitney p-value.
pub const EXACT_MANN_WHITNEY_MAX_N: usize = 60;
/// At most this many assignments enumerated for the exact Kruskal–Wallis p-value.
pub const EXACT_KRUSKAL_WALLIS_MAX_ASSIGNMENTS: f64 = 2.0e6;

/// Twice the midrank (1-based) of every value in `values`, an integer so that sums of
/// ranks are exact; and the size of every group of tied values.
pub fn doubled_midranks(values: &[f64]) -> (Vec<u64>, Vec<usize>) {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut ranks = vec![0; values.len()];
    let mut ties = Vec::new();
    let mut i = 0;
    while i < order.len() {
        let mut j = i + 1;
        while j < order.len() && values[order[j]] == values[order[i]] {
            j += 1;
        }
        // Positions i..j (0-based) share the midrank (i + 1 + j) / 2.
        for &k in &order[i..j] {
            ranks[k] = (i + 1 + j) as u64;
        }
        if j - i > 1 {
            ties.push(j - i);
        }
        i = j;
    }
    (ranks, ties)
}

/// Σ (t³ − t) over the tie groups.
fn tie_sum(ties: &[usize]) -> f64 {
    ties.iter().map(|&t| (t * t * t - t) as f64).sum()
}

/// The standard normal's upper tail P(Z > z).
pub fn normal_upper(z: f64) -> f64 {
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// The χ² distribution's upper tail P(X > x) with `df` degrees of freedom.
pub fn chi_square_upper(x: f64, df: f64) -> f64 {
    if x <= 0.0 {
        1.0
    } else {
        gamma_ur(0.5 * df, 0.5 * x)
    }
}

/// A Mann–Whitney U test of two groups (two-sided).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MannWhitney {
    /// U of the first group: its rank sum − n₁(n₁ + 1)/2 (R's `W`).
    pub u: f64,
    /// Group sizes.
    pub n1: usize,
    /// Group sizes.
    pub n2: usize,
    /// The normal deviate with tie and continuity correction.
    pub z: f64,
    /// Two-sided p-value of the normal approximation.
    pub p_asymptotic: f64,
    /// Two-sided exact p-value (the conditional permutation test on the midranks), when
    /// n₁ + n₂ ≤ [`EXACT_MANN_WHITNEY_MAX_N`].
    pub p_exact: Option<f64>,
}

impl MannWhitney {
    /// The exact p-value when there is one, else the asymptotic.
    pub fn p(&self) -> f64 {
        self.p_exact.unwrap_or(self.p_asymptotic)
    }
}

/// Mann–Whitney U of `x` against `y`; `None` when either group is empty.
pub fn mann_whitney(x: &[f64], y: &[f64]) -> Option<MannWhitney> {
    let (n1, n2) = (x.len(), y.len());
    if n1 == 0 || n2 == 0 {
        return None;
    }
    let pooled: Vec<f64> = x.iter().chain(y).copied().collect();
    let (ranks, ties) = doubled_midranks(&pooled);
    let n = (n1 + n2) as f64;
    let r1: u64 = ranks[..n1].iter().sum();
    let u = r1 as f64 / 2.0 - (n1 * (n1 + 1)) as f64 / 2.0;
    let (a, b) = (n1 as f64, n2 as f64);
    let sigma = (a * b / 12.0 * ((n + 1.0) - tie_sum(&ties) / (n * (n - 1.0)))).sqrt();
    let d = u - a * b / 2.0;
    let z = if sigma > 0.0 {
        (d - 0.5 * d.signum()) / sigma
    } else {
        0.0
    };
    let p_asymptotic = (2.0 * normal_upper(z.abs())).min(1.0);
    let p_exact = (n1 + n2 <= EXACT_MANN_WHITNEY_MAX_N).then(|| {
        let counts = rank_sum_counts(&ranks, n1);
        let total: f64 = counts.iter().sum();
        let below: f64 = counts[..=r1 as usize].iter().sum();
        let above: f64 = counts[r1 as usize..].iter().sum();
        (2.0 * below.min(above) / total).min(1.0)
    });
    Some(MannWhitney {
        u,
        n1,
        n2,
        z,
        p_asymptotic,
        p_exact,
    })
}

/// `counts[s]`: how many of the C(n, k) ways of choosing `k` of the values have doubled
/// rank sum `s` (dynamic programming over the values, k-subsets by sum).
fn rank_sum_counts(doubled: &[u64], k: usize) -> Vec<f64> {
    let max: usize = doubled.iter().map(|&r| r as usize).sum();
    // ways[j][s]: subsets of size j of the values seen so far with sum s.
    let mut ways = vec![vec![0.0f64; max + 1]; k + 1];
    ways[0][0] = 1.0;
    for &r in doubled {
        let r = r as usize;
        for j in (1..=k).rev() {
            let (lower, upper) = ways.split_at_mut(j);
            for s in (r..=max).rev() {
                upper[0][s] += lower[j - 1][s - r];
            }
        }
    }
    ways.swap_remove(k)
}

/// A Kruskal–Wallis H test of k ≥ 2 groups.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KruskalWallis {
    /// H, tie-corrected (R's "Kruskal-Wallis chi-squared").
    pub h: f64,
    /// Degrees of freedom k − 1.
    pub df: usize,
    /// p-value from the χ² approximation.
    pub p_asymptotic: f64,
    /// Exact permutation p-value when at most
    /// [`EXACT_KRUSKAL_WALLIS_MAX_ASSIGNMENTS`] assignments exist.
    pub p_exact: Option<f64>,
}

impl KruskalWallis {
    /// The exact p-value when there is one, else the asymptotic.
    pub fn p(&self) -> f64 {
        self.p_exact.unwrap_or(self.p_asymptotic)
    }
}

/// Kruskal–Wallis H of `groups`; `None` with fewer than two non-empty groups or when
/// every value is tied.
pub fn kruskal_wallis(groups: &[&[f64]]) -> Option<KruskalWallis> {
    let groups: Vec<&[f64]> = groups.iter().copied().filter(|g| !g.is_empty()).collect();
    if groups.len() < 2 {
        return None;
    }
    let sizes: Vec<usize> = groups.iter().map(|g| g.len()).collect();
    let pooled: Vec<f64> = groups.iter().flat_map(|g| g.iter().copied()).collect();
    let (ranks, ties) = doubled_midranks(&pooled);
    let n = pooled.len() as f64;
    let correction = 1.0 - tie_sum(&ties) / (n * n * n - n);
    if correction <= 0.0 {
        return None;
    }
    let mut sums = Vec::with_capacity(sizes.len());
    let mut at = 0;
    for &m in &sizes {
        sums.push(ranks[at..at + m].iter().sum::<u64>());
        at += m;
    }
    // Σ (2Rᵢ)²/nᵢ: H grows with it, so the exact test counts assignments where it is at
    // least the observed.
    let score = |sums: &[u64]| -> f64 {
        sums.iter()
            .zip(&sizes)
            .map(|(&s, &m)| (s * s) as f64 / m as f64)
            .sum()
    };
    let observed = score(&sums);
    let h = (12.0 * (observed / 4.0) / (n * (n + 1.0)) - 3.0 * (n + 1.0)) / correction;
    let df = sizes.len() - 1;
    let p_asymptotic = chi_square_upper(h, df as f64);
    let p_exact = (assignments(&sizes) <= EXACT_KRUSKAL_WALLIS_MAX_ASSIGNMENTS).then(|| {
        let mut state = Enumeration {
            ranks: &ranks,
            sizes: &sizes,
            left: sizes.clone(),
            sums: vec![0; sizes.len()],
            threshold: observed * (1.0 - 1e-12),
            at_least: 0,
            total: 0,
        };
        state.assign(0, &score);
        state.at_least as f64 / state.total as f64
    });
    Some(KruskalWallis {
        h,
        df,
        p_asymptotic,
        p_exact,
    })
}

/// The multinomial N! / Π nᵢ! (as a float).
fn assignments(sizes: &[usize]) -> f64 {
    let mut left: usize = sizes.iter().sum();
    let mut total = 1.0;
    for &m in sizes {
        // C(left, m)
        for i in 0..m {
            total *= (left - i) as f64 / (i + 1) as f64;
        }
        left -= m;
    }
    total.round()
}

/// Every assignment of the pooled ranks to groups of the given sizes.
struct Enumeration<'a> {
    ranks: &'a [u64],
    sizes: &'a [usize],
    left: Vec<usize>,
    sums: Vec<u64>,
    threshold: f64,
    at_least: u64,
    total: u64,
}

impl Enumeration<'_> {
    fn assign(&mut self, i: usize, score: &dyn Fn(&[u64]) -> f64) {
        if i == self.ranks.len() {
            self.total += 1;
            if score(&self.sums) >= self.threshold {
                self.at_least += 1;
            }
            return;
        }
        for g in 0..self.sizes.len() {
            if self.left[g] > 0 {
                self.left[g] -= 1;
                self.sums[g] += self.ranks[i];
                self.assign(i + 1, score);
                self.sums[g] -= self.ranks[i];
                self.left[g] += 1;
            }
        }
    }
}

/// Holm's step-down adjustment of `p` (each adjusted p-value in the input's order):
/// sorted ascending, the j-th (from 0) becomes max over i ≤ j of min(1, (m − i) pᵢ).
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut adjusted = vec![0.0; m];
    let mut running: f64 = 0.0;
    for (i, &k) in order.iter().enumerate() {
        running = running.max(((m - i) as f64 * p[k]).min(1.0));
        adjusted[k] = running;
    }
    adjusted
}
