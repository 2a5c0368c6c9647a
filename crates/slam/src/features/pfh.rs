//! Point feature histogram (PFH) of one whisk's contact cloud (thesis §2.5.1.1,
//! Eq 2.39–2.44; Rusu et al. 2008).
//!
//! 1. Each point's normal is the principal axis of least spread of itself and its three
//!    nearest neighbours (the thesis' neighbourhood for sparse whisker contacts), flipped
//!    to face the viewpoint, the array origin (Eq 2.40). The thesis text names the
//!    *largest* eigenvalue's eigenvector; that is the direction of greatest spread, which
//!    lies in the surface, not normal to it — a slip, since it cites Rusu et al., whose
//!    normal is the least-spread axis. [`NormalAxis::Greatest`] reproduces the text.
//! 2. For every unordered pair within `radius` (r_β, 0.3 m: every contact of a whisk), the
//!    source is the point whose normal makes the smaller angle with the line joining them,
//!    |n·(p_t − p_s)| the larger ([`SourceRule::Rusu`]; a tie within 10⁻⁹ keeps the first):
//!    Rusu et al.'s rule, "arccos(n_i·p_ji) ≤ arccos(n_j·p_ij)", as PCL's
//!    `computePairFeatures` applies it (on |cos|, so a normal's sign does not matter). The
//!    thesis cites Rusu et al. and says the same in words, but Eq 2.41 prints the
//!    comparison without the arccos, which reverses it — a misprint; the two rules pick
//!    different sources in about half of all pairs. [`SourceRule::Printed`] reproduces
//!    Eq 2.41 as printed. Then the Darboux frame u = n_s, v = (p_t − p_s) × u normalised,
//!    w = u × v (Eq 2.42; the thesis divides by δ, which leaves v short of unit length
//!    unless u ⟂ p_t − p_s); then α = v·n_t, θ = atan2(w·n_t, u·n_t),
//!    φ = u·(p_t − p_s)/δ and δ = ‖p_t − p_s‖ (Eq 2.43).
//! 3. Each feature is normalised to its range — α, φ ∈ [−1, 1], θ ∈ [−π, π],
//!    δ ∈ [0, r_β] — and cut into `divisions` equal bins (d); the pair increments bin
//!    Σ bᵢ·dⁱ (Eq 2.44, with the min subtracted and 0-based indices as the prose describes).
//! 4. The histogram is divided by the number of pairs binned, so it sums to 1. (The thesis
//!    divides by k(k+1)/2, which is not the number of unordered pairs k(k−1)/2.) Pairs
//!    whose line is parallel to the source normal have no Darboux frame and are skipped.

use nalgebra::{Matrix3, Point3, SymmetricEigen, Vector3};
use serde::{Deserialize, Serialize};

/// Which principal axis of a neighbourhood is taken as its normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NormalAxis {
    /// Least spread: the normal of the best-fitting plane (Rusu et al.; default).
    #[default]
    Least,
    /// Greatest spread, as the thesis' text words it.
    Greatest,
}

/// Which point of a pair is the source (Eq 2.41).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SourceRule {
    /// The point whose normal makes the smaller angle with the joining line (Rusu et al.,
    /// PCL; default).
    #[default]
    Rusu,
    /// Eq 2.41 as printed: p1 iff n1·(p2 − p1) ≤ n2·(p1 − p2).
    Printed,
}

/// PFH parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PfhParams {
    /// Divisions per feature, d (the histogram has d⁴ bins).
    pub divisions: usize,
    /// Pair radius r_β (m): pairs farther apart are not counted; also δ's range.
    pub radius_m: f64,
    /// Neighbours (besides the point itself) of each normal's neighbourhood.
    pub neighbours: usize,
    /// Normal axis.
    pub normal_axis: NormalAxis,
    /// Source point rule.
    pub source_rule: SourceRule,
}

impl Default for PfhParams {
    fn default() -> Self {
        Self {
            divisions: 3,
            radius_m: 0.3,
            neighbours: 3,
            normal_axis: NormalAxis::Least,
            source_rule: SourceRule::Rusu,
        }
    }
}

/// The four pair features (Eq 2.43).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairFeatures {
    /// α = v·n_t.
    pub alpha: f64,
    /// θ = atan2(w·n_t, u·n_t) (rad).
    pub theta: f64,
    /// φ = u·(p_t − p_s)/δ.
    pub phi: f64,
    /// δ = ‖p_t − p_s‖ (m).
    pub delta: f64,
}

/// Unit normals of `points` (Eq 2.39–2.40), facing `viewpoint`. Points with fewer than
/// two neighbours get the direction to the viewpoint.
pub fn normals(
    points: &[Point3<f64>],
    viewpoint: &Point3<f64>,
    params: &PfhParams,
) -> Vec<Vector3<f64>> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut others: Vec<(f64, usize)> = points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(j, q)| ((q - p).norm_squared(), j))
                .collect();
            others.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let hood: Vec<Point3<f64>> = std::iter::once(*p)
                .chain(
                    others
                        .iter()
                        .take(params.neighbours)
                        .map(|&(_, j)| points[j]),
                )
                .collect();
            let towards = viewpoint - p;
            let n = if hood.len() < 3 {
                towards
            } else {
                principal_axis(&hood, params.normal_axis)
            };
            let n = n.try_normalize(0.0).unwrap_or_else(Vector3::z);
            // Eq 2.40: flip a normal that points away from the viewpoint.
            if towards.dot(&n) < 0.0 { -n } else { n }
        })
        .collect()
}

/// The least- or greatest-spread principal axis of `points` (unit, sign arbitrary).
fn principal_axis(points: &[Point3<f64>], axis: NormalAxis) -> Vector3<f64> {
    let n = points.len() as f64;
    let mean = points.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / n;
    let cov = points.iter().fold(Matrix3::zeros(), |a, p| {
        let d = p.coords - mean;
        a + d * d.transpose()
    }) / n;
    let eig = SymmetricEigen::new(cov);
    let pick = (0..3)
        .reduce(|a, b| {
            let better = match axis {
                NormalAxis::Least => eig.eigenvalues[b] < eig.eigenvalues[a],
                NormalAxis::Greatest => eig.eigenvalues[b] > eig.eigenvalues[a],
            };
            if better { b } else { a }
        })
        .unwrap_or(0);
    eig.eigenvectors.column(pick).into_owned()
}

/// The pair features of two oriented points (Eq 2.41–2.43) with Rusu et al.'s source
/// rule; None when the line between them is parallel to the source normal (no Darboux
/// frame) or they coincide.
pub fn pair_features(
    p1: &Point3<f64>,
    n1: &Vector3<f64>,
    p2: &Point3<f64>,
    n2: &Vector3<f64>,
) -> Option<PairFeatures> {
    pair_features_with(p1, n1, p2, n2, SourceRule::Rusu)
}

/// [`pair_features`] with the source chosen by `rule`.
pub fn pair_features_with(
    p1: &Point3<f64>,
    n1: &Vector3<f64>,
    p2: &Point3<f64>,
    n2: &Vector3<f64>,
    rule: SourceRule,
) -> Option<PairFeatures> {
    let d12 = p2 - p1;
    let first = match rule {
        // The smaller angle between normal and line: the larger |cos|. Equal within
        // rounding (parallel normals, whose φ would change sign with the choice) keeps p1,
        // so that the choice does not depend on where the pair sits.
        SourceRule::Rusu => n1.dot(&d12).abs() >= n2.dot(&d12).abs() - 1e-9 * d12.norm(),
        SourceRule::Printed => n1.dot(&d12) <= n2.dot(&(-d12)),
    };
    let (ps, ns, pt, nt) = if first {
        (p1, n1, p2, n2)
    } else {
        (p2, n2, p1, n1)
    };
    let d = pt - ps;
    let delta = d.norm();
    if delta == 0.0 {
        return None;
    }
    let u = *ns;
    let v = d.cross(&u).try_normalize(1e-12 * delta)?;
    let w = u.cross(&v);
    Some(PairFeatures {
        alpha: v.dot(nt),
        theta: w.dot(nt).atan2(u.dot(nt)),
        phi: u.dot(&d) / delta,
        delta,
    })
}

/// Bin index of one feature value in [lo, hi] cut into `d` bins (clamped at the ends).
fn bin(value: f64, lo: f64, hi: f64, d: usize) -> usize {
    let t = ((value - lo) / (hi - lo) * d as f64).floor();
    (t.max(0.0) as usize).min(d - 1)
}

/// The histogram bin of a pair (Eq 2.44).
pub fn bin_index(f: &PairFeatures, params: &PfhParams) -> usize {
    let d = params.divisions;
    let pi = std::f64::consts::PI;
    [
        bin(f.alpha, -1.0, 1.0, d),
        bin(f.theta, -pi, pi, d),
        bin(f.phi, -1.0, 1.0, d),
        bin(f.delta, 0.0, params.radius_m, d),
    ]
    .iter()
    .rev()
    .fold(0, |acc, &b| acc * d + b)
}

/// The PFH of a contact cloud seen from `viewpoint`: d⁴ bins summing to 1 (all zero when
/// fewer than two points, or no pair within the radius).
pub fn histogram(points: &[Point3<f64>], viewpoint: &Point3<f64>, params: &PfhParams) -> Vec<f64> {
    let d = params.divisions.max(1);
    let mut h = vec![0.0; d.pow(4)];
    let n = normals(points, viewpoint, params);
    let mut count = 0usize;
    for j1 in 0..points.len() {
        for j2 in 0..j1 {
            if (points[j1] - points[j2]).norm() > params.radius_m {
                continue;
            }
            if let Some(f) =
                pair_features_with(&points[j1], &n[j1], &points[j2], &n[j2], params.source_rule)
            {
                h[bin_index(&f, params)] += 1.0;
                count += 1;
            }
        }
    }
    if count > 0 {
        for b in &mut h {
            *b /= count as f64;
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn three_point_example_by_hand() {
        let p1 = Point3::origin();
        let p2 = Point3::new(1.0, 0.0, 0.0);
        let p3 = Point3::new(0.0, 2.0, 0.0);
        let n1 = Vector3::z();
        let n2 = Vector3::new(0.6, 0.0, 0.8);
        let n3 = Vector3::new(0.0, 0.6, 0.8);
        // (1, 2): n1·(p2−p1) = 0 > n2·(p1−p2) = −0.6, so p2 is the source: u = n2,
        // d = (−1, 0, 0), v = d × u / ‖·‖ = (0, 1, 0), w = u × v = (−0.8, 0, 0.6).
        let f = pair_features(&p1, &n1, &p2, &n2).unwrap();
        assert!(close(f.alpha, 0.0) && close(f.phi, -0.6) && close(f.delta, 1.0));
        assert!(close(f.theta, 0.6f64.atan2(0.8)));
        // (1, 3): the source is p3: u = n3, d = (0, −2, 0), v = (−1, 0, 0),
        // w = (0, −0.8, 0.6).
        let f = pair_features(&p1, &n1, &p3, &n3).unwrap();
        assert!(close(f.alpha, 0.0) && close(f.phi, -0.6) && close(f.delta, 2.0));
        assert!(close(f.theta, 0.6f64.atan2(0.8)));
        // (2, 3): n2·(p3−p2) = −0.6 > n3·(p2−p3) = −1.2, so p3 is the source: u = n3,
        // d = (1, −2, 0), d × u = (−1.6, −0.8, 0.6) of norm √3.56, u × (d × u) =
        // (1, −1.28, 0.96); target normal n2.
        let f = pair_features(&p2, &n2, &p3, &n3).unwrap();
        let k = 3.56f64.sqrt();
        assert!(close(f.alpha, (-1.6 * 0.6 + 0.6 * 0.8) / k));
        assert!(close(f.theta, ((0.6 + 0.96 * 0.8) / k).atan2(0.64)));
        assert!(close(f.phi, -1.2 / 5f64.sqrt()));
        assert!(close(f.delta, 5f64.sqrt()));
        // Swapping the arguments picks the same source.
        assert_eq!(pair_features(&p3, &n3, &p2, &n2), Some(f));
        // A line along the source normal has no Darboux frame.
        let up = Point3::new(0.0, 0.0, -1.0);
        assert_eq!(pair_features(&p1, &n1, &up, &n1), None);
    }

    /// A pair where the rules differ, by hand. p1 = 0, p2 = (1, 0, 0); n1 at 60° from the
    /// line (cos 0.5), n2 at 25.8° (|cos| 0.9, pointing back along it).
    /// Eq 2.41 as printed: n1·(p2 − p1) = 0.5 ≤ n2·(p1 − p2) = 0.9, so p1 is the source and
    /// φ = n1·d/δ = 0.5. Rusu / PCL: 0.5 < 0.9, so p2 (the smaller angle) is the source:
    /// u = n2, d = p1 − p2 = (−1, 0, 0), φ = u·d = 0.9, v = d × u / ‖·‖ = (0, 1, 0),
    /// w = u × v = (−s, 0, −0.9) with s = √0.19, α = v·n1 = 0,
    /// θ = atan2(w·n1, u·n1) = atan2(−0.5 s − 0.9 √0.75, −0.45 + s √0.75).
    #[test]
    fn the_source_is_the_smaller_angle_not_equation_2_41_as_printed() {
        let (p1, p2) = (Point3::origin(), Point3::new(1.0, 0.0, 0.0));
        let s = 0.19f64.sqrt();
        let n1 = Vector3::new(0.5, 0.0, 0.75f64.sqrt());
        let n2 = Vector3::new(-0.9, 0.0, s);
        let f = pair_features(&p1, &n1, &p2, &n2).unwrap();
        assert!(close(f.phi, 0.9) && close(f.alpha, 0.0) && close(f.delta, 1.0));
        let theta = (-0.5 * s - 0.9 * 0.75f64.sqrt()).atan2(-0.45 + s * 0.75f64.sqrt());
        assert!(close(f.theta, theta), "{} vs {theta}", f.theta);
        assert_eq!(pair_features(&p2, &n2, &p1, &n1), Some(f));
        let printed = pair_features_with(&p1, &n1, &p2, &n2, SourceRule::Printed).unwrap();
        assert!(close(printed.phi, 0.5));
        // Flipping a normal's sign does not change Rusu's choice.
        let g = pair_features(&p1, &n1, &p2, &(-n2)).unwrap();
        assert!(close(g.phi, -0.9));
    }

    #[test]
    fn coplanar_points_fill_the_bins_of_equation_2_44() {
        // Three points in z = 0 seen from above: every normal is +z (least spread, facing
        // the viewpoint), so α = θ = φ = 0 (bins 1, 1, 1 of 3) and δ alone varies:
        // 0.05 m (bin 0 of [0, 0.3]) and 0.25, 0.255 m (bin 2).
        let points = [
            Point3::origin(),
            Point3::new(0.05, 0.0, 0.0),
            Point3::new(0.0, 0.25, 0.0),
        ];
        let view = Point3::new(0.1, 0.1, 1.0);
        let params = PfhParams::default();
        for n in normals(&points, &view, &params) {
            assert!((n - Vector3::z()).norm() < 1e-12);
        }
        let h = histogram(&points, &view, &params);
        assert_eq!(h.len(), 81);
        let base = 1 + 3 + 9;
        assert!(close(h[base], 1.0 / 3.0));
        assert!(close(h[base + 27 * 2], 2.0 / 3.0));
        assert!(close(h.iter().sum::<f64>(), 1.0));
        // The thesis' wording (greatest spread) gives in-plane "normals" instead.
        let greatest = PfhParams {
            normal_axis: NormalAxis::Greatest,
            ..params
        };
        for n in normals(&points, &view, &greatest) {
            assert!(n.z.abs() < 1e-12);
        }
    }

    #[test]
    fn pair_features_are_invariant_under_rigid_transforms() {
        use rand::RngExt;
        let mut rng = crate::rng::substream(7, "test/pfh");
        let points: Vec<Point3<f64>> = (0..12)
            .map(|_| {
                Point3::new(
                    rng.random_range(-0.1..0.1),
                    rng.random_range(-0.1..0.1),
                    0.2 + rng.random_range(-0.05..0.05),
                )
            })
            .collect();
        let view = Point3::origin();
        let t = Isometry3::from_parts(
            Translation3::new(0.3, -1.2, 0.7),
            UnitQuaternion::from_euler_angles(0.4, -1.1, 2.5),
        );
        let moved: Vec<Point3<f64>> = points.iter().map(|p| t * p).collect();
        let params = PfhParams::default();
        let (n, m) = (
            normals(&points, &view, &params),
            normals(&moved, &(t * view), &params),
        );
        let mut pairs = 0;
        for i in 0..points.len() {
            assert!((t * n[i] - m[i]).norm() < 1e-9);
            for j in 0..i {
                let a = pair_features(&points[i], &n[i], &points[j], &n[j]).unwrap();
                let b = pair_features(&moved[i], &m[i], &moved[j], &m[j]).unwrap();
                for (x, y) in [
                    (a.alpha, b.alpha),
                    (a.theta, b.theta),
                    (a.phi, b.phi),
                    (a.delta, b.delta),
                ] {
                    assert!((x - y).abs() < 1e-9, "{a:?} vs {b:?}");
                }
                pairs += 1;
            }
        }
        assert_eq!(pairs, 66);
        assert_eq!(
            histogram(&points, &view, &params),
            histogram(&moved, &(t * view), &params)
        );
    }
}
