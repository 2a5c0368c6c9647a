//! The mode-switch cue (`whisker_slam::navigation::mode_switch`, §7.1) on what the robot
//! senses while it drives: each whisk's contact points and free points in the plan of its
//! odometry frame, the latest `window_whisks` whisks kept, and the cue asked after every
//! whisk that touched; each answer scored against the piece the newest contact truly lies
//! on (an object, or a wall, post or floor).
//!
//! - A contact point is the front end's point (array frame, with its noise) carried by the
//!   array's pose at the dead-reckoned base pose: only what the robot knows.
//! - A free point is the tip of a whisker that touched nothing, at full protraction.
//!   A contact missed by the detector (`[kinematic]` detection probability) is taken for
//!   free space too, as it would be on a robot.

use nalgebra::{Isometry3, Point2, Point3};
use std::collections::{BTreeMap, VecDeque};
use whisker_sim::environment::Environment;
use whisker_sim::sensing::kinematic::RigidWhisker;
use whisker_slam::contact::ContactCycle;
use whisker_slam::navigation::mode_switch::{Outline, Verdict};

/// The latest whisks' contact and free points in the plan.
pub struct PlanView {
    window: usize,
    /// Each whisk's own contacts and free points, oldest first.
    whisks: VecDeque<Outline>,
}

impl PlanView {
    /// A view remembering `window` whisks.
    pub fn new(window: usize) -> Self {
        Self {
            window,
            whisks: VecDeque::new(),
        }
    }

    /// Adds a whisk seen with the array at `array` (the plan's frame): its contacts and
    /// the tips of the whiskers that touched nothing, the oldest whisk forgotten.
    pub fn add(&mut self, cycle: &ContactCycle, whiskers: &[RigidWhisker], array: &Isometry3<f64>) {
        let plan = |p: Point3<f64>| Point2::new(p.x, p.y);
        let contacts = cycle
            .contacts
            .iter()
            .map(|c| plan(array * c.point))
            .collect();
        let free = whiskers
            .iter()
            .enumerate()
            .filter(|(i, _)| cycle.contacts.iter().all(|c| c.whisker != *i))
            .map(|(_, w)| plan(w.shaft_point(array, w.protracted, w.module.beam.length)))
            .collect();
        self.whisks.push_back(Outline { contacts, free });
        while self.whisks.len() > self.window {
            self.whisks.pop_front();
        }
    }

    /// The outline of the remembered whisks, oldest first.
    pub fn outline(&self) -> Outline {
        let mut o = Outline::default();
        for w in &self.whisks {
            o.contacts.extend(&w.contacts);
            o.free.extend(&w.free);
        }
        o
    }
}

/// The index of the piece of `environment` nearest to `point` (world): the piece a
/// contact lies on.
pub fn piece_at(environment: &Environment, point: &Point3<f64>) -> Option<usize> {
    environment
        .pieces
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // In the piece's own frame, where parry measures.
            let local = p.pose.inverse() * point;
            let q = parry3d_f64::math::Vector::new(local.x, local.y, local.z);
            (i, p.shape.distance_to_local_point(q, true))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// The cue's answers against the truth.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SwitchTally {
    /// [truth: wall, object][verdict: wall, object, undecided].
    pub counts: [[usize; 3]; 2],
    /// Each object the cue called an object while its newest contact lay on it: the
    /// first update it did.
    pub objects_found: BTreeMap<String, usize>,
}

impl SwitchTally {
    /// Counts a verdict at `update` whose newest contact truly lies on `piece`, an object
    /// when `object`.
    pub fn add(&mut self, update: usize, verdict: Verdict, piece: &str, object: bool) {
        let v = match verdict {
            Verdict::Wall => 0,
            Verdict::Object => 1,
            Verdict::Undecided => 2,
        };
        self.counts[object as usize][v] += 1;
        if object && verdict == Verdict::Object {
            self.objects_found.entry(piece.to_owned()).or_insert(update);
        }
    }

    /// `summary.json`'s `switch`.
    pub fn json(&self) -> serde_json::Value {
        let row =
            |r: &[usize; 3]| serde_json::json!({"wall": r[0], "object": r[1], "undecided": r[2]});
        serde_json::json!({
            "decisions": self.counts.iter().flatten().sum::<usize>(),
            "on_walls": row(&self.counts[0]),
            "on_objects": row(&self.counts[1]),
            "objects_found": self.objects_found,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wall's first metre then a 0.2 m box, each touched at 5 cm steps, with free
    /// points where the array reaches past the box's ends: the cue on the view says wall,
    /// then (once the wall has left the window) object; the tally counts by the truth.
    #[test]
    fn the_view_forgets_old_whisks_and_the_tally_scores_by_the_truth() {
        use whisker_slam::contact::Contact;
        use whisker_slam::navigation::mode_switch::ModeSwitch;
        let whiskers: Vec<RigidWhisker> = Vec::new();
        let mut view = PlanView::new(4);
        let cue = ModeSwitch::default();
        let whisk = |xs: &[f64]| ContactCycle {
            index: 0,
            start_s: 0.0,
            array_pose: Isometry3::identity(),
            contacts: xs
                .iter()
                .map(|&x| Contact {
                    whisker: 0,
                    time_s: 0.0,
                    angle_rad: 1.0,
                    radial_distance: 0.1,
                    point: Point3::new(x, 0.0, 0.0),
                    slope: 0.0,
                })
                .collect(),
        };
        for k in 0..4 {
            let xs: Vec<f64> = (0..5).map(|i| 0.25 * k as f64 + 0.05 * i as f64).collect();
            view.add(&whisk(&xs), &whiskers, &Isometry3::identity());
        }
        assert_eq!(cue.decide(&view.outline()).verdict, Verdict::Wall);
        // The box at x 3.0–3.2: four whisks on it push the wall out of the window.
        for _ in 0..4 {
            view.add(
                &whisk(&[3.0, 3.05, 3.1, 3.15, 3.2]),
                &whiskers,
                &Isometry3::identity(),
            );
        }
        let o = view.outline();
        assert_eq!(o.contacts.len(), 20);
        assert!(o.contacts.iter().all(|p| p.x >= 3.0));
        let mut tally = SwitchTally::default();
        tally.add(3, Verdict::Wall, "office wall 0", false);
        tally.add(9, Verdict::Undecided, "object box", true);
        tally.add(11, Verdict::Object, "object box", true);
        tally.add(12, Verdict::Object, "object box", true);
        assert_eq!(tally.counts, [[1, 0, 0], [0, 2, 1]]);
        assert_eq!(tally.objects_found.get("object box"), Some(&11));
    }
}
