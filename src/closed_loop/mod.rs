//! The closed loop of thesis Chapter 6: the robot decides where to whisk next, moves there
//! with the arm, whisks, runs WhiskerRatSLAM, updates its confidence in each known object
//! and either builds an object map (§6.1.3) or stops once it has recognised the object
//! (§6.2). This is a library API: `whisker run` with an `[explore]` section, the tests and
//! batch trials all call [`run`].
//!
//! One iteration (one whisk, one SLAM step):
//! 1. the goal: the surface placement controller's correction when the last region is not
//!    settled (SPC on, at most K per region), otherwise the strategy's next goal — the
//!    ellipsoid's next face (map building), the sphere's next face (default), or the next
//!    segment of a step to an experience (FEH, LSR);
//! 2. the arm: IK from the current joints, a joint move at the speed limit, checked for
//!    collisions; a goal that is unreachable or would touch the object is dropped (the
//!    arm stays; counted) and the strategy's next goal tried, up to 8 times;
//! 3. one whisk cycle at the reached pose: kinematic sensing with the §6.1.3.1.2 contact
//!    noise (sub-streams `kinematic/whisker/NN`), or physics whiskers through the signal
//!    front end ([`Sensor`]);
//! 4. odometry since the last whisk with the Eq 6.4–6.11 noise (sub-stream
//!    `explore/odometry`), features (PFH + SDA), one WhiskerRatSLAM step (Alg 2);
//! 5. recognition: a re-localisation into an experience of a loaded map feeds that
//!    object's raw confidence; IC integrates it (§6.2);
//! 6. the SPC's decision on this whisk's contacts (world points: the robot knows its own
//!    arm) and the strategy's bookkeeping (re-planning on re-localisation).
//!
//! Fallbacks, all counted in `summary.json`: `unreachable` and `collision` goals (dropped;
//! a face goal that would touch the object is first pushed back along its axis, 2 cm at a
//! time up to 10 cm: `pushed_back`),
//! `lost_contact` (a whisk with no contact: FEH/LSR give way to the default trajectory),
//! `spc_limit` (a region left unsettled after K adjustments).

pub mod dataset;
mod log;
mod map_accuracy;
mod outputs;
pub mod robot;
mod strategy;
mod whisk_recording;

use crate::error::{Error, Result};
use crate::plan::Plan;
use crate::record::GraphSchedule;
use crate::record::SensorColumns;
use crate::record::{Recorder, Reporter, Silent};
use crate::scenario::explore::{ExploreConfig, Task};
use crate::scenario::{Scenario, Sensing};
use crate::sensing::held::PhysicsSensing;
use log::{Row, Summary};
use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use rand::RngExt;
use robot::{Motion, Robot};
use std::collections::{BTreeMap, VecDeque};
use std::path::Path;
use strategy::Heading;
use whisker_sim::environment::Environment;
use whisker_sim::sensing::kinematic::{KinematicArray, SweepTarget};
use whisker_slam::contact::ContactCycle;
use whisker_slam::exploration::goal_mesh::GoalMesh;
use whisker_slam::exploration::placement::{self, Placement};
use whisker_slam::exploration::tour::FaceTour;
use whisker_slam::recognition::Recognition;
use whisker_slam::rng::substream;
use whisker_slam::sensor::Sample;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

pub use log::{CSV_NAME, SUMMARY_NAME};
pub use outputs::{describe, write};

/// Attempts at a goal per iteration before the array whisks where it is.
const GOAL_ATTEMPTS: usize = 8;
/// A face goal that would touch the object is pushed back this far (m) …
const RETREAT_M: f64 = 0.02;
/// … at most this many times.
const RETREATS: usize = 5;

/// What a closed-loop run produced.
pub struct Outcome {
    /// `explore.csv`'s text.
    pub csv: String,
    /// `summary.json`'s value.
    pub summary: serde_json::Value,
    /// Map building: the object map built.
    pub map: Option<ObjectMap>,
    /// The true array pose at every whisk, for the recording.
    pub poses: Vec<Isometry3<f64>>,
    /// Each whisk's contacts (world), for the recording.
    pub contacts: Vec<Vec<crate::record::Contact>>,
    /// `contacts.csv`'s text: every registered contact of every whisk.
    pub contacts_csv: String,
    /// Each whisk's time (s).
    pub times: Vec<f64>,
    /// The chain configuration at every whisk.
    pub joints: Vec<Vec<f64>>,
    /// Each whisk's contacts (array frame), as SLAM saw them.
    pub cycles: Vec<ContactCycle>,
    /// Each whisk's odometry since the previous one (Eq 6.4–6.11 noise), as SLAM saw it.
    pub odometry: Vec<whisker_slam::sensor::Odometry>,
    /// The array's pose before the first move.
    pub start: Isometry3<f64>,
}

/// How a whisk is sensed.
enum Sensor {
    /// The anticipated intersect with the §6.1.3.1.2 noise (sub-streams
    /// `kinematic/whisker/NN`).
    Kinematic(KinematicArray),
    /// Physics whiskers of `[array]` held still for one whisk (RCP at the sensor's
    /// saturation unless `[array]` sets it), the signal front end and the radial-distance
    /// model of `[frontend]` (as `whisker object-slam --sensing physics`; sub-streams
    /// `explore/physics/<whisk>`).
    Physics(Box<PhysicsSensing>),
}

impl Sensor {
    /// One whisk cycle (number `k`, at time `t`) with the array held at `pose`, and the
    /// cycle's duration (s).
    /// Physics: also the whisk's samples of every whisker.
    fn whisk(
        &mut self,
        target: &SweepTarget,
        k: u64,
        t: f64,
        pose: &Isometry3<f64>,
        seed: u64,
    ) -> (ContactCycle, f64, Option<Vec<Vec<Sample>>>) {
        match self {
            Sensor::Kinematic(a) => (
                a.sense(target, k, t, pose),
                1.0 / a.patterns[0].frequency,
                None,
            ),
            Sensor::Physics(p) => {
                let (mut c, streams) = p.whisk_streams(
                    target,
                    k as usize,
                    pose,
                    seed,
                    &format!("explore/physics/{k}"),
                );
                c.start_s = t;
                (c, 1.0, Some(streams))
            }
        }
    }
}

/// The state of a run.
struct Loop<'a> {
    config: &'a ExploreConfig,
    truth: String,
    robot: Robot,
    sensing: Sensor,
    target: SweepTarget,
    slam: WhiskerRatSlam,
    recognition: Option<Recognition>,
    tour: FaceTour,
    start_face: usize,
    /// Pending SPC correction and the adjustments made in this region.
    spc: Option<Isometry3<f64>>,
    adjustments: usize,
    /// FEH/LSR: segments still to go of the current step, and the step's target.
    segments: VecDeque<Isometry3<f64>>,
    stepping_to: Option<usize>,
    heading: Heading,
    /// The last experience of a loaded map re-localised into and the true pose then.
    anchor: Option<(usize, Isometry3<f64>)>,
    fallbacks: BTreeMap<&'static str, usize>,
    time: f64,
    /// The recording, its map schedule and its buffered physics streams.
    recording: Option<&'a dyn Recorder>,
    reporter: &'a dyn Reporter,
    graph: GraphSchedule,
    columns: Option<SensorColumns>,
}

/// Runs the closed loop of `scenario` (read from `file`) in `environment`.
pub fn run(
    scenario: &Scenario,
    file: &Path,
    plan: Plan,
    environment: &Environment,
) -> Result<Outcome> {
    run_logged(scenario, file, plan, environment, None, None, &Silent)
}

/// [`run`], physics whisks' samples handed to `log` (stream `explore/physics/<k>`), each
/// whisk logged to `recording` ([`record`]).
pub fn run_logged(
    scenario: &Scenario,
    file: &Path,
    plan: Plan,
    environment: &Environment,
    log: Option<crate::sensing::held::WhiskLog>,
    recording: Option<&dyn Recorder>,
    reporter: &dyn Reporter,
) -> Result<Outcome> {
    let config = scenario
        .explore
        .as_ref()
        .ok_or_else(|| Error::field(file, "explore", "the scenario has no [explore] section"))?;
    let names = scenario.object_names();
    let truth = config.object_name(file, &names)?;
    let index = names.iter().position(|n| *n == truth).expect("validated");
    let piece = &environment.pieces[index];
    let world: Vec<Point3<f64>> = piece.mesh.vertices.iter().map(|v| piece.pose * v).collect();
    let (centre, half) = bounding_box(&world);
    let chain = crate::sensing::array::array_chain(scenario, file, &plan)?;
    let robot = Robot::new(plan, chain, environment, scenario.seed)?;
    let start_pose = robot.array_pose();
    let hits = robot.colliding(&robot.q);
    if !hits.is_empty() {
        return Err(Error::field(
            file,
            "arm.initial_joints_deg",
            format!(
                "the arm starts inside the environment ({})",
                hits.join(", ")
            ),
        ));
    }
    let sensing = match scenario.sensing {
        Sensing::Physics => {
            let mut p = PhysicsSensing::with_configs(
                environment.physics_pieces(),
                scenario.frontend.model(file)?,
                scenario.array.whisker_configs(file)?,
            );
            p.log = log;
            Sensor::Physics(Box::new(p))
        }
        _ => {
            let configs = scenario.array.whisker_configs(file)?;
            let whiskers = configs.iter().map(|c| c.rigid()).collect();
            let patterns = configs.iter().map(|c| c.pattern).collect();
            let noise = scenario.kinematic.noise(file)?;
            Sensor::Kinematic(KinematicArray::new(
                whiskers,
                patterns,
                noise,
                scenario.seed,
            ))
        }
    };
    let (map, recognition, mesh) = match config.task {
        Task::Map => {
            let semi = half * 3f64.sqrt() + Vector3::repeat(config.standoff_m);
            (
                ObjectMap::default(),
                None,
                GoalMesh::ellipsoid(centre, semi, config.mesh_faces),
            )
        }
        Task::Recognise => {
            let mut appended = ObjectMap::default();
            for (name, path) in config.map_files(file) {
                let m = ObjectMap::load(&path)
                    .map_err(|e| Error::field(file, &format!("explore.maps.{name}"), e))?;
                appended.append(&m, &name);
            }
            // The thesis' "bounding sphere + standoff" keeps a box's faces out of reach
            // (15 cm for the Box); the mean half extent + the SPC band's middle puts the
            // side faces in reach, so the default trajectory touches without the SPC too.
            let band = 0.5 * (config.placement.near_m + config.placement.far_m);
            let radius = config.sphere_radius_m.unwrap_or(half.mean() + band);
            let objects: Vec<String> = config.maps.keys().cloned().collect();
            (
                appended,
                Some(Recognition::new(objects, config.recognition)),
                GoalMesh::sphere(centre, radius, config.mesh_faces),
            )
        }
    };
    let tour = FaceTour::new(mesh, config.min_height_m);
    if tour.usable() == 0 {
        return Err(Error::field(
            file,
            "explore.min_height_m",
            "every goal face lies below it",
        ));
    }
    let start_face = match config.task {
        // Map building starts at the face nearest the arm's base.
        Task::Map => tour.nearest_usable(&Point3::origin()),
        // The default trajectory's start face comes from the seed (§6.3).
        Task::Recognise => {
            let mut rng = substream(scenario.seed, "explore/start-face");
            let usable = tour.usable_faces();
            usable[rng.random_range(0..usable.len())]
        }
    };
    let mut state = Loop {
        config,
        truth,
        robot,
        sensing,
        target: SweepTarget::of(environment),
        slam: WhiskerRatSlam::new(config.slam, map),
        recognition,
        tour,
        start_face,
        spc: None,
        adjustments: 0,
        segments: VecDeque::new(),
        stepping_to: None,
        heading: Heading::Default,
        anchor: None,
        fallbacks: BTreeMap::new(),
        time: 0.0,
        recording,
        reporter,
        graph: GraphSchedule::default(),
        columns: match (recording, scenario.sensing) {
            (Some(rec), Sensing::Physics) => Some(SensorColumns::new(
                rec,
                "sensors",
                &whisker_sim::whisker::array::labels(),
            )?),
            _ => None,
        },
    };
    state.run(scenario.seed, start_pose)
}

impl Loop<'_> {
    fn count(&mut self, what: &'static str) {
        *self.fallbacks.entry(what).or_default() += 1;
    }

    /// The strategy's next goal (not the SPC's), and its kind for the log.
    fn strategy_goal(&mut self) -> Option<(Isometry3<f64>, String)> {
        if let Some(seg) = self.segments.pop_front() {
            let to = self.stepping_to.map_or(String::new(), |e| e.to_string());
            return Some((seg, format!("step:{to}")));
        }
        let level = self.robot.array_pose().rotation * Vector3::y();
        let face = self.tour.next(self.start_face)?;
        Some((self.tour.goal(face, &level), format!("face:{face}")))
    }

    fn done(&self) -> bool {
        match (&self.recognition, self.config.task) {
            (_, Task::Map) => self.tour.loops >= self.config.map_loops,
            (Some(r), Task::Recognise) => r.all_reached(self.config.stop_ic),
            (None, Task::Recognise) => true,
        }
    }

    fn run(&mut self, seed: u64, start: Isometry3<f64>) -> Result<Outcome> {
        let mut odometry_rng = substream(seed, "explore/odometry");
        let objects: Vec<String> = self.config.maps.keys().cloned().collect();
        let mut previous = start;
        let mut out = Outcome {
            csv: log::header(&objects, self.robot.chain.dof()),
            summary: serde_json::Value::Null,
            map: None,
            poses: Vec::new(),
            contacts: Vec::new(),
            contacts_csv: crate::sensing::contact::HEADER.to_string(),
            times: Vec::new(),
            joints: Vec::new(),
            cycles: Vec::new(),
            odometry: Vec::new(),
            start,
        };
        let mut relocalisations = 0usize;
        let mut truth_at_creation: Vec<(usize, Isometry3<f64>)> = Vec::new();
        let mut truth_at_revisit: Vec<(usize, Isometry3<f64>)> = Vec::new();
        let mut rc_sums: BTreeMap<String, f64> = objects.iter().map(|o| (o.clone(), 0.0)).collect();
        let pixels: Vec<String> = whisker_sim::whisker::array::modules()
            .iter()
            .map(|m| m.pixel())
            .collect();
        for iteration in 0..self.config.max_iterations {
            if self.done() {
                break;
            }
            // 1–2. Goal and move.
            let (goal, status) = self.go();
            if self.done() {
                break;
            }
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
                .apply(&(previous.inverse() * pose), &mut odometry_rng);
            previous = pose;
            let features = whisker_slam::features::whisk::whisk_features(&cycle, &points);
            let before = self.slam.map.experiences.len();
            let step = self.slam.step(&features, &odometry);
            if step.created {
                truth_at_creation.push((step.experience, pose));
            } else if step.relocalised {
                truth_at_revisit.push((step.experience, pose));
            }
            // 5. Recognition: re-localisations into a loaded map's experiences.
            let onto = (step.relocalised && step.experience < before)
                .then(|| self.slam.map.experiences[step.experience].object.clone())
                .flatten();
            if onto.is_some() {
                relocalisations += 1;
                self.anchor = Some((step.experience, pose));
            }
            if let Some(r) = &mut self.recognition {
                r.update(onto.as_deref());
                for (o, s) in rc_sums.iter_mut() {
                    *s += r.raw.confidence[o];
                }
            }
            // 6. SPC and the strategy.
            let decision = if self.config.spc {
                self.place(&pose, &world)
            } else {
                "off"
            };
            if world.is_empty() {
                self.count("lost_contact");
                self.abandon_step();
            } else if let Some(r) = self.recognition.take() {
                self.replan(&r, onto.as_deref(), step.experience, &features, &pose);
                self.recognition = Some(r);
            }
            let row = Row {
                iteration,
                time: self.time,
                goal: goal.as_ref(),
                status,
                reached: &pose,
                joints: &self.robot.q,
                contacts: world.len(),
                step: &step,
                onto: onto.as_deref(),
                recognition: self.recognition.as_ref(),
                heading: self.heading.name(),
                spc: decision,
            };
            log::row(&mut out.csv, &row, &objects);
            out.poses.push(pose);
            out.contacts.push(crate::sensing::contact::append_cycle(
                &mut out.contacts_csv,
                &cycle,
                &pose,
                &pixels,
            ));
            if let (Some(rec), Some(contacts)) = (self.recording, out.contacts.last()) {
                let whisk = whisk_recording::Whisk {
                    iteration,
                    start,
                    period,
                    goal: goal.as_ref(),
                    pose: &pose,
                    contacts,
                    step: &step,
                    onto: onto.as_deref(),
                    spc: decision,
                    streams: streams.as_deref(),
                };
                self.record(rec, &whisk)?;
            }
            out.times.push(self.time);
            out.joints.push(self.robot.q.clone());
            out.cycles.push(cycle);
            out.odometry.push(odometry);
            if matches!(self.sensing, Sensor::Physics(_)) && (iteration + 1) % 10 == 0 {
                self.reporter.note(&format!(
                    "  explore: {}/{} whisks (physics), {relocalisations} re-localisations",
                    iteration + 1,
                    self.config.max_iterations
                ));
            }
        }
        let iterations = out.poses.len();
        let map_accuracy =
            map_accuracy::measure(&self.slam.map, &truth_at_creation, &truth_at_revisit);
        let summary = Summary {
            task: self.config.task,
            truth: &self.truth,
            strategy: self.config.strategy,
            spc: self.config.spc,
            iterations,
            relocalisations,
            experiences: self.slam.map.experiences.len(),
            faces_per_loop: self.tour.usable(),
            loops: self.tour.loops,
            recognition: self.recognition.as_ref(),
            mean_rc: rc_sums
                .iter()
                .map(|(o, s)| (o.clone(), s / iterations.max(1) as f64))
                .collect(),
            fallbacks: &self.fallbacks,
            map_accuracy,
            time: self.time,
        };
        out.summary = summary.json();
        if let Some(rec) = self.recording {
            self.record_end(rec, &out.summary)?;
        }
        if self.config.task == Task::Map {
            out.map = Some(self.slam.map.clone());
        }
        Ok(out)
    }

    /// Step 2: the next goal (the SPC's pending correction, else the strategy's), and the
    /// move there; a refused goal is counted and the next one tried, up to
    /// [`GOAL_ATTEMPTS`]. Returns the last goal tried and the move's status.
    fn go(&mut self) -> (Option<(Isometry3<f64>, String)>, &'static str) {
        let mut goal = None;
        let mut status = "none";
        for _ in 0..GOAL_ATTEMPTS {
            let (mut pose, kind) = match self.spc.take() {
                Some(p) => (p, "spc".to_string()),
                None => match self.strategy_goal() {
                    Some(g) => g,
                    None => break,
                },
            };
            let mut motion = self.robot.move_to(&pose);
            // A face goal inside the object (a sphere cuts a box's corners) is pushed back
            // along its pointing axis, 2 cm at a time, up to 10 cm.
            if kind.starts_with("face") {
                for k in 1..=RETREATS {
                    if !matches!(motion, Motion::Collision(_)) {
                        break;
                    }
                    let back = pose * Translation3::new(0.0, 0.0, -RETREAT_M * k as f64);
                    motion = self.robot.move_to(&back);
                    if matches!(motion, Motion::Reached { .. }) {
                        self.count("pushed_back");
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
                Motion::Unreachable => self.count("unreachable"),
                Motion::Collision(_) => self.count("collision"),
            }
            // A refused SPC correction ends the region; a refused segment the step.
            self.adjustments = 0;
            if kind.starts_with("step") {
                self.abandon_step();
            }
            goal = Some((pose, kind));
        }
        (goal, status)
    }

    /// Runs the SPC on this whisk's contacts; returns its decision's name.
    fn place(&mut self, pose: &Isometry3<f64>, world: &[Point3<f64>]) -> &'static str {
        let p = &self.config.placement;
        let decision = placement::correct(p, pose, world);
        let name = match decision {
            Placement::Approach(_) => "approach",
            Placement::Turn(_) => "turn",
            Placement::Move(_) => "move",
            Placement::BackOff(_) => "back_off",
            Placement::Done(_) => "done",
        };
        if matches!(decision, Placement::Done(_)) {
            self.adjustments = 0;
        } else if self.adjustments >= p.max_adjustments {
            self.count("spc_limit");
            self.adjustments = 0;
        } else {
            self.adjustments += 1;
            self.spc = decision.pose();
        }
        name
    }
}

/// The centre and half extents of a mesh's bounding box.
fn bounding_box(points: &[Point3<f64>]) -> (Point3<f64>, Vector3<f64>) {
    let (lo, hi) = whisker_sim::environment::mesh::bounds(points);
    (nalgebra::center(&lo, &hi), (hi - lo) / 2.0)
}
