//! The surface placement controller's bookkeeping in the loop (§6.1.1, Alg 7–8): its
//! decision on each whisk's contacts, the correction it leaves pending for the next goal,
//! and the adjustments it has made in the current region (at most K, `max_adjustments`).

use super::goal::{Fallback, Fallbacks};
use nalgebra::{Isometry3, Point3};
use whisker_slam::exploration::placement::{self, Placement, PlacementParams};

/// What the SPC decided on a whisk (`explore.csv`'s `spc` column).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpcDecision {
    /// SPC is switched off (`explore.spc = false`).
    Off,
    /// Too few contacts: move towards the surface.
    Approach,
    /// Turn towards the contacts' median (condition 1).
    Turn,
    /// Move along the pointing axis into the distance band (condition 2).
    Move,
    /// Too close: back off.
    BackOff,
    /// Every condition met: the region is settled.
    Done,
}

impl SpcDecision {
    /// Its name in `explore.csv` and the recording's event log.
    pub fn name(self) -> &'static str {
        match self {
            SpcDecision::Off => "off",
            SpcDecision::Approach => "approach",
            SpcDecision::Turn => "turn",
            SpcDecision::Move => "move",
            SpcDecision::BackOff => "back_off",
            SpcDecision::Done => "done",
        }
    }

    /// Whether the decision moves the array (a correction).
    pub fn corrects(self) -> bool {
        !matches!(self, SpcDecision::Off | SpcDecision::Done)
    }
}

/// The SPC's state between whisks.
#[derive(Debug, Clone, Default)]
pub struct Spc {
    /// The correction to make next, if any.
    pending: Option<Isometry3<f64>>,
    /// The adjustments made in the current region.
    adjustments: usize,
}

impl Spc {
    /// The pending correction, taken (the next goal).
    pub fn take(&mut self) -> Option<Isometry3<f64>> {
        self.pending.take()
    }

    /// Whether a correction is pending (the region is not settled yet).
    pub fn is_pending(&self) -> bool {
        self.pending.is_some()
    }

    /// Ends the region (a refused goal: the next one starts a new region).
    pub fn end_region(&mut self) {
        self.adjustments = 0;
    }

    /// The decision on a whisk's contacts `world` with the array at `pose`; a correction
    /// is left pending unless the region is settled or has had its K adjustments (then
    /// counted in `fallbacks`).
    pub fn decide(
        &mut self,
        params: &PlacementParams,
        pose: &Isometry3<f64>,
        world: &[Point3<f64>],
        fallbacks: &mut Fallbacks,
    ) -> SpcDecision {
        let decision = placement::correct(params, pose, world);
        let name = match decision {
            Placement::Approach(_) => SpcDecision::Approach,
            Placement::Turn(_) => SpcDecision::Turn,
            Placement::Move(_) => SpcDecision::Move,
            Placement::BackOff(_) => SpcDecision::BackOff,
            Placement::Done(_) => SpcDecision::Done,
        };
        if matches!(decision, Placement::Done(_)) {
            self.adjustments = 0;
        } else if self.adjustments >= params.max_adjustments {
            fallbacks.count(Fallback::SpcLimit);
            self.adjustments = 0;
        } else {
            self.adjustments += 1;
            self.pending = decision.pose();
        }
        name
    }
}
