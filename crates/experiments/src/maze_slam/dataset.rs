//! Maze datasets (experiment `maze-slam`, thesis Ch 3): the run of `whisker maze-slam` for
//! one seed written as a log, and read back into the same RatSLAM input.
//!
//! Physics sensing writes level `streams`: one whisk file per 1 Hz whisk cycle, the array
//! moving along the path meanwhile; replay runs the same front end on them. Kinematic
//! sensing has no signal: it writes level `contacts` (one whisk per update, the sweep's
//! contact angles). Either way `log/odometry.csv` holds the odometry of every 1.5 Hz
//! update (turn, then distance: the order RatSLAM integrates) with the §3.1.2 error, and
//! `log/poses.csv` the end effector's pose at 1 Hz as the robot's odometry puts it.
//! Ground truth: `truth/poses.csv` (the true planar pose of every update),
//! `truth/odometry.csv` (noise-free), `truth/contacts.csv` (the rigid sweep without
//! noise: per update for kinematic sensing, at each whisk cycle's start pose for
//! physics) and `truth/scenario.toml`.

use super::physics_images::{self as maze_physics, ImageFrontEnd};
use crate::dataset_format::manifest::{
    ContactNoiseInfo, Experiment, Level, Manifest, MazeInfo, NoiseInfo, Role, SensorInfo,
    SensorNoise,
};
use crate::dataset_format::records::{self, POSE_COLUMNS};
use crate::dataset_format::table::{Table, columns};
use crate::dataset_format::{Staging, array_info, rigid_whiskers};
use crate::maze_slam::path::Sample;
use crate::maze_slam::{
    Geometry, Sensed, Settings, Setup, UPDATE_HZ, kinematic_contacts, kinematic_whiskers,
    physics_sets,
};
use crate::record::Reporter;
use nalgebra::UnitQuaternion;
use rayon::prelude::*;
use std::fmt::Write;
use std::path::Path;
use whisker_scenario::ScenarioFile;
use whisker_scenario::maze_slam::AngleEstimate;
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::kinematic::KinematicArray;
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::sensing::physics::DT;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::pose::wrap;
use whisker_slam::ratslam::RatSlamParams;
use whisker_slam::ratslam::odometry::{noisy_steps, true_steps};
use whisker_slam::rng::substream_key;
use whisker_slam::sensor::SAMPLE_RATE_HZ;

pub const ODOMETRY_COLUMNS: &str = "update,time_s,turn_rad,distance_m";
const TRUTH_COLUMNS: &str = "update,time_s,x_m,y_m,heading_rad";

/// What the sensing of a maze dataset wrote and how: the level, the rigid whiskers the
/// array info describes, the sensor and front end (physics), the noise, the image sets, the
/// whisk rate and the noise-free contacts of ground truth.
struct SensingLog {
    level: Level,
    whiskers: Vec<whisker_sim::sensing::kinematic::RigidWhisker>,
    sensor: Option<SensorInfo>,
    frontend: Option<Vec<whisker_slam::frontend::contact::FrontEndParams>>,
    sensor_noise: Option<SensorNoise>,
    contact_noise: Option<ContactNoiseInfo>,
    image_sets: Vec<(String, String)>,
    whisk_hz: f64,
    anticipated: Vec<whisker_slam::contact::ContactCycle>,
}

/// What both kinds of sensing read: the scenario file, the setup, the environment's
/// sweep target, the seed, whether noise is left out.
struct MazeRun<'a> {
    file: &'a ScenarioFile,
    setup: &'a Setup,
    target: &'a whisker_sim::sensing::kinematic::SweepTarget,
    seed: u64,
    clean: bool,
}

/// Writes the maze scenario of `file` (its seed the dataset's; as run: `scenario_text`)
/// into `s`; `clean` leaves out every noise.
pub fn write(
    file: &ScenarioFile,
    scenario_text: &str,
    clean: bool,
    s: &mut Staging,
    reporter: &dyn Reporter,
) -> Result<Manifest> {
    let scenario = &file.scenario;
    let seed = scenario.seed;
    let o = Settings::of(&file.path);
    let setup = Setup::new(&o, file)?;
    let environment = file.environment()?.environment;
    let (g, truth) = (&setup.geometry, &setup.truth);
    let config = &scenario.maze_slam;
    let target = whisker_sim::sensing::kinematic::SweepTarget::of(&environment);
    let clean_steps = true_steps(truth);
    let steps = if clean {
        clean_steps.clone()
    } else {
        noisy_steps(&clean_steps, &config.odometry, seed)
    };
    let run = MazeRun {
        file,
        setup: &setup,
        target: &target,
        seed,
        clean,
    };
    let log = match &setup.physics {
        None => kinematic_log(&run, s)?,
        Some(physics) => physics_log(&run, physics, &environment, s, reporter)?,
    };
    let array = array_info(&log.whiskers);
    // The odometry, the pose log, ground truth.
    let mut poses = String::from(TRUTH_COLUMNS) + "\n";
    for (k, p) in truth.iter().enumerate() {
        let t = k as f64 / UPDATE_HZ;
        let _ = writeln!(poses, "{k},{t:?},{:?},{:?},{:?}", p.x, p.y, p.th);
    }
    s.put(
        "log/odometry.csv",
        Role::Log,
        odometry_csv(&steps).as_bytes(),
    )?;
    s.put(
        "log/poses.csv",
        Role::Log,
        pose_log(truth[0], &steps, g, log.level, log.whisk_hz).as_bytes(),
    )?;
    s.put("truth/poses.csv", Role::Truth, poses.as_bytes())?;
    s.put(
        "truth/odometry.csv",
        Role::Truth,
        odometry_csv(&clean_steps).as_bytes(),
    )?;
    s.put(
        "truth/contacts.csv",
        Role::Truth,
        records::contacts_csv(&log.anticipated, &array.labels).as_bytes(),
    )?;
    s.put("truth/scenario.toml", Role::Truth, scenario_text.as_bytes())?;
    Ok(Manifest {
        sensor: log.sensor,
        noise: NoiseInfo {
            sensor: log.sensor_noise,
            odometry: (!clean && config.odometry.enabled).then_some(config.odometry),
            contacts: log.contact_noise,
            ..NoiseInfo::default()
        },
        maze: Some(MazeInfo {
            update_hz: UPDATE_HZ,
            updates: truth.len(),
            plane_z_m: g.plane_z,
            board_z_m: g.board_z,
            yaw0_rad: g.yaw0,
            circuit_starts: setup.starts.clone(),
            kidnap: config.kidnap,
            image_sets: log.image_sets,
            frontend: log.frontend,
            ratslam: config.ratslam,
            tuned: config.tuned.clone(),
        }),
        ..Manifest::new(Experiment::MazeSlam, log.level, seed, array)
    })
}

/// Kinematic sensing: `log/contacts.csv`, the rigid sweep's contacts of every update with
/// the scenario's contact noise (level `contacts`).
fn kinematic_log(run: &MazeRun, s: &mut Staging) -> Result<SensingLog> {
    let (g, truth) = (&run.setup.geometry, &run.setup.truth);
    let whiskers = kinematic_whiskers();
    let noise = if run.clean {
        ContactNoise::NONE
    } else {
        run.file.scenario.kinematic.noise(&run.file.path)?
    };
    let key = substream_key(run.seed, "maze-slam/sensing");
    let control = run.file.whisker_configs()?[0].control;
    let cycles = kinematic_contacts(truth, run.target, noise, key, g, control);
    let labels = array_info(&whiskers).labels;
    s.put(
        "log/contacts.csv",
        Role::Log,
        records::contacts_csv(&cycles, &labels).as_bytes(),
    )?;
    Ok(SensingLog {
        anticipated: kinematic_contacts(
            truth,
            run.target,
            ContactNoise::NONE,
            0,
            g,
            Default::default(),
        ),
        level: Level::Contacts,
        whiskers,
        sensor: None,
        frontend: None,
        sensor_noise: None,
        contact_noise: ContactNoiseInfo::of(noise),
        image_sets: vec![(run.setup.set_names[0].clone(), "contacts".to_string())],
        whisk_hz: UPDATE_HZ,
    })
}

/// Physics sensing: one whisk file of 2 kHz streams per whisk cycle (level `streams`), and
/// the rigid sweep at each cycle's start pose as ground truth.
fn physics_log(
    run: &MazeRun,
    physics: &maze_physics::PhysicsWhiskers,
    environment: &whisker_sim::environment::Environment,
    s: &mut Staging,
    reporter: &dyn Reporter,
) -> Result<SensingLog> {
    let (g, truth) = (&run.setup.geometry, &run.setup.truth);
    let (mut configs, rcp) = (physics.configs.clone(), &physics.contact);
    if run.clean {
        for c in &mut configs {
            c.sensor.noise_counts = 0.0;
            c.sensor.angle_noise_rad = 0.0;
        }
    }
    let key = substream_key(run.seed, "maze-slam/physics");
    let detection = crate::sensing::detection::Detection::of_scenario(&run.file.scenario);
    let (configs, front) = maze_physics::calibrated(configs, *rcp, &detection, key);
    let whiskers = front.rigid.clone();
    let labels = array_info(&whiskers).labels;
    let model = configs[0].sensor;
    let whisk_hz = front.frequency;
    let whisks = maze_physics::cycles(truth.len(), whisk_hz);
    let mut sweep = KinematicArray::new(
        whiskers.clone(),
        vec![WhiskingPattern::default(); whiskers.len()],
        ContactNoise::NONE,
        0,
    );
    let pieces = environment.physics_pieces();
    let mut anticipated = Vec::new();
    maze_physics::simulate(truth, &pieces, configs, key, g, reporter, |c, streams| {
        let csv = records::whisk_csv(&labels, &streams, model.angle_resolution_rad)?;
        s.put(
            &format!("log/whisks/{}", records::whisk_name(c)),
            Role::Log,
            csv.as_bytes(),
        )?;
        let t = c as f64 / whisk_hz;
        let pose = maze_physics::pose_at(truth, t, g);
        anticipated.push(sweep.sense(run.target, c as u64, t, &pose));
        Ok::<(), Error>(())
    })?;
    Ok(SensingLog {
        level: Level::Streams,
        whiskers,
        sensor: Some(SensorInfo {
            sample_rate_hz: SAMPLE_RATE_HZ,
            whisk_hz,
            samples_per_whisk: maze_physics::per_cycle(whisk_hz),
            whisks,
            angle_resolution_rad: model.angle_resolution_rad,
            saturation_counts: model.saturation_counts,
        }),
        sensor_noise: (model.noise_counts > 0.0 || model.angle_noise_rad > 0.0)
            .then_some(SensorNoise::of(&model)),
        contact_noise: None,
        frontend: Some(front.params.clone()),
        image_sets: run
            .file
            .scenario
            .maze_slam
            .images
            .iter()
            .zip(&run.setup.set_names)
            .map(|(e, n)| (n.clone(), e.name().to_string()))
            .collect(),
        whisk_hz,
        anticipated,
    })
}

/// An odometry file's text: per update, its time, turn (rad) and distance (m).
pub fn odometry_csv(steps: &[(f64, f64)]) -> String {
    let mut csv = String::from(ODOMETRY_COLUMNS) + "\n";
    for (k, (d, turn)) in steps.iter().enumerate() {
        let _ = writeln!(csv, "{k},{:?},{turn:?},{d:?}", k as f64 / UPDATE_HZ);
    }
    csv
}

/// Reads an odometry file of `n` updates (any `n` if None): (distance, turn) per update.
pub fn read_odometry(path: &Path, n: Option<usize>) -> Result<Vec<(f64, f64)>> {
    let table = Table::read(path, &columns(ODOMETRY_COLUMNS))?;
    if let Some(n) = n
        && table.len() != n
    {
        return Err(table.error(
            table.len() + 1,
            format!("expected {n} updates, got {}", table.len()),
        ));
    }
    let mut steps = Vec::with_capacity(table.len());
    for row in table.rows() {
        let row = row?;
        row.expect(0, steps.len())?;
        row.f64(1)?;
        steps.push((row.f64(3)?, row.f64(2)?));
    }
    Ok(steps)
}

/// The pose log of a dataset whose odometry is now `steps`, from the first pose of its
/// pose log in `dir`.
pub fn pose_log_of(dir: &Path, m: &Manifest, steps: &[(f64, f64)]) -> Result<String> {
    let info = m.maze.as_ref().expect("a maze dataset");
    let g = geometry(info);
    let start = first_pose(&m.file(dir, "log/poses.csv")?, &g)?;
    let whisk_hz = m.sensor.map_or(UPDATE_HZ, |s| s.whisk_hz);
    Ok(pose_log(start, steps, &g, m.level, whisk_hz))
}

/// The maze's geometry from the manifest.
fn geometry(info: &MazeInfo) -> Geometry {
    Geometry {
        plane_z: info.plane_z_m,
        board_z: info.board_z_m,
        yaw0: info.yaw0_rad,
    }
}

/// The planar pose of the pose log's first row.
fn first_pose(path: &Path, g: &Geometry) -> Result<Sample> {
    let (_, pose, _) = records::read_poses(path)?.swap_remove(0);
    let level = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, g.yaw0);
    let turn = pose.rotation * level.inverse();
    Ok(Sample {
        x: pose.translation.x,
        y: pose.translation.y,
        th: turn.euler_angles().2,
    })
}

/// The 1 Hz pose log: the pose the robot's odometry gives (from `start`, each update's
/// turn then distance), at whole seconds, with the latest whisk completed by then.
fn pose_log(
    start: Sample,
    steps: &[(f64, f64)],
    g: &Geometry,
    level: Level,
    whisk_hz: f64,
) -> String {
    let mut at = start;
    let mut dead_reckoned = Vec::with_capacity(steps.len());
    for (k, &(d, t)) in steps.iter().enumerate() {
        if k > 0 {
            at.th = wrap(at.th + t);
            at.x += d * at.th.cos();
            at.y += d * at.th.sin();
        }
        dead_reckoned.push(at);
    }
    let duration = (steps.len() - 1) as f64 / UPDATE_HZ;
    let mut csv = String::from(POSE_COLUMNS) + "\n";
    for second in 0..=(duration.floor() as usize) {
        let t = second as f64;
        let k = ((t * UPDATE_HZ + 1e-9).floor() as usize).min(steps.len() - 1);
        let whisk = match level {
            // Whisk cycle c is complete at (c + 1)/f.
            Level::Streams => match (t * whisk_hz + 1e-9).floor() as usize {
                0 => String::new(),
                done => records::whisk_name(done - 1),
            },
            Level::Contacts => format!("whisk_{k:06}"),
        };
        csv += &records::pose_row(t, &g.pose(&dead_reckoned[k]), &whisk);
    }
    csv
}

/// What a maze dataset's replay runs: RatSLAM's input, its parameters, the tuned ones per
/// image set and variant, and whether to run the kidnapped variant.
pub type Replay = (
    Sensed,
    RatSlamParams,
    std::collections::BTreeMap<String, whisker_scenario::maze_slam::Tuned>,
    bool,
);

/// Reads a maze dataset ([`Replay`]).
pub fn read(dir: &Path, m: &Manifest) -> Result<Replay> {
    let info = m.maze_section(dir)?;
    let file = dir.join(crate::dataset_format::manifest::FILE);
    check_info(&file, info, m.level)?;
    let n = info.updates;
    let g = geometry(info);
    let whiskers = rigid_whiskers(dir, &m.array)?;
    // The odometry.
    let steps = read_odometry(&m.file(dir, "log/odometry.csv")?, Some(n))?;
    // Ground truth, if present; else the estimate starts at the pose log's first pose.
    let truth = if m.has_truth(dir) {
        Some(read_truth(dir, m, n)?)
    } else {
        None
    };
    // The pose log is read (and so checked) either way; ground truth, when present,
    // gives the true start instead of the log's.
    let logged = first_pose(&m.file(dir, "log/poses.csv")?, &g)?;
    let start = truth.as_ref().map_or(logged, |t| t[0]);
    let image_sets = match m.level {
        Level::Contacts => {
            let cycles =
                records::read_contacts(&m.file(dir, "log/contacts.csv")?, n, &m.array.labels)?;
            let images = cycles
                .iter()
                .map(|c| g.contact_image(c, &whiskers))
                .collect();
            vec![(info.image_sets[0].0.clone(), images)]
        }
        Level::Streams => stream_images(dir, m, &file, whiskers, &g)?,
    };
    let sensed = Sensed {
        seed: m.seed,
        truth,
        start,
        starts: info.circuit_starts.clone(),
        steps,
        image_sets,
    };
    Ok((sensed, info.ratslam, info.tuned.clone(), info.kidnap))
}

/// The `maze` section's rate and circuits, as a maze run can replay them.
fn check_info(file: &Path, info: &MazeInfo, level: Level) -> Result {
    if info.update_hz != UPDATE_HZ {
        return Err(Error::field(
            file,
            "maze.update_hz",
            format!("expected {UPDATE_HZ} (the rate of §3.1.2)"),
        ));
    }
    check_image_sets(file, info, level)?;
    let n = info.updates;
    let starts = &info.circuit_starts;
    if n < 2
        || starts.len() < 2
        || starts.windows(2).any(|w| w[0] >= w[1])
        || starts[starts.len() - 1] >= n
    {
        return Err(Error::field(
            file,
            "maze.circuit_starts",
            "expected at least 2 increasing updates below maze.updates (at least 2)",
        ));
    }
    if info.kidnap && starts.len() < 4 {
        return Err(Error::field(
            file,
            "maze.kidnap",
            "the kidnapped variant needs 4 circuits",
        ));
    }
    Ok(())
}

/// The `maze.image_sets`: at least one, names distinct, exactly one at level contacts
/// (its images come from `log/contacts.csv`); the estimates of level streams are checked
/// where they are used.
fn check_image_sets(file: &Path, info: &MazeInfo, level: Level) -> Result {
    let sets = &info.image_sets;
    let distinct = sets
        .iter()
        .enumerate()
        .all(|(i, (a, _))| sets[..i].iter().all(|(b, _)| a != b));
    let one = level != Level::Contacts || sets.len() == 1;
    if sets.is_empty() || !distinct || !one {
        return Err(Error::field(
            file,
            "maze.image_sets",
            format!(
                "{} set(s): expected at least one [name, estimate] pair with distinct names \
                 (exactly one at level contacts)",
                sets.len()
            ),
        ));
    }
    Ok(())
}

/// `truth/poses.csv`: the true planar pose of each of the `n` updates.
fn read_truth(dir: &Path, m: &Manifest, n: usize) -> Result<Vec<Sample>> {
    let table = Table::read(&m.file(dir, "truth/poses.csv")?, &columns(TRUTH_COLUMNS))?;
    let mut truth = Vec::with_capacity(n);
    for row in table.rows() {
        let row = row?;
        row.expect(0, truth.len())?;
        row.f64(1)?;
        truth.push(Sample {
            x: row.f64(2)?,
            y: row.f64(3)?,
            th: row.f64(4)?,
        });
    }
    if truth.len() != n {
        return Err(table.error(table.len() + 1, format!("expected {n} updates")));
    }
    Ok(truth)
}

/// The image sets of level `streams`: the front end run again on every whisk file, each
/// update's images from the cycles around it (§3.1.3).
fn stream_images(
    dir: &Path,
    m: &Manifest,
    file: &Path,
    whiskers: Vec<whisker_sim::sensing::kinematic::RigidWhisker>,
    g: &Geometry,
) -> Result<Vec<super::ImageSet>> {
    let info = m.maze_section(dir)?;
    let n = info.updates;
    let sensor = m.sensor_section(dir)?;
    let params = info.frontend.clone().ok_or_else(|| {
        Error::field(
            file,
            "maze.frontend",
            "level \"streams\" needs the front end's parameters",
        )
    })?;
    if sensor.sample_rate_hz != SAMPLE_RATE_HZ || params.len() != whiskers.len() {
        return Err(Error::field(
            file,
            "sensor.sample_rate_hz",
            format!("expected {SAMPLE_RATE_HZ} Hz and one front-end entry per whisker"),
        ));
    }
    let front = ImageFrontEnd {
        params,
        rigid: whiskers,
        frequency: sensor.whisk_hz,
    };
    if maze_physics::per_cycle(sensor.whisk_hz) != sensor.samples_per_whisk
        || maze_physics::cycles(n, sensor.whisk_hz) != sensor.whisks
        || (1.0 / DT - SAMPLE_RATE_HZ).abs() > 1e-9
    {
        return Err(Error::field(
            file,
            "sensor",
            "samples_per_whisk and whisks do not match whisk_hz and the updates",
        ));
    }
    let by_cycle = (0..sensor.whisks)
        .into_par_iter()
        .map(|c| {
            let streams = crate::dataset_format::whisk_streams(dir, m, "log/whisks", c)?;
            Ok(front.cycle(&streams, g))
        })
        .collect::<Result<Vec<_>>>()?;
    let (max, contact) = front.per_update(&by_cycle, n);
    let mut estimates = Vec::new();
    for (name, e) in &info.image_sets {
        estimates.push(match e.as_str() {
            "max_angle" => AngleEstimate::MaxAngle,
            "contact_angle" => AngleEstimate::ContactAngle,
            _ => {
                return Err(Error::field(
                    file,
                    "maze.image_sets",
                    format!("{name}: expected \"max_angle\" or \"contact_angle\", got {e:?}"),
                ));
            }
        });
    }
    let names: Vec<String> = info.image_sets.iter().map(|(n, _)| n.clone()).collect();
    Ok(physics_sets(&estimates, &names, max, contact))
}
