//! The base's route as the updates of a run: where the base truly is at each update and
//! what its odometry reads.
//!
//! The route of `[navigate]` is driven leg by leg: a turn in place towards the next
//! waypoint at `turn_rate_deg_s`, then straight at `speed_m_s`, each update moving the
//! base by at most what it covers in one update period (the last step of a turn or a leg
//! shorter, so that every waypoint and heading is reached exactly). The base starts at
//! the first waypoint facing the second and ends each lap back at the first. Odometry is
//! the motion between consecutive true poses read through the wheeled-base error model
//! (`whisker_slam::navigation::base_odometry`), drawn from the sub-stream
//! `navigate/odometry` of the seed.

use whisker_scenario::navigate::NavigateConfig;
use whisker_slam::navigation::base_odometry::{BaseMotion, BaseOdometryNoise};
use whisker_slam::pose::{Pose2, wrap};
use whisker_slam::rng::substream;

/// The true pose of the base at every update, the start first, for updates `period_s`
/// apart.
pub fn poses(config: &NavigateConfig, period_s: f64) -> Vec<Pose2> {
    let step = config.base.speed_m_s * period_s;
    let turn = config.base.turn_rate_deg_s.to_radians() * period_s;
    let legs = config.legs();
    let headings = config.headings();
    let heading = |i: usize| headings[i];
    let (a, _) = legs[0];
    let mut at = Pose2 {
        x: a.x,
        y: a.y,
        th: heading(0),
    };
    let mut out = vec![at];
    for _ in 0..config.laps {
        for (i, &(a, b)) in legs.iter().enumerate() {
            // Within a billionth of a step, the last step of a turn or a leg is a whole
            // one (no sliver of an update for rounding).
            let mut left = wrap(heading(i) - at.th);
            while left.abs() > 1e-12 {
                if left.abs() <= turn * (1.0 + 1e-9) {
                    (at.th, left) = (heading(i), 0.0);
                } else {
                    let d = turn.copysign(left);
                    (at.th, left) = (wrap(at.th + d), left - d);
                }
                out.push(at);
            }
            let length = (b - a).norm();
            let n = (length / step - 1e-9).ceil().max(1.0) as usize;
            for k in 1..=n {
                let s = k as f64 * step / length;
                let p = if k == n { b } else { a + (b - a) * s };
                (at.x, at.y) = (p.x, p.y);
                out.push(at);
            }
        }
    }
    out
}

/// What the odometry reads between consecutive `truth` poses (one fewer than poses),
/// with `noise` drawn from the sub-stream `navigate/odometry` of `seed`.
/// The index of each lap's last pose in `truth` (the route's poses, [`poses`]): where
/// the base arrives back at the first waypoint. Laps differ in length: the first starts
/// facing its first leg, the others turn towards it first.
pub fn lap_ends(truth: &[Pose2], config: &NavigateConfig) -> Vec<usize> {
    let [x, y] = config.route_m[0];
    let at = |i: usize| (truth[i].x, truth[i].y) == (x, y);
    (1..truth.len()).filter(|&i| at(i) && !at(i - 1)).collect()
}

/// The kidnapped robot (`navigate.kidnap`): `truth` (the route's poses, [`poses`]) with
/// the last lap's legs from its first waypoint to its middle one cut out, and the index
/// of the first pose after the carry. None when the route has one lap.
pub fn kidnap(truth: &[Pose2], config: &NavigateConfig) -> Option<(Vec<Pose2>, usize)> {
    let start = *lap_ends(truth, config).get(config.laps.checked_sub(2)?)?;
    let [x, y] = config.route_m[config.route_m.len() / 2];
    let arrive = (start + 1..truth.len()).find(|&i| (truth[i].x, truth[i].y) == (x, y))?;
    let mut cut = truth[..=start].to_vec();
    cut.extend_from_slice(&truth[arrive..]);
    Some((cut, start + 1))
}

pub fn odometry(truth: &[Pose2], noise: &BaseOdometryNoise, seed: u64) -> Vec<BaseMotion> {
    let mut rng = substream(seed, "navigate/odometry");
    truth
        .windows(2)
        .map(|w| noise.read(&BaseMotion::between(&w[0], &w[1]), &mut rng))
        .collect()
}

/// The poses dead-reckoned from `start` through `motions`, `start` first.
pub fn dead_reckon(start: Pose2, motions: &[BaseMotion]) -> Vec<Pose2> {
    let mut at = start;
    std::iter::once(start)
        .chain(motions.iter().map(|m| {
            at = m.apply(&at);
            at
        }))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_scenario::navigate::BaseConfig;

    fn square(laps: usize) -> NavigateConfig {
        NavigateConfig {
            route_m: vec![[1.0, 1.0], [3.0, 1.0], [3.0, 2.5], [1.0, 2.5]],
            laps,
            base: BaseConfig {
                speed_m_s: 0.1,
                turn_rate_deg_s: 30.0,
                ..BaseConfig::default()
            },
            odometry: BaseOdometryNoise::default(),
            switch: Default::default(),
            terrain: Default::default(),
            ratslam: whisker_scenario::navigate::office_ratslam(),
            object: None,
            fusion: true,
            kidnap: false,
        }
    }

    #[test]
    fn the_route_is_driven_within_the_speeds_through_every_waypoint_and_back() {
        let config = square(2);
        let period = 1.0;
        let truth = poses(&config, period);
        for w in truth.windows(2) {
            let (d, t) = (
                (w[1].x - w[0].x).hypot(w[1].y - w[0].y),
                wrap(w[1].th - w[0].th),
            );
            assert!(
                d <= 0.1 + 1e-9 && t.abs() <= 30f64.to_radians() + 1e-9,
                "{w:?}"
            );
            // A turn in place or a straight step along the heading, never both.
            assert!(d == 0.0 || t == 0.0, "{w:?}");
            if d > 0.0 {
                let along = (w[1].y - w[0].y).atan2(w[1].x - w[0].x);
                assert!(wrap(along - w[0].th).abs() < 1e-12, "{w:?}");
            }
        }
        let last = truth.last().unwrap();
        assert_eq!((last.x, last.y), (1.0, 1.0));
        for p in &config.route_m {
            let visits = truth.iter().filter(|q| (q.x, q.y) == (p[0], p[1])).count();
            // Each waypoint is reached each lap (and turned at: one pose per turn update).
            assert!(visits >= 2, "{p:?} {visits}");
        }
        // 7 m a lap at 0.1 m per update is 70 drive updates; 3 turns of 90° at 30° per
        // update in the first lap, 4 in the second (the first waypoint's too).
        assert_eq!(truth.len(), 1 + 2 * 70 + 7 * 3);
    }

    /// The carry starts where the last lap starts (the first waypoint) and lands on the
    /// middle waypoint; nothing else changes.
    #[test]
    fn the_kidnap_cuts_the_last_laps_first_half() {
        let config = square(2);
        let truth = poses(&config, 1.0);
        let (cut, j) = kidnap(&truth, &config).unwrap();
        let before = cut[j - 1];
        assert_eq!((before.x, before.y), (1.0, 1.0));
        assert_eq!((cut[j].x, cut[j].y), (3.0, 2.5));
        assert_eq!(&cut[..j], &truth[..j]);
        // The second lap's first half (two legs of 20 and 15 steps, one turn of 3) is gone.
        assert_eq!(truth.len() - cut.len(), 3 + 20 + 3 + 15 - 1);
        assert_eq!(cut.last(), truth.last());
        assert!(kidnap(&poses(&square(1), 1.0), &square(1)).is_none());
        // Lap 1: 70 steps and three turns of 3; lap 2 turns at the start too.
        assert_eq!(lap_ends(&truth, &config), vec![79, 161]);
    }

    #[test]
    fn noise_free_odometry_dead_reckons_the_truth_and_noise_follows_the_seed() {
        let config = square(1);
        let truth = poses(&config, 0.5);
        let exact = BaseOdometryNoise {
            enabled: false,
            ..BaseOdometryNoise::default()
        };
        let reckoned = dead_reckon(truth[0], &odometry(&truth, &exact, 0));
        for (r, t) in reckoned.iter().zip(&truth) {
            assert!((r.x - t.x).abs() < 1e-9 && (r.y - t.y).abs() < 1e-9);
            assert!(wrap(r.th - t.th).abs() < 1e-9);
        }
        let noisy = BaseOdometryNoise::default();
        let a = odometry(&truth, &noisy, 3);
        assert_eq!(a, odometry(&truth, &noisy, 3));
        assert_ne!(a, odometry(&truth, &noisy, 4));
        // After a lap the noisy dead reckoning has drifted from the start it returned to.
        let end = *dead_reckon(truth[0], &a).last().unwrap();
        assert!((end.x - 1.0).hypot(end.y - 1.0) > 1e-3, "{end:?}");
    }
}
