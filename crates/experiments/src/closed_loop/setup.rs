//! A closed-loop run set up from its scenario: the object's goal mesh (the ellipsoid of
//! map building, the sphere of recognition), the known maps, the robot at its initial
//! joints clear of the environment, and the sensing.

use super::goal::Fallbacks;
use super::placement::Spc;
use super::robot::Robot;
use super::state::{Loop, Records, Sensor};
use super::strategy::Course;
use crate::record::{GraphSchedule, Recorder, Reporter, SensorColumns};
use crate::sensing::held::{PhysicsSensing, WhiskLog};
use crate::surface::MeshSurface;
use nalgebra::{Point3, Vector3};
use rand::RngExt;
use std::path::Path;
use whisker_scenario::ScenarioFile;
use whisker_scenario::Sensing;
use whisker_scenario::explore::{ExploreConfig, MapGoals, Task};
use whisker_scenario::plan::Plan;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::Environment;
use whisker_sim::sensing::kinematic::{KinematicArray, SweepTarget};
use whisker_slam::exploration::goal_mesh::GoalMesh;
use whisker_slam::exploration::tour::FaceTour;
use whisker_slam::recognition::Recognition;
use whisker_slam::rng::substream;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

/// Where a run's outputs go besides its result: the physics whisks' samples (`log`), the
/// recording, and what it says; and the object maps it knows besides `[explore].maps`
/// (`learned`: name and map, e.g. built earlier by the mobile robot, issue #36).
pub struct Outlets<'a> {
    pub log: Option<WhiskLog>,
    pub recording: Option<&'a dyn Recorder>,
    pub reporter: &'a dyn Reporter,
    pub learned: &'a [(String, ObjectMap)],
}

/// The run of the closed loop `config` of the scenario in `file` in `environment`, ready
/// to start.
pub fn build<'a>(
    file: &ScenarioFile,
    config: &ExploreConfig,
    plan: Plan,
    environment: &Environment,
    outlets: Outlets<'a>,
) -> Result<Loop<'a>> {
    let (scenario, path) = (&file.scenario, file.path.as_path());
    let names = scenario.object_names();
    let truth = config.object_name(path, &names)?;
    let index = names.iter().position(|n| *n == truth).expect("validated");
    let piece = &environment.pieces[index];
    // The explored object in the world.
    let object = whisker_sim::environment::Mesh {
        vertices: piece.mesh.vertices.iter().map(|v| piece.pose * v).collect(),
        triangles: piece.mesh.triangles.clone(),
    };
    let (centre, half) = bounding_box(&object.vertices);
    let chain = crate::sensing::array::array_chain(file, &plan)?;
    let robot = Robot::new(plan, chain, environment, scenario.seed)?;
    let hits = robot.colliding(&robot.q);
    if !hits.is_empty() {
        return Err(Error::field(
            path,
            "arm.initial_joints_deg",
            format!(
                "the arm starts inside the environment ({})",
                hits.join(", ")
            ),
        ));
    }
    let sensing = sensor(file, environment, outlets.log)?;
    let surface =
        MeshSurface::new(&object, centre).map_err(|e| Error::field(path, "explore.object", e))?;
    let (map, recognition, mesh) = goals(config, path, &surface, half, outlets.learned)?;
    let tour = FaceTour::new(mesh, config.min_height_m);
    if tour.usable() == 0 {
        return Err(Error::field(
            path,
            "explore.min_height_m",
            "every goal face lies below it",
        ));
    }
    let start_face = start_face(config.task, &tour, scenario.seed);
    let columns = match (outlets.recording, scenario.sensing) {
        (Some(rec), Sensing::Physics) => Some(SensorColumns::new(
            rec,
            "sensors",
            &whisker_sim::whisker::array::labels(),
        )?),
        _ => None,
    };
    let own_links = map.links.len();
    Ok(Loop {
        config: config.clone(),
        truth,
        robot,
        sensing,
        target: SweepTarget::of(environment),
        slam: WhiskerRatSlam::new(config.slam, map),
        recognition,
        course: Course::new(tour, start_face, own_links),
        spc: Spc::default(),
        fallbacks: Fallbacks::default(),
        time: 0.0,
        records: Records {
            recording: outlets.recording,
            reporter: outlets.reporter,
            graph: GraphSchedule::default(),
            columns,
        },
        sensed: crate::sensing::array::map_sensing(file)?,
    })
}

/// How the run of the scenario in `file` whisks in `environment`: physics whiskers
/// (their samples handed to `log`) or the kinematic sweep.
pub fn sensor(
    file: &ScenarioFile,
    environment: &Environment,
    log: Option<WhiskLog>,
) -> Result<Sensor> {
    let scenario = &file.scenario;
    Ok(match scenario.sensing {
        Sensing::Physics => {
            let mut p = PhysicsSensing::of_scenario(file, environment.physics_pieces())?;
            p.log = log;
            Sensor::Physics(Box::new(p))
        }
        _ => {
            let configs = file.whisker_configs()?;
            let whiskers = configs.iter().map(|c| c.rigid()).collect();
            let patterns = configs.iter().map(|c| c.pattern).collect();
            let noise = scenario.kinematic.noise(&file.path)?;
            Sensor::Kinematic(Box::new(
                KinematicArray::new(whiskers, patterns, noise, scenario.seed)
                    .with_control(configs[0].control),
            ))
        }
    })
}

/// The task's map (empty, or the known maps appended: the files', then `learned`),
/// recognition (none when building a map) and goal mesh around the object (its `surface`,
/// seen from its bounding box's centre; `half` the box's extents).
fn goals(
    config: &ExploreConfig,
    file: &Path,
    surface: &MeshSurface,
    half: Vector3<f64>,
    learned: &[(String, ObjectMap)],
) -> Result<(ObjectMap, Option<Recognition>, GoalMesh)> {
    let centre = surface.centre;
    Ok(match config.task {
        Task::Map => {
            let semi = half * 3f64.sqrt();
            let mesh = match config.map_goals {
                MapGoals::Reach => {
                    GoalMesh::around(surface, semi, config.standoff_m, config.mesh_faces)
                }
                MapGoals::Ellipsoid => GoalMesh::ellipsoid(
                    centre,
                    semi + Vector3::repeat(config.standoff_m),
                    config.mesh_faces,
                ),
            };
            (ObjectMap::default(), None, mesh)
        }
        Task::Recognise => {
            let mut appended = ObjectMap::default();
            for (name, path) in config.map_files(file) {
                let m = ObjectMap::load(&path)
                    .map_err(|e| Error::field(file, &format!("explore.maps.{name}"), e))?;
                appended.append(&m, &name);
            }
            for (name, m) in learned {
                appended.append(m, name);
            }
            // The thesis' "bounding sphere + standoff" keeps a box's faces out of reach
            // (15 cm for the Box); the mean half extent + the SPC band's middle puts the
            // side faces in reach, so the default trajectory touches without the SPC too.
            // Where the sphere comes nearer the object than the band's middle (inside the
            // Box's top and bottom, 17.5 cm from its centre) its goals move out to it.
            let band = 0.5 * (config.placement.near_m + config.placement.far_m);
            let radius = config.sphere_radius_m.unwrap_or(half.mean() + band);
            let objects: Vec<String> = config
                .maps
                .keys()
                .chain(learned.iter().map(|(name, _)| name))
                .cloned()
                .collect();
            (
                appended,
                Some(Recognition::new(objects, config.recognition)),
                GoalMesh::sphere(centre, radius, config.mesh_faces).outside(surface, band),
            )
        }
    })
}

/// The face a run starts at: map building the one nearest the arm's base, the default
/// trajectory one drawn from the seed (§6.3).
fn start_face(task: Task, tour: &FaceTour, seed: u64) -> usize {
    match task {
        Task::Map => tour.nearest_usable(&Point3::origin()),
        Task::Recognise => {
            let mut rng = substream(seed, "explore/start-face");
            let usable = tour.usable_faces();
            usable[rng.random_range(0..usable.len())]
        }
    }
}

/// The centre and half extents of a mesh's bounding box.
fn bounding_box(points: &[Point3<f64>]) -> (Point3<f64>, Vector3<f64>) {
    let (lo, hi) = whisker_sim::environment::mesh::bounds(points);
    (nalgebra::center(&lo, &hi), (hi - lo) / 2.0)
}
