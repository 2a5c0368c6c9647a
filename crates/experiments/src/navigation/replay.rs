//! `whisker slam DIR` on a navigation dataset ([`super::dataset`], issue #36): the
//! robot's own decisions ([`Navigator`]) on the logged whisks and odometry — the tactile
//! images, planar RatSLAM, the cue, where to stop and how to dock, the landmarks — and at
//! each stop the logged closed loops replayed open loop, as a closed-loop dataset is:
//! WhiskerRatSLAM and recognition against the known maps and the maps built so far, and
//! map building where the log has one (the built map is learned as `object-<n>`, as the
//! live robot learned it). The replay's stops must be the log's (`log/stops.csv`): a log
//! whose stops the robot's decisions do not reproduce is refused.
//!
//! It writes `path.csv`, `stops.csv` and `summary.json` in the formats of `whisker run`
//! (scenarios/README.md, `[navigate]`): with the ground truth they equal the live run's
//! files but for what needs the office itself (the `touched` column, the collisions and
//! the cue's verdicts scored against the pieces: empty or `null`); without `truth/`, also
//! the true poses, the objects at the stops and every metric judged against the truth.

use super::closures::{self, StepRecord};
use super::dataset::{
    ODOMETRY_COLUMNS, STOPS_COLUMNS, TRUTH_COLUMNS, TRUTH_STOPS_COLUMNS, stop_dir,
};
use super::navigator::{Navigator, StopRules};
use super::object_mode::{self, Episode};
use super::outputs::{self, Known};
use super::posture::Posture;
use super::terrain::{Stop, TerrainRun, Update};
use crate::closed_loop::dataset::run_slam;
use crate::dataset_format::manifest::{FILE, Manifest, NavigateObjectInfo};
use crate::dataset_format::records;
use crate::dataset_format::table::{Table, columns};
use crate::object_slam::dataset::read_odometry;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use std::collections::BTreeMap;
use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_slam::navigation::base_odometry::BaseMotion;
use whisker_slam::navigation::map_error;
use whisker_slam::pose::Pose2;
use whisker_slam::ratslam::metrics::{
    ExperienceMetric, consecutive, energy_metric, experience_metric,
};
use whisker_slam::recognition::Recognition;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

/// What the replay found: `summary.json`'s value (as `whisker run` writes it, with
/// `null` for what the dataset cannot say).
#[derive(Debug, Clone, serde::Serialize)]
#[serde(transparent)]
pub struct Report(pub serde_json::Value);

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "Navigation replay (the robot's decisions on the logged whisks, odometry and \
             stops; the office itself is not in a dataset: collisions and the cue's scores \
             are null)"
        )?;
        writeln!(f, "{}", outputs::console(&self.0, None))
    }
}

/// The logged stops: (update, duration, recognition whisks, map-building whisks).
type LoggedStop = (usize, f64, usize, usize);

/// Ground truth, when the dataset has it.
struct Truth {
    poses: Vec<Pose2>,
    /// The object at each stop (none: a wall), by update.
    objects: BTreeMap<usize, Option<String>>,
    first_lap_end: usize,
    carried_at: Option<usize>,
}

/// Replays the navigation dataset in `dir`; files into `out`.
pub fn replay(dir: &Path, m: &Manifest, out: Option<&Path>) -> Result<Report> {
    let file = dir.join(FILE);
    let info = m
        .navigate
        .as_ref()
        .ok_or_else(|| Error::field(&file, "navigate", "missing"))?;
    let n = info.updates;
    let whiskers = crate::dataset_format::rigid_whiskers(dir, &m.array)?;
    // The odometry first: its rows must number the manifest's updates.
    let readings = read_readings(&m.file(dir, "log/odometry.csv")?, n)?;
    let cycles = records::read_contacts(&m.file(dir, "log/contacts.csv")?, n, &m.array.labels)?;
    let log_poses = records::read_poses(&m.file(dir, "log/poses.csv")?)?;
    let logged = read_stops(&m.file(dir, "log/stops.csv")?)?;
    let truth = match m.has_truth(dir) {
        true => Some(read_truth(dir, m, n)?),
        false => None,
    };
    // The estimate starts where the base truly stood, or where its pose log says.
    let start = match &truth {
        Some(t) => t.poses[0],
        None => {
            let p = &log_poses[0].1;
            let (_, _, yaw) = p.rotation.euler_angles();
            Pose2 {
                x: p.translation.x,
                y: p.translation.y,
                th: yaw,
            }
        }
    };
    let q = info.posture.array_quaternion;
    let posture = Posture {
        q: info.posture.joints_rad.clone(),
        array: Isometry3::from_parts(
            Translation3::from(info.posture.array_position_m),
            UnitQuaternion::new_unchecked(Quaternion::new(q[3], q[0], q[1], q[2])),
        ),
        mount: info.posture.mount_height_m,
    };
    let rules = info.object.as_ref().map(|o| StopRules {
        by_base: o.dock == "base",
        dock_distance_m: o.dock_distance_m,
        revisit_m: o.revisit_m,
        landmark_energy: o.landmark_energy,
        landmark_gate_m: o.landmark_gate_m,
    });
    let mut robot = Navigator::new(
        info.ratslam,
        info.switch,
        (whiskers, posture.clone()),
        rules,
        info.fusion,
    );
    let mut stops_log = logged.iter();
    let known = match &info.object {
        Some(o) => known_maps(dir, m, o)?,
        None => Vec::new(),
    };
    let mut learned = object_mode::Learned::default();
    let (mut updates, mut steps, mut stops) = (Vec::new(), Vec::new(), Vec::new());
    let mut dead_reckoned = Vec::with_capacity(n);
    let mut clock = 0.0;
    for (k, cycle) in cycles.iter().enumerate() {
        let truth_at = truth.as_ref().map_or_else(Pose2::default, |t| t.poses[k]);
        let seen = robot.update(&start, &readings[k], cycle);
        dead_reckoned.push(seen.dead_reckoned);
        let step = seen.step;
        steps.push(StepRecord::of(&step, (k, clock), truth_at, false));
        updates.push(Update {
            truth: truth_at,
            time_s: clock,
            reading: readings[k],
            contacts: cycle.contacts.len(),
            image: seen.image,
            template: step.template,
            experience: step.experience,
            event: step.event,
            switch: seen.decision.as_ref().map(|d| (d.verdict, String::new())),
        });
        clock += 1.0 / info.update_hz;
        let Some((decision, dock)) = seen
            .decision
            .and_then(|d| robot.stop(&d).map(|dock| (d, dock)))
        else {
            continue;
        };
        let stops_file = dir.join("log/stops.csv");
        let logged_stop = stops_log.next().ok_or_else(|| {
            Error::Input(format!(
                "{}: the robot stops after update {k}, but the log lists no more stops",
                stops_file.display()
            ))
        })?;
        let &(at, duration, ..) = logged_stop;
        if at != k {
            return Err(Error::Input(format!(
                "{}: the next stop is logged after update {at}, but the robot stops after \
                 update {k}",
                stops_file.display()
            )));
        }
        let object = truth.as_ref().map(|t| t.objects.get(&k).cloned().flatten());
        let maps = (known.as_slice(), &mut learned);
        let episode = replay_stop((dir, m), info.object.as_ref(), logged_stop, maps, object)?;
        clock += duration;
        let landmark = robot.landmark(episode.identified.as_deref()).map(|s| {
            steps.push(StepRecord::of(&s, (k, clock), truth_at, true));
            (s.experience, s.event)
        });
        stops.push(Stop {
            update: k,
            truth: truth_at,
            dock,
            centre: decision.centre,
            episode,
            landmark,
            time_s: duration,
            loops: Default::default(),
        });
    }
    if let Some((at, ..)) = stops_log.next() {
        return Err(Error::Input(format!(
            "{}: a stop is logged after update {at}, but the robot did not stop there",
            dir.join("log/stops.csv").display()
        )));
    }
    let log: Vec<usize> = updates.iter().map(|u| u.experience).collect();
    let estimate = robot.slam.map.placed(&log, &start);
    let known_truth = truth.as_ref();
    let poses: Vec<Pose2> = known_truth.map_or_else(Vec::new, |t| t.poses.clone());
    let first_lap_end = known_truth.map_or(0, |t| t.first_lap_end);
    let run = TerrainRun {
        map_error: known_truth.and_then(|_| map_error::measure(&estimate, &poses)),
        odometry_error: known_truth.and_then(|_| map_error::measure(&dead_reckoned, &poses)),
        metric: match known_truth {
            Some(_) => experience_metric(&log, &poses, first_lap_end, 0.1, 25f64.to_radians()),
            // Unknown without the truth; `summary.json` says null.
            None => ExperienceMetric {
                arr: f64::NAN,
                arcr: f64::NAN,
                relocalisations: 0,
                correct: 0,
            },
        },
        energy: known_truth
            .and_then(|_| energy_metric(&estimate, &poses, &consecutive(poses.len())))
            .unwrap_or(f64::NAN),
        templates: robot.slam.view.templates.len(),
        experiences: robot.slam.map.experiences.len(),
        first_lap_end,
        arm_collisions: Vec::new(),
        base_collisions: Vec::new(),
        posture,
        switch: Default::default(),
        closures: closures::judge(&steps, known_truth.and_then(|t| t.carried_at)),
        stops,
        time_s: clock,
        updates,
        cycles,
        estimate,
        dead_reckoned,
    };
    let known = Known {
        truth: truth.is_some(),
        world: false,
    };
    let flags = (info.object.is_some(), info.fusion, info.kidnap);
    let (path, stops, summary) = outputs::tables(&run, m.seed, flags, known);
    if let Some(out) = out {
        whisker_scenario::files::create_dir(out)?;
        whisker_scenario::files::write_atomic(&out.join("path.csv"), path.as_bytes())?;
        whisker_scenario::files::write_atomic(&out.join("stops.csv"), stops.as_bytes())?;
        whisker_scenario::files::write_json(&out.join("summary.json"), &summary)?;
    }
    Ok(Report(summary))
}

/// A logged stop of the dataset in `dir`: its closed loops replayed with object mode's
/// parameters `o`, knowing the `known` maps and those `learned` so far (the map it builds
/// is learned); `object` the true object there (outer none: no ground truth).
fn replay_stop(
    (dir, m): (&Path, &Manifest),
    o: Option<&NavigateObjectInfo>,
    &(k, _, recognise, map): &LoggedStop,
    (known, learned): (&[(String, ObjectMap)], &mut object_mode::Learned),
    object: Option<Option<String>>,
) -> Result<Episode> {
    let mut episode = Episode {
        object: object.clone().flatten(),
        whisks: recognise + map,
        ..Episode::default()
    };
    let Some(o) = o else {
        return Ok(episode);
    };
    if recognise > 0 {
        let (cycles, odometry) = read_loop(dir, m, k, "recognise", recognise)?;
        let mut appended = ObjectMap::default();
        let mut names = Vec::new();
        for (name, map) in known.iter().chain(&learned.maps) {
            appended.append(map, name);
            names.push(name.clone());
        }
        let mut slam = WhiskerRatSlam::new(o.slam, appended);
        let mut recognition = Recognition::new(names.clone(), o.recognition);
        run_slam(
            &cycles,
            &odometry,
            &names,
            &mut slam,
            Some(&mut recognition),
        );
        episode.identified = recognition.identified().map(|(i, _)| i.to_string());
        episode.ic = recognition.integrated.clone();
    }
    // Scored as the live run scores it: a learned map stands for the object it was
    // built at (known only with the ground truth).
    episode.stands_for = match (&episode.identified, &object) {
        (Some(i), Some(_)) => Some(learned.built_at.get(i).unwrap_or(i).clone()),
        _ => None,
    };
    if map > 0 {
        let (cycles, odometry) = read_loop(dir, m, k, "map", map)?;
        let mut slam = WhiskerRatSlam::new(o.slam, ObjectMap::default());
        run_slam(&cycles, &odometry, &[], &mut slam, None);
        let label = format!("object-{}", learned.maps.len() + 1);
        if let Some(Some(at)) = &object {
            learned.built_at.insert(label.clone(), at.clone());
        }
        learned.maps.push((label.clone(), slam.map.rested()));
        episode.mapped = Some(label);
    }
    Ok(episode)
}

/// A stop's logged loop `task` of `n` whisks: contacts and odometry (the pose log is
/// checked, not replayed).
fn read_loop(
    dir: &Path,
    m: &Manifest,
    k: usize,
    task: &str,
    n: usize,
) -> Result<(
    Vec<whisker_slam::contact::ContactCycle>,
    Vec<whisker_slam::sensor::Odometry>,
)> {
    let at = |f: &str| m.file(dir, &format!("log/{}/{task}/{f}", stop_dir(k)));
    // The odometry first: its rows must number the logged whisks.
    let odometry = read_odometry(&at("odometry.csv")?, n)?;
    let cycles = records::read_contacts(&at("contacts.csv")?, n, &m.array.labels)?;
    records::read_poses(&at("poses.csv")?)?;
    Ok((cycles, odometry))
}

/// The known object maps of `log/maps/`, in the manifest's order.
fn known_maps(
    dir: &Path,
    m: &Manifest,
    o: &NavigateObjectInfo,
) -> Result<Vec<(String, ObjectMap)>> {
    o.maps
        .iter()
        .map(|name| {
            let path = m.file(dir, &format!("log/maps/{name}.json"))?;
            let map = ObjectMap::load(&path)
                .map_err(|e| Error::Input(format!("{}: {e}", path.display())))?;
            Ok((name.clone(), map))
        })
        .collect()
}

/// `log/odometry.csv`: `n` updates in order, each's reading (a noisy reading may drive
/// backwards a little; the first row is not applied).
fn read_readings(path: &Path, n: usize) -> Result<Vec<BaseMotion>> {
    let table = Table::read(path, &columns(ODOMETRY_COLUMNS))?;
    if table.len() != n {
        return Err(table.error(
            table.len() + 1,
            format!(
                "expected {n} updates (the manifest's navigate.updates), got {}",
                table.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(n);
    for row in table.rows() {
        let row = row?;
        row.expect(0, out.len())?;
        row.f64(1)?;
        let r = BaseMotion {
            rot1: row.f64(2)?,
            trans: row.f64(3)?,
            rot2: row.f64(4)?,
        };
        out.push(r);
    }
    Ok(out)
}

/// `log/stops.csv`.
fn read_stops(path: &Path) -> Result<Vec<LoggedStop>> {
    let table = Table::read(path, &columns(STOPS_COLUMNS))?;
    let mut out: Vec<LoggedStop> = Vec::new();
    for row in table.rows() {
        let row = row?;
        let at = row.index(0, usize::MAX)?;
        if out.last().is_some_and(|s| s.0 >= at) {
            return Err(row.error("column 1 (update): stops must be in increasing order"));
        }
        let duration = row.f64(1)?;
        if duration < 0.0 {
            return Err(row.error("column 2 (duration_s): expected a time ≥ 0"));
        }
        out.push((
            at,
            duration,
            row.index(2, usize::MAX)?,
            row.index(3, usize::MAX)?,
        ));
    }
    Ok(out)
}

/// The ground truth of `n` updates.
fn read_truth(dir: &Path, m: &Manifest, n: usize) -> Result<Truth> {
    let path = m.file(dir, "truth/poses.csv")?;
    let table = Table::read(&path, &columns(TRUTH_COLUMNS))?;
    if table.len() != n {
        return Err(table.error(table.len() + 1, format!("expected {n} updates")));
    }
    let mut poses = Vec::with_capacity(n);
    for row in table.rows() {
        let row = row?;
        row.expect(0, poses.len())?;
        row.f64(1)?;
        poses.push(Pose2 {
            x: row.f64(2)?,
            y: row.f64(3)?,
            th: row.f64(4)?,
        });
    }
    let path = m.file(dir, "truth/stops.csv")?;
    let table = Table::read(&path, &columns(TRUTH_STOPS_COLUMNS))?;
    let mut objects = BTreeMap::new();
    for row in table.rows() {
        let row = row?;
        let object = Some(row.text(3))
            .filter(|o| !o.is_empty())
            .map(String::from);
        objects.insert(row.index(0, n)?, object);
    }
    let path = m.file(dir, "truth/route.json")?;
    let bad = |e: String| Error::Input(format!("{}: {e}", path.display()));
    let text = std::fs::read_to_string(&path).map_err(|e| bad(e.to_string()))?;
    let route: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    let first_lap_end = route["first_lap_end"]
        .as_u64()
        .ok_or_else(|| bad("field `first_lap_end`: expected an update".into()))?
        as usize;
    let carried_at = match &route["carried_at"] {
        serde_json::Value::Null => None,
        v => Some(
            v.as_u64()
                .ok_or_else(|| bad("field `carried_at`: expected an update or null".into()))?
                as usize,
        ),
    };
    Ok(Truth {
        poses,
        objects,
        first_lap_end,
        carried_at,
    })
}
