//! Performance metrics of planar RatSLAM (thesis §3.2.3): the Experience Metric
//! (Algorithm 1: average rate of re-localisation ARR and of correct re-localisation ARCR)
//! and the Energy Metric (Eq 3.2–3.3, after Kümmerle et al. 2009).

use crate::pose::Pose2;

/// The Experience Metric's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExperienceMetric {
    /// ARR: re-localisations over the experiences logged after the base set.
    pub arr: f64,
    /// ARCR: correct re-localisations over re-localisations (NaN if none).
    pub arcr: f64,
    /// Re-localisations counted (η).
    pub relocalisations: usize,
    /// Correct ones (η_c).
    pub correct: usize,
}

/// Algorithm 1 on the experience log `log` (the current experience at each update) and
/// the true poses `truth` at the same updates; `base_end` is the last index (0-based) of
/// the base set (the first loop); a re-localisation is correct within `max_position` (m)
/// and `max_angle` (rad) (the thesis: 0.1 m, 25°).
///
/// Read as written except one line: the correctness test is κ_c1 **or** κ_c2 — "a
/// re-localisation onto a valid experience within the thresholds, or staying on an
/// experience that was a correct re-localisation". With "and", as printed, a jump could
/// never be correct (κ_c2 needs e_i = e_{i−1}) and ARCR would always be 0.
pub fn experience_metric(
    log: &[usize],
    truth: &[Pose2],
    base_end: usize,
    max_position: f64,
    max_angle: f64,
) -> ExperienceMetric {
    let n = log.len().min(truth.len());
    let mut valid: Vec<usize> = Vec::new();
    for &e in &log[..(base_end + 1).min(n)] {
        if !valid.contains(&e) {
            valid.push(e);
        }
    }
    let (mut relocalised, mut correct_set) = (Vec::new(), Vec::new());
    let mut correct_now = true;
    let mut correct = 0usize;
    for i in base_end + 1..n {
        let (prev, e) = (log[i - 1], log[i]);
        let past = &log[..i];
        let seen = past.contains(&e);
        let ordinary_stay = e == prev && !relocalised.contains(&prev);
        if seen && !ordinary_stay {
            relocalised.push(e);
        }
        if relocalised.contains(&e) {
            let j = past.iter().rposition(|&x| x == e).expect("seen before");
            let dp = (truth[i].x - truth[j].x).hypot(truth[i].y - truth[j].y);
            let dth = crate::pose::wrap(truth[i].th - truth[j].th).abs();
            let within = valid.contains(&e) && dp < max_position && dth < max_angle;
            let staying_correct = e == prev && correct_set.contains(&prev);
            if within || staying_correct {
                correct_set.push(e);
                correct += 1;
                correct_now = true;
            } else {
                correct_now = false;
            }
        }
        if correct_now && !valid.contains(&prev) {
            valid.push(prev);
        }
    }
    let eta = relocalised.len();
    ExperienceMetric {
        arr: eta as f64 / n.saturating_sub(base_end + 1).max(1) as f64,
        arcr: if eta == 0 {
            f64::NAN
        } else {
            correct as f64 / eta as f64
        },
        relocalisations: eta,
        correct,
    }
}

/// The Energy Metric (Eq 3.2–3.3): over the relations (i, j), the mean of the squared
/// translation (m²) plus squared rotation (rad²) of δ_ij ⊖ δ*_ij, where δ_ij = x_j ⊖ x_i
/// from the estimated poses and δ*_ij from the true ones. None if there is no relation.
pub fn energy_metric(
    estimate: &[Pose2],
    truth: &[Pose2],
    relations: &[(usize, usize)],
) -> Option<f64> {
    if relations.is_empty() {
        return None;
    }
    let sum: f64 = relations
        .iter()
        .map(|&(i, j)| {
            let d = estimate[i].relative(&estimate[j]);
            let t = truth[i].relative(&truth[j]);
            let e = t.relative(&d);
            e.x * e.x + e.y * e.y + e.th * e.th
        })
        .sum();
    Some(sum / relations.len() as f64)
}

/// Relations between consecutive samples: (0, 1), (1, 2), …
pub fn consecutive(n: usize) -> Vec<(usize, usize)> {
    (1..n).map(|j| (j - 1, j)).collect()
}
