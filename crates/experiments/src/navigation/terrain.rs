//! Terrain mode in the office (issue #36; thesis Ch 3 on the platform of Fig 5.1, §7.1):
//! the base drives its route while the arm holds the array in a fixed posture beside it,
//! its whiskers reaching the walls the route follows; each update is one whisk (1 Hz, the
//! whisking frequency) at the base's pose, its contacts become a tactile image, and planar
//! RatSLAM takes the image with the base's odometry.
//!
//! - **Posture.** `[navigate.terrain]` gives the array's pose in the arm's base frame; IK
//!   (from the arm's initial joints) finds the joints that hold it, and the arm's base link
//!   stands `mount_height_m` above the floor at the base's centre. The array's world pose
//!   at base pose B = (x, y, θ) is B (lifted to the mount) × the posture's array pose.
//! - **Sensing.** The kinematic sweep (the anticipated intersect of each rigid whisker,
//!   the `[kinematic]` detection noise; sub-stream `navigate/sensing` of the seed) at that
//!   pose. A whisker's pixel is its contact angle scaled so that an early contact is
//!   bright ([`super::navigator::image`]): along a wall beside the array the angle at which a whisker meets
//!   it is what changes with the wall's distance and shape, as the tip's height is over
//!   the maze's board (§3.1.1, where the array faces the surface).
//! - **RatSLAM.** One [`RatSlam::step_gated`] per update with the odometry's drive and
//!   its two turns summed (the route turns in place or drives straight, so one of the two
//!   is noise), pose cells of `[navigate.ratslam]`. A whisk that touched nothing is blank
//!   and says nothing of the place: its template does not inject (blank templates matching
//!   each other would pull the pose cells to wherever the first blank whisk was; on the
//!   default office this made no systematic difference, docs/navigation.md).
//! - **The mode-switch cue** ([`super::plan_view`]) after every whisk while the latest
//!   whisks hold a contact, on their contacts and free points in the odometry frame,
//!   scored against the piece the newest contact lies on.
//! - **Object mode** ([`super::object_mode`], with `[navigate.object]`): at the cue's
//!   "object" the base stops, the arm (or the base) faces the outline, the Ch 6 closed loop
//!   identifies it, and with `navigate.fusion` the identity becomes a landmark step of the
//!   planar map. Every step is judged against the truth ([`super::closures`]);
//!   `navigate.kidnap` carries the robot at the start of the last lap ([`route::kidnap`]).
//! - **Checks.** Every update, the base's disc ([`super::footprint`]) and every arm link
//!   are tested against the environment; a run that touches anything says where.

use super::closures::{self, Closures, StepRecord};
use super::navigator::Navigator;
use super::object_mode::{self, Episode};
use super::plan_view::{self, SwitchTally};
use super::posture::Posture;
use super::{footprint, route};
use crate::maze_slam::run_recording::RunRecording;
use crate::record::Reporter;
use crate::sensing::held::PhysicsSensing;
use nalgebra::{Isometry3, Point2, Point3};
use whisker_scenario::Scenario;
use whisker_scenario::ScenarioFile;
use whisker_scenario::Sensing;
use whisker_scenario::navigate::NavigateConfig;
use whisker_scenario::object_mode::DockBy;
use whisker_scenario::plan::Plan;
use whisker_scenario::{Error, Result};
use whisker_sim::arm::LinkShapes;
use whisker_sim::environment::Environment;
use whisker_sim::environment::solids::Solids;
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::physics::WhiskerConfig;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::contact::ContactCycle;
use whisker_slam::navigation::base_odometry::BaseMotion;
use whisker_slam::navigation::map_error::{self, MapError};
use whisker_slam::navigation::mode_switch::Verdict;
use whisker_slam::pose::Pose2;
use whisker_slam::ratslam::experience_map::MapEvent;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::metrics::{
    ExperienceMetric, consecutive, energy_metric, experience_metric,
};
use whisker_slam::rng::substream_key;

/// Updates per second: one whisk each at the whisking frequency (1 Hz).
pub const UPDATE_HZ: f64 = 1.0;

/// How the terrain whisks are sensed.
enum Whisks {
    /// The kinematic sweep, whisk by whisk (sub-stream `navigate/sensing`).
    Kinematic(KinematicArray),
    /// Physics whiskers of `[array]` held at each update's array pose through the signal
    /// front end, all simulated first, in parallel (streams `navigate/physics/<update>`).
    Physics(std::vec::IntoIter<ContactCycle>),
}

impl Whisks {
    /// Update `k`'s whisk at `pose` (time `t`), and the world point its newest contact
    /// truly lies at: the sweep's noise-free intersect, or (physics) the sensed point.
    fn next(
        &mut self,
        target: &SweepTarget,
        k: usize,
        t: f64,
        pose: &Isometry3<f64>,
    ) -> (ContactCycle, Option<Point3<f64>>) {
        match self {
            Self::Kinematic(a) => {
                let c = a.sense(target, k as u64, t, pose);
                let p = c.contacts.last().map(|n| {
                    a.intersects
                        .iter()
                        .find(|(w, _)| *w == n.whisker)
                        .expect("a detected contact has its intersect")
                        .1
                });
                (c, p)
            }
            Self::Physics(cycles) => {
                let mut c = cycles.next().expect("one physics whisk per update");
                c.start_s = t;
                let p = c.contacts.last().map(|n| c.array_pose * n.point);
                (c, p)
            }
        }
    }
}

/// The whiskers (rigid, for the images and free points) and the whisks of `scenario`'s
/// sensing; `poses` gives every update's array pose (physics simulates them first).
fn whisks(
    file: &ScenarioFile,
    environment: &Environment,
    target: &SweepTarget,
    reporter: &dyn Reporter,
    poses: impl FnOnce() -> Vec<Isometry3<f64>>,
) -> Result<(Vec<RigidWhisker>, Whisks)> {
    let scenario = &file.scenario;
    let configs = file.whisker_configs()?;
    let whiskers = shafts(file, &configs);
    Ok(match scenario.sensing {
        Sensing::Physics => {
            let physics = PhysicsSensing::of_scenario(file, environment.physics_pieces())?;
            let cycles = physics.sense(target, &poses(), scenario.seed, "navigate", reporter);
            (whiskers, Whisks::Physics(cycles.into_iter()))
        }
        _ => {
            let patterns = vec![WhiskingPattern::default(); whiskers.len()];
            let noise = scenario.kinematic.noise(&file.path)?;
            let key = substream_key(scenario.seed, "navigate/sensing");
            let array = KinematicArray::new(whiskers.clone(), patterns, noise, key)
                .with_control(configs[0].control);
            (whiskers, Whisks::Kinematic(array))
        }
    })
}

/// The straight shafts a run's images and free points are made with (its whiskers
/// `configs`): the physics array's, or the kinematic sweep's.
pub fn shafts(file: &ScenarioFile, configs: &[WhiskerConfig]) -> Vec<RigidWhisker> {
    match file.scenario.sensing {
        Sensing::Physics => configs.iter().map(|c| c.rigid()).collect(),
        _ => crate::maze_slam::kinematic_whiskers(),
    }
}

/// One update of a terrain run.
#[derive(Debug, Clone)]
pub struct Update {
    /// The base's true pose.
    pub truth: Pose2,
    /// The robot's clock at the whisk (s): the updates and the stops before it.
    pub time_s: f64,
    /// What the odometry read since the previous update (none at the first).
    pub reading: BaseMotion,
    /// Contacts detected.
    pub contacts: usize,
    /// The tactile image.
    pub image: TactileImage,
    /// The template matched or made, and the current experience after the update.
    pub template: usize,
    pub experience: usize,
    /// What the experience map did.
    pub event: MapEvent,
    /// The mode-switch cue's verdict while the window holds a contact, and the piece the
    /// window's newest contact truly lies on ([`super::plan_view`]).
    pub switch: Option<(Verdict, String)>,
}

/// A stop in object mode ([`object_mode`]).
#[derive(Debug, Clone)]
pub struct Stop {
    /// The update after which the base stopped, and where it truly stood.
    pub update: usize,
    pub truth: Pose2,
    /// How it docked.
    pub dock: object_mode::Dock,
    /// The outline's centre in the odometry frame.
    pub centre: Point2<f64>,
    /// What the closed loop found.
    pub episode: Episode,
    /// The landmark's step in the planar map (fused runs that identified something): the
    /// experience and what the map did.
    pub landmark: Option<(usize, MapEvent)>,
    /// The stop's time: the closed loops, the turns there and back, and the base's
    /// drives (s).
    pub time_s: f64,
    /// The closed loops as the robot logged them.
    pub loops: object_mode::Loops,
}

/// The time (s) a stop's dock takes there and back: the turns (the base's at
/// `turn_rate_deg_s`, or the arm's pan at its joint speed limit) and the base's drives.
fn dock_time(
    dock: &object_mode::Dock,
    by_base: bool,
    config: &NavigateConfig,
    scenario: &Scenario,
) -> f64 {
    2.0 * dock.drive / config.base.speed_m_s
        + 2.0
            * match by_base {
                true => dock.turn.abs().to_degrees() / config.base.turn_rate_deg_s,
                false => dock.turn.abs() / scenario.arm.joint_speed_limit_rad_s,
            }
}

/// A terrain run and its evaluation.
pub struct TerrainRun {
    /// Every update, the start first.
    pub updates: Vec<Update>,
    /// Each update's whisk: its contacts (array frame) as SLAM saw them.
    pub cycles: Vec<ContactCycle>,
    /// Each update's estimate: the final relaxed map's pose of the experience current
    /// then, the first update's experience placed at the start pose.
    pub estimate: Vec<Pose2>,
    /// The odometry alone, integrated from the start pose (the baseline).
    pub dead_reckoned: Vec<Pose2>,
    /// The estimate's and the dead-reckoned path's errors after their best rigid fits.
    pub map_error: Option<MapError>,
    pub odometry_error: Option<MapError>,
    /// ARR and ARCR (Algorithm 1; base set = the first lap; 0.1 m and 25°).
    pub metric: ExperienceMetric,
    /// The Energy Metric (Eq 3.2 on consecutive updates).
    pub energy: f64,
    pub templates: usize,
    pub experiences: usize,
    /// The last update of the first lap.
    pub first_lap_end: usize,
    /// (update, link or piece) of every collision: the arm's links, the base's disc.
    pub arm_collisions: Vec<(usize, String)>,
    pub base_collisions: Vec<(usize, String)>,
    /// The arm holding the array: its joints, the array over the base.
    pub posture: Posture,
    /// The mode-switch cue's verdicts against the truth.
    pub switch: SwitchTally,
    /// Object mode's stops.
    pub stops: Vec<Stop>,
    /// Every re-localisation judged against the truth; the kidnapped robot's recovery.
    pub closures: Closures,
    /// The robot's time over the run (s): the updates and the stops.
    pub time_s: f64,
}

/// Runs terrain mode over `config`'s route in `environment` (scenario `scenario`, read
/// from `file`, its arm `plan`), with object mode's stops when `[navigate.object]` is
/// given, its progress said to `reporter`; with `recording`, each update into the office's
/// recording and each stop's closed loops into recordings of their own.
pub fn run(
    file: &ScenarioFile,
    plan: &Plan,
    environment: &Environment,
    config: &NavigateConfig,
    reporter: &dyn Reporter,
    recording: Option<(&mut RunRecording, object_mode::StopRecorder)>,
) -> Result<TerrainRun> {
    let scenario = &file.scenario;
    let (mut recording, record) = match recording {
        Some((run, stops)) => (Some(run), Some(stops)),
        None => (None, None),
    };
    let chain = crate::sensing::array::array_chain(file, plan)?;
    let posture = Posture::solve(&config.terrain, &chain, &plan.waypoints[0], &file.path)?;
    let route = route::poses(config, 1.0 / UPDATE_HZ);
    let (truth, carried) = match config.kidnap {
        false => (route, None),
        true => {
            let (cut, j) = route::kidnap(&route, config).ok_or_else(|| {
                Error::field(
                    &file.path,
                    "navigate.kidnap",
                    "the route never reaches its middle waypoint",
                )
            })?;
            (cut, Some(j))
        }
    };
    let mut readings = route::odometry(&truth, &config.odometry, scenario.seed);
    if let Some(j) = carried {
        // Carried: the wheels did not turn.
        readings[j - 1] = BaseMotion::default();
    }
    // The base's disc stands as tall as the arm's mount.
    let mut base_collisions = footprint::collisions(
        environment,
        &truth,
        config.base.radius_m,
        config.terrain.mount_height_m,
    )?;
    let solids = Solids::new(environment).map_err(|e| Error::Failure(e.to_string()))?;
    let shapes = LinkShapes::new(&plan.model);
    let joints = plan.model_joints(&posture.q);

    let target = SweepTarget::of(environment);
    let (whiskers, mut whisks) = whisks(file, environment, &target, reporter, || {
        truth.iter().map(|b| posture.array_pose(b)).collect()
    })?;
    let mut robot = Navigator::of(config, whiskers, posture.clone());
    let mut updates = Vec::with_capacity(truth.len());
    let mut cycles = Vec::with_capacity(truth.len());
    let mut steps = Vec::with_capacity(truth.len());
    let mut arm_collisions = Vec::new();
    let mut dead_reckoned = Vec::with_capacity(truth.len());
    let mut switch = SwitchTally::default();
    let mut stops: Vec<Stop> = Vec::new();
    let mut newest_piece = None;
    let mut learned = object_mode::Learned::default();
    let setting = object_mode::Setting {
        file,
        plan,
        environment,
        record,
    };
    let mut clock = 0.0;
    for (k, b) in truth.iter().enumerate() {
        whisker_scenario::stop::check()?;
        let reading = match k {
            0 => BaseMotion::default(),
            _ => readings[k - 1],
        };
        for link in shapes.colliding_at(&plan.model, &joints, &posture.arm_base(b), &solids) {
            arm_collisions.push((k, link));
        }
        let (cycle, newest) = whisks.next(&target, k, clock, &posture.array_pose(b));
        let seen = robot.update(&truth[0], &reading, &cycle);
        let dr = seen.dead_reckoned;
        dead_reckoned.push(dr);
        // The piece the window's newest contact truly lies on.
        if let Some(p) = newest {
            newest_piece = plan_view::piece_at(environment, &p);
        }
        let decided = seen.decision.map(|d| (d, newest_piece));
        if let Some((decision, Some(piece))) = &decided {
            let name = &environment.pieces[*piece].name;
            switch.add(k, decision.verdict, name, *piece < scenario.objects.len());
        }
        let step = seen.step;
        steps.push(StepRecord::of(&step, (k, clock), *b, false));
        if let Some(r) = recording.as_deref_mut() {
            r.update(
                k,
                &seen.image,
                &robot.slam,
                &step,
                Some(b),
                k + 1 == truth.len(),
            )?;
        }
        updates.push(Update {
            truth: *b,
            time_s: clock,
            reading,
            contacts: cycle.contacts.len(),
            image: seen.image,
            template: step.template,
            experience: step.experience,
            event: step.event,
            switch: decided
                .as_ref()
                .and_then(|(d, p)| p.map(|p| (d.verdict, environment.pieces[p].name.clone()))),
        });
        cycles.push(cycle);
        clock += 1.0 / UPDATE_HZ;
        let (Some(om), Some((decision, piece))) = (&config.object, decided) else {
            reporter.progress("updates", k as u64 + 1, truth.len() as u64);
            continue;
        };
        let Some(dock) = robot.stop(&decision) else {
            reporter.progress("updates", k as u64 + 1, truth.len() as u64);
            continue;
        };
        let by_base = om.dock == DockBy::Base;
        // Docked by the arm: the frame of the arm's base turned by the shoulder's pan
        // (its axis is the base link's vertical through its origin).
        let docked = dock.docked(b);
        if by_base {
            if let Some(next) = readings.get_mut(k) {
                let manoeuvre = dock.reading(&config.odometry, scenario.seed, k);
                *next = object_mode::compose(&manoeuvre, next);
            }
            for (_, what) in footprint::collisions(
                environment,
                &[docked],
                config.base.radius_m,
                config.terrain.mount_height_m,
            )? {
                base_collisions.push((k, what));
            }
        }
        let (episode, loops) = match piece.filter(|&p| p < scenario.objects.len()) {
            Some(piece) => object_mode::explore(
                &setting,
                om,
                &posture.arm_base(&docked),
                piece,
                k,
                &mut learned,
            )?,
            None => Default::default(),
        };
        let time_s = episode.time_s + dock_time(&dock, by_base, config, scenario);
        clock += time_s;
        let landmark = robot.landmark(episode.identified.as_deref()).map(|s| {
            steps.push(StepRecord::of(&s, (k, clock), *b, true));
            (s.experience, s.event)
        });
        if let (Some(r), Some((x, _)), Some(id)) =
            (recording.as_deref_mut(), landmark, &episode.identified)
            && r.landmarks.iter().all(|(at, _)| *at != x)
        {
            r.landmarks.push((x, id.clone()));
        }
        if let Some(r) = recording.as_deref() {
            let e = &episode;
            let files: Vec<String> = [("recognise", &loops.recognise), ("map", &loops.map)]
                .iter()
                .filter(|(_, l)| l.is_some())
                .map(|(task, _)| format!("stops/{k:06}-{task}.rrd"))
                .collect();
            r.rec.event(&format!(
                "update {k}: stop facing {}: identified {} ({}){}{}",
                e.object.as_deref().unwrap_or("a wall"),
                e.identified.as_deref().unwrap_or("nothing"),
                e.outcome(),
                match landmark {
                    Some((x, ev)) => format!(", landmark experience {x} ({ev:?})"),
                    None => String::new(),
                },
                match files.is_empty() {
                    true => String::new(),
                    false => format!("; its closed loops: {}", files.join(", ")),
                }
            ))?;
            r.rec.marker(
                &format!("world/runs/{}/stops", r.name),
                [b.x, b.y, r.z],
                0.08,
                Some([200, 40, 200]),
            )?;
        }
        stops.push(Stop {
            update: k,
            truth: *b,
            dock,
            centre: decision.centre,
            episode,
            landmark,
            time_s,
            loops,
        });
        reporter.progress("updates", k as u64 + 1, truth.len() as u64);
    }
    let log: Vec<usize> = updates.iter().map(|u| u.experience).collect();
    let estimate = robot.slam.map.placed(&log, &truth[0]);
    let first_lap_end = route::lap_ends(&truth, config)[0];
    Ok(TerrainRun {
        map_error: map_error::measure(&estimate, &truth),
        odometry_error: map_error::measure(&dead_reckoned, &truth),
        metric: experience_metric(&log, &truth, first_lap_end, 0.1, 25f64.to_radians()),
        energy: energy_metric(&estimate, &truth, &consecutive(truth.len())).unwrap_or(f64::NAN),
        templates: robot.slam.view.templates.len(),
        experiences: robot.slam.map.experiences.len(),
        first_lap_end,
        arm_collisions,
        base_collisions,
        posture,
        switch,
        closures: closures::judge(&steps, carried),
        stops,
        time_s: clock,
        updates,
        cycles,
        estimate,
        dead_reckoned,
    })
}
