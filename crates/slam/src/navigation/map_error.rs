//! The error of a planar map whose frame is arbitrary: a SLAM map is defined only up to a
//! rigid motion of the plane (its first experience sits wherever the network started), so
//! its poses are compared with the true ones after the rigid motion that best maps them
//! onto the truth (least squares over the positions, paired by index: the planar case of
//! Umeyama 1991 without scale, in closed form). Used for the office run's map and for its
//! dead-reckoned baseline alike (issue #36).

use crate::pose::{Pose2, wrap};
use serde::Serialize;

/// The best rigid motion of the plane mapping `from` onto `to` (paired by index): the
/// rotation θ = atan2(Σ a×b, Σ a·b) of the centred points and the translation of the
/// centroids. None for fewer than 2 points or when every point coincides.
pub fn rigid_fit(from: &[Pose2], to: &[Pose2]) -> Option<Pose2> {
    let n = from.len().min(to.len());
    if n < 2 {
        return None;
    }
    let centroid = |p: &[Pose2]| {
        let (x, y) = p[..n]
            .iter()
            .fold((0.0, 0.0), |(x, y), q| (x + q.x, y + q.y));
        (x / n as f64, y / n as f64)
    };
    let (fx, fy) = centroid(from);
    let (tx, ty) = centroid(to);
    let (mut cross, mut dot) = (0.0, 0.0);
    for (a, b) in from[..n].iter().zip(&to[..n]) {
        let (ax, ay, bx, by) = (a.x - fx, a.y - fy, b.x - tx, b.y - ty);
        cross += ax * by - ay * bx;
        dot += ax * bx + ay * by;
    }
    if cross.hypot(dot) < 1e-300 {
        return None;
    }
    let th = cross.atan2(dot);
    let (s, c) = th.sin_cos();
    Some(Pose2 {
        x: tx - (c * fx - s * fy),
        y: ty - (s * fx + c * fy),
        th,
    })
}

/// A map's error against the truth after the best rigid fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MapError {
    /// Root mean square position error (m).
    pub rms_m: f64,
    /// Largest position error (m).
    pub max_m: f64,
    /// Root mean square heading error (deg).
    pub heading_rms_deg: f64,
    /// The rigid motion applied to the estimate (x, y in m, θ in rad).
    pub fit: Pose2,
}

/// The error of `estimate` against `truth` (paired by index) after [`rigid_fit`]; None
/// where no fit exists.
pub fn measure(estimate: &[Pose2], truth: &[Pose2]) -> Option<MapError> {
    let fit = rigid_fit(estimate, truth)?;
    let n = estimate.len().min(truth.len());
    let (mut sq, mut max, mut sq_th) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (e, t) in estimate[..n].iter().zip(&truth[..n]) {
        let moved = fit.compose(e);
        let d = (moved.x - t.x).hypot(moved.y - t.y);
        sq += d * d;
        max = max.max(d);
        sq_th += wrap(moved.th - t.th).powi(2);
    }
    Some(MapError {
        rms_m: (sq / n as f64).sqrt(),
        max_m: max,
        heading_rms_deg: (sq_th / n as f64).sqrt().to_degrees(),
        fit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<Pose2> {
        [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0), (1.0, 0.5)]
            .iter()
            .enumerate()
            .map(|(k, &(x, y))| Pose2 {
                x,
                y,
                th: 0.3 * k as f64,
            })
            .collect()
    }

    /// A map that is the truth moved rigidly (by a motion computed here with sines and
    /// cosines, independently of `Pose2::compose`) is fitted back exactly.
    #[test]
    fn a_rigidly_moved_map_has_no_error() {
        let truth = square();
        let (th, dx, dy) = (2.0_f64, -3.0, 4.5);
        let moved: Vec<Pose2> = truth
            .iter()
            .map(|p| Pose2 {
                x: th.cos() * p.x - th.sin() * p.y + dx,
                y: th.sin() * p.x + th.cos() * p.y + dy,
                th: wrap(p.th + th),
            })
            .collect();
        let e = measure(&moved, &truth).unwrap();
        assert!(e.rms_m < 1e-12 && e.max_m < 1e-12, "{e:?}");
        assert!(e.heading_rms_deg < 1e-10, "{e:?}");
        assert!((wrap(e.fit.th + th)).abs() < 1e-12, "{e:?}");
    }

    /// Four points at (±1, 0), (0, ±1) with one moved by d along its radius: the best
    /// fit leaves the rotation alone (the displacement is radial and symmetric about its
    /// axis) and shifts the centroid by d/4, so the errors are 3d/4 at the moved point
    /// and d/4 at the other three: rms = d·√(12/64).
    #[test]
    fn one_displaced_point_gives_the_hand_computed_error() {
        let p = |x, y| Pose2 { x, y, th: 0.0 };
        let truth = vec![p(1.0, 0.0), p(0.0, 1.0), p(-1.0, 0.0), p(0.0, -1.0)];
        let d = 0.2;
        let mut estimate = truth.clone();
        estimate[0].x += d;
        let e = measure(&estimate, &truth).unwrap();
        assert!(
            (e.rms_m - d * (12.0_f64 / 64.0).sqrt()).abs() < 1e-12,
            "{e:?}"
        );
        assert!((e.max_m - 0.75 * d).abs() < 1e-12, "{e:?}");
        assert!(e.fit.th.abs() < 1e-12);
    }

    #[test]
    fn too_few_or_coincident_points_have_no_fit() {
        let one = vec![Pose2::default()];
        assert!(rigid_fit(&one, &one).is_none());
        let same = vec![Pose2::default(); 3];
        assert!(rigid_fit(&same, &same).is_none());
    }
}
