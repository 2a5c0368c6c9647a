//! The robot's side of a navigation run (issue #36, thesis Fig 5.1, §7.1): everything the
//! mobile robot computes from what it senses — the odometry, the whisks' contacts and
//! what its stops found — and nothing it could not know. The live run
//! ([`super::terrain`]) and the replay of a dataset ([`super::dataset`]) both drive it,
//! so a replay decides, stops and maps exactly as the robot did.
//!
//! Per update ([`Navigator::update`]): the odometry's reading dead-reckons the base; the
//! whisk becomes a tactile image ([`image`]) and one planar RatSLAM step
//! (Ch 3; a whisk that touched nothing does not inject); its contacts and free points join
//! the cue's plan view ([`super::plan_view`]) at the dead-reckoned pose, and the cue
//! decides while the window holds a contact. At an "object" whose outline lies farther than
//! `revisit_m` from the last stop's, [`Navigator::stop`] docks ([`Dock`]); after the stop's
//! closed loop, [`Navigator::landmark`] makes the identity a landmark step (with fusion).

use super::object_mode::{self, Dock, Landmarks};
use super::plan_view::PlanView;
use super::posture::Posture;
use nalgebra::Point2;
use whisker_scenario::navigate::NavigateConfig;
use whisker_scenario::object_mode::{DockBy, ObjectModeConfig};
use whisker_sim::sensing::kinematic::RigidWhisker;
use whisker_slam::contact::ContactCycle;
use whisker_slam::navigation::base_odometry::BaseMotion;
use whisker_slam::navigation::mode_switch::{Decision, ModeSwitch, Verdict};
use whisker_slam::pose::Pose2;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::{RatSlam, RatSlamParams, Step};

/// The tactile image of a whisk (`super::terrain`'s module documentation): each contacted whisker's
/// pixel 1 + 254 × (θ_p − θ) / (θ_p − θ_r), θ its contact angle and θ_r, θ_p its
/// retraction and protraction limits; 0 where it touched nothing.
pub fn image(cycle: &ContactCycle, whiskers: &[RigidWhisker]) -> TactileImage {
    let mut image = TactileImage::default();
    for c in &cycle.contacts {
        let w = &whiskers[c.whisker];
        let early = ((w.protracted - c.angle_rad) / (w.protracted - w.retracted)).clamp(0.0, 1.0);
        image.pixels[c.whisker] = 1 + (254.0 * early).round() as u8;
    }
    image
}

/// What the robot does at its stops (`[navigate.object]`, as far as the robot's own
/// decisions need it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopRules {
    /// Dock by the base (true) or by the arm's pan.
    pub by_base: bool,
    /// The outline's centre this far ahead when docking by the base (m).
    pub dock_distance_m: f64,
    /// A stop needs the outline's centre farther than this from the last stop's (m).
    pub revisit_m: f64,
    /// A re-observed landmark's energy, and the landmark gate (m).
    pub landmark_energy: f64,
    pub landmark_gate_m: f64,
}

impl StopRules {
    /// The rules of `[navigate.object]`.
    pub fn of(o: &ObjectModeConfig) -> Self {
        Self {
            by_base: o.dock == DockBy::Base,
            dock_distance_m: o.dock_distance_m,
            revisit_m: o.revisit_m,
            landmark_energy: o.landmark_energy,
            landmark_gate_m: o.landmark_gate_m,
        }
    }
}

/// What one update gave.
pub struct Perceived {
    /// The dead-reckoned base pose.
    pub dead_reckoned: Pose2,
    pub image: TactileImage,
    pub step: Step,
    /// The cue's decision, while the window holds a contact.
    pub decision: Option<Decision>,
}

/// The mobile robot's mind: planar RatSLAM, the cue's view, the landmarks.
pub struct Navigator {
    pub slam: RatSlam,
    view: PlanView,
    switch: ModeSwitch,
    whiskers: Vec<RigidWhisker>,
    posture: Posture,
    rules: Option<StopRules>,
    fusion: bool,
    landmarks: Landmarks,
    /// The last stop's outline centre.
    last_stop: Option<Point2<f64>>,
    /// The dead-reckoned base pose.
    at: Option<Pose2>,
}

impl Navigator {
    /// A robot that starts at `start` (the odometry frame's origin pose).
    pub fn new(
        ratslam: RatSlamParams,
        switch: ModeSwitch,
        (whiskers, posture): (Vec<RigidWhisker>, Posture),
        rules: Option<StopRules>,
        fusion: bool,
    ) -> Self {
        Self {
            slam: RatSlam::new(ratslam),
            view: PlanView::new(switch.window_whisks),
            switch,
            whiskers,
            posture,
            landmarks: Landmarks::new(rules.map_or(0.0, |r| r.landmark_gate_m)),
            rules,
            fusion,
            last_stop: None,
            at: None,
        }
    }

    /// The robot of `config` (its whiskers and posture given).
    pub fn of(config: &NavigateConfig, whiskers: Vec<RigidWhisker>, posture: Posture) -> Self {
        Self::new(
            config.ratslam,
            config.switch,
            (whiskers, posture),
            config.object.as_ref().map(StopRules::of),
            config.fusion,
        )
    }

    /// One update: `reading` since the last update (ignored at the first, which stands
    /// at `start`), and the whisk's `cycle`.
    pub fn update(
        &mut self,
        start: &Pose2,
        reading: &BaseMotion,
        cycle: &ContactCycle,
    ) -> Perceived {
        let dr = match &self.at {
            None => *start,
            Some(at) => reading.apply(at),
        };
        self.at = Some(dr);
        let image = image(cycle, &self.whiskers);
        self.view
            .add(cycle, &self.whiskers, &self.posture.array_pose(&dr));
        let outline = self.view.outline();
        let decision = (!outline.contacts.is_empty()).then(|| self.switch.decide(&outline));
        // A whisk that touched nothing says nothing of the place: it does not inject.
        let touched = !cycle.contacts.is_empty();
        let step =
            self.slam
                .step_gated(&image, reading.trans, reading.rot1 + reading.rot2, touched);
        Perceived {
            dead_reckoned: dr,
            image,
            step,
            decision,
        }
    }

    /// Whether the robot stops at `decision` (object mode, an "object" outline not
    /// visited at the last stop), and how it docks.
    pub fn stop(&mut self, decision: &Decision) -> Option<Dock> {
        let rules = self.rules?;
        let dr = self.at?;
        let visited = self
            .last_stop
            .is_some_and(|c| (c - decision.centre).norm() <= rules.revisit_m);
        if decision.verdict != Verdict::Object || visited {
            return None;
        }
        self.last_stop = Some(decision.centre);
        Some(match rules.by_base {
            true => Dock::toward(&dr, &decision.centre, rules.dock_distance_m),
            false => Dock {
                turn: object_mode::facing(&dr, &decision.centre),
                drive: 0.0,
            },
        })
    }

    /// The landmark step of a stop that identified `identity` (with fusion; none
    /// otherwise).
    pub fn landmark(&mut self, identity: Option<&str>) -> Option<Step> {
        let (id, rules) = (identity?, self.rules?);
        self.fusion.then(|| {
            self.landmarks
                .observe(&mut self.slam, id, rules.landmark_energy)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;
    use nalgebra::Point3;
    use whisker_slam::contact::Contact;

    fn cycle(contacts: &[(usize, f64)]) -> ContactCycle {
        ContactCycle {
            index: 0,
            start_s: 0.0,
            array_pose: Isometry3::identity(),
            contacts: contacts
                .iter()
                .map(|&(whisker, angle)| Contact {
                    whisker,
                    time_s: 0.0,
                    angle_rad: angle.to_radians(),
                    radial_distance: 0.1,
                    point: Point3::origin(),
                    slope: 0.0,
                })
                .collect(),
        }
    }

    /// 40°–140° whisks: a contact at 40° is 255, at 140° 1, at 90° 1 + 127 = 128; an
    /// untouched whisker 0.
    #[test]
    fn the_image_scales_the_contact_angle_early_bright() {
        let ws = crate::maze_slam::kinematic_whiskers();
        let img = image(&cycle(&[(0, 40.0), (5, 140.0), (17, 90.0)]), &ws);
        let mut want = [0u8; 18];
        (want[0], want[5], want[17]) = (255, 1, 128);
        assert_eq!(img.pixels, want);
    }
}
