//! Navigation datasets (experiment `navigate`, issue #36; docs/dataset.md): an office run
//! written as the robot would log it — each update's whisk, the base's odometry and pose
//! log, and each stop's closed loops in the closed-loop layout — with the ground truth
//! beside it; [`super::replay`] runs the robot's own decisions on it again. Physics
//! sensing is logged at the same level (contacts: what the signal front end detected in
//! the Hall readings, with `noise.sensor` saying the readings' noise), not as 2 kHz
//! streams: ~0.7 MB a whisk, gigabytes for the default office's thousands of stop whisks.
//!
//! ```text
//! log/contacts.csv                    each update's whisk (whisk = update), array frame
//! log/odometry.csv                    update,time_s,rot1_rad,trans_m,rot2_rad
//! log/poses.csv                       the base dead-reckoned at each update (pose-log format)
//! log/stops.csv                       update,duration_s,recognise_whisks,map_whisks
//! log/stops/NNNNNN/<recognise|map>/{contacts,odometry,poses}.csv   a stop's closed loops
//! log/maps/<object>.json              the known object maps
//! truth/poses.csv                     update,time_s,x_m,y_m,heading_rad
//! truth/stops.csv                     update,x_m,y_m,object (empty: the stop was at a wall)
//! truth/route.json                    first_lap_end, carried_at (the kidnap; null)
//! truth/stops/NNNNNN/<task>/poses.csv the loops' reached poses (arm's base frame)
//! truth/run/{path.csv,stops.csv,summary.json}, truth/scenario.toml   the live run
//! ```

use super::object_mode::LoopLog;
use super::outputs::{self, Known};
use super::terrain::{self, TerrainRun};
use crate::dataset_format::manifest::{
    ContactNoiseInfo, Experiment, Level, Manifest, NavigateInfo, NavigateObjectInfo, NoiseInfo,
    PostureInfo, Role, SensorNoise,
};
use crate::dataset_format::{Staging, array_info, records};
use crate::object_slam::dataset::{odometry_csv, pose_log};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::fmt::Write;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::navigate::NavigateConfig;
use whisker_scenario::object_mode::DockBy;
use whisker_slam::pose::Pose2;

/// The header of `log/odometry.csv`.
pub const ODOMETRY_COLUMNS: &str = "update,time_s,rot1_rad,trans_m,rot2_rad";
/// The header of `log/stops.csv`.
pub const STOPS_COLUMNS: &str = "update,duration_s,recognise_whisks,map_whisks";
/// The header of `truth/poses.csv`.
pub const TRUTH_COLUMNS: &str = "update,time_s,x_m,y_m,heading_rad";
/// The header of `truth/stops.csv`.
pub const TRUTH_STOPS_COLUMNS: &str = "update,x_m,y_m,object";

/// A stop's folder under `log/` or `truth/`.
pub fn stop_dir(update: usize) -> String {
    format!("stops/{update:06}")
}

/// The base's pose on the floor as a 3-D pose (z 0, yawed by the heading).
pub fn floor_pose(b: &Pose2) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(b.x, b.y, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), b.th),
    )
}

/// Runs the `[navigate]` (`config`) of the scenario in `file` (its seed the dataset's)
/// and writes it into `s`; `scenario_text` is the scenario as run.
pub fn write(
    file: &ScenarioFile,
    config: &NavigateConfig,
    scenario_text: &str,
    s: &mut Staging,
    reporter: &dyn crate::record::Reporter,
) -> Result<Manifest> {
    let scenario = &file.scenario;
    let physics = scenario.sensing == whisker_scenario::Sensing::Physics;
    let plan = whisker_scenario::plan::Plan::new(file)?;
    let environment = file.environment()?.environment;
    outputs::check(file, config, &plan, &environment)?;
    let run = terrain::run(file, &plan, &environment, config, reporter, None)?;
    let configs = file.whisker_configs()?;
    let array = array_info(&terrain::shafts(file, &configs));
    put_log(&run, &array.labels, s)?;
    let maps = match &config.object {
        Some(o) => crate::closed_loop::dataset::put_maps(&file.path, &o.explore, s)?,
        None => Vec::new(),
    };
    put_truth(&run, (scenario.seed, config), scenario_text, s)?;
    let posture = &run.posture;
    let (t, q) = (
        posture.array.translation.vector,
        posture.array.rotation.coords,
    );
    let info = NavigateInfo {
        updates: run.updates.len(),
        update_hz: terrain::UPDATE_HZ,
        fusion: config.fusion,
        kidnap: config.kidnap,
        odometry_noise: config.odometry,
        posture: PostureInfo {
            joints_rad: posture.q.clone(),
            mount_height_m: posture.mount,
            array_position_m: [t.x, t.y, t.z],
            array_quaternion: [q.x, q.y, q.z, q.w],
        },
        switch: config.switch,
        ratslam: config.ratslam,
        object: config.object.as_ref().map(|o| NavigateObjectInfo {
            dock: match o.dock {
                DockBy::Arm => "arm".into(),
                DockBy::Base => "base".into(),
            },
            dock_distance_m: o.dock_distance_m,
            revisit_m: o.revisit_m,
            landmark_energy: o.landmark_energy,
            landmark_gate_m: o.landmark_gate_m,
            maps,
            odometry_noise: o.explore.odometry,
            slam: o.explore.slam,
            recognition: o.explore.recognition,
            stops: run.stops.len(),
        }),
    };
    Ok(Manifest {
        // Physics: the front end's detections of the noisy Hall readings (level contacts:
        // the streams would be ~0.7 MB a whisk, gigabytes for an office's stops).
        noise: match physics {
            true => NoiseInfo {
                sensor: Some(SensorNoise::of(&configs[0].sensor)),
                ..NoiseInfo::default()
            },
            false => NoiseInfo {
                contacts: ContactNoiseInfo::of(scenario.kinematic.noise(&file.path)?),
                ..NoiseInfo::default()
            },
        },
        navigate: Some(info),
        ..Manifest::new(Experiment::Navigate, Level::Contacts, scenario.seed, array)
    })
}

/// What the robot logged: whisks, odometry, pose log, stops and their loops.
fn put_log(run: &TerrainRun, labels: &[String], s: &mut Staging) -> Result {
    s.put(
        "log/contacts.csv",
        Role::Log,
        records::contacts_csv(&run.cycles, labels).as_bytes(),
    )?;
    let (mut odometry, mut poses) = (
        String::from(ODOMETRY_COLUMNS) + "\n",
        String::from(records::POSE_COLUMNS) + "\n",
    );
    for (k, u) in run.updates.iter().enumerate() {
        let r = &u.reading;
        let _ = writeln!(
            odometry,
            "{k},{:?},{:?},{:?},{:?}",
            u.time_s, r.rot1, r.trans, r.rot2
        );
        let pose = floor_pose(&run.dead_reckoned[k]);
        poses += &records::pose_row(u.time_s, &pose, &format!("whisk_{k:06}"));
    }
    s.put("log/odometry.csv", Role::Log, odometry.as_bytes())?;
    s.put("log/poses.csv", Role::Log, poses.as_bytes())?;
    let mut stops = String::from(STOPS_COLUMNS) + "\n";
    for stop in &run.stops {
        let whisks = |l: &Option<LoopLog>| l.as_ref().map_or(0, |l| l.cycles.len());
        let _ = writeln!(
            stops,
            "{},{:?},{},{}",
            stop.update,
            stop.time_s,
            whisks(&stop.loops.recognise),
            whisks(&stop.loops.map)
        );
        for (task, l) in [
            ("recognise", &stop.loops.recognise),
            ("map", &stop.loops.map),
        ] {
            let Some(l) = l else { continue };
            let dir = format!("log/{}/{task}", stop_dir(stop.update));
            let contacts = records::contacts_csv(&l.cycles, labels);
            s.put(
                &format!("{dir}/contacts.csv"),
                Role::Log,
                contacts.as_bytes(),
            )?;
            let odometry = odometry_csv(&l.odometry);
            s.put(
                &format!("{dir}/odometry.csv"),
                Role::Log,
                odometry.as_bytes(),
            )?;
            let log = pose_log(&l.start, &l.odometry, true, Some(&l.times));
            s.put(&format!("{dir}/poses.csv"), Role::Log, log.as_bytes())?;
        }
    }
    s.put("log/stops.csv", Role::Log, stops.as_bytes())
}

/// The ground truth: true poses, the objects at the stops, the route's laps and carry,
/// the loops' reached poses, the live run's files and the scenario.
fn put_truth(
    run: &TerrainRun,
    (seed, config): (u64, &NavigateConfig),
    text: &str,
    s: &mut Staging,
) -> Result {
    let mut poses = String::from(TRUTH_COLUMNS) + "\n";
    for (k, u) in run.updates.iter().enumerate() {
        let b = &u.truth;
        let _ = writeln!(poses, "{k},{:?},{:?},{:?},{:?}", u.time_s, b.x, b.y, b.th);
    }
    s.put("truth/poses.csv", Role::Truth, poses.as_bytes())?;
    let mut stops = String::from(TRUTH_STOPS_COLUMNS) + "\n";
    for stop in &run.stops {
        let object = stop.episode.object.as_deref().unwrap_or("");
        let b = &stop.truth;
        let _ = writeln!(stops, "{},{:?},{:?},{object}", stop.update, b.x, b.y);
        for (task, l) in [
            ("recognise", &stop.loops.recognise),
            ("map", &stop.loops.map),
        ] {
            let Some(l) = l else { continue };
            let path = format!("truth/{}/{task}/poses.csv", stop_dir(stop.update));
            let csv = records::truth_poses_csv(&l.poses, &l.times);
            s.put(&path, Role::Truth, csv.as_bytes())?;
        }
    }
    s.put("truth/stops.csv", Role::Truth, stops.as_bytes())?;
    let route = serde_json::json!({
        "first_lap_end": run.first_lap_end,
        "carried_at": run.closures.kidnap.as_ref().map(|r| r.after_update),
    });
    let route = serde_json::to_string_pretty(&route).expect("plain JSON") + "\n";
    s.put("truth/route.json", Role::Truth, route.as_bytes())?;
    let flags = (config.object.is_some(), config.fusion, config.kidnap);
    let (path, stops, summary) = outputs::tables(run, seed, flags, Known::ALL);
    s.put("truth/run/path.csv", Role::Truth, path.as_bytes())?;
    s.put("truth/run/stops.csv", Role::Truth, stops.as_bytes())?;
    // As `whisker run` writes it.
    let summary = serde_json::to_string(&summary).expect("plain JSON");
    s.put("truth/run/summary.json", Role::Truth, summary.as_bytes())?;
    s.put("truth/scenario.toml", Role::Truth, text.as_bytes())
}
