//! What a whisking strategy does to the array's contacts along a physics run (thesis
//! §2.3.1; Grant et al. 2009 suggest spread reduction makes the whiskers touch at about
//! the same time and bend less): per whisk cycle, which whiskers touched, when each first
//! touched, and how far each shaft bent — `summary.json`'s `whisking` block.
//!
//! A whisker touches in a cycle when its |y| reaches 20 × its free-whisking σ (the RCP
//! threshold of §3.2.2, calibrated for every physics run whatever the strategy, so that
//! every condition is measured alike). Cycles follow whisker A1's pattern (they start
//! fully retracted); the run's first cycle is not counted (every strategy whisks it open
//! loop: it is the one that finds the surface), nor is a cycle cut off by the end of the
//! run. Bending is the shaft's largest curvature (`Whisker::max_curvature`) over the
//! cycle.

use serde::Serialize;

/// One whisker's cycle so far: its first contact time (s after the cycle's start) and
/// its largest curvature (1/m).
#[derive(Debug, Clone, Copy, Default)]
struct WhiskerCycle {
    first_contact: Option<f64>,
    curvature: f64,
}

/// The metrics of a run (means over what they are measured on; null when nothing was).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct WhiskingSummary {
    /// Whisk cycles completed.
    pub whisks: usize,
    /// Whiskers touching per whisk.
    pub contacts_per_whisk: f64,
    /// Whiskers that touched at least once.
    pub whiskers_touching: usize,
    /// Time from the cycle's start to a whisker's first contact (s), over the (whisker,
    /// whisk) pairs with a contact.
    pub first_contact_s: Option<f64>,
    /// Spread of first-contact times across the array (s): the latest minus the earliest
    /// in a whisk, over whisks where at least two whiskers touched.
    pub contact_spread_s: Option<f64>,
    /// The same spread as a standard deviation (s).
    pub contact_spread_sd_s: Option<f64>,
    /// A touching whisker's largest shaft curvature in the whisk (1/m), over the (whisker,
    /// whisk) pairs with a contact.
    pub max_curvature_per_m: Option<f64>,
    /// The largest curvature of any shaft in the run (1/m).
    pub peak_curvature_per_m: f64,
}

impl WhiskingSummary {
    /// The console line: `whisking  1.50 whiskers touching per whisk (3 of 18), first
    /// contact 0.133 s into the whisk, spread 0.200 s, max curvature 3.3 /m`.
    pub fn line(&self) -> String {
        let s =
            |v: Option<f64>, unit: &str| v.map_or("–".to_string(), |x| format!("{x:.3} {unit}"));
        format!(
            "whisking   {:.2} whiskers touching per whisk over {} whisks ({} touched), first contact {} into the whisk, spread across the array {}, touching shafts' max curvature {} (summary.json: whisking)",
            self.contacts_per_whisk,
            self.whisks,
            self.whiskers_touching,
            s(self.first_contact_s, "s"),
            s(self.contact_spread_s, "s"),
            s(self.max_curvature_per_m, "/m"),
        )
    }
}

/// Accumulates the metrics sample by sample.
#[derive(Debug, Clone)]
pub struct WhiskingMetrics {
    /// Each whisker's contact threshold (counts).
    thresholds: Vec<f64>,
    cycle: Option<(i64, f64)>,
    past_first: bool,
    current: Vec<WhiskerCycle>,
    touched: Vec<bool>,
    whisks: usize,
    contacts: usize,
    first: Vec<f64>,
    spreads: Vec<(f64, f64)>,
    curvatures: Vec<f64>,
    peak: f64,
}

fn mean(v: impl IntoIterator<Item = f64>) -> Option<f64> {
    let (n, sum) = v
        .into_iter()
        .fold((0usize, 0.0), |(n, s), x| (n + 1, s + x));
    (n > 0).then(|| sum / n as f64)
}

impl WhiskingMetrics {
    /// Metrics for whiskers with contact thresholds `thresholds` (counts).
    pub fn new(thresholds: Vec<f64>) -> Self {
        let n = thresholds.len();
        Self {
            thresholds,
            cycle: None,
            past_first: false,
            current: vec![WhiskerCycle::default(); n],
            touched: vec![false; n],
            whisks: 0,
            contacts: 0,
            first: Vec::new(),
            spreads: Vec::new(),
            curvatures: Vec::new(),
            peak: 0.0,
        }
    }

    /// Takes the sample of time `t` (s) in whisk cycle `cycle`: each whisker's y
    /// deflection (counts) and shaft curvature (1/m).
    pub fn push(&mut self, t: f64, cycle: i64, y: &[f64], curvature: &[f64]) {
        match self.cycle {
            Some((k, _)) if k == cycle => {}
            Some(_) => {
                self.close();
                self.cycle = Some((cycle, t));
            }
            None => self.cycle = Some((cycle, t)),
        }
        let start = self.cycle.map_or(t, |(_, s)| s);
        for (w, c) in self.current.iter_mut().enumerate() {
            c.curvature = c.curvature.max(curvature[w]);
            if c.first_contact.is_none() && y[w].abs() >= self.thresholds[w] {
                c.first_contact = Some(t - start);
            }
        }
    }

    /// Closes the current cycle (the run's first is dropped).
    fn close(&mut self) {
        if !self.past_first {
            self.past_first = true;
            self.current
                .iter_mut()
                .for_each(|c| *c = WhiskerCycle::default());
            return;
        }
        let times: Vec<f64> = self
            .current
            .iter()
            .filter_map(|c| c.first_contact)
            .collect();
        self.whisks += 1;
        self.contacts += times.len();
        for (w, c) in self.current.iter().enumerate() {
            self.peak = self.peak.max(c.curvature);
            if let Some(t) = c.first_contact {
                self.first.push(t);
                self.curvatures.push(c.curvature);
                self.touched[w] = true;
            }
        }
        if times.len() >= 2 {
            let lo = times.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = times.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let m = times.iter().sum::<f64>() / times.len() as f64;
            let var = times.iter().map(|t| (t - m).powi(2)).sum::<f64>() / (times.len() - 1) as f64;
            self.spreads.push((hi - lo, var.sqrt()));
        }
        self.current
            .iter_mut()
            .for_each(|c| *c = WhiskerCycle::default());
    }

    /// The metrics of the cycles completed (the last one, cut off by the end of the run,
    /// is not: a run of whole cycles ends with the first sample of the next).
    pub fn summary(&self) -> WhiskingSummary {
        let m = self;
        WhiskingSummary {
            whisks: m.whisks,
            contacts_per_whisk: if m.whisks == 0 {
                0.0
            } else {
                m.contacts as f64 / m.whisks as f64
            },
            whiskers_touching: m.touched.iter().filter(|&&t| t).count(),
            first_contact_s: mean(m.first.iter().copied()),
            contact_spread_s: mean(m.spreads.iter().map(|s| s.0)),
            contact_spread_sd_s: mean(m.spreads.iter().map(|s| s.1)),
            max_curvature_per_m: mean(m.curvatures.iter().copied()),
            peak_curvature_per_m: m.peak,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_made_cycles_give_the_hand_computed_metrics() {
        // Three whiskers, threshold 10 counts; cycles of 4 samples 0.1 s apart, the
        // first (every whisker touching hard) not counted.
        let mut m = WhiskingMetrics::new(vec![10.0; 3]);
        for i in 0..4 {
            m.push(-0.4 + i as f64 * 0.1, -1, &[50.0; 3], &[99.0; 3]);
        }
        // Cycle 0: whisker 0 touches at its 2nd sample (0.1 s in), whisker 2 at its 4th
        // (0.3 s in), whisker 1 never; curvatures peak at 2, 1, 5.
        let ys0 = [
            [0.0, 0.0, 0.0],
            [12.0, 0.0, 0.0],
            [-30.0, 9.9, 0.0],
            [0.0, 0.0, 10.0],
        ];
        let k0 = [
            [0.5, 1.0, 0.0],
            [2.0, 0.5, 1.0],
            [1.0, 0.0, 5.0],
            [0.0, 0.0, 4.0],
        ];
        for (i, (y, k)) in ys0.iter().zip(&k0).enumerate() {
            m.push(i as f64 * 0.1, 0, y, k);
        }
        // Cycle 1: only whisker 1 touches, at its 1st sample; curvature 3.
        for i in 0..4 {
            let y = [0.0, if i == 0 { 50.0 } else { 0.0 }, 0.0];
            m.push(0.4 + i as f64 * 0.1, 1, &y, &[0.0, 3.0, 0.0]);
        }
        // Cycle 2 has begun (cut off): not counted.
        m.push(0.8, 2, &[99.0, 99.0, 99.0], &[9.0, 9.0, 9.0]);
        let s = m.summary();
        assert_eq!(s.whisks, 2);
        assert!((s.contacts_per_whisk - 1.5).abs() < 1e-12);
        assert_eq!(s.whiskers_touching, 3);
        // First contacts 0.1, 0.3 (cycle 0) and 0.0 (cycle 1): mean 0.4/3.
        assert!((s.first_contact_s.unwrap() - 0.4 / 3.0).abs() < 1e-12);
        // Only cycle 0 has two touching whiskers: spread 0.2 s, SD 0.2/√2.
        assert!((s.contact_spread_s.unwrap() - 0.2).abs() < 1e-12);
        assert!((s.contact_spread_sd_s.unwrap() - 0.2 / 2f64.sqrt()).abs() < 1e-12);
        // Curvatures of touching pairs: 2 (w0), 5 (w2), 3 (w1): mean 10/3; peak 5.
        assert!((s.max_curvature_per_m.unwrap() - 10.0 / 3.0).abs() < 1e-12);
        assert_eq!(s.peak_curvature_per_m, 5.0);
    }
}
