//! Object identification by appended object maps (thesis §5.2.2.2, Figs 5.16–5.17; §6.2).
//!
//! [`Identification`] is the §5.2 belief: each known object's belief is a leaky integrator
//! fed by re-localisations onto that object's experiences, with a fixed decay. Each whisk,
//! every belief decays by `decay`, and the object re-localised onto (if any) receives
//! `impulse`: c ← decay·c + impulse·[re-localised onto it]. With `impulse = 1 − decay`
//! ([`Identification::new`]) a belief is an exponential moving average of the
//! re-localisation rate, in [0, 1], with a time constant of 1/(1 − decay) whisks.
//!
//! [`Recognition`] is Chapter 6's decision on top of it (§6.1.2.4, §6.2, Fig 6.4): the raw
//! confidence RC (the leaky integrator, impulse 1 and decay 0.8 per iteration by default,
//! so that sustained re-localisation plateaus at 5 — Fig 6.4 compares RC against
//! thresholds of 3 and 4), the integrated confidence IC_k(t) = Σ_{τ≤t} RC_k(τ), and the
//! identified object: the first whose IC reaches the threshold (300, Fig 6.7). SRT is the
//! iteration at which the true object's IC first reaches it; the identity margin IM is the
//! first crossing of any other object minus the true object's (our reading of §6.2, which
//! gives no formula). A crossing that has not happened by the end of a run is censored at the run's last
//! iteration.

use crate::invalid::Invalid;
use std::collections::BTreeMap;

/// Per-object identification confidence.
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    /// Decay per whisk.
    pub decay: f64,
    /// What a re-localisation onto an object adds to its belief.
    pub impulse: f64,
    /// Confidence per known object.
    pub confidence: BTreeMap<String, f64>,
}

impl Identification {
    /// All beliefs at 0 for the `objects` known; impulse 1 − decay (a moving average).
    pub fn new<S: Into<String>>(objects: impl IntoIterator<Item = S>, decay: f64) -> Self {
        Self::with_impulse(objects, decay, 1.0 - decay)
    }

    /// All beliefs at 0 for the `objects` known, with the given decay and impulse.
    pub fn with_impulse<S: Into<String>>(
        objects: impl IntoIterator<Item = S>,
        decay: f64,
        impulse: f64,
    ) -> Self {
        Self {
            decay,
            impulse,
            confidence: objects.into_iter().map(|o| (o.into(), 0.0)).collect(),
        }
    }

    /// One whisk: decay every belief, and feed the object re-localised onto (if any).
    pub fn update(&mut self, relocalised_onto: Option<&str>) {
        for (object, c) in self.confidence.iter_mut() {
            let hit = relocalised_onto == Some(object.as_str());
            *c = self.decay * *c + if hit { self.impulse } else { 0.0 };
        }
    }

    /// The object with the highest confidence (the first by name on ties).
    pub fn best(&self) -> Option<(&str, f64)> {
        self.confidence
            .iter()
            .fold(None, |best: Option<(&str, f64)>, (o, &c)| match best {
                Some((_, b)) if b >= c => best,
                _ => Some((o.as_str(), c)),
            })
    }
}

/// Parameters of Chapter 6's recognition (§6.2).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RecognitionParams {
    /// RC's decay per iteration (0.8) [gap: the thesis says only "fixed"].
    pub decay: f64,
    /// What one re-localisation adds to RC (1) [gap].
    pub impulse: f64,
    /// θ_IC, the integrated-confidence threshold (300, chosen in Fig 6.7).
    pub threshold: f64,
}

impl Default for RecognitionParams {
    fn default() -> Self {
        Self {
            decay: 0.8,
            impulse: 1.0,
            threshold: 300.0,
        }
    }
}

impl RecognitionParams {
    /// Checks the values; returns the offending field and what was expected.
    pub fn validate(&self) -> Result<(), Invalid> {
        if !(self.decay.is_finite() && (0.0..1.0).contains(&self.decay)) {
            return Err(Invalid::field(
                "decay",
                format!("expected 0 ≤ decay < 1, got {}", self.decay),
            ));
        }
        for (f, v) in [("impulse", self.impulse), ("threshold", self.threshold)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Invalid::field(
                    f,
                    format!("expected a positive number, got {v}"),
                ));
            }
        }
        Ok(())
    }
}

/// How a recognition trial ended (§6.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// The true object's IC reached the threshold first.
    Correct,
    /// Another object's IC reached it first.
    Wrong,
    /// No IC reached it.
    None,
}

/// Raw and integrated confidence per known object over a trial (§6.1.2.4, §6.2).
#[derive(Debug, Clone, PartialEq)]
pub struct Recognition {
    /// Parameters.
    pub params: RecognitionParams,
    /// RC per object (the leaky integrator).
    pub raw: Identification,
    /// IC per object.
    pub integrated: BTreeMap<String, f64>,
    /// Iteration (1-based: the count of updates) at which each object's IC first
    /// reached the threshold.
    pub crossed: BTreeMap<String, u64>,
    /// Updates so far.
    pub iterations: u64,
}

impl Recognition {
    /// All confidences at 0 for the `objects` known.
    pub fn new<S: Into<String>>(
        objects: impl IntoIterator<Item = S>,
        params: RecognitionParams,
    ) -> Self {
        let raw = Identification::with_impulse(objects, params.decay, params.impulse);
        let integrated = raw.confidence.keys().map(|k| (k.clone(), 0.0)).collect();
        Self {
            params,
            raw,
            integrated,
            crossed: BTreeMap::new(),
            iterations: 0,
        }
    }

    /// One iteration: RC decays and takes the re-localisation (if any), IC adds RC.
    pub fn update(&mut self, relocalised_onto: Option<&str>) {
        self.raw.update(relocalised_onto);
        self.iterations += 1;
        for (object, ic) in self.integrated.iter_mut() {
            *ic += self.raw.confidence[object];
            if *ic >= self.params.threshold && !self.crossed.contains_key(object) {
                self.crossed.insert(object.clone(), self.iterations);
            }
        }
    }

    /// The identified object: the first whose IC reached the threshold, and when (on a
    /// tie, the one with the larger IC, then the first by name).
    pub fn identified(&self) -> Option<(&str, u64)> {
        self.crossed
            .iter()
            .min_by(|a, b| {
                a.1.cmp(b.1)
                    .then(self.integrated[b.0].total_cmp(&self.integrated[a.0]))
                    .then(a.0.cmp(b.0))
            })
            .map(|(o, &t)| (o.as_str(), t))
    }

    /// Whether every object's IC has reached `threshold`.
    pub fn all_reached(&self, threshold: f64) -> bool {
        self.integrated.values().all(|&ic| ic >= threshold)
    }

    /// The outcome for the true object `truth`.
    pub fn outcome(&self, truth: &str) -> Outcome {
        match self.identified() {
            None => Outcome::None,
            Some((o, _)) if o == truth => Outcome::Correct,
            Some(_) => Outcome::Wrong,
        }
    }

    /// SRT: the iteration at which `truth`'s IC first reached the threshold; `Err` with
    /// the iterations run when it never did (censored).
    pub fn srt(&self, truth: &str) -> Result<u64, u64> {
        self.crossed.get(truth).copied().ok_or(self.iterations)
    }

    /// IM: the first crossing of any other object minus `truth`'s (iterations), each
    /// crossing that has not happened taken at the last iteration; and whether that
    /// censoring happened. None when no object crossed at all.
    pub fn identity_margin(&self, truth: &str) -> Option<(f64, bool)> {
        if self.crossed.is_empty() {
            return None;
        }
        let end = self.iterations;
        let correct = self.crossed.get(truth);
        let wrong = self
            .crossed
            .iter()
            .filter(|(o, _)| o.as_str() != truth)
            .map(|(_, &t)| t)
            .min();
        let censored = correct.is_none() || wrong.is_none();
        let im = wrong.unwrap_or(end) as f64 - correct.copied().unwrap_or(end) as f64;
        Some((im, censored))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_integrator_follows_its_closed_form() {
        let mut id = Identification::new(["box", "mug"], 0.9);
        for _ in 0..10 {
            id.update(Some("box"));
        }
        // After n hits from 0: 1 − 0.9ⁿ; after m more whisks without: ·0.9ᵐ.
        let after_hits = 1.0 - 0.9f64.powi(10);
        assert!((id.confidence["box"] - after_hits).abs() < 1e-15);
        for _ in 0..5 {
            id.update(None);
        }
        assert!((id.confidence["box"] - after_hits * 0.9f64.powi(5)).abs() < 1e-15);
        assert_eq!(id.confidence["mug"], 0.0);
        assert_eq!(id.best().unwrap().0, "box");
        id.update(Some("skull"));
        assert!(!id.confidence.contains_key("skull"));
    }
    #[test]
    fn raw_and_integrated_confidence_follow_their_closed_forms() {
        // RC with impulse 1, decay 0.8 after n hits: (1 − 0.8ⁿ)/(1 − 0.8) → 5.
        let mut r = Recognition::new(["box", "box_stack"], RecognitionParams::default());
        let mut ic = 0.0;
        for n in 1..=20 {
            r.update(Some("box"));
            let rc = (1.0 - 0.8f64.powi(n)) / 0.2;
            ic += rc;
            assert!((r.raw.confidence["box"] - rc).abs() < 1e-12);
            assert!((r.integrated["box"] - ic).abs() < 1e-9);
        }
        assert_eq!(r.integrated["box_stack"], 0.0);
        assert_eq!(r.identified(), None);
        assert_eq!(r.outcome("box"), Outcome::None);
        assert_eq!(r.identity_margin("box"), None);
        // Sustained: IC grows by ~5 per iteration; the crossing of 300 is where the
        // closed form Σ (1 − 0.8ᵏ)/0.2 first reaches it.
        let mut k = 20;
        while r.crossed.is_empty() {
            r.update(Some("box"));
            k += 1;
        }
        let closed = |n: i32| (1..=n).map(|j| (1.0 - 0.8f64.powi(j)) / 0.2).sum::<f64>();
        assert!(closed(k) >= 300.0 && closed(k - 1) < 300.0);
        assert_eq!(r.srt("box"), Ok(k as u64));
        assert_eq!(r.identified(), Some(("box", k as u64)));
        assert_eq!(r.outcome("box"), Outcome::Correct);
        assert_eq!(r.outcome("box_stack"), Outcome::Wrong);
        // The other never crosses: IM censored at the last iteration.
        for _ in 0..10 {
            r.update(None);
        }
        let end = r.iterations as f64;
        assert_eq!(r.identity_margin("box"), Some((end - k as f64, true)));
        assert_eq!(r.srt("box_stack"), Err(r.iterations));
        assert_eq!(r.identity_margin("box_stack"), Some((k as f64 - end, true)));
    }

    #[test]
    fn identity_margin_is_the_gap_between_the_two_crossings() {
        let p = RecognitionParams {
            threshold: 10.0,
            ..RecognitionParams::default()
        };
        let mut r = Recognition::new(["a", "b"], p);
        // a every iteration, b every other one.
        for i in 0..40 {
            r.update(Some("a"));
            if i % 2 == 0 {
                r.update(Some("b"));
            }
        }
        let (ta, tb) = (r.crossed["a"], r.crossed["b"]);
        assert!(ta < tb);
        assert_eq!(r.identity_margin("a"), Some(((tb - ta) as f64, false)));
        assert_eq!(
            r.identity_margin("b"),
            Some(((ta as f64) - tb as f64, false))
        );
    }
}
