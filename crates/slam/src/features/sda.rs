//! Slope distribution array (SDA, thesis §5.1.1.1.3): the surface slope each of the
//! array's whiskers sensed in one whisk, in whisker-index order (18 values), `None` where a
//! whisker made no contact.

use crate::contact::ContactCycle;
use serde::{Deserialize, Serialize};

/// One whisk's slopes per whisker (index = whisker index); `None`: no contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Sda(pub Vec<Option<f64>>);

impl Sda {
    /// The SDA of a whisk cycle's contacts over an array of `whiskers` whiskers (a whisker
    /// with several contacts keeps its first).
    pub fn from_cycle(cycle: &ContactCycle, whiskers: usize) -> Self {
        let mut slopes = vec![None; whiskers];
        for c in &cycle.contacts {
            if let Some(s) = slopes.get_mut(c.whisker) {
                s.get_or_insert(c.slope);
            }
        }
        Self(slopes)
    }

    /// The values with missing contacts as 0 — the array the similarity measure compares
    /// (a whisker without contact reads as a flat slope, as in a zero-initialised array).
    pub fn filled(&self) -> Vec<f64> {
        self.0.iter().map(|s| s.unwrap_or(0.0)).collect()
    }
}
