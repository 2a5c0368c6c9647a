//! Whisking control (thesis §2.2.2, §2.3.1, §3.2.2, §4.1.1): an open-loop cosine
//! protraction/retraction, optionally modulated by rapid cessation of protraction (RCP),
//! and shaped by the array's contact-triggered strategies ([`super::strategies`]).
//!
//! Open loop: θ(t) = θ_mid − A·cos(2π f t + φ), with θ_mid = (θ_r + θ_p)/2 and
//! A = (θ_p − θ_r)/2 — fully retracted (40°) at the start of each cycle, fully protracted
//! (140°) half way through (1 Hz by default, §2.2.2).
//!
//! RCP, two controllers:
//! - **retract** (§4.1.1, Ch 4–6): once the magnitude of the y deflection reaches a
//!   threshold while protracting, protraction stops at once and the whisker retracts from
//!   where it is, on a half-cosine that reaches the retraction limit at the end of the
//!   current cycle; the next cycle starts open-loop again.
//! - **amplitude** (§3.2.2, Ch 3): the desired trajectory is "perturbed by local feedback
//!   from the whisker deflection sensors": the perturbation P is the mean of the |y| in
//!   excess of the threshold over this cycle's samples in contact, and the stroke is scaled
//!   about the cycle's initial angle by g = max(0, 1 − gain · P / (saturation − threshold))
//!   — "an increase in perturbation resulted in a decrease of whisking amplitude, while
//!   keeping the initial whisking angle at the start of each cycle constant". P starts at
//!   the threshold's excess (≈ 0), so the command stays continuous; each cycle starts with
//!   g = 1. The thesis gives no gain; 1 (the default) stops the stroke when the mean
//!   reading in contact saturates.
//!
//! The threshold is either 20 × the standard deviation of the deflection during free
//! whisking (§3.2.2) or the sensor's saturation value (§4.1.1) — "reaches", not
//! "exceeds": a saturated reading equals the saturation value and never exceeds it.

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

/// §3.2.2's RCP: the stroke scaled by 1 − `gain` · P / (`saturation` − threshold).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmplitudeRcp {
    /// Dimensionless gain (1: the stroke stops when the mean reading in contact saturates).
    pub gain: f64,
    /// The sensor's saturation (counts).
    pub saturation: f64,
}

/// The amplitude controller's cycle: its index, its initial angle, and the samples in
/// contact so far (count, sum of |y| − threshold).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Perturbation {
    cycle: i64,
    start: f64,
    samples: u32,
    excess: f64,
}

/// A whisker's motor controller: the pattern, RCP if enabled, and the stroke shaping of
/// the array's strategies ([`super::strategies`]: spread reduction, contact-induced
/// asymmetry) if enabled.
#[derive(Debug, Clone, PartialEq)]
pub struct Controller {
    /// The open-loop pattern.
    pub pattern: WhiskingPattern,
    /// Contact threshold on |y| in ADC counts (None: contacts are not detected).
    pub contact_threshold: Option<f64>,
    /// Whether a contact stops protraction at once and retracts (RCP) — or, with
    /// `amplitude`, scales the stroke (§3.2.2).
    pub rcp: bool,
    /// §3.2.2's amplitude RCP instead of the retraction (None: retract).
    amplitude: Option<AmplitudeRcp>,
    perturbation: Option<Perturbation>,
    /// Stroke shaping (None: the open-loop cosine, bit for bit).
    shaping: Option<Shaping>,
    /// Active early retraction: (cycle, start time, start angle, target angle).
    retraction: Option<(i64, f64, f64, f64)>,
    last_command: f64,
    protracting: bool,
}

/// What the array's strategies did to a whisker's stroke at one sample (recorded with
/// the sensor streams, `docs/recording.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ControlState {
    /// RCP: retracting early after a contact (§3.2.2).
    pub rcp: bool,
    /// Spread reduction engaged: the stroke's limits are the narrowed ones.
    pub narrowed: bool,
    /// Contact-induced asymmetry: protraction held after a contact on this side.
    pub held: bool,
}

/// A stroke made of half-cosines, each from where the command was when the half-cycle
/// began to that half's target: the protraction half to the (possibly narrowed)
/// protraction limit, the retraction half to the (possibly narrowed) retraction limit.
/// With the pattern's own limits throughout it is the open-loop cosine.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Shaping {
    /// The narrowed (retracted, protracted) limits of spread reduction.
    narrowed_limits: (f64, f64),
    /// Whether the next half-cycle takes the narrowed limits.
    narrowed: bool,
    /// The current half-cycle: (cycle, retracting).
    half: (i64, bool),
    /// This half's start and target angles.
    from: f64,
    to: f64,
    /// A protraction hold (contact-induced asymmetry) until the cycle's retraction half.
    hold: Option<f64>,
}

impl Shaping {
    /// The target of a half-cycle.
    fn target(&self, pattern: &WhiskingPattern, retracting: bool) -> f64 {
        match (retracting, self.narrowed) {
            (true, true) => self.narrowed_limits.0,
            (true, false) => pattern.retracted,
            (false, true) => self.narrowed_limits.1,
            (false, false) => pattern.protracted,
        }
    }

    /// The shaped stroke at time `t` of cycle `k`; `rcp_end` is where an RCP retraction
    /// that has just ended with its cycle left the whisker.
    fn angle(&mut self, pattern: &WhiskingPattern, t: f64, k: i64, rcp_end: Option<f64>) -> f64 {
        let u = (pattern.frequency * t + pattern.phase / TAU - k as f64).clamp(0.0, 1.0);
        let retracting = u >= 0.5;
        if (k, retracting) != self.half {
            // Each half starts where the last one ended: its target (or its hold), or
            // where RCP left the whisker. The first half-cycle of all starts from the
            // pattern's own limit (the command so far is the open-loop one).
            self.from = match (rcp_end, self.hold) {
                _ if self.half.0 == i64::MIN => {
                    if retracting {
                        pattern.protracted
                    } else {
                        pattern.retracted
                    }
                }
                (Some(end), _) => end,
                (None, Some(h)) if !self.half.1 => self.to.min(h),
                (None, _) => self.to,
            };
            self.half = (k, retracting);
            self.to = self.target(pattern, retracting);
            if !retracting {
                self.hold = None;
            }
        }
        let s = if retracting { 2.0 * u - 1.0 } else { 2.0 * u };
        let a = self.from + (self.to - self.from) * (1.0 - (PI * s).cos()) / 2.0;
        match self.hold {
            Some(h) if !retracting => a.min(h),
            _ => a,
        }
    }
}

impl Controller {
    /// A controller for `pattern` detecting contacts at `contact_threshold` counts (if
    /// given), with RCP if `rcp`.
    pub fn new(pattern: WhiskingPattern, contact_threshold: Option<f64>, rcp: bool) -> Self {
        Self {
            pattern,
            contact_threshold,
            rcp,
            amplitude: None,
            perturbation: None,
            shaping: None,
            retraction: None,
            last_command: pattern.angle(0.0),
            protracting: true,
        }
    }

    /// The same controller with its stroke shaped by the array's strategies, spread
    /// reduction narrowing it to `narrowed_limits` (retracted, protracted; rad) when
    /// engaged.
    pub fn shaped(mut self, narrowed_limits: (f64, f64)) -> Self {
        self.shaping = Some(Shaping {
            narrowed_limits,
            narrowed: false,
            half: (i64::MIN, false),
            from: self.pattern.retracted,
            to: self.pattern.protracted,
            hold: None,
        });
        self
    }

    /// The same controller with §3.2.2's amplitude RCP instead of the retraction (when
    /// `rcp` is on).
    pub fn with_amplitude(mut self, amplitude: AmplitudeRcp) -> Self {
        self.amplitude = Some(amplitude);
        self
    }

    /// The amplitude RCP's stroke gain this cycle so far (1: unperturbed).
    pub fn amplitude_gain(&self) -> f64 {
        match (self.amplitude, self.perturbation, self.contact_threshold) {
            (Some(a), Some(p), Some(t)) if p.samples > 0 => {
                let mean = p.excess / f64::from(p.samples);
                (1.0 - a.gain * mean / (a.saturation - t).max(f64::MIN_POSITIVE)).max(0.0)
            }
            _ => 1.0,
        }
    }

    /// Whether an early retraction is under way.
    pub fn retracting_early(&self) -> bool {
        self.retraction.is_some()
    }

    /// Whether reading `y` (counts) is a contact: |y| reaches the contact threshold.
    pub fn in_contact(&self, y: f64) -> bool {
        self.contact_threshold.is_some_and(|t| y.abs() >= t)
    }

    /// Whether the last command was on a protraction stroke.
    pub fn protracting(&self) -> bool {
        self.protracting
    }

    /// The strategies' state after the last command.
    pub fn state(&self) -> ControlState {
        ControlState {
            rcp: self.retraction.is_some() || self.amplitude_gain() < 1.0,
            narrowed: self.shaping.is_some_and(|s| s.narrowed),
            held: self.shaping.is_some_and(|s| s.hold.is_some() && !s.half.1),
        }
    }

    /// Spread reduction: whether the half-cycles from the next one on take the narrowed
    /// limits (no effect on an unshaped controller).
    pub fn set_narrowed(&mut self, narrowed: bool) {
        if let Some(s) = &mut self.shaping {
            s.narrowed = narrowed;
        }
    }

    /// Contact-induced asymmetry: stop protracting where the whisker is now, until the
    /// cycle's retraction half (no effect while retracting, when already held, or on an
    /// unshaped controller).
    pub fn hold(&mut self) {
        let last = self.last_command;
        if let Some(s) = &mut self.shaping
            && !s.half.1
            && s.hold.is_none()
        {
            s.hold = Some(last);
        }
    }

    /// The commanded angle at time `t` (s), given the latest y deflection reading
    /// (counts). Call once per sample, in time order.
    pub fn command(&mut self, t: f64, y: f64) -> f64 {
        let k = self.pattern.cycle(t);
        let rcp_end = self
            .retraction
            .filter(|&(cycle, ..)| cycle != k)
            .map(|(.., target)| target);
        if rcp_end.is_some() {
            self.retraction = None;
        }
        let (stroke, protracting) = match &mut self.shaping {
            None => {
                let open = self.pattern.angle(t);
                (open, open > self.last_command)
            }
            Some(s) => {
                let a = s.angle(&self.pattern, t, k, rcp_end);
                (a, !s.half.1)
            }
        };
        if let (true, Some(_)) = (self.rcp, self.amplitude) {
            let angle = self.scaled(k, stroke, y);
            self.protracting = protracting;
            self.last_command = angle;
            return angle;
        }
        if self.rcp && self.retraction.is_none() && protracting && self.in_contact(y) {
            // Back to the retraction limit by the cycle's end: the pattern's, or the
            // narrowed one of spread reduction (never forwards).
            let target = match &self.shaping {
                None => self.pattern.retracted,
                Some(s) => s.target(&self.pattern, true).min(self.last_command),
            };
            self.retraction = Some((k, t, self.last_command, target));
        }
        let angle = match self.retraction {
            Some((cycle, t0, a0, r)) => {
                let end = self.pattern.cycle_end(cycle);
                let s = ((t - t0) / (end - t0)).clamp(0.0, 1.0);
                r + (a0 - r) * (1.0 + (PI * s).cos()) / 2.0
            }
            None => stroke,
        };
        self.protracting = protracting && self.retraction.is_none();
        self.last_command = angle;
        angle
    }
}

impl Controller {
    /// §3.2.2: `stroke` at cycle `k` scaled about the cycle's initial angle by the gain of
    /// this cycle's contacts, `y` counted first.
    fn scaled(&mut self, k: i64, stroke: f64, y: f64) -> f64 {
        let p = match self.perturbation {
            Some(p) if p.cycle == k => p,
            _ => Perturbation {
                cycle: k,
                start: stroke,
                samples: 0,
                excess: 0.0,
            },
        };
        self.perturbation = Some(p);
        if let (true, Some(t)) = (self.in_contact(y), self.contact_threshold) {
            let q = self.perturbation.as_mut().expect("set");
            q.samples += 1;
            q.excess += y.abs() - t;
        }
        p.start + (stroke - p.start) * self.amplitude_gain()
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

    /// §3.2.2: pressed from 0.1 s of a cycle on at a steady reading Y, the stroke's peak
    /// excursion falls to (1 − (Y − T)/(S − T)) of the open loop's — in proportion to the
    /// mean deflection in excess of the threshold — while the cycle starts and ends at the
    /// same initial angle; a cycle without contact is the open loop, bit for bit.
    #[test]
    fn amplitude_rcp_scales_the_stroke_by_the_mean_deflection() {
        let p = WhiskingPattern::default();
        let (t, s) = (40.0, 2047.0);
        let dt = 1.0 / 2000.0;
        let full = p.protracted - p.retracted;
        let mut peaks = Vec::new();
        for y_contact in [200.0, 600.0, 1000.0] {
            let mut c = Controller::new(p, Some(t), true).with_amplitude(AmplitudeRcp {
                gain: 1.0,
                saturation: s,
            });
            let mut trace = Vec::new();
            for i in 0..4000 {
                let time = i as f64 * dt;
                let y = if (0.1..1.0).contains(&time) {
                    y_contact
                } else {
                    0.0
                };
                trace.push(c.command(time, y));
                if (0.2..0.9).contains(&time) {
                    assert!(c.state().rcp);
                }
            }
            assert_eq!(trace[0], p.angle(0.0));
            assert!((trace[1999] - p.retracted).abs() < 1e-4, "{}", trace[1999]);
            let peak = trace[..2000].iter().cloned().fold(f64::MIN, f64::max) - p.retracted;
            let expected = full * (1.0 - (y_contact - t) / (s - t));
            assert!((peak - expected).abs() < 1e-6, "{peak} vs {expected}");
            // The second cycle touches nothing: the open loop exactly.
            for (i, &a) in trace.iter().enumerate().skip(2000) {
                assert_eq!(a, p.angle(i as f64 * dt), "sample {i}");
            }
            peaks.push(peak);
        }
        // The amplitude lost grows in proportion to the excess: (Y − T) 160, 560, 960.
        let lost: Vec<f64> = peaks.iter().map(|pk| full - pk).collect();
        assert!((lost[1] / lost[0] - 560.0 / 160.0).abs() < 1e-9);
        assert!((lost[2] / lost[0] - 960.0 / 160.0).abs() < 1e-9);
        // Without contact at all the controller is the open loop.
        let mut c = Controller::new(p, Some(t), true).with_amplitude(AmplitudeRcp {
            gain: 1.0,
            saturation: s,
        });
        for i in 0..2000 {
            let time = i as f64 * dt;
            assert_eq!(c.command(time, 30.0), p.angle(time));
            assert!(!c.state().rcp);
        }
    }

    #[test]
    fn rcp_stops_protraction_and_retracts_by_the_end_of_the_cycle() {
        let p = WhiskingPattern::default();
        let mut c = Controller::new(p, Some(40.0), true);
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
