//! The contact-triggered whisking strategies of rats (thesis §2.3.1, after Grant et al.
//! 2009 and Mitchinson et al. 2007) for the whole array: rapid cessation of protraction
//! (RCP, per whisker, [`super::control`]), spread reduction (SR) and contact-induced
//! asymmetry (CIA), which couple the whiskers.
//!
//! A contact is a reading whose |y| reaches the whisker's contact threshold — the RCP
//! threshold of §3.2.2 (20 × the free-whisking σ) or §4.1.1 (saturation) — or, in the
//! kinematic sweep, a detected anticipated contact.
//!
//! **Spread reduction** (§2.3.1: "the range between protraction and retraction is
//! reduced ... the whiskers' mean position is shifted in the rostral direction and the
//! whisking range is concentrated to an area closer to the protraction limit"): after a
//! contact anywhere on the array, every whisker's stroke narrows to `range_fraction` of
//! its amplitude about a centre moved `centre_shift` towards protraction; the full
//! stroke returns after `release_cycles` whole cycles without a contact. The change
//! takes effect at the next half-cycle (a contact while protracting: the retraction that
//! follows already stops at the narrowed retraction limit), each half-cycle a
//! half-cosine from where the whisker is, so the command stays continuous. Neither the
//! thesis nor Grant et al. give the amounts for this array; the defaults are chosen:
//! half the range (100° → 50°; rats' "foveal" whisking narrows a ~70° stroke to ~20°)
//! and a 20° shift (40°–140° → 85°–135°: both limits move in, the centre from 90° to
//! 110°), released after 2 quiet cycles (asymmetric whisking lasts one to three cycles).
//!
//! **Contact-induced asymmetry** (§2.3.1; Mitchinson et al. 2007: "reduced protraction
//! on the side ipsilateral to an obstruction ... in the same whisk cycle as the initial
//! contact"): the array's two sides are its halves either side of the array frame's
//! x–z plane — columns A–C (azimuths 30°–150°, +y) and D–F (210°–330°, −y). A contact on
//! one side while it protracts stops the protraction of every whisker on that side where
//! it is, until the cycle's retraction; the other side continues its stroke (the
//! increased contralateral protraction of the rat is not modelled: the stroke already
//! reaches the motors' protraction limit, Fig 2.8). With RCP as well, the touching
//! whisker itself retracts while its side holds.

use super::control::{AmplitudeRcp, Controller, WhiskingPattern};
use whisker_slam::invalid::Invalid;

/// Spread reduction's parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpreadReduction {
    /// Fraction of the stroke's amplitude kept while engaged (0–1].
    pub range_fraction: f64,
    /// How far the stroke's centre moves towards protraction while engaged (rad, ≥ 0).
    pub centre_shift: f64,
    /// Whole whisk cycles without a contact before the full stroke returns (≥ 1).
    pub release_cycles: u32,
}

impl Default for SpreadReduction {
    /// Half the range, 20° towards protraction, released after 2 quiet cycles.
    fn default() -> Self {
        Self {
            range_fraction: 0.5,
            centre_shift: 20f64.to_radians(),
            release_cycles: 2,
        }
    }
}

impl SpreadReduction {
    /// The narrowed (retracted, protracted) limits of `pattern`.
    pub fn limits(&self, pattern: &WhiskingPattern) -> (f64, f64) {
        let centre = (pattern.retracted + pattern.protracted) / 2.0 + self.centre_shift;
        let half = (pattern.protracted - pattern.retracted) / 2.0 * self.range_fraction;
        (centre - half, centre + half)
    }

    /// Checks the parameters against `pattern`: the narrowed stroke must lie within the
    /// pattern's limits (the motors' range). The error names the parameter.
    pub fn check(&self, pattern: &WhiskingPattern) -> Result<(), Invalid> {
        if !(self.range_fraction > 0.0 && self.range_fraction <= 1.0) {
            return Err((
                "range_fraction",
                format!("expected 0 < fraction ≤ 1, got {}", self.range_fraction),
            )
                .into());
        }
        if !(self.centre_shift.is_finite() && self.centre_shift >= 0.0) {
            return Err((
                "centre_shift_deg",
                format!(
                    "expected a finite angle ≥ 0, got {}",
                    self.centre_shift.to_degrees()
                ),
            )
                .into());
        }
        if self.release_cycles == 0 {
            return Err(("release_cycles", "expected at least 1".into()).into());
        }
        let (lo, hi) = self.limits(pattern);
        if hi > pattern.protracted + 1e-12 {
            let room = (pattern.protracted - pattern.retracted) / 2.0 * (1.0 - self.range_fraction);
            return Err((
                "centre_shift_deg",
                format!(
                    "the narrowed stroke {:.1}°–{:.1}° passes the protraction limit {:.1}°: \
                     with range_fraction {} the shift can be at most {:.1}°",
                    lo.to_degrees(),
                    hi.to_degrees(),
                    pattern.protracted.to_degrees(),
                    self.range_fraction,
                    room.to_degrees()
                ),
            )
                .into());
        }
        Ok(())
    }
}

/// Which strategies drive the array's whisking beyond the open-loop stroke.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WhiskingControl {
    /// RCP (per whisker).
    pub rcp: bool,
    /// RCP scales the stroke (§3.2.2) instead of retracting (§4.1.1) (None: retract).
    pub rcp_amplitude: Option<AmplitudeRcp>,
    /// Spread reduction, if enabled.
    pub spread_reduction: Option<SpreadReduction>,
    /// Contact-induced asymmetry.
    pub asymmetry: bool,
}

impl WhiskingControl {
    /// Whether a strategy couples the whiskers (SR or CIA): the array's whiskers then
    /// step together, each sample's contacts reaching every controller.
    pub fn couples(&self) -> bool {
        self.spread_reduction.is_some() || self.asymmetry
    }

    /// A short name: `open-loop`, or the strategies joined by `+` (`rcp+sr+cia`).
    pub fn name(&self) -> String {
        let parts: Vec<&str> = [
            (self.rcp && self.rcp_amplitude.is_none(), "rcp"),
            (self.rcp && self.rcp_amplitude.is_some(), "rcp-amplitude"),
            (self.spread_reduction.is_some(), "sr"),
            (self.asymmetry, "cia"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| *n)
        .collect();
        if parts.is_empty() {
            "open-loop".into()
        } else {
            parts.join("+")
        }
    }

    /// A controller of `pattern` under these strategies.
    pub fn controller(
        &self,
        pattern: WhiskingPattern,
        contact_threshold: Option<f64>,
    ) -> Controller {
        let mut c = Controller::new(pattern, contact_threshold, self.rcp);
        if let Some(a) = self.rcp_amplitude {
            c = c.with_amplitude(a);
        }
        match (self.couples(), self.spread_reduction) {
            (false, _) => c,
            (true, Some(sr)) => c.shaped(sr.limits(&pattern)),
            (true, None) => c.shaped((pattern.retracted, pattern.protracted)),
        }
    }
}

/// The array's side of a whisker in column `column` (0–5): 0 for A–C, 1 for D–F.
pub fn side(column: usize) -> usize {
    usize::from(column >= 3)
}

/// Spread reduction's state: engaged or not, and the quiet cycles counted since the last
/// contact.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SpreadState {
    /// Whether the narrowed stroke is in force.
    pub engaged: bool,
    quiet: u32,
    touched: bool,
}

impl SpreadState {
    /// A contact: engage, restart the count.
    pub fn contact(&mut self) {
        self.engaged = true;
        self.quiet = 0;
        self.touched = true;
    }

    /// A whisk cycle ended: one more quiet cycle if it had no contact, released after
    /// `release` of them.
    pub fn end_cycle(&mut self, release: u32) {
        if !self.touched {
            self.quiet = self.quiet.saturating_add(1);
            if self.quiet >= release {
                self.engaged = false;
            }
        }
        self.touched = false;
    }
}

/// The coupling strategies of a physics array: sees every whisker's contact after each
/// sample and sets their controllers for the next.
#[derive(Debug, Clone)]
pub struct ArrayController {
    control: WhiskingControl,
    /// Each whisker's side.
    sides: Vec<usize>,
    /// The pattern whose cycles count spread reduction's quiet cycles (the first
    /// whisker's; the array's whiskers share a frequency by default), and the sample
    /// period (a cycle is over when the next sample lies in the next one).
    clock: WhiskingPattern,
    dt: f64,
    cycle: i64,
    spread: SpreadState,
}

impl ArrayController {
    /// The strategies `control` over whiskers in `columns` (their array columns), cycles
    /// counted on `clock`, samples `dt` (s) apart.
    pub fn new(
        control: WhiskingControl,
        columns: &[usize],
        clock: WhiskingPattern,
        dt: f64,
    ) -> Self {
        Self {
            control,
            sides: columns.iter().map(|&c| side(c)).collect(),
            clock,
            dt,
            cycle: clock.cycle(0.0),
            spread: SpreadState::default(),
        }
    }

    /// After the sample of time `t` (s): `contacts[i]` whether whisker i read a contact;
    /// sets every controller for the next sample.
    pub fn update(&mut self, t: f64, contacts: &[bool], controllers: &mut [&mut Controller]) {
        // The cycle the next sample lies in: cycles before it are over.
        let next = self.clock.cycle(t + self.dt);
        if let Some(sr) = self.control.spread_reduction {
            if contacts.iter().any(|&c| c) {
                self.spread.contact();
            }
            for _ in self.cycle..next {
                self.spread.end_cycle(sr.release_cycles);
            }
            for c in controllers.iter_mut() {
                c.set_narrowed(self.spread.engaged);
            }
        }
        self.cycle = self.cycle.max(next);
        if self.control.asymmetry {
            for side in 0..2 {
                let touched = contacts
                    .iter()
                    .zip(controllers.iter())
                    .zip(&self.sides)
                    .any(|((&hit, c), &s)| s == side && hit && c.protracting());
                if touched {
                    for (c, _) in controllers
                        .iter_mut()
                        .zip(&self.sides)
                        .filter(|(_, s)| **s == side)
                    {
                        c.hold();
                    }
                }
            }
        }
    }

    /// Whether spread reduction is engaged.
    pub fn narrowed(&self) -> bool {
        self.spread.engaged
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 1.0 / 2000.0;

    /// Runs `n` controllers of the default pattern under `control` for `seconds`,
    /// `contact(i, t)` saying whether whisker i (columns `columns`) reads a contact at t;
    /// each whisker's commands.
    fn run(
        control: WhiskingControl,
        columns: &[usize],
        seconds: f64,
        contact: impl Fn(usize, f64) -> bool,
    ) -> Vec<Vec<f64>> {
        let p = WhiskingPattern::default();
        let mut cs: Vec<Controller> = columns
            .iter()
            .map(|_| control.controller(p, Some(10.0)))
            .collect();
        let mut array = ArrayController::new(control, columns, p, DT);
        let mut out = vec![Vec::new(); columns.len()];
        let mut ys = vec![0.0; columns.len()];
        for k in 1..=(seconds / DT).round() as usize {
            let t = k as f64 * DT;
            for (i, c) in cs.iter_mut().enumerate() {
                out[i].push(c.command(t, ys[i]));
            }
            let hits: Vec<bool> = (0..columns.len()).map(|i| contact(i, t)).collect();
            for (y, &h) in ys.iter_mut().zip(&hits) {
                *y = if h { 100.0 } else { 0.0 };
            }
            let mut refs: Vec<&mut Controller> = cs.iter_mut().collect();
            array.update(t, &hits, &mut refs);
        }
        out
    }

    /// Min and max of `trace` over seconds [a, b).
    fn range(trace: &[f64], a: f64, b: f64) -> (f64, f64) {
        let (i, j) = ((a / DT).round() as usize, (b / DT).round() as usize);
        trace[i..j]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }

    #[test]
    fn spread_reduction_narrows_both_limits_moves_the_centre_and_releases() {
        let sr = SpreadReduction {
            range_fraction: 0.4,
            centre_shift: 15f64.to_radians(),
            release_cycles: 2,
        };
        let control = WhiskingControl {
            spread_reduction: Some(sr),
            ..Default::default()
        };
        // Contacts 0.3–0.32 s (cycle 0) and 1.3–1.32 s (cycle 1), none after.
        let trace = &run(control, &[0], 8.0, |_, t| {
            (0.3..0.32).contains(&t) || (1.3..1.32).contains(&t)
        })[0];
        let deg = f64::to_radians;
        // By hand: centre 90° + 15° = 105°, half range 50° × 0.4 = 20°: 85°–125°.
        let (lo, hi) = (deg(85.0), deg(125.0));
        // Cycle 0 protracts fully, then retracts to the narrowed limit.
        let (a, b) = range(trace, 0.0, 0.5);
        assert!((b - deg(140.0)).abs() < 1e-6 && a < deg(41.0), "{a} {b}");
        assert!(
            (trace[1999] - lo).abs() < 1e-4,
            "{}",
            trace[1999].to_degrees()
        );
        // Cycles 1–3 (engaged until two quiet cycles, 2 and 3, have passed) span the
        // narrowed stroke: both limits moved in, the centre 15° towards protraction.
        for c in 1..4 {
            let (a, b) = range(trace, c as f64, c as f64 + 1.0);
            assert!(
                (a - lo).abs() < 1e-4 && (b - hi).abs() < 1e-4,
                "cycle {c}: {a} {b}"
            );
            assert!(((a + b) / 2.0 - deg(105.0)).abs() < 1e-4);
        }
        // Released at the end of cycle 3: cycle 4 protracts to 140° from 85°, retracts
        // to 40°; cycle 5 is the open-loop stroke again.
        let (a, b) = range(trace, 4.0, 4.5);
        assert!(
            (b - deg(140.0)).abs() < 1e-6 && (a - lo).abs() < 1e-4,
            "{a} {b}"
        );
        assert!((trace[9999] - deg(40.0)).abs() < 1e-4);
        let p = WhiskingPattern::default();
        for (k, a) in trace.iter().enumerate().skip(5 * 2000).take(2000) {
            let t = (k + 1) as f64 * DT;
            assert!((a - p.angle(t)).abs() < 1e-9, "{t}");
        }
        // Continuous throughout: no step larger than the open loop's largest.
        let max_step = trace
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        assert!(
            max_step <= deg(50.0) * std::f64::consts::TAU * DT * 1.0001,
            "{max_step}"
        );
    }

    #[test]
    fn without_contacts_the_shaped_stroke_is_the_open_loop_one() {
        let control = WhiskingControl {
            rcp: true,
            rcp_amplitude: None,
            spread_reduction: Some(SpreadReduction::default()),
            asymmetry: true,
        };
        let traces = run(control, &[0, 4], 3.0, |_, _| false);
        let p = WhiskingPattern::default();
        for trace in traces {
            for (k, a) in trace.iter().enumerate() {
                assert!((a - p.angle((k + 1) as f64 * DT)).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn asymmetry_holds_the_touching_side_and_lets_the_other_protract() {
        let control = WhiskingControl {
            asymmetry: true,
            ..Default::default()
        };
        // Whiskers in columns A, C (side 0) and D, F (side 1); A touches at 0.25 s.
        let columns = [0, 2, 3, 5];
        let traces = run(control, &columns, 2.0, |i, t| {
            i == 0 && (0.25..0.27).contains(&t)
        });
        let p = WhiskingPattern::default();
        // The command of the sample whose reading was the first contact.
        let first = (1..)
            .find(|k| (0.25..0.27).contains(&(*k as f64 * DT)))
            .unwrap();
        let at_contact = traces[0][first - 1];
        assert!((at_contact - p.angle(first as f64 * DT)).abs() < 1e-9);
        for (i, trace) in traces.iter().enumerate() {
            let (_, top) = range(trace, 0.0, 0.5);
            // Columns A and C are one side, D and F the other (as documented).
            if columns[i] < 3 {
                // Held where the contact was read, not protracting.
                assert!((top - at_contact).abs() < 1e-9, "whisker {i}: {top}");
                assert!(trace[600..1000].iter().all(|&a| (a - top).abs() < 1e-9));
            } else {
                assert!((top - p.protracted).abs() < 1e-9, "whisker {i}: {top}");
            }
            // Every whisker retracts to the limit and whisks open loop in cycle 1.
            assert!((trace[1999] - p.retracted).abs() < 1e-9);
            let (a, b) = range(trace, 1.0, 2.0);
            assert!((a - p.retracted).abs() < 1e-6 && (b - p.protracted).abs() < 1e-6);
        }
        // With RCP too, the touching whisker retracts while its side-mate holds.
        let both = WhiskingControl {
            rcp: true,
            asymmetry: true,
            ..Default::default()
        };
        let traces = run(both, &columns, 1.0, |i, t| {
            i == 0 && (0.25..0.27).contains(&t)
        });
        // At 0.45 s RCP has brought the touching whisker 8° back (its half-cosine
        // reaches 40° at 1 s).
        assert!(traces[0][899] < at_contact - 0.1, "RCP retracts");
        assert!(
            (traces[1][899] - at_contact).abs() < 1e-9,
            "side-mate holds"
        );
        assert!(
            (traces[2][999] - p.protracted).abs() < 1e-6,
            "other side protracts"
        );
    }

    #[test]
    fn narrowed_strokes_outside_the_motors_range_are_refused() {
        let p = WhiskingPattern::default();
        let sr = SpreadReduction {
            range_fraction: 0.5,
            centre_shift: 30f64.to_radians(),
            release_cycles: 1,
        };
        let e = sr.check(&p).unwrap_err();
        assert_eq!(e.field, "centre_shift_deg");
        assert!(e.message.contains("at most 25.0°"), "{e}");
        let ok = SpreadReduction {
            centre_shift: 25f64.to_radians(),
            ..sr
        };
        assert!(ok.check(&p).is_ok());
        assert_eq!(
            SpreadReduction {
                range_fraction: 0.0,
                ..ok
            }
            .check(&p)
            .unwrap_err()
            .field,
            "range_fraction"
        );
        assert_eq!(
            SpreadReduction {
                release_cycles: 0,
                ..ok
            }
            .check(&p)
            .unwrap_err()
            .field,
            "release_cycles"
        );
    }
}
