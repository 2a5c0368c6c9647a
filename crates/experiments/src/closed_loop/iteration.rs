//! One iteration of the closed loop (see the module documentation of `closed_loop`):
//! the goal and the move, the whisk, odometry and WhiskerRatSLAM, recognition, the SPC
//! and the strategy, and what each whisk writes and records.

use super::goal::{Fallback, GoalKind};
use super::log::{self, Row, Summary};
use super::map_accuracy;
use super::placement::SpcDecision;
use super::robot::Motion;
use super::state::Whisk;
use super::state::{Loop, Outcome, Sensor, Tally, Whisked, relocalised_into};
use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use whisker_scenario::Result;
use whisker_scenario::explore::{Strategy, Task};

/// Attempts at a goal per iteration before the array whisks where it is.
const GOAL_ATTEMPTS: usize = 8;
/// A face goal that would touch the object is pushed back this far (m) …
const RETREAT_M: f64 = 0.02;
/// … at most this many times.
const RETREATS: usize = 5;

impl Loop<'_> {
    /// Steps 3–5: one whisk where the array is, odometry since the last, WhiskerRatSLAM,
    /// and recognition.
    pub(super) fn whisk(&mut self, iteration: usize, seed: u64, tally: &mut Tally) -> Whisked {
        // 3. Whisk where the array is.
        let pose = self.robot.array_pose();
        let start = self.time;
        let (cycle, period, streams) =
            self.sensing
                .whisk(&self.target, iteration as u64, self.time, &pose, seed);
        self.time += period;
        let points: Vec<Point3<f64>> = cycle.contacts.iter().map(|c| c.point).collect();
        let world: Vec<Point3<f64>> = points.iter().map(|p| pose * p).collect();
        // 4. Odometry and SLAM.
        let odometry = self
            .config
            .odometry
            .apply(&(tally.previous.inverse() * pose), &mut tally.odometry_rng);
        tally.previous = pose;
        let features = whisker_slam::features::whisk::whisk_features(&cycle, &points);
        let before = self.slam.map.experiences.len();
        let step = self.slam.whisk(&features, points.len(), &odometry);
        if let Some(s) = step {
            if s.created {
                tally.truth_at_creation.push((s.experience, pose));
            } else if s.relocalised {
                tally.truth_at_revisit.push((s.experience, pose));
            }
        }
        // 5. Recognition: re-localisations into a loaded map's experiences.
        let relocalised = relocalised_into(&self.slam.map, step, before);
        if let Some((experience, o)) = &relocalised {
            tally.relocalisations += 1;
            self.course.anchor_at(o.clone(), *experience, pose);
        }
        let onto = relocalised.map(|(_, o)| o);
        if let Some(r) = &mut self.recognition {
            r.update(onto.as_deref());
            for (o, s) in tally.rc_sums.iter_mut() {
                *s += r.raw.confidence[o];
            }
        }
        Whisked {
            pose,
            start,
            period,
            cycle,
            streams,
            world,
            odometry,
            features,
            step,
            onto,
        }
    }

    /// Step 6: the SPC's decision on the whisk's contacts and the strategy's bookkeeping.
    pub(super) fn decide(&mut self, w: &Whisked) -> SpcDecision {
        let decision = if self.config.spc {
            let p = &self.config.placement;
            self.spc.decide(p, &w.pose, &w.world, &mut self.fallbacks)
        } else {
            SpcDecision::Off
        };
        if w.world.is_empty() {
            self.fallbacks.count(Fallback::LostContact);
            self.course.abandon_step();
        } else if let Some(step) = w.step
            && let Some(r) = &self.recognition
        {
            self.course.replan(
                (&self.config, &self.slam.map),
                r,
                (w.onto.as_deref(), step.experience),
                (&w.features, &w.pose),
                !self.spc.is_pending(),
            );
        }
        decision
    }

    /// The whisk's row of `explore.csv`, its contacts, its record and its place in the
    /// outcome; progress every 10 physics whisks.
    pub(super) fn log(
        &mut self,
        iteration: usize,
        (goal, status): (Option<&(Isometry3<f64>, GoalKind)>, &'static str),
        w: Whisked,
        decision: SpcDecision,
        tally: &mut Tally,
        out: &mut Outcome,
    ) -> Result {
        let row = Row {
            iteration,
            time: self.time,
            goal,
            status,
            reached: &w.pose,
            joints: &self.robot.q,
            contacts: w.world.len(),
            step: w.step.as_ref(),
            onto: w.onto.as_deref(),
            recognition: self.recognition.as_ref(),
            heading: self.course.heading_name(),
            spc: decision.name(),
        };
        log::row(&mut out.csv, &row, &tally.objects);
        out.poses.push(w.pose);
        out.contacts.push(crate::sensing::contact::append_cycle(
            &mut out.contacts_csv,
            &w.cycle,
            &w.pose,
            &tally.pixels,
        ));
        if let (Some(rec), Some(contacts)) = (self.records.recording, out.contacts.last()) {
            let whisk = Whisk {
                iteration,
                start: w.start,
                period: w.period,
                goal,
                pose: &w.pose,
                contacts,
                step: w.step.as_ref(),
                onto: w.onto.as_deref(),
                spc: decision,
                streams: w.streams.as_deref(),
            };
            self.record(rec, &whisk)?;
        }
        out.times.push(self.time);
        out.joints.push(self.robot.q.clone());
        out.cycles.push(w.cycle);
        out.odometry.push(w.odometry);
        if matches!(self.sensing, Sensor::Physics(_)) && (iteration + 1).is_multiple_of(10) {
            self.records.reporter.note(&format!(
                "  explore: {}/{} whisks (physics), {} re-localisations",
                iteration + 1,
                self.config.max_iterations,
                tally.relocalisations
            ));
        }
        Ok(())
    }

    /// The run's summary (and end of the recording); the map built.
    pub(super) fn finish(&mut self, tally: Tally, mut out: Outcome) -> Result<Outcome> {
        let iterations = out.poses.len();
        let map_accuracy = map_accuracy::measure(
            &self.slam.map,
            &tally.truth_at_creation,
            &tally.truth_at_revisit,
        );
        let summary = Summary {
            task: self.config.task,
            truth: &self.truth,
            strategy: self.config.strategy,
            spc: self.config.spc,
            iterations,
            relocalisations: tally.relocalisations,
            experiences: self.slam.map.experiences.len(),
            faces_per_loop: self.course.faces_per_loop(),
            loops: self.course.loops(),
            recognition: self.recognition.as_ref(),
            mean_rc: tally
                .rc_sums
                .iter()
                .map(|(o, s)| (o.clone(), s / iterations.max(1) as f64))
                .collect(),
            fallbacks: &self.fallbacks,
            map_accuracy,
            time: self.time,
            lsr_plans: (self.config.strategy == Strategy::Lsr).then_some(self.course.lsr_plans()),
        };
        out.summary = summary.json();
        if let Some(rec) = self.records.recording {
            self.record_end(rec, &out.summary)?;
        }
        if self.config.task == Task::Map {
            let mut map = self.slam.map.rested();
            map.sensing = Some(self.sensed.clone());
            out.map = Some(map);
        }
        Ok(out)
    }

    pub(super) fn done(&self) -> bool {
        match (&self.recognition, self.config.task) {
            (_, Task::Map) => self.course.loops() >= self.config.map_loops,
            (Some(r), Task::Recognise) => {
                (self.config.stop_on_identity && r.identified().is_some())
                    || r.all_reached(self.config.stop_ic)
            }
            (None, Task::Recognise) => true,
        }
    }

    /// Step 1: the first goal the loop tries next — the SPC's pending correction, else the
    /// strategy's next goal (none: the array whisks where it is). Taking it moves the SPC
    /// and the strategy on, as trying it does.
    pub(super) fn next_goal(&mut self) -> Option<(Isometry3<f64>, GoalKind)> {
        let level = self.robot.array_pose().rotation * Vector3::y();
        match self.spc.take() {
            Some(p) => Some((p, GoalKind::Spc)),
            None => self.course.next_goal(&level),
        }
    }

    /// Step 2: the move to `first` (the goal of [`Self::next_goal`], its pose possibly
    /// replaced by a caller's); a refused goal is counted and, when `retry`, the next one
    /// tried ([`Self::next_goal`]), up to [`GOAL_ATTEMPTS`]. Returns the last goal tried
    /// and the move's status.
    pub(super) fn go(
        &mut self,
        first: Option<(Isometry3<f64>, GoalKind)>,
        retry: bool,
    ) -> (Option<(Isometry3<f64>, GoalKind)>, &'static str) {
        let mut goal = None;
        let mut status = "none";
        let mut next = first;
        for attempt in 0..GOAL_ATTEMPTS {
            if attempt > 0 {
                if !retry {
                    break;
                }
                next = self.next_goal();
            }
            let Some((mut pose, kind)) = next.take() else {
                break;
            };
            let mut motion = self.robot.move_to(&pose);
            // A face goal inside the object (a sphere cuts a box's corners) is pushed back
            // along its pointing axis, 2 cm at a time, up to 10 cm.
            if let GoalKind::Face(_) = kind {
                for k in 1..=RETREATS {
                    if !matches!(motion, Motion::Collision(_)) {
                        break;
                    }
                    let back = pose * Translation3::new(0.0, 0.0, -RETREAT_M * k as f64);
                    motion = self.robot.move_to(&back);
                    if matches!(motion, Motion::Reached { .. }) {
                        self.fallbacks.count(Fallback::PushedBack);
                        pose = back;
                    }
                }
            }
            status = motion.status();
            match motion {
                Motion::Reached { duration } => {
                    self.time += duration;
                    return (Some((pose, kind)), status);
                }
                Motion::Unreachable => self.fallbacks.count(Fallback::Unreachable),
                Motion::Collision(_) => self.fallbacks.count(Fallback::Collision),
            }
            // A refused SPC correction ends the region; a refused segment the step.
            self.spc.end_region();
            if let GoalKind::Step(_) = kind {
                self.course.abandon_step();
            }
            goal = Some((pose, kind));
        }
        (goal, status)
    }
}
