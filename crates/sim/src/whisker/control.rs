//! Whisking control (thesis §2.2.2, §2.3.1, §3.2.2, §4.1.1): an open-loop cosine
//! protraction/retraction, optionally modulated by rapid cessation of protraction (RCP).
//!
//! Open loop: θ(t) = θ_mid − A·cos(2π f t + φ), with θ_mid = (θ_r + θ_p)/2 and
//! A = (θ_p − θ_r)/2 — fully retracted (40°) at the start of each cycle, fully protracted
//! (140°) half way through (1 Hz by default, §2.2.2).
//!
//! RCP: once the magnitude of the y deflection reaches a threshold while protracting,
//! protraction stops at once and the whisker retracts from where it is, on a half-cosine
//! that reaches the retraction limit at the end of the current cycle; the next cycle
//! starts open-loop again. The threshold is either 20 × the standard deviation of the
//! deflection during free whisking (§3.2.2) or the sensor's saturation value (§4.1.1) —
//! "reaches", not "exceeds": a saturated reading equals the saturation value and never
//! exceeds it.

use std::f64::consts::{PI, TAU};

/// How the RCP threshold is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RcpThreshold {
    /// A multiple of the free-whisking deflection noise's standard deviation (§3.2.2: 20).
    NoiseMultiple(f64),
    /// The sensor's maximum detectable deflection (§4.1.1).
    Saturation,
}

/// A whisker's whisking pattern.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WhiskingPattern {
    /// Fully retracted angle (rad).
    pub retracted: f64,
    /// Fully protracted angle (rad).
    pub protracted: f64,
    /// Whisking frequency (Hz).
    pub frequency: f64,
    /// Phase (rad).
    pub phase: f64,
}

impl Default for WhiskingPattern {
    /// 40°–140° at 1 Hz, phase 0 (§2.2.2).
    fn default() -> Self {
        Self {
            retracted: super::array::RETRACTED,
            protracted: super::array::PROTRACTED,
            frequency: 1.0,
            phase: 0.0,
        }
    }
}

impl WhiskingPattern {
    /// Open-loop angle at time `t` (s).
    pub fn angle(&self, t: f64) -> f64 {
        let mid = (self.retracted + self.protracted) / 2.0;
        let amp = (self.protracted - self.retracted) / 2.0;
        mid - amp * (TAU * self.frequency * t + self.phase).cos()
    }

    /// Time after a cycle's start at which open-loop protraction reaches `angle` (s),
    /// the inverse of [`WhiskingPattern::angle`] on the protraction half-cycle (angles
    /// outside the range are clamped to it).
    pub fn protraction_time(&self, angle: f64) -> f64 {
        let mid = (self.retracted + self.protracted) / 2.0;
        let amp = (self.protracted - self.retracted) / 2.0;
        ((mid - angle) / amp).clamp(-1.0, 1.0).acos() / (TAU * self.frequency)
    }

    /// Index of the whisk cycle that time `t` lies in (cycles start fully retracted).
    pub fn cycle(&self, t: f64) -> i64 {
        ((self.frequency * t + self.phase / TAU) + 1e-9).floor() as i64
    }

    /// Time at which cycle `k` ends (s).
    fn cycle_end(&self, k: i64) -> f64 {
        ((k + 1) as f64 - self.phase / TAU) / self.frequency
    }
}

/// A whisker's motor controller: the pattern, and RCP if enabled.
#[derive(Debug, Clone, PartialEq)]
pub struct Controller {
    /// The open-loop pattern.
    pub pattern: WhiskingPattern,
    /// RCP threshold on |y| in ADC counts (None: open loop).
    pub rcp_threshold: Option<f64>,
    /// Active early retraction: (cycle, start time, start angle).
    retraction: Option<(i64, f64, f64)>,
    last_command: f64,
}

impl Controller {
    /// A controller for `pattern`, with RCP at `rcp_threshold` counts if given.
    pub fn new(pattern: WhiskingPattern, rcp_threshold: Option<f64>) -> Self {
        Self {
            pattern,
            rcp_threshold,
            retraction: None,
            last_command: pattern.angle(0.0),
        }
    }

    /// Whether an early retraction is under way.
    pub fn retracting_early(&self) -> bool {
        self.retraction.is_some()
    }

    /// The commanded angle at time `t` (s), given the latest y deflection reading
    /// (counts). Call once per sample, in time order.
    pub fn command(&mut self, t: f64, y: f64) -> f64 {
        let k = self.pattern.cycle(t);
        if self.retraction.is_some_and(|(cycle, _, _)| cycle != k) {
            self.retraction = None;
        }
        let open = self.pattern.angle(t);
        if let (Some(threshold), None) = (self.rcp_threshold, self.retraction)
            && y.abs() >= threshold
            && open > self.last_command
        {
            self.retraction = Some((k, t, self.last_command));
        }
        let angle = match self.retraction {
            Some((cycle, t0, a0)) => {
                let end = self.pattern.cycle_end(cycle);
                let s = ((t - t0) / (end - t0)).clamp(0.0, 1.0);
                let r = self.pattern.retracted;
                r + (a0 - r) * (1.0 + (PI * s).cos()) / 2.0
            }
            None => open,
        };
        self.last_command = angle;
        angle
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_loop_spans_the_limits_once_per_cycle() {
        let p = WhiskingPattern::default();
        assert!((p.angle(0.0) - p.retracted).abs() < 1e-12);
        assert!((p.angle(0.5) - p.protracted).abs() < 1e-12);
        assert!((p.angle(1.0) - p.retracted).abs() < 1e-12);
        assert_eq!(p.cycle(0.0), 0);
        assert_eq!(p.cycle(0.999), 0);
        assert_eq!(p.cycle(1.0), 1);
    }

    #[test]
    fn rcp_stops_protraction_and_retracts_by_the_end_of_the_cycle() {
        let p = WhiskingPattern::default();
        let mut c = Controller::new(p, Some(40.0));
        let dt = 1.0 / 2000.0;
        let mut trace = Vec::new();
        for i in 0..4000 {
            let t = i as f64 * dt;
            // A contact from 0.3 s to 0.35 s in the first cycle only.
            let y = if (0.3..0.35).contains(&t) { 100.0 } else { 0.0 };
            trace.push(c.command(t, y));
        }
        let at = |t: f64| trace[(t / dt).round() as usize];
        // Protraction stops at the crossing: never above the angle at 0.3 s afterwards.
        let stop = at(0.3);
        assert!(trace[600..2000].iter().all(|&a| a <= stop + 1e-12));
        assert!(stop < p.protracted - 0.1);
        // Back at the retraction limit at the end of the cycle, then open loop again.
        assert!((trace[1999] - p.retracted).abs() < 1e-4);
        assert!((at(1.5) - p.protracted).abs() < 1e-12);
        // Monotonic retraction after the trigger.
        assert!(trace[601..2000].windows(2).all(|w| w[1] <= w[0] + 1e-12));
    }
}
