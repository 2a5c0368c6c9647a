//! The state of a closed-loop run: the robot, its sensing, WhiskerRatSLAM, recognition,
//! the strategy's course, the SPC, what is recorded, and what a run produces.

use super::goal::{Fallbacks, GoalKind};
use super::placement::{Spc, SpcDecision};
use super::robot::Robot;
use super::strategy::Course;
use crate::record::{Contact, GraphSchedule, Recorder, Reporter, SensorColumns};
use crate::sensing::held::PhysicsSensing;
use nalgebra::Isometry3;
use nalgebra::Point3;
use std::collections::BTreeMap;
use whisker_scenario::explore::ExploreConfig;
use whisker_sim::sensing::kinematic::{KinematicArray, SweepTarget};
use whisker_slam::contact::ContactCycle;
use whisker_slam::features::similarity::Features;
use whisker_slam::recognition::Recognition;
use whisker_slam::rng::StreamRng;
use whisker_slam::sensor::Odometry;
use whisker_slam::sensor::Sample;
use whisker_slam::whisker_ratslam::object_map::{MapSensing, ObjectMap};
use whisker_slam::whisker_ratslam::slam::Step;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

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
    pub contacts: Vec<Vec<Contact>>,
    /// `contacts.csv`'s text: every registered contact of every whisk.
    pub contacts_csv: String,
    /// Each whisk's time (s).
    pub times: Vec<f64>,
    /// The chain configuration at every whisk.
    pub joints: Vec<Vec<f64>>,
    /// Each whisk's contacts (array frame), as SLAM saw them.
    pub cycles: Vec<ContactCycle>,
    /// Each whisk's odometry since the previous one (Eq 6.4–6.11 noise), as SLAM saw it.
    pub odometry: Vec<Odometry>,
    /// The array's pose before the first move.
    pub start: Isometry3<f64>,
    /// Physics: each whisker's detection levels, as the run detected.
    pub levels: Option<Vec<whisker_slam::frontend::contact::FrontEndParams>>,
}

/// How a whisk is sensed.
pub enum Sensor {
    /// The anticipated intersect with the §6.1.3.1.2 noise (sub-streams
    /// `kinematic/whisker/NN`).
    Kinematic(Box<KinematicArray>),
    /// Physics whiskers of `[array]` held still for one whisk (RCP as `[array] rcp`
    /// says), the signal front end of `[frontend]` (detection levels, radial-distance
    /// model; sub-streams `explore/physics/<whisk>`).
    Physics(Box<PhysicsSensing>),
}

impl Sensor {
    /// One whisk cycle (number `k`, at time `t`) with the array held at `pose`, and the
    /// cycle's duration (s).
    /// Physics: also the whisk's samples of every whisker.
    pub fn whisk(
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

/// The state of a run: the robot and its sensing, WhiskerRatSLAM and recognition, the
/// strategy's course, the SPC, the fallbacks counted, the simulated time and what is
/// recorded. Built by `setup::build`, stepped by `Episode` (`episode`, `iteration`); its
/// parts keep their own state behind their own methods.
pub struct Loop<'a> {
    pub(super) config: ExploreConfig,
    /// The explored object's name.
    pub(super) truth: String,
    pub(super) robot: Robot,
    pub(super) sensing: Sensor,
    pub(super) target: SweepTarget,
    pub(super) slam: WhiskerRatSlam,
    /// Recognition (none while building a map).
    pub(super) recognition: Option<Recognition>,
    pub(super) course: Course,
    pub(super) spc: Spc,
    pub(super) fallbacks: Fallbacks,
    /// Simulated time (s).
    pub(super) time: f64,
    pub(super) records: Records<'a>,
    /// How the run senses, as a map it builds records it.
    pub(super) sensed: MapSensing,
}

/// What a run records and says: the recording with its map schedule and buffered physics
/// streams, and the reporter of its progress.
pub struct Records<'a> {
    pub recording: Option<&'a dyn Recorder>,
    pub reporter: &'a dyn Reporter,
    pub graph: GraphSchedule,
    pub columns: Option<SensorColumns>,
}

/// What a run gathers whisk by whisk besides its outputs.
pub struct Tally {
    pub odometry_rng: StreamRng,
    /// The array's pose at the previous whisk.
    pub previous: Isometry3<f64>,
    pub relocalisations: usize,
    /// True poses where experiences were made and re-localised into (map accuracy).
    pub truth_at_creation: Vec<(usize, Isometry3<f64>)>,
    pub truth_at_revisit: Vec<(usize, Isometry3<f64>)>,
    /// Each loaded object's raw confidence, summed over the whisks.
    pub rc_sums: BTreeMap<String, f64>,
    /// The loaded objects.
    pub objects: Vec<String>,
    /// The whiskers' labels.
    pub pixels: Vec<String>,
}

/// One whisk and what WhiskerRatSLAM made of it.
pub struct Whisked {
    /// Where the array was, when the whisk started (s) and how long it took.
    pub pose: Isometry3<f64>,
    pub start: f64,
    pub period: f64,
    pub cycle: ContactCycle,
    /// Physics: every whisker's samples.
    pub streams: Option<Vec<Vec<Sample>>>,
    /// The contacts in the world.
    pub world: Vec<Point3<f64>>,
    pub odometry: Odometry,
    pub features: Features,
    /// None while no experience exists (whisks with fewer than μ contacts before the
    /// first with enough: a new experience needs contact).
    pub step: Option<Step>,
    /// The loaded object re-localised into, if any.
    pub onto: Option<String>,
}

/// One whisk's record.
pub struct Whisk<'a> {
    pub iteration: usize,
    /// When the whisk started and how long it took (s).
    pub start: f64,
    pub period: f64,
    pub goal: Option<&'a (Isometry3<f64>, GoalKind)>,
    pub pose: &'a Isometry3<f64>,
    pub contacts: &'a [Contact],
    pub step: Option<&'a Step>,
    pub onto: Option<&'a str>,
    pub spc: SpcDecision,
    /// Physics: every whisker's samples of the whisk.
    pub streams: Option<&'a [Vec<Sample>]>,
}

/// The loaded map a whisk's SLAM `step` re-localised into: an experience that existed
/// before the whisk (the map held `before`) and was recorded on a loaded object (§5.2.2.2);
/// that experience and the object's name.
pub fn relocalised_into(
    map: &ObjectMap,
    step: Option<Step>,
    before: usize,
) -> Option<(usize, String)> {
    let s = step.filter(|s| s.relocalised && s.experience < before)?;
    Some((s.experience, map.experiences[s.experience].object.clone()?))
}
