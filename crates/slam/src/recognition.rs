//! Object identification by appended object maps (thesis §5.2.2.2, Figs 5.16–5.17): each
//! known object's belief is a leaky integrator fed by re-localisations onto that object's
//! experiences, with a fixed decay.
//!
//! Each whisk, every belief decays by `decay`, and the object re-localised onto (if any)
//! receives `1 − decay`: c ← decay·c + (1 − decay)·[re-localised onto it]. A belief is
//! thus an exponential moving average of the re-localisation rate onto the object, in
//! [0, 1], with a time constant of 1/(1 − decay) whisks.

use std::collections::BTreeMap;

/// Per-object identification confidence.
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    /// Decay per whisk (0.95: a time constant of 20 whisks).
    pub decay: f64,
    /// Confidence per known object.
    pub confidence: BTreeMap<String, f64>,
}

impl Identification {
    /// All beliefs at 0 for the `objects` known.
    pub fn new<S: Into<String>>(objects: impl IntoIterator<Item = S>, decay: f64) -> Self {
        Self {
            decay,
            confidence: objects.into_iter().map(|o| (o.into(), 0.0)).collect(),
        }
    }

    /// One whisk: decay every belief, and feed the object re-localised onto (if any).
    pub fn update(&mut self, relocalised_onto: Option<&str>) {
        for (object, c) in self.confidence.iter_mut() {
            let hit = relocalised_onto == Some(object.as_str());
            *c = self.decay * *c + if hit { 1.0 - self.decay } else { 0.0 };
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
}
