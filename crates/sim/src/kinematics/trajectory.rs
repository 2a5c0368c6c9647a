//! Joint-space trajectories through waypoints under a joint-speed limit.
//!
//! The thesis moved the arm with MoveIt at low joint speeds (0.1 rad/s for all joints,
//! §2.2.1). Here a segment between two joint-space waypoints is a straight line in joint
//! space, travelled at constant speed so that the joint with the largest excursion
//! (relative to its own limit) moves at exactly its limit and all joints arrive together.
//! Accelerations are not limited (the arm is position-controlled and slow). Each waypoint
//! can be held for a dwell time before the next segment starts.

/// A piecewise-linear joint trajectory: `knots[k]` is reached at `times[k]` (s).
#[derive(Debug, Clone, PartialEq)]
pub struct JointTrajectory {
    /// Knot times, non-decreasing, starting at 0.
    pub times: Vec<f64>,
    /// Joint positions at the knots.
    pub knots: Vec<Vec<f64>>,
}

impl JointTrajectory {
    /// Plans the path through `waypoints` (the first is the start) with per-joint speed
    /// limits `speed` (> 0), holding waypoint `k` for `holds[k]` seconds after reaching it.
    pub fn through(waypoints: &[Vec<f64>], holds: &[f64], speed: &[f64]) -> Self {
        assert!(!waypoints.is_empty(), "a trajectory needs a start");
        assert_eq!(holds.len(), waypoints.len(), "one hold per waypoint");
        let mut times = vec![0.0];
        let mut knots = vec![waypoints[0].clone()];
        let mut t = 0.0;
        for (k, w) in waypoints.iter().enumerate() {
            if k > 0 {
                let prev = &waypoints[k - 1];
                let duration = w
                    .iter()
                    .zip(prev)
                    .zip(speed)
                    .map(|((a, b), v)| (a - b).abs() / v)
                    .fold(0.0, f64::max);
                t += duration;
                times.push(t);
                knots.push(w.clone());
            }
            if holds[k] > 0.0 {
                t += holds[k];
                times.push(t);
                knots.push(w.clone());
            }
        }
        Self { times, knots }
    }

    /// Total duration (s).
    pub fn duration(&self) -> f64 {
        *self.times.last().expect("non-empty")
    }

    /// Joint positions at time `t` (clamped to the trajectory's span).
    pub fn sample(&self, t: f64) -> Vec<f64> {
        let k = self.times.partition_point(|&tk| tk <= t);
        if k == 0 {
            return self.knots[0].clone();
        }
        if k == self.times.len() {
            return self.knots[k - 1].clone();
        }
        let (t0, t1) = (self.times[k - 1], self.times[k]);
        let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
        self.knots[k - 1]
            .iter()
            .zip(&self.knots[k])
            .map(|(a, b)| a + s * (b - a))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speed_limit_is_met_and_reached_by_the_slowest_joint() {
        let w = vec![vec![0.0, 0.0], vec![1.0, -0.2], vec![1.0, 0.4]];
        let speed = [0.1, 0.05];
        let traj = JointTrajectory::through(&w, &[0.0, 2.0, 0.0], &speed);
        // Segment 1: joint 0 needs 10 s, joint 1 needs 4 s; hold 2 s; segment 2: 12 s.
        assert!((traj.duration() - 24.0).abs() < 1e-12);
        let dt = 0.01;
        let mut peak = [0.0f64; 2];
        let mut t = 0.0;
        while t < traj.duration() {
            let (a, b) = (traj.sample(t), traj.sample(t + dt));
            for j in 0..2 {
                let v = (b[j] - a[j]).abs() / dt;
                assert!(v <= speed[j] * (1.0 + 1e-9), "joint {j} at {v} rad/s");
                peak[j] = peak[j].max(v);
            }
            t += dt;
        }
        assert!((peak[0] - 0.1).abs() < 1e-9 && (peak[1] - 0.05).abs() < 1e-9);
        assert_eq!(traj.sample(10.0), w[1]);
        assert_eq!(traj.sample(11.5), w[1]);
        assert_eq!(traj.sample(1e9), w[2]);
        assert_eq!(traj.sample(-1.0), w[0]);
    }
}
