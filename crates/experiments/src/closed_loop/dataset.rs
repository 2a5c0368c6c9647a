//! Closed-loop datasets (experiment `closed-loop`, thesis Ch 6): the path a closed-loop
//! run took — one whisk per iteration where the policy put the array — written as a log,
//! and replayed open loop: the same contacts and odometry through the same WhiskerRatSLAM
//! and recognition (§6.2), without the arm or the policy. The replay's SLAM and
//! recognition columns equal the live `explore.csv`'s, its recognition the live
//! `summary.json`'s.
//!
//! Kinematic sensing: level `contacts`, `log/contacts.csv`; physics sensing: level
//! `streams`, `log/whisks/whisk_NNNNNN.csv` (one per whisk) and `log/radial_model.json`,
//! the front end run at replay. Both:
//! `log/odometry.csv` (6-D, Eq 6.4–6.11 noise), `log/poses.csv` (dead-reckoned from the
//! start pose), `log/maps/<object>.json` (the known object maps: the robot's prior
//! knowledge). Ground truth: `truth/poses.csv` (the reached pose of each whisk),
//! `truth/contacts.csv` (the rigid sweep without noise), `truth/explore.csv` and
//! `truth/summary.json` (the live run's own log, its policy decisions and the true
//! object), `truth/scenario.toml`.

use crate::dataset_format::manifest::{
    ClosedLoopInfo, ContactNoiseInfo, Experiment, Level, Manifest, NoiseInfo, Role, SensorInfo,
    SensorNoise,
};
use crate::dataset_format::whisks::{WhiskFiles, put_model, replay_sensing};
use crate::dataset_format::{Staging, array_info, records};
use crate::object_slam::dataset::{odometry_csv, pose_log, read_odometry};
use nalgebra::Point3;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;
use whisker_scenario::ScenarioFile;
use whisker_scenario::explore::ExploreConfig;
use whisker_scenario::explore::Task;
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::contact::ContactCycle;
use whisker_slam::recognition::Outcome;
use whisker_slam::recognition::Recognition;
use whisker_slam::sensor::{Odometry, SAMPLE_RATE_HZ};
use whisker_slam::whisker_ratslam::object_map::{MapSensing, ObjectMap, SensedBy};
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

/// Runs the closed loop `config` of the scenario in `file` (its `seed` the dataset's) and
/// writes the path it took into `s`; `scenario_text` is the scenario as run.
pub fn write(
    file: &ScenarioFile,
    config: &ExploreConfig,
    scenario_text: &str,
    s: &mut Staging,
    reporter: &dyn crate::record::Reporter,
) -> Result<Manifest> {
    let scenario = &file.scenario;
    let plan = whisker_scenario::plan::Plan::new(file)?;
    let environment = file.environment()?.environment;
    let configs = file.whisker_configs()?;
    let whiskers: Vec<RigidWhisker> = configs.iter().map(|c| c.rigid()).collect();
    let array = array_info(&whiskers);
    let physics = scenario.sensing == whisker_scenario::Sensing::Physics;
    // Physics: each whisk's samples to its whisk file as the loop runs.
    let files = physics.then(|| {
        let dir = s.path("log/whisks");
        let path = move |_: &str, k: usize| dir.join(records::whisk_name(k));
        WhiskFiles::new(
            path,
            array.labels.clone(),
            configs[0].sensor.angle_resolution_rad,
        )
    });
    let log = files.as_ref().map(|f| f.log.clone());
    let outcome =
        super::session::run_logged(file, config, plan, &environment, (log, None), reporter)?;
    if let Some(files) = &files {
        files.finish()?;
    }
    if physics {
        for k in 0..outcome.poses.len() {
            s.register(&format!("log/whisks/{}", records::whisk_name(k)), Role::Log)?;
        }
        put_model(s, &scenario.frontend.model(&file.path)?)?;
    } else {
        s.put(
            "log/contacts.csv",
            Role::Log,
            records::contacts_csv(&outcome.cycles, &array.labels).as_bytes(),
        )?;
    }
    s.put(
        "log/odometry.csv",
        Role::Log,
        odometry_csv(&outcome.odometry).as_bytes(),
    )?;
    let log = pose_log(
        &outcome.start,
        &outcome.odometry,
        true,
        Some(&outcome.times),
    );
    s.put("log/poses.csv", Role::Log, log.as_bytes())?;
    let maps = put_maps(&file.path, config, s)?;
    put_truth(
        &outcome,
        &configs,
        &whiskers,
        &array.labels,
        &environment,
        scenario_text,
        s,
    )?;
    manifest(file, config, &configs, &outcome, maps, array)
}

/// The manifest of a closed loop's dataset.
fn manifest(
    file: &ScenarioFile,
    config: &ExploreConfig,
    configs: &[whisker_sim::sensing::physics::WhiskerConfig],
    outcome: &super::Outcome,
    maps: Vec<String>,
    array: crate::dataset_format::manifest::ArrayInfo,
) -> Result<Manifest> {
    let scenario = &file.scenario;
    let physics = scenario.sensing == whisker_scenario::Sensing::Physics;
    let noise = scenario.kinematic.noise(&file.path)?;
    let sensor = configs[0].sensor;
    Ok(Manifest {
        sensor: physics.then_some(SensorInfo {
            sample_rate_hz: SAMPLE_RATE_HZ,
            whisk_hz: configs[0].pattern.frequency,
            samples_per_whisk: (SAMPLE_RATE_HZ / configs[0].pattern.frequency).round() as usize,
            whisks: outcome.poses.len(),
            angle_resolution_rad: sensor.angle_resolution_rad,
            saturation_counts: sensor.saturation_counts,
        }),
        noise: NoiseInfo {
            contacts: if physics {
                None
            } else {
                ContactNoiseInfo::of(noise)
            },
            sensor: physics.then_some(SensorNoise::of(&sensor)),
            ..NoiseInfo::default()
        },
        closed_loop: Some(ClosedLoopInfo {
            task: match config.task {
                Task::Map => "map".into(),
                Task::Recognise => "recognise".into(),
            },
            whisks: outcome.poses.len(),
            maps,
            odometry_noise: config.odometry,
            slam: config.slam,
            recognition: config.recognition,
            frontend: outcome.levels.clone(),
        }),
        ..Manifest::new(
            Experiment::ClosedLoop,
            if physics {
                Level::Streams
            } else {
                Level::Contacts
            },
            scenario.seed,
            array,
        )
    })
}

/// The known object maps (the robot's prior knowledge) copied to `log/maps/`; their names.
pub(crate) fn put_maps(
    file: &Path,
    config: &ExploreConfig,
    s: &mut Staging,
) -> Result<Vec<String>> {
    let mut maps = Vec::new();
    for (name, path) in config.map_files(file) {
        let bytes = std::fs::read(&path).map_err(|e| {
            Error::field(
                file,
                &format!("explore.maps.{name}"),
                format!("{}: {e}", path.display()),
            )
        })?;
        s.put(&format!("log/maps/{name}.json"), Role::Log, &bytes)?;
        maps.push(name);
    }
    Ok(maps)
}

/// Ground truth: the reached poses, the rigid sweep's noise-free contacts at them, the live
/// run's own log and summary, the scenario as run.
fn put_truth(
    outcome: &super::Outcome,
    configs: &[whisker_sim::sensing::physics::WhiskerConfig],
    whiskers: &[RigidWhisker],
    labels: &[String],
    environment: &whisker_sim::environment::Environment,
    scenario_text: &str,
    s: &mut Staging,
) -> Result {
    let poses = records::truth_poses_csv(&outcome.poses, &outcome.times);
    s.put("truth/poses.csv", Role::Truth, poses.as_bytes())?;
    let mut sweep = KinematicArray::new(
        whiskers.to_vec(),
        configs
            .iter()
            .map(|c| c.pattern)
            .collect::<Vec<WhiskingPattern>>(),
        ContactNoise::NONE,
        0,
    );
    let target = whisker_sim::sensing::kinematic::SweepTarget::of(environment);
    let anticipated: Vec<_> = outcome
        .poses
        .iter()
        .enumerate()
        .map(|(k, p)| sweep.sense(&target, k as u64, outcome.times[k], p))
        .collect();
    s.put(
        "truth/contacts.csv",
        Role::Truth,
        records::contacts_csv(&anticipated, labels).as_bytes(),
    )?;
    s.put("truth/explore.csv", Role::Truth, outcome.csv.as_bytes())?;
    let summary = serde_json::to_string_pretty(&outcome.summary).expect("plain JSON") + "\n";
    s.put("truth/summary.json", Role::Truth, summary.as_bytes())?;
    s.put("truth/scenario.toml", Role::Truth, scenario_text.as_bytes())?;
    Ok(())
}

/// What recognition found in a replay.
#[derive(Debug, Clone, Serialize)]
pub struct ReplayRecognition {
    pub identified: Option<String>,
    pub identified_at: Option<u64>,
    pub crossings: BTreeMap<String, u64>,
    pub final_rc: BTreeMap<String, f64>,
    pub final_ic: BTreeMap<String, f64>,
    /// These need the true object: absent without ground truth.
    pub outcome: Option<Outcome>,
    pub srt: Option<u64>,
    pub im: Option<f64>,
    /// The IC threshold.
    #[serde(skip)]
    pub threshold: f64,
}

/// A closed-loop replay's summary (`summary.json` in `--out`; `--json`).
#[derive(Debug, Clone, Serialize)]
pub struct ReplaySummary {
    pub task: String,
    /// The true object (from the ground truth, when present).
    pub object: Option<String>,
    pub whisks: usize,
    pub relocalisations: usize,
    pub experiences: usize,
    pub recognition: Option<ReplayRecognition>,
}

impl std::fmt::Display for ReplaySummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "Closed-loop replay (open loop on the recorded path, Ch 6): {} whisks, {} re-localisations into known maps, {} experiences",
            self.whisks, self.relocalisations, self.experiences
        )?;
        if let Some(r) = &self.recognition {
            match (&r.identified, r.identified_at) {
                (Some(o), Some(t)) => writeln!(
                    f,
                    "  identified {o} at whisk {t} (IC threshold {})",
                    r.threshold
                )?,
                _ => writeln!(f, "  nothing identified (IC threshold {})", r.threshold)?,
            }
            match (&self.object, &r.outcome) {
                (Some(t), Some(outcome)) => writeln!(f, "  true object {t}: {outcome:?}")?,
                _ => writeln!(f, "  true object: n/a (no ground truth)")?,
            }
        }
        Ok(())
    }
}

/// Replays a closed-loop dataset open loop: WhiskerRatSLAM and recognition on its contacts
/// and odometry.
pub fn replay(dir: &Path, m: &Manifest, out: Option<&Path>) -> Result<ReplaySummary> {
    let file = dir.join(crate::dataset_format::manifest::FILE);
    let Some(info) = m.closed_loop.as_ref() else {
        return Err(Error::field(&file, "closed_loop", "missing"));
    };
    let n = info.whisks;
    let cycles = read_cycles(dir, m, n)?;
    let odometry = read_odometry(&m.file(dir, "log/odometry.csv")?, n)?;
    // The pose log is not replayed (SLAM runs on the odometry) but is checked as
    // docs/dataset.md promises: a malformed log is refused, not ignored.
    records::read_poses(&m.file(dir, "log/poses.csv")?)?;
    let appended = known_maps(dir, m, info)?;
    // The true object, when the ground truth is there.
    let object = if m.has_truth(dir) {
        Some(true_object(dir, m)?)
    } else {
        None
    };
    let mut slam = WhiskerRatSlam::new(info.slam, appended);
    let mut recognition =
        (info.task == "recognise").then(|| Recognition::new(info.maps.clone(), info.recognition));
    let (csv, relocalisations) = run_slam(
        &cycles,
        &odometry,
        &info.maps,
        &mut slam,
        recognition.as_mut(),
    );
    let truth = object.as_deref();
    let summary = ReplaySummary {
        task: info.task.clone(),
        whisks: n,
        relocalisations,
        experiences: slam.map.experiences.len(),
        recognition: recognition.as_ref().map(|r| found(r, truth)),
        object,
    };
    if let Some(out) = out {
        let sensed = MapSensing {
            mode: match m.level {
                Level::Streams => SensedBy::Physics,
                _ => SensedBy::Kinematic,
            },
            array: format!("replayed from the dataset in {}", dir.display()),
        };
        write_replay(out, &csv, &summary, (&slam, sensed), info)?;
    }
    Ok(summary)
}

/// Each whisk's contacts: read (level `contacts`) or sensed again from the whisk files.
fn read_cycles(dir: &Path, m: &Manifest, n: usize) -> Result<Vec<ContactCycle>> {
    Ok(match m.level {
        Level::Contacts => {
            records::read_contacts(&m.file(dir, "log/contacts.csv")?, n, &m.array.labels)?
        }
        // Physics: the front end and the radial-distance model on each whisk file, with
        // the live run's draws (sub-streams `explore/physics/<k>` of its seed).
        Level::Streams => {
            let levels = m.closed_loop.as_ref().and_then(|c| c.frontend.as_deref());
            let p = replay_sensing(dir, m, levels.map(|l| ("closed_loop.frontend", l)))?;
            (0..n)
                .into_par_iter()
                .map(|k| {
                    let streams = crate::dataset_format::whisk_streams(dir, m, "log/whisks", k)?;
                    Ok(p.contacts(k, &streams, m.seed, &format!("explore/physics/{k}")))
                })
                .collect::<Result<Vec<_>>>()?
        }
    })
}

/// The known object maps of `log/maps/`, appended into one.
fn known_maps(dir: &Path, m: &Manifest, info: &ClosedLoopInfo) -> Result<ObjectMap> {
    let mut appended = ObjectMap::default();
    for name in &info.maps {
        let path = m.file(dir, &format!("log/maps/{name}.json"))?;
        let map =
            ObjectMap::load(&path).map_err(|e| Error::Input(format!("{}: {e}", path.display())))?;
        appended.append(&map, name);
    }
    Ok(appended)
}

/// The true object's name, from the live run's `truth/summary.json`.
fn true_object(dir: &Path, m: &Manifest) -> Result<String> {
    let path = m.file(dir, "truth/summary.json")?;
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::Input(format!("{}: {e}", path.display())))?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Error::Input(format!("{}: {e}", path.display())))?;
    let object = v["object"].as_str().map(String::from).ok_or_else(|| {
        Error::Input(format!(
            "{}: field `object`: expected the true object's name",
            path.display()
        ))
    })?;
    Ok(object)
}

/// WhiskerRatSLAM (and recognition, if any) whisk by whisk; returns `replay.csv`'s text and
/// the number of re-localisations into known maps.
pub(crate) fn run_slam(
    cycles: &[ContactCycle],
    odometry: &[Odometry],
    maps: &[String],
    slam: &mut WhiskerRatSlam,
    mut recognition: Option<&mut Recognition>,
) -> (String, usize) {
    let mut csv =
        String::from("whisk,contacts,matched,experience,created,relocalised,relocalised_object");
    for prefix in ["rc", "ic"] {
        for name in maps {
            let _ = write!(csv, ",{prefix}_{name}");
        }
    }
    csv.push('\n');
    let mut relocalisations = 0;
    for (k, (cycle, odo)) in cycles.iter().zip(odometry).enumerate() {
        let points: Vec<Point3<f64>> = cycle.contacts.iter().map(|c| c.point).collect();
        let features = whisker_slam::features::whisk::whisk_features(cycle, &points);
        let before = slam.map.experiences.len();
        let step = slam.whisk(&features, points.len(), odo);
        let onto = super::state::relocalised_into(&slam.map, step, before).map(|(_, o)| o);
        relocalisations += usize::from(onto.is_some());
        if let Some(r) = recognition.as_deref_mut() {
            r.update(onto.as_deref());
        }
        let _ = write!(
            csv,
            "{k},{},{},{}",
            points.len(),
            super::log::step_columns(step.as_ref()),
            onto.as_deref().unwrap_or("")
        );
        for name in maps {
            let _ = write!(
                csv,
                ",{}",
                recognition
                    .as_deref()
                    .map_or(0.0, |r| r.raw.confidence[name])
            );
        }
        for name in maps {
            let _ = write!(
                csv,
                ",{}",
                recognition.as_deref().map_or(0.0, |r| r.integrated[name])
            );
        }
        csv.push('\n');
    }
    (csv, relocalisations)
}

/// What recognition found, scored against the true object when known.
fn found(r: &Recognition, truth: Option<&str>) -> ReplayRecognition {
    let identified = r.identified();
    ReplayRecognition {
        identified: identified.map(|(o, _)| o.to_string()),
        identified_at: identified.map(|(_, t)| t),
        crossings: r.crossed.clone(),
        final_rc: r.raw.confidence.clone(),
        final_ic: r.integrated.clone(),
        outcome: truth.map(|t| r.outcome(t)),
        srt: truth.and_then(|t| r.srt(t).ok()),
        im: truth.and_then(|t| r.identity_margin(t)).map(|(v, _)| v),
        threshold: r.params.threshold,
    }
}

/// `replay.csv`, `summary.json` and, for a map task, `map.json` in `out` (the map of
/// `slam`, recording its sensing).
fn write_replay(
    out: &Path,
    csv: &str,
    summary: &ReplaySummary,
    (slam, sensed): (&WhiskerRatSlam, MapSensing),
    info: &ClosedLoopInfo,
) -> Result {
    whisker_scenario::files::create_dir(out)?;
    whisker_scenario::files::write_atomic(&out.join("replay.csv"), csv.as_bytes())?;
    let value = serde_json::to_value(summary).expect("plain data");
    let text = serde_json::to_string_pretty(&value).expect("plain JSON") + "\n";
    whisker_scenario::files::write_atomic(&out.join("summary.json"), text.as_bytes())?;
    if info.task == "map" {
        let mut map = slam.map.rested();
        map.sensing = Some(sensed);
        whisker_scenario::files::write_json(&out.join("map.json"), &map)?;
    }
    Ok(())
}
