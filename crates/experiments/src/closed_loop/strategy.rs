//! The strategies' bookkeeping after each whisk (thesis §6.1.2, §6.1.3.2): the default
//! trajectory while no object is likely or contact is lost; otherwise follow experience
//! history (FEH) or the least similar region (LSR), re-planning on re-localisation, and
//! each step to an experience cut into segments (`whisker_slam::exploration::tour::segments`).

use super::state::{Heading, Loop};
use nalgebra::Isometry3;
use std::collections::VecDeque;
use whisker_scenario::explore::Strategy;
use whisker_slam::exploration::feh::Follower;
use whisker_slam::exploration::lsr::{self, Replan, Scope};
use whisker_slam::exploration::tour;
use whisker_slam::features::similarity::Features;
use whisker_slam::recognition::Recognition;

/// RC below this counts as zero (§6.1.3.2's "zero confidence").
pub const ZERO_RC: f64 = 1e-3;

impl Loop<'_> {
    /// Drops the step under way (its segments, its target) and returns to the default
    /// trajectory.
    pub(super) fn abandon_step(&mut self) {
        self.segments.clear();
        self.stepping_to = None;
        self.heading = Heading::Default;
    }

    /// FEH/LSR bookkeeping after a whisk (§6.1.2, §6.1.3.2): the default trajectory while
    /// no object is likely; otherwise follow or re-plan.
    pub(super) fn replan(
        &mut self,
        r: &Recognition,
        onto: Option<&str>,
        current: usize,
        features: &Features,
        pose: &Isometry3<f64>,
    ) {
        // The objects with a raw confidence above zero.
        let likely: Vec<String> = r
            .raw
            .confidence
            .iter()
            .filter(|(_, c)| **c >= ZERO_RC)
            .map(|(o, _)| o.clone())
            .collect();
        let strategy = self.config.strategy;
        if strategy == Strategy::Default || likely.is_empty() {
            if !matches!(self.heading, Heading::Default) {
                self.abandon_step();
            }
            return;
        }
        let leader = r.raw.best().map(|(o, _)| o.to_string()).unwrap_or_default();
        // A step whose segments are all done (and settled) reached its target: the array is
        // taken to be there, in the target's map — unless this whisk re-localised into that
        // map, which says where in it the array is.
        let reached = self.segments.is_empty() && self.spc.is_none() && self.stepping_to.is_some();
        if reached && let Some(t) = self.stepping_to.take() {
            let map = self.slam.map.experiences[t].object.clone();
            if let Some(o) = map.filter(|o| onto != Some(o.as_str())) {
                self.anchors.insert(o, (t, *pose));
            }
        }
        let next = match strategy {
            Strategy::Feh => {
                let following = matches!(self.heading, Heading::Feh(_));
                match onto {
                    Some(o) if o == leader => {
                        let after = match &self.heading {
                            Heading::Feh(f) if f.object == o => Some(f.index),
                            _ => None,
                        };
                        Follower::start(&self.slam.map, o, current, after).map(|f| {
                            let t = f.target();
                            self.heading = Heading::Feh(f);
                            t
                        })
                    }
                    _ if following && reached => match &mut self.heading {
                        Heading::Feh(f) => Some(f.advance()),
                        _ => None,
                    },
                    _ => None,
                }
            }
            Strategy::Lsr => {
                let continuing =
                    matches!(&self.heading, Heading::Lsr { leader: l, .. } if *l == leader);
                let relocalised = self.config.lsr.replan == Replan::Relocalisation
                    && onto.is_some_and(|o| likely.iter().any(|l| l == o));
                let keep = continuing && !relocalised;
                let stepping = self.stepping_to.is_some() || !self.segments.is_empty();
                match &mut self.heading {
                    Heading::Lsr { path, .. } if keep && reached && !path.is_empty() => {
                        path.pop_front()
                    }
                    _ if keep && stepping => None,
                    _ => self.plan_lsr(&likely, leader, current, features),
                }
            }
            Strategy::Default => None,
        };
        if let Some(target) = next
            && let Some(anchor) = self.anchor(target)
            && let Some(goal) =
                tour::step_goal(&self.slam.map, anchor, target, self.config.step_pose)
        {
            self.segments = tour::segments(pose, &goal, self.config.segment_m);
            self.stepping_to = Some(target);
        }
    }

    /// The anchor a step to experience `target` starts from: the last re-localisation into
    /// (or step onto) the target's map.
    fn anchor(&self, target: usize) -> Option<(usize, Isometry3<f64>)> {
        let object = self.slam.map.experiences[target].object.as_deref()?;
        self.anchors.get(object).copied()
    }

    /// LSR's new plan over the `likely` objects' maps from their anchors (§6.1.2.3): the
    /// heading along its path and the first node to step to.
    fn plan_lsr(
        &mut self,
        likely: &[String],
        leader: String,
        current: usize,
        features: &Features,
    ) -> Option<usize> {
        let starts: Vec<usize> = likely
            .iter()
            .filter_map(|o| self.anchors.get(o).map(|a| a.0))
            .collect();
        let scope = Scope {
            objects: likely,
            own_links: self.own_links,
            starts: &starts,
        };
        let plan = lsr::plan(&self.slam.map, features, current, &scope, &self.config.lsr)?;
        self.lsr_plans.add(&plan);
        let mut path: VecDeque<usize> = plan.path.into_iter().skip(1).collect();
        let first = path.pop_front();
        self.heading = Heading::Lsr { path, leader };
        first
    }
}
