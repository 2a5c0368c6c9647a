//! The strategies' course (thesis §6.1.2, §6.1.3.2): the default trajectory's tour of the
//! goal mesh's faces while no object is likely or contact is lost; otherwise follow
//! experience history (FEH) or the least similar region (LSR), re-planning on
//! re-localisation, each step to an experience cut into segments
//! (`whisker_slam::exploration::tour::segments`) and started from the target map's anchor.

use super::goal::GoalKind;
use nalgebra::{Isometry3, Vector3};
use std::collections::{BTreeMap, VecDeque};
use whisker_scenario::explore::{ExploreConfig, Strategy};
use whisker_slam::exploration::feh::Follower;
use whisker_slam::exploration::lsr::{self, Replan, Scope};
use whisker_slam::exploration::tour::{self, FaceTour};
use whisker_slam::features::similarity::Features;
use whisker_slam::recognition::Recognition;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// RC below this counts as zero (§6.1.3.2's "zero confidence").
pub const ZERO_RC: f64 = 1e-3;

/// Where FEH or LSR is heading.
enum Heading {
    /// The default trajectory's faces.
    Default,
    /// Following a history (FEH).
    Feh(Follower),
    /// Along an LSR path: the remaining nodes after the one being stepped to.
    Lsr {
        path: VecDeque<usize>,
        leader: String,
    },
}

/// LSR's plans over a run (`summary.json`'s `lsr`).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct LsrTally {
    /// Plans made.
    pub plans: usize,
    /// Plans whose least similar row was shared by more than one experience (|E_smin| > 1).
    pub tied_targets: usize,
    /// Rows passed over as unreachable, summed over the plans.
    pub rows_skipped: usize,
}

impl LsrTally {
    /// Counts `plan`.
    fn add(&mut self, plan: &lsr::LsrPlan) {
        self.plans += 1;
        self.tied_targets += usize::from(plan.tied > 1);
        self.rows_skipped += plan.skipped;
    }
}

/// The strategy's course through a run: the tour, the step under way, where FEH or LSR is
/// heading, and the anchors steps start from.
pub struct Course {
    /// The default trajectory's faces, and the face it starts at.
    tour: FaceTour,
    start_face: usize,
    /// FEH/LSR: segments still to go of the current step, and the step's target.
    segments: VecDeque<Isometry3<f64>>,
    stepping_to: Option<usize>,
    heading: Heading,
    /// Per loaded object: the last experience of its map re-localised into or stepped to,
    /// and the true pose then (steps start there, §6.1.2.1).
    anchors: BTreeMap<String, (usize, Isometry3<f64>)>,
    /// How many links the loaded maps brought (the run's own links come after them).
    own_links: usize,
    /// What LSR's plans were like.
    lsr_plans: LsrTally,
}

impl Course {
    /// A course along `tour` from `start_face`, over a map whose first `own_links` links
    /// are the loaded maps'.
    pub fn new(tour: FaceTour, start_face: usize, own_links: usize) -> Self {
        Self {
            tour,
            start_face,
            segments: VecDeque::new(),
            stepping_to: None,
            heading: Heading::Default,
            anchors: BTreeMap::new(),
            own_links,
            lsr_plans: LsrTally::default(),
        }
    }

    /// The next goal (the step's next segment, else the tour's next face, the array kept
    /// `level` along its y axis); none when the tour has no usable face.
    pub fn next_goal(&mut self, level: &Vector3<f64>) -> Option<(Isometry3<f64>, GoalKind)> {
        if let Some(seg) = self.segments.pop_front() {
            return Some((seg, GoalKind::Step(self.stepping_to)));
        }
        let face = self.tour.next(self.start_face)?;
        Some((self.tour.goal(face, level), GoalKind::Face(face)))
    }

    /// Loops of the tour completed.
    pub fn loops(&self) -> usize {
        self.tour.loops
    }

    /// Usable faces in one loop of the tour.
    pub fn faces_per_loop(&self) -> usize {
        self.tour.usable()
    }

    /// The experience a step is heading to, if any.
    pub fn stepping_to(&self) -> Option<usize> {
        self.stepping_to
    }

    /// The `strategy_state` column of `explore.csv`.
    pub fn heading_name(&self) -> &'static str {
        match self.heading {
            Heading::Default => "default",
            Heading::Feh(_) => "feh",
            Heading::Lsr { .. } => "lsr",
        }
    }

    /// What LSR's plans were like.
    pub fn lsr_plans(&self) -> LsrTally {
        self.lsr_plans
    }

    /// A re-localisation into `object`'s map at `experience` with the array at `pose`:
    /// the anchor of the next step into that map.
    pub fn anchor_at(&mut self, object: String, experience: usize, pose: Isometry3<f64>) {
        self.anchors.insert(object, (experience, pose));
    }

    /// Drops the step under way (its segments, its target) and returns to the default
    /// trajectory.
    pub fn abandon_step(&mut self) {
        self.segments.clear();
        self.stepping_to = None;
        self.heading = Heading::Default;
    }

    /// FEH/LSR bookkeeping after a whisk (§6.1.2, §6.1.3.2) of the loop `config` over
    /// `map`, the array at `pose`, the SLAM's `current` experience, the whisk's `features`,
    /// `onto` the loaded map re-localised into, `settled` whether the SPC has no correction
    /// pending: the default trajectory while no object is likely; otherwise follow or
    /// re-plan.
    pub fn replan(
        &mut self,
        (config, map): (&ExploreConfig, &ObjectMap),
        r: &Recognition,
        (onto, current): (Option<&str>, usize),
        (features, pose): (&Features, &Isometry3<f64>),
        settled: bool,
    ) {
        // The objects with a raw confidence above zero.
        let likely: Vec<String> = r
            .raw
            .confidence
            .iter()
            .filter(|(_, c)| **c >= ZERO_RC)
            .map(|(o, _)| o.clone())
            .collect();
        let strategy = config.strategy;
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
        let reached = self.segments.is_empty() && settled && self.stepping_to.is_some();
        if reached && let Some(t) = self.stepping_to.take() {
            let object = map.experiences[t].object.clone();
            if let Some(o) = object.filter(|o| onto != Some(o.as_str())) {
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
                        Follower::start(map, o, current, after).map(|f| {
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
                let relocalised = config.lsr.replan == Replan::Relocalisation
                    && onto.is_some_and(|o| likely.iter().any(|l| l == o));
                let keep = continuing && !relocalised;
                let stepping = self.stepping_to.is_some() || !self.segments.is_empty();
                match &mut self.heading {
                    Heading::Lsr { path, .. } if keep && reached && !path.is_empty() => {
                        path.pop_front()
                    }
                    _ if keep && stepping => None,
                    _ => self.plan_lsr((config, map), &likely, leader, (current, features)),
                }
            }
            Strategy::Default => None,
        };
        if let Some(target) = next
            && let Some(anchor) = self.anchor(map, target)
            && let Some(goal) = tour::step_goal(map, anchor, target, config.step_pose)
        {
            self.segments = tour::segments(pose, &goal, config.segment_m);
            self.stepping_to = Some(target);
        }
    }

    /// The anchor a step to experience `target` starts from: the last re-localisation into
    /// (or step onto) the target's map.
    fn anchor(&self, map: &ObjectMap, target: usize) -> Option<(usize, Isometry3<f64>)> {
        let object = map.experiences[target].object.as_deref()?;
        self.anchors.get(object).copied()
    }

    /// LSR's new plan over the `likely` objects' maps from their anchors (§6.1.2.3): the
    /// heading along its path and the first node to step to.
    fn plan_lsr(
        &mut self,
        (config, map): (&ExploreConfig, &ObjectMap),
        likely: &[String],
        leader: String,
        (current, features): (usize, &Features),
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
        let plan = lsr::plan(map, features, current, &scope, &config.lsr)?;
        self.lsr_plans.add(&plan);
        let mut path: VecDeque<usize> = plan.path.into_iter().skip(1).collect();
        let first = path.pop_front();
        self.heading = Heading::Lsr { path, leader };
        first
    }
}
