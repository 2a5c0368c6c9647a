//! Object mode on the mobile robot (issue #36; thesis Fig 5.1, Ch 6, §7.1): when the
//! mode-switch cue says "object", the base stops, the robot docks facing the outline, and
//! the Ch 6 closed loop (`[navigate.object.explore]`: SPC + a strategy, the known object
//! maps, a whisk budget, stopping at the first identity) runs there in the arm's base
//! frame: the environment is carried into it (B⁻¹, B the arm's base in the world), its
//! floor `mount_height_m` below the arm. The robot then undocks and drives on.
//!
//! - **Which object.** The closed loop's goal sphere is centred on the object's bounding
//!   box, as in Ch 6 where the object's place is given; the stop takes it from the piece
//!   the newest contact truly lies on. A stop at a wall (the cue wrong) runs no loop: it
//!   costs the turns and counts as a wrong switch.
//! - **Docking** ([`Dock`]). By default (`dock = "arm"`) the shoulder's pan joint turns
//!   the arm to face the outline's centre and the base stays: the closed loop runs in the
//!   arm's base frame turned about its vertical axis, which every configuration of the
//!   real arm spans. With `dock = "base"` the base turns in place to face the outline's
//!   centre and drives until it lies `dock_distance_m` ahead (the Ch 6 set-up: the
//!   object's centre ~0.55 m in front of the arm); after the loop it backs up and turns
//!   back. The odometry reads both legs with its errors (sub-stream
//!   `navigate/dock/<update>` of the seed); what they leave is carried into the next
//!   update's reading. The docked footprint is checked for collisions like the route's.
//! - **Unmapped objects.** A stop whose loop identifies nothing builds the object's map
//!   (Ch 6 map building, `map_whisks`) and learns it as `object-<n>` ([`Learned`]) for the
//!   stops after it.
//! - **Seeds.** Each stop's closed loop runs with seed `substream_key(seed,
//!   "navigate/stop/<update>")`, so no two stops share their noise.
//! - **The landmark.** An identity becomes a landmark in the planar map
//!   ([`whisker_slam::ratslam::RatSlam::step_landmark`], when `navigate.fusion`): the
//!   first recognition makes its template, the next closes the loop there.

use crate::closed_loop;
use crate::record::Recorder;
use nalgebra::{Isometry3, Point2};
use std::collections::BTreeMap;
use whisker_scenario::explore::{ExploreConfig, Task};
use whisker_scenario::object_mode::ObjectModeConfig;
use whisker_scenario::plan::Plan;
use whisker_scenario::{Error, Result};
use whisker_scenario::{Experiment, ScenarioFile};
use whisker_sim::environment::Environment;
use whisker_slam::navigation::base_odometry::{BaseMotion, BaseOdometryNoise};
use whisker_slam::pose::{Pose2, wrap};
use whisker_slam::ratslam::{RatSlam, Step};
use whisker_slam::rng::{substream, substream_key};
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// What one stop found (the default: a stop at a wall, no loop run).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Episode {
    /// The object's name, or none when the stop was at a wall or the floor plan.
    pub object: Option<String>,
    /// What the closed loop identified (none: no object's IC reached the threshold).
    pub identified: Option<String>,
    /// The true object the identified map stands for: the identity itself for a known
    /// map, the object it was built at for a learned one.
    pub stands_for: Option<String>,
    /// The name of the map built here (an unmapped object, `map_unmapped`).
    pub mapped: Option<String>,
    /// Each known object's integrated confidence IC at the end (§6.2).
    pub ic: BTreeMap<String, f64>,
    /// Closed-loop whisks: recognition, and map building when it mapped.
    pub whisks: usize,
    /// Simulated time of those closed loops (s).
    pub time_s: f64,
}

impl Episode {
    /// "correct", "wrong", "none" (nothing identified) or "wall" (the cue stopped at a
    /// wall).
    pub fn outcome(&self) -> &'static str {
        match (&self.object, &self.stands_for) {
            (None, _) => "wall",
            (Some(_), None) => "none",
            (Some(o), Some(i)) if o == i => "correct",
            _ => "wrong",
        }
    }
}

/// A stop's closed loop as the robot logged it (datasets): each whisk's contacts (array
/// frame) and 6-D odometry as SLAM saw them, the array's pose before the first move, and
/// (ground truth) each whisk's time and reached pose in the arm's base frame.
#[derive(Debug, Clone)]
pub struct LoopLog {
    pub cycles: Vec<whisker_slam::contact::ContactCycle>,
    pub odometry: Vec<whisker_slam::sensor::Odometry>,
    pub start: Isometry3<f64>,
    pub times: Vec<f64>,
    pub poses: Vec<Isometry3<f64>>,
}

impl LoopLog {
    fn of(o: &closed_loop::Outcome) -> Self {
        Self {
            cycles: o.cycles.clone(),
            odometry: o.odometry.clone(),
            start: o.start,
            times: o.times.clone(),
            poses: o.poses.clone(),
        }
    }
}

/// A stop's closed loops: recognition, and map building when it identified nothing.
#[derive(Debug, Clone, Default)]
pub struct Loops {
    pub recognise: Option<LoopLog>,
    pub map: Option<LoopLog>,
}

/// The turn in place (rad) that faces the base at `base` towards `centre` (both in the
/// same frame): the bearing of the centre from the base's heading.
pub fn facing(base: &Pose2, centre: &Point2<f64>) -> f64 {
    wrap((centre.y - base.y).atan2(centre.x - base.x) - base.th)
}

/// How the base docks at a stop: it turns `turn` (rad) in place towards the outline, then
/// drives `drive` (m) straight at it; after the closed loop it backs the same distance and
/// turns back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dock {
    pub turn: f64,
    pub drive: f64,
}

impl Dock {
    /// The dock from `base` that brings `centre` (same frame) `distance` ahead of the
    /// base's centre (never driving backwards to get there).
    pub fn toward(base: &Pose2, centre: &Point2<f64>, distance: f64) -> Self {
        let d = (centre.x - base.x).hypot(centre.y - base.y);
        Self {
            turn: facing(base, centre),
            drive: (d - distance).max(0.0),
        }
    }

    /// Where the base stands docked, from `base`.
    pub fn docked(&self, base: &Pose2) -> Pose2 {
        self.out().apply(base)
    }

    fn out(&self) -> BaseMotion {
        BaseMotion {
            rot1: self.turn,
            trans: self.drive,
            rot2: 0.0,
        }
    }

    /// The odometry's reading of the whole manoeuvre, out and back, as one motion (truly
    /// none): each leg read with the model's errors (sub-stream `navigate/dock/<update>`
    /// of `seed`); backing up is read as driving forward, the distance's sign flipped.
    pub fn reading(&self, noise: &BaseOdometryNoise, seed: u64, update: usize) -> BaseMotion {
        let mut rng = substream(seed, &format!("navigate/dock/{update}"));
        let out = noise.read(&self.out(), &mut rng);
        let back = BaseMotion {
            rot1: 0.0,
            trans: self.drive,
            rot2: -self.turn,
        };
        let back = noise.read(&back, &mut rng);
        let start = Pose2::default();
        let there = out.apply(&start);
        let heading = there.th + back.rot1;
        let end = Pose2 {
            x: there.x - back.trans * heading.cos(),
            y: there.y - back.trans * heading.sin(),
            th: wrap(heading + back.rot2),
        };
        BaseMotion::between(&start, &end)
    }
}

/// `first` then `then`, as one motion.
pub fn compose(first: &BaseMotion, then: &BaseMotion) -> BaseMotion {
    let start = Pose2::default();
    BaseMotion::between(&start, &then.apply(&first.apply(&start)))
}

/// Starts the recording of a stop's closed loop: its name (`NNNNNN-recognise`,
/// `NNNNNN-map`) and what its camera frames (the object, in the arm's base frame).
pub type StopRecorder<'a> = &'a dyn Fn(&str, &Environment) -> Result<Box<dyn Recorder>>;

/// What a stop's closed loop runs in: the scenario's `file`, its arm and the office;
/// `record` records each loop (none: no recordings).
pub struct Setting<'a> {
    pub file: &'a ScenarioFile,
    pub plan: &'a Plan,
    pub environment: &'a Environment,
    pub record: Option<StopRecorder<'a>>,
}

/// Runs the closed loop `config` of `stop` in `local` knowing `learned`, recorded as
/// `name` when `record` is given (the camera on `focus`): the loop's whisks, then the
/// arm's motion.
fn recorded_loop(
    (stop, config, plan): (&ScenarioFile, &ExploreConfig, &Plan),
    (local, focus): (&Environment, &Environment),
    learned: &[(String, ObjectMap)],
    record: Option<StopRecorder>,
    name: &str,
) -> Result<closed_loop::Outcome> {
    let rec = match record {
        Some(start) => {
            let rec = start(name, focus)?;
            rec.environment(local)?;
            Some(rec)
        }
        None => None,
    };
    let outcome =
        closed_loop::run_recorded(stop, config, plan.clone(), local, learned, rec.as_deref())?;
    if let Some(rec) = rec {
        closed_loop::record_arm(rec.as_ref(), plan, &outcome)?;
        rec.finish()?;
    }
    Ok(outcome)
}

/// Runs the closed loop of `config` at the object `piece` of the setting's environment
/// (an index of `scenario.objects`), the arm's base at `arm_base` in the world; `update`
/// names the stop's seed.
pub fn explore(
    setting: &Setting,
    config: &ObjectModeConfig,
    arm_base: &Isometry3<f64>,
    piece: usize,
    update: usize,
    learned: &mut Learned,
) -> Result<(Episode, Loops)> {
    let Setting {
        file,
        plan,
        environment,
        record,
    } = *setting;
    let name = file.scenario.object_names()[piece].clone();
    let mut stop = file.clone();
    let recognise = config.episode(&name);
    stop.scenario.experiment = Experiment::ClosedLoop(Box::new(recognise.clone()));
    stop.scenario.seed = substream_key(file.scenario.seed, &format!("navigate/stop/{update}"));
    let to_base = arm_base.inverse();
    let mut local = environment.clone();
    for p in &mut local.pieces {
        p.pose = to_base * p.pose;
    }
    let at = (&stop, &recognise, plan);
    let focus = Environment {
        pieces: vec![local.pieces[piece].clone()],
    };
    let loop_name = format!("{update:06}-recognise");
    let outcome = recorded_loop(at, (&local, &focus), &learned.maps, record, &loop_name)?;
    let mut loops = Loops {
        recognise: Some(LoopLog::of(&outcome)),
        map: None,
    };
    let s = &outcome.summary;
    let identified = s["recognition"]["identified"].as_str().map(String::from);
    let (whisks, time_s) = effort(s)?;
    let ic = s["recognition"]["final_ic"]
        .as_object()
        .map(|m| {
            m.iter()
                .map(|(k, v)| (k.clone(), v.as_f64().unwrap_or(f64::NAN)))
                .collect()
        })
        .unwrap_or_default();
    let mut episode = Episode {
        stands_for: identified
            .as_ref()
            .map(|i| learned.built_at.get(i).unwrap_or(i).clone()),
        object: Some(name.clone()),
        identified,
        ic,
        whisks,
        time_s,
        mapped: None,
    };
    if episode.identified.is_none() && config.map_unmapped {
        // None of the known objects: build its map (Ch 6 map building) and learn it.
        let mapping = ExploreConfig {
            task: Task::Map,
            maps: Default::default(),
            max_iterations: config.map_whisks,
            ..recognise
        };
        stop.scenario.experiment = Experiment::ClosedLoop(Box::new(mapping.clone()));
        let loop_name = format!("{update:06}-map");
        let at = (&stop, &mapping, plan);
        let built = recorded_loop(at, (&local, &focus), &[], record, &loop_name)?;
        let (whisks, time_s) = effort(&built.summary)?;
        episode.whisks += whisks;
        episode.time_s += time_s;
        loops.map = Some(LoopLog::of(&built));
        if let Some(map) = built.map {
            let label = format!("object-{}", learned.maps.len() + 1);
            learned.built_at.insert(label.clone(), name);
            learned.maps.push((label.clone(), map));
            episode.mapped = Some(label);
        }
    }
    Ok((episode, loops))
}

/// A closed loop's whisks and simulated time (s), from its `summary.json` value.
fn effort(summary: &serde_json::Value) -> Result<(usize, f64)> {
    let whisks = summary["iterations"]
        .as_u64()
        .ok_or_else(|| Error::Failure("the closed loop's summary has no iterations".into()))?;
    let time_s = summary["simulated_time_s"].as_f64().unwrap_or(f64::NAN);
    Ok((whisks as usize, time_s))
}

/// The object maps the robot built at stops where it recognised nothing (names
/// `object-<n>`), and the true object each was built at (for scoring only).
#[derive(Debug, Clone, Default)]
pub struct Learned {
    pub maps: Vec<(String, ObjectMap)>,
    pub built_at: BTreeMap<String, String>,
}

/// The landmarks in the planar map: each an identity and the experience it was first
/// seen at. An identity re-observed within `gate_m` of one of its landmarks (the map's
/// current estimate against the landmark experience's relaxed pose) is that one; else a
/// new landmark of that identity (keyed `identity#n` in the local view).
#[derive(Debug, Clone, Default)]
pub struct Landmarks {
    pub gate_m: f64,
    /// (identity, experience) of each landmark, in order of creation.
    pub known: Vec<(String, usize)>,
}

impl Landmarks {
    /// No landmarks yet.
    pub fn new(gate_m: f64) -> Self {
        Self {
            gate_m,
            known: Vec::new(),
        }
    }

    /// One RatSLAM step on the recognised `identity` (energy `energy` when re-observed).
    pub fn observe(&mut self, slam: &mut RatSlam, identity: &str, energy: f64) -> Step {
        let here = slam.map.pose();
        let near = self
            .known
            .iter()
            .enumerate()
            .filter(|(_, (id, _))| id == identity)
            .map(|(i, (_, e))| {
                let p = slam.map.experiences[*e].pose;
                (i, (p.x - here.x).hypot(p.y - here.y))
            })
            .filter(|&(_, d)| d <= self.gate_m)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let n = near.map_or(self.known.len(), |(i, _)| i);
        let step = slam.step_landmark(&format!("{identity}#{n}"), energy, 0.0, 0.0);
        if near.is_none() {
            self.known.push((identity.to_string(), step.experience));
        }
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn facing_is_the_bearing_from_the_heading() {
        let base = Pose2 {
            x: 1.0,
            y: 1.0,
            th: std::f64::consts::FRAC_PI_2,
        };
        // Straight to the base's right (east while it faces north): −90°.
        let turn = facing(&base, &Point2::new(1.65, 1.0));
        assert!((turn + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Ahead and to the left: +45°.
        let turn = facing(&base, &Point2::new(0.5, 1.5));
        assert!((turn - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
    }

    /// Docking brings the centre `distance` ahead; noise-free odometry reads the
    /// manoeuvre as no motion; with noise the heading error follows the seed and the update
    /// and its spread is the model's: rot1 and rot2 of both legs, σ = α₁|turn| + α₂·drive
    /// on the turns and α₂·drive on the others.
    #[test]
    fn the_dock_faces_the_outline_and_its_reading_follows_the_model() {
        let base = Pose2 {
            x: 1.0,
            y: 1.0,
            th: 0.3,
        };
        let centre = Point2::new(1.2, 1.9);
        let dock = Dock::toward(&base, &centre, 0.45);
        let docked = dock.docked(&base);
        let ahead = (centre.x - docked.x, centre.y - docked.y);
        assert!((ahead.0.hypot(ahead.1) - 0.45).abs() < 1e-12);
        assert!((ahead.1.atan2(ahead.0) - docked.th).abs() < 1e-12);
        let exact = BaseOdometryNoise {
            enabled: false,
            ..BaseOdometryNoise::default()
        };
        let r = dock.reading(&exact, 3, 7);
        assert!(
            r.trans.abs() < 1e-12 && (r.rot1 + r.rot2).abs() < 1e-12,
            "{r:?}"
        );
        let noise = BaseOdometryNoise::default();
        assert_eq!(dock.reading(&noise, 3, 7), dock.reading(&noise, 3, 7));
        assert_ne!(dock.reading(&noise, 3, 7), dock.reading(&noise, 3, 8));
        let n = 4000;
        let var = (0..n)
            .map(|k| {
                let r = dock.reading(&noise, 1, k);
                wrap(r.rot1 + r.rot2).powi(2)
            })
            .sum::<f64>()
            / n as f64;
        let [a1, a2, ..] = noise.alpha;
        let (t, d) = (dock.turn.abs(), dock.drive);
        let want = 2.0 * (a1 * t + a2 * d).powi(2) + 2.0 * (a2 * d).powi(2);
        assert!((var / want - 1.0).abs() < 0.1, "{var} vs {want}");
    }

    /// Composing a quarter turn and a metre's drive: the base ends a metre to the left.
    #[test]
    fn composed_motions_end_where_both_take_the_base() {
        let turn = BaseMotion {
            rot2: std::f64::consts::FRAC_PI_2,
            ..BaseMotion::default()
        };
        let drive = BaseMotion {
            trans: 1.0,
            ..BaseMotion::default()
        };
        let end = compose(&turn, &drive).apply(&Pose2::default());
        assert!(end.x.abs() < 1e-12 && (end.y - 1.0).abs() < 1e-12);
        assert!((end.th - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    /// A learned map is scored by the object it was built at, a known one by its name.
    #[test]
    fn a_learned_map_is_scored_by_where_it_was_built() {
        let e = |object: Option<&str>, stands_for: Option<&str>| Episode {
            object: object.map(String::from),
            identified: stands_for.map(|_| "object-1".to_string()),
            stands_for: stands_for.map(String::from),
            ..Episode::default()
        };
        assert_eq!(e(Some("barrel"), Some("barrel")).outcome(), "correct");
        assert_eq!(e(Some("box"), Some("barrel")).outcome(), "wrong");
        assert_eq!(e(Some("barrel"), None).outcome(), "none");
        assert_eq!(e(None, None).outcome(), "wall");
    }

    /// Data association: "box" seen again near its landmark closes onto it; "box" seen
    /// 3.5 m away (beyond the gate) is a second box, a new landmark, not a closure.
    #[test]
    fn a_landmark_is_the_same_only_within_the_gate() {
        let mut slam = RatSlam::new(whisker_scenario::navigate::office_ratslam());
        let mut marks = Landmarks::new(1.5);
        let blank = whisker_slam::ratslam::local_view::TactileImage::default();
        let first = marks.observe(&mut slam, "box", 1.0);
        let drive = |slam: &mut RatSlam, n: usize| {
            for _ in 0..n {
                slam.step_gated(&blank, 0.1, 0.0, false);
            }
        };
        drive(&mut slam, 35);
        let far = marks.observe(&mut slam, "box", 1.0);
        assert!(far.new_template && far.template != first.template);
        assert_eq!(marks.known.len(), 2);
        // Back 3.4 m (turned round): within the gate of the first box.
        slam.step_gated(&blank, 0.0, std::f64::consts::PI, false);
        drive(&mut slam, 34);
        let again = marks.observe(&mut slam, "box", 1.0);
        assert_eq!(again.template, first.template);
        assert_eq!(again.experience, first.experience);
        assert_eq!(marks.known.len(), 2);
        assert_eq!(
            slam.view.templates[first.template].landmark.as_deref(),
            Some("box#0")
        );
    }
}
