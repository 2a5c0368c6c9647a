//! Follow experience history, FEH (thesis §6.1.2.2): replay the map-building trajectory,
//! where re-localisations were most frequent, from the place the array re-localised.
//!
//! On a re-localisation into experience e of object k, the history H is k's segment of
//! the experience history (the experience current after each map-building whisk) with
//! consecutive repeats collapsed; the next target is the entry after e's occurrence at or
//! after the last followed index (else after its first occurrence), wrapping to the start.
//! Reaching a target makes the one after it the next (our reading of §6.1.2.2).

use crate::whisker_ratslam::object_map::ObjectMap;

/// The experience history of one object, consecutive repeats collapsed.
pub fn history(map: &ObjectMap, object: &str) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::new();
    for h in &map.history {
        let label = map
            .experiences
            .get(h.experience)
            .and_then(|e| e.object.as_deref());
        if label == Some(object) && out.last() != Some(&h.experience) {
            out.push(h.experience);
        }
    }
    out
}

/// A follower of one object's history.
#[derive(Debug, Clone, PartialEq)]
pub struct Follower {
    /// The object whose history is followed.
    pub object: String,
    /// Its history (consecutive repeats collapsed).
    pub history: Vec<usize>,
    /// Index in the history of the current target.
    pub index: usize,
}

impl Follower {
    /// Starts following `object`'s history from a re-localisation into `experience`
    /// (None when the experience is not in that history, or the history is too short).
    pub fn start(
        map: &ObjectMap,
        object: &str,
        experience: usize,
        after: Option<usize>,
    ) -> Option<Self> {
        let history = history(map, object);
        if history.len() < 2 {
            return None;
        }
        let from = after.unwrap_or(0).min(history.len());
        let at = history[from..]
            .iter()
            .position(|&e| e == experience)
            .map(|i| i + from)
            .or_else(|| history.iter().position(|&e| e == experience))?;
        Some(Self {
            object: object.to_string(),
            index: (at + 1) % history.len(),
            history,
        })
    }

    /// The current target.
    pub fn target(&self) -> usize {
        self.history[self.index]
    }

    /// The target was reached: the next one.
    pub fn advance(&mut self) -> usize {
        self.index = (self.index + 1) % self.history.len();
        self.target()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::whisker_ratslam::object_map::HistoryEntry;

    fn map() -> ObjectMap {
        let mut m = ObjectMap::default();
        for i in 0..5 {
            m.add(
                Default::default(),
                [0.0; 6],
                &nalgebra::Isometry3::identity(),
                Some(if i < 4 { "box" } else { "mug" }.into()),
            );
        }
        for (s, e) in [0, 0, 1, 2, 2, 3, 1, 4].into_iter().enumerate() {
            m.history.push(HistoryEntry {
                sample: s as u64,
                experience: e,
                relocalised: false,
            });
        }
        m
    }

    #[test]
    fn the_history_is_collapsed_and_followed_with_wrap() {
        let m = map();
        assert_eq!(history(&m, "box"), vec![0, 1, 2, 3, 1]);
        assert_eq!(history(&m, "mug"), vec![4]);
        // Re-localised into 1: the first occurrence is index 1, next target 2.
        let mut f = Follower::start(&m, "box", 1, None).unwrap();
        assert_eq!(f.target(), 2);
        assert_eq!(f.advance(), 3);
        assert_eq!(f.advance(), 1);
        assert_eq!(f.advance(), 0); // wraps
        // Re-localised into 1 again after index 3: the later occurrence (4) is taken.
        let f = Follower::start(&m, "box", 1, Some(3)).unwrap();
        assert_eq!((f.index, f.target()), (0, 0));
        assert!(Follower::start(&m, "box", 4, None).is_none());
        assert!(Follower::start(&m, "mug", 4, None).is_none());
    }
}
