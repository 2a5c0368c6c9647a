//! What `whisker run` writes for a `[navigate]` scenario (documented in
//! `scenarios/README.md`, `[navigate]`): `path.csv`, one row per update, `summary.json`,
//! the run's figures, and `path.svg`, the paths over the office's plan; and what it says
//! on the console.

use super::closures::Closures;
use super::terrain::{self, TerrainRun};
use crate::maze_slam::run_recording::RunRecording;
use crate::record::{Context, Eye, Layout, Target};
use serde_json::json;
use std::path::Path;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::files;
use whisker_scenario::navigate::NavigateConfig;
use whisker_scenario::plan::Plan;
use whisker_sim::environment::Environment;
use whisker_slam::navigation::map_error::MapError;
use whisker_slam::navigation::mode_switch::Verdict;
use whisker_slam::ratslam::experience_map::MapEvent;

/// The run's name in the recording (`slam/office`, `world/runs/office`).
pub const RUN: &str = "office";

/// The files a navigation run writes.
pub const FILES: &str = "path.csv, stops.csv, summary.json, path.svg";

/// What a run's files can say: the truth (true poses, the objects at the stops, and
/// what is judged against them) and the world (collisions, the piece a contact touched,
/// the cue's verdicts scored). A live run knows both; the replay of a dataset knows no
/// world, and without its `truth/` no truth: those columns are left empty and those
/// `summary.json` fields are `null`, never zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Known {
    pub truth: bool,
    pub world: bool,
}

impl Known {
    /// A live run's.
    pub const ALL: Known = Known {
        truth: true,
        world: true,
    };
}

/// The columns of `path.csv` and `stops.csv` that need the truth, and the one that
/// needs the world.
const PATH_TRUTH: [&str; 3] = ["true_x_m", "true_y_m", "true_heading_rad"];
const PATH_WORLD: [&str; 1] = ["touched"];
const STOPS_TRUTH: [&str; 4] = ["true_x_m", "true_y_m", "object", "outcome"];

/// `summary.json`'s fields that need the truth, and those that need the world.
const SUMMARY_TRUTH: [&str; 10] = [
    "closures",
    "recovery",
    "first_lap_end",
    "map_error",
    "odometry_error",
    "arr",
    "arcr",
    "relocalisations",
    "correct_relocalisations",
    "energy_metric",
];
const SUMMARY_WORLD: [&str; 4] = ["arm_collisions", "base_collisions", "collisions", "switch"];
/// `summary.json`'s `objects` fields that score the stops against the true objects.
const OBJECTS_TRUTH: [&str; 4] = ["correct", "wrong", "none", "wall"];

/// `csv` with the columns named `names` left empty.
fn blank(csv: String, names: &[&str]) -> String {
    use whisker_slam::csv_records::{header, records};
    let header = header(&csv);
    let gone: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| names.contains(h))
        .map(|(i, _)| i)
        .collect();
    let mut out = header.iter().collect::<Vec<_>>().join(",") + "\n";
    for (_, record) in records(&csv) {
        let cells: Vec<&str> = record
            .iter()
            .enumerate()
            .map(|(i, c)| if gone.contains(&i) { "" } else { c })
            .collect();
        out += &cells.join(",");
        out.push('\n');
    }
    out
}

/// `path.csv`, `stops.csv` and `summary.json` of `run` as far as `known`; `flags` are
/// (object mode, fusion, kidnap).
pub fn tables(
    run: &TerrainRun,
    seed: u64,
    flags: (bool, bool, bool),
    known: Known,
) -> (String, String, serde_json::Value) {
    let (mut path, mut stops) = (path_csv(run), stops_csv(run));
    let mut summary = summary(run, seed, flags);
    if !known.truth {
        path = blank(path, &PATH_TRUTH);
        stops = blank(stops, &STOPS_TRUTH);
        for k in SUMMARY_TRUTH {
            summary[k] = serde_json::Value::Null;
        }
        for k in OBJECTS_TRUTH {
            summary["objects"][k] = serde_json::Value::Null;
        }
    }
    if !known.world {
        path = blank(path, &PATH_WORLD);
        for k in SUMMARY_WORLD {
            summary[k] = serde_json::Value::Null;
        }
    }
    (path, stops, summary)
}

/// Checks what the navigation run `n` of the scenario in `file` needs beyond the
/// scenario's own fields: the arm's terrain posture, and the route clear of the office's
/// walls and posts and of the objects (the first pieces of `environment`); says what it
/// would do. `whisker check` and `whisker run` both call it, before anything is written.
pub fn check(
    file: &ScenarioFile,
    n: &NavigateConfig,
    plan: &Plan,
    environment: &Environment,
) -> Result<String> {
    let scenario = &file.scenario;
    let objects = Environment {
        pieces: environment.pieces[..scenario.objects.len()].to_vec(),
    };
    n.check_route(&file.path, &floor_plan(file)?, &objects)?;
    let chain = crate::sensing::array::array_chain(file, plan)?;
    let posture =
        super::posture::Posture::solve(&n.terrain, &chain, &plan.waypoints[0], &file.path)?;
    let t = &n.terrain;
    let joints: Vec<String> = posture
        .q
        .iter()
        .map(|q| format!("{:.1}", q.to_degrees()))
        .collect();
    Ok(format!(
        "{}\nterrain    the arm's base {} m above the floor holds the array at {:?} m, rpy {:?}° \
         (joints [{}]°); one whisk per update at {} Hz",
        n.describe(),
        t.mount_height_m,
        t.array_position_m,
        t.array_rpy_deg,
        joints.join(", "),
        terrain::UPDATE_HZ
    ))
}

/// The floor plan of the scenario's `[office]`, which `[navigate]` drives round.
fn floor_plan(file: &ScenarioFile) -> Result<whisker_sim::environment::floor_plan::FloorPlan> {
    match &file.scenario.office {
        Some(office) => office.checked_plan(&file.path),
        // Refused when the scenario was read (NavigateConfig::validate).
        None => Err(file.error(
            "navigate",
            "[navigate] drives round an office: expected an [office] section",
        )),
    }
}

/// Runs the `[navigate]` (`config`) of the scenario in `file` in `environment` and writes
/// its outputs into `dir` (which exists).
pub fn write(
    file: &ScenarioFile,
    config: &NavigateConfig,
    (plan, environment): (&Plan, &Environment),
    dir: &Path,
    rrd: &Target,
    ctx: Context,
) -> Result {
    let scenario = &file.scenario;
    let recorder = ctx.scenario_recording(
        &file.path,
        scenario.seed,
        scenario.output.recording,
        dir,
        rrd,
        Layout::SlamRuns {
            runs: vec![RUN.into()],
            images: true,
            timeline: "update",
            eye: Eye::of(environment, &[]).map(steep),
        },
    )?;
    if let Some(rec) = &recorder {
        rec.environment(environment)?;
    }
    let mut recording = recorder.as_deref().map(|rec| RunRecording {
        rec,
        name: RUN.into(),
        z: config.terrain.mount_height_m + config.terrain.array_position_m[2],
        hz: terrain::UPDATE_HZ,
        graph: Default::default(),
        landmarks: Vec::new(),
    });
    let start = std::time::Instant::now();
    // Each stop's closed loops, recorded as `whisker run` records an [explore] scenario,
    // into stops/NNNNNN-<recognise|map>.rrd beside the office's recording.
    let stops_dir = rrd
        .path(Some(dir), scenario.output.recording)
        .map(|p| p.parent().unwrap_or(dir).join("stops"));
    let stem = file.path.file_stem().unwrap_or_default().to_string_lossy();
    let record_stop =
        |name: &str, focus: &Environment| -> Result<Box<dyn crate::record::Recorder>> {
            let dir = stops_dir.as_ref().expect("only with a recording");
            files::create_dir(dir)?;
            let id = format!("{}-stop-{name}", crate::record::id(&stem, scenario.seed));
            // The object and the arm's base.
            let eye = Eye::of(focus, &[[0.0; 3]]);
            ctx.recordings.create(
                &dir.join(format!("{name}.rrd")),
                &id,
                Layout::ClosedLoop { eye },
            )
        };
    let stops: super::object_mode::StopRecorder = &record_stop;
    let run = terrain::run(
        file,
        plan,
        environment,
        config,
        ctx.reporter,
        recording.as_mut().map(|r| (r, stops)),
    )?;
    if let Some(r) = &recording {
        let truth: Vec<_> = run.updates.iter().map(|u| u.truth).collect();
        r.finish(Some(&truth), &run.estimate)?;
        let odometry: Vec<[f64; 3]> = run.dead_reckoned.iter().map(|p| [p.x, p.y, r.z]).collect();
        r.rec.trajectory(
            &format!("world/runs/{RUN}/odometry"),
            &odometry,
            [150, 150, 150],
        )?;
    }
    if let Some(rec) = recorder {
        rec.finish()?;
    }
    let flags = (config.object.is_some(), config.fusion, config.kidnap);
    let (path, stops, summary) = tables(&run, scenario.seed, flags, Known::ALL);
    files::write_atomic(&dir.join("path.csv"), path.as_bytes())?;
    files::write_atomic(&dir.join("stops.csv"), stops.as_bytes())?;
    let floor = floor_plan(file)?;
    let objects: Vec<(String, [f64; 2], [f64; 2])> = environment.pieces[..scenario.objects.len()]
        .iter()
        .map(|p| {
            let (lo, hi) = whisker_scenario::navigate::plan_rectangle(p);
            (p.name.clone(), [lo.x, lo.y], [hi.x, hi.y])
        })
        .collect();
    let figure = dir.join("path.svg");
    let title = format!(
        "{}, seed {}: map {:.3} m rms, odometry alone {:.3} m rms (after the best rigid fits)",
        file.path.file_name().unwrap_or_default().to_string_lossy(),
        scenario.seed,
        run.map_error.map_or(f64::NAN, |e| e.rms_m),
        run.odometry_error.map_or(f64::NAN, |e| e.rms_m),
    );
    let svg = super::figure::path_svg(&figure, &floor, &objects, &run, &title)?;
    files::write_atomic(&figure, svg.as_bytes())?;
    files::write_json(&dir.join("summary.json"), &summary)?;
    ctx.say(&console(&summary, Some(start.elapsed().as_secs_f64())));
    Ok(())
}

/// The console account of `summary.json` (`wall`: seconds it took, if timed): the run,
/// and with object mode its stops, closures and kidnap.
pub fn console(summary: &serde_json::Value, wall: Option<f64>) -> String {
    let mut text = results(summary, wall);
    if summary["mode"] == "terrain+object" {
        text += "\n";
        text += &object_results(summary);
    }
    if !summary["switch"].is_null() {
        return text;
    }
    // A replay: no office to collide with or to score the cue against, and (without
    // ground truth) no metric judged against the truth.
    let lines: Vec<String> = text
        .lines()
        .filter(|l| !l.starts_with("switch ") && !l.starts_with("collisions "))
        .map(|l| l.replace("null", "–"))
        .collect();
    lines.join("\n")
        + "\noffice     not in a dataset: collisions and the cue's verdicts scored against the \
           pieces are unknown (– = unknown; without truth/ also every metric judged against the \
           truth)"
}

/// `eye` moved to look down on its target from about 70° of elevation, at the same
/// distance: the office's paths run 0.25 m above the floor beside 0.5 m walls, which hide
/// them from the usual 40°.
fn steep(eye: Eye) -> Eye {
    let d: Vec<f64> = (0..3).map(|i| eye.position[i] - eye.target[i]).collect();
    let distance = d.iter().map(|v| v * v).sum::<f64>().sqrt();
    let dir = [0.0, -0.35, 1.0];
    let norm = dir.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
    Eye {
        position: [0, 1, 2].map(|i| eye.target[i] + dir[i] / norm * distance),
        target: eye.target,
    }
}

/// `path.csv`: per update the true, dead-reckoned and estimated base poses, the
/// contacts, template and experience.
fn path_csv(run: &TerrainRun) -> String {
    let mut csv = String::from(
        "update,time_s,true_x_m,true_y_m,true_heading_rad,odometry_x_m,odometry_y_m,\
         odometry_heading_rad,est_x_m,est_y_m,est_heading_rad,contacts,template,experience,event,\
         verdict,touched\n",
    );
    for (k, u) in run.updates.iter().enumerate() {
        let (o, e) = (run.dead_reckoned[k], run.estimate[k]);
        let event = event_name(u.event);
        let (verdict, touched) = match &u.switch {
            None => ("", ""),
            Some((Verdict::Wall, piece)) => ("wall", piece.as_str()),
            Some((Verdict::Object, piece)) => ("object", piece.as_str()),
            Some((Verdict::Undecided, piece)) => ("undecided", piece.as_str()),
        };
        csv += &format!(
            "{k},{},{},{},{},{},{},{},{},{},{},{},{},{},{event},{verdict},{touched}\n",
            k as f64 / terrain::UPDATE_HZ,
            u.truth.x,
            u.truth.y,
            u.truth.th,
            o.x,
            o.y,
            o.th,
            e.x,
            e.y,
            e.th,
            u.contacts,
            u.template,
            u.experience
        );
    }
    csv
}

fn event_name(e: MapEvent) -> &'static str {
    match e {
        MapEvent::Stay => "stay",
        MapEvent::Created => "created",
        MapEvent::Relocalised => "relocalised",
    }
}

/// `stops.csv`: per stop of object mode where the base stood, what it explored and
/// found, and the landmark's step in the planar map.
fn stops_csv(run: &TerrainRun) -> String {
    let mut csv = String::from(
        "update,true_x_m,true_y_m,turn_deg,drive_m,outline_x_m,outline_y_m,object,identified,outcome,\
         whisks,time_s,landmark_experience,landmark_event,ic,mapped\n",
    );
    for s in &run.stops {
        let e = &s.episode;
        let (exp, event) = match s.landmark {
            Some((x, ev)) => (x.to_string(), event_name(ev)),
            None => (String::new(), ""),
        };
        csv += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{exp},{event},{},{}\n",
            s.update,
            s.truth.x,
            s.truth.y,
            s.dock.turn.to_degrees(),
            s.dock.drive,
            s.centre.x,
            s.centre.y,
            e.object.as_deref().unwrap_or(""),
            e.identified.as_deref().unwrap_or(""),
            e.outcome(),
            e.whisks,
            s.time_s,
            e.ic.iter()
                .map(|(k, v)| format!("{k}={v:.0}"))
                .collect::<Vec<_>>()
                .join(" "),
            e.mapped.as_deref().unwrap_or(""),
        );
    }
    csv
}

/// `summary.json`'s `stops`: counts by outcome, whisks and time.
fn stops_json(run: &TerrainRun) -> serde_json::Value {
    let count = |o: &str| {
        run.stops
            .iter()
            .filter(|s| s.episode.outcome() == o)
            .count()
    };
    json!({
        "stops": run.stops.len(),
        "correct": count("correct"),
        "wrong": count("wrong"),
        "none": count("none"),
        "wall": count("wall"),
        "whisks": run.stops.iter().map(|s| s.episode.whisks).sum::<usize>(),
        // Folded from +0: an empty f64 sum is -0, which summary.json and the console showed.
        "time_s": run.stops.iter().fold(0.0, |t, s| t + s.time_s),
        "landmarks": run.stops.iter().filter(|s| s.landmark.is_some()).count(),
        "mapped": run.stops.iter().filter(|s| s.episode.mapped.is_some()).count(),
    })
}

/// `summary.json`'s `closures`: true and false by images and by landmarks, and all false.
fn closures_json(c: &Closures) -> serde_json::Value {
    json!({
        "image_true": c.image_true,
        "image_false": c.image_false,
        "landmark_true": c.landmark_true,
        "landmark_false": c.landmark_false,
        "false": c.image_false + c.landmark_false,
    })
}

/// `summary.json`'s `recovery`: the kidnapped robot's (null when not kidnapped);
/// `recovered` and `by_landmark` are 1 or 0 so that batches average them into rates.
fn recovery_json(c: &Closures) -> serde_json::Value {
    match &c.kidnap {
        None => serde_json::Value::Null,
        Some(r) => json!({
            "after_update": r.after_update,
            "recovered": u8::from(r.recovered_at.is_some()),
            "recovered_at": r.recovered_at,
            "by_landmark": u8::from(r.by_landmark),
            "time_s": r.time_s,
            "false_before": r.false_before,
        }),
    }
}

fn error_json(e: &Option<MapError>) -> serde_json::Value {
    match e {
        Some(e) => {
            json!({"rms_m": e.rms_m, "max_m": e.max_m, "heading_rms_deg": e.heading_rms_deg})
        }
        None => serde_json::Value::Null,
    }
}

/// `summary.json`; `flags` are (object mode, fusion, kidnap).
fn summary(
    run: &TerrainRun,
    seed: u64,
    (object, fusion, kidnap): (bool, bool, bool),
) -> serde_json::Value {
    let whisks_with_contact = run.updates.iter().filter(|u| u.contacts > 0).count();
    let arm = run.arm_collisions.iter().map(|c| ("arm", c));
    let collisions: Vec<serde_json::Value> = arm
        .chain(run.base_collisions.iter().map(|c| ("base", c)))
        .map(|(by, (k, what))| json!({"update": k, "by": by, "what": what}))
        .collect();
    json!({
        "seed": seed,
        "mode": if object { "terrain+object" } else { "terrain" },
        "fusion": fusion,
        "kidnap": kidnap,
        "time_s": run.time_s,
        "objects": stops_json(run),
        "closures": closures_json(&run.closures),
        "recovery": recovery_json(&run.closures),
        "updates": run.updates.len(),
        "first_lap_end": run.first_lap_end,
        "whisks_with_contact": whisks_with_contact,
        "contacts": run.updates.iter().map(|u| u.contacts).sum::<usize>(),
        "templates": run.templates,
        "experiences": run.experiences,
        "map_error": error_json(&run.map_error),
        "odometry_error": error_json(&run.odometry_error),
        "arr": run.metric.arr,
        "arcr": if run.metric.arcr.is_nan() { serde_json::Value::Null } else { json!(run.metric.arcr) },
        "relocalisations": run.metric.relocalisations,
        "correct_relocalisations": run.metric.correct,
        "energy_metric": run.energy,
        "arm_collisions": run.arm_collisions.len(),
        "base_collisions": run.base_collisions.len(),
        "collisions": collisions,
        "switch": run.switch.json(),
        "posture_joints_deg": run.posture.q.iter().map(|q| q.to_degrees()).collect::<Vec<f64>>(),
    })
}

/// The console lines on object mode, the closures and the kidnap, explained.
fn object_results(s: &serde_json::Value) -> String {
    let o = &s["objects"];
    let c = &s["closures"];
    let kidnap = match s["recovery"].as_object() {
        None => String::new(),
        Some(k) => match k["recovered_at"].as_u64() {
            Some(at) => format!(
                "\nkidnap     carried at update {}; re-localised at update {at}, {:.0} s later, by \
                 {} ({} false re-localisations before)",
                k["after_update"],
                k["time_s"].as_f64().unwrap_or(f64::NAN),
                if k["by_landmark"] == true {
                    "a recognised object"
                } else {
                    "the walls"
                },
                k["false_before"]
            ),
            None => format!(
                "\nkidnap     carried at update {}; never re-localised ({} false \
                 re-localisations)",
                k["after_update"], k["false_before"]
            ),
        },
    };
    format!(
        "objects    {} stops ({} whisks, {:.0} s): {} correct, {} wrong, {} none, {} at walls; {} \
         landmark steps (fusion {})\nclosures   images {} true, {} false; landmarks {} true, {} \
         false (true: onto an experience made within 0.3 m of where the base is){kidnap}\n  \
         a stop = the cue said object, the arm (or with dock = base the base) turned to face it and the Ch 6 closed loop ran; \
         none = no object's confidence reached the threshold (right for an unmapped object); \
         at walls = the cue was wrong (no loop runs)",
        o["stops"],
        o["whisks"],
        o["time_s"].as_f64().unwrap_or(f64::NAN),
        o["correct"],
        o["wrong"],
        o["none"],
        o["wall"],
        o["landmarks"],
        if s["fusion"] == true { "on" } else { "off" },
        c["image_true"],
        c["image_false"],
        c["landmark_true"],
        c["landmark_false"],
    )
}

/// The console account of `summary.json` (`wall`: seconds it took, if timed), explained.
fn results(s: &serde_json::Value, wall: Option<f64>) -> String {
    let sw = &s["switch"];
    let found = match sw["objects_found"].as_object() {
        Some(m) if !m.is_empty() => m
            .iter()
            .map(|(name, k)| format!("{name} (update {k})"))
            .collect::<Vec<_>>()
            .join(", "),
        _ => "none".into(),
    };
    let f = |v: &serde_json::Value| v.as_f64().map_or("–".to_owned(), |x| format!("{x:.3}"));
    format!(
        "navigated  {} updates{}, {} with contact ({} contacts): {} templates, \
         {} experiences\nmap error  {} m rms, {} m max after the best rigid fit (odometry \
         alone: {} m rms, {} m max)\nARR {}  ARCR {}  ({} re-localisations after the first \
         lap, {} correct within 0.1 m and 25°); Energy Metric {}\ncollisions arm {}, base {}\nswitch     {} verdicts after whisks that touched: on walls {} wall, {} object, \
         {} undecided; on objects {} object, {} wall, {} undecided; objects found: {}\n  \
         map error = each update's map pose against the truth after the rigid motion that fits \
         them best (a map's frame is arbitrary); ARR, ARCR, Energy Metric: Algorithm 1 and Eq \
         3.2 of the thesis (Ch 3); switch = the mode-switch cue (docs/navigation.md) scored \
         against the piece the newest contact lies on",
        s["updates"],
        wall.map_or(String::new(), |w| format!(" ({w:.1} s wall)")),
        s["whisks_with_contact"],
        s["contacts"],
        s["templates"],
        s["experiences"],
        f(&s["map_error"]["rms_m"]),
        f(&s["map_error"]["max_m"]),
        f(&s["odometry_error"]["rms_m"]),
        f(&s["odometry_error"]["max_m"]),
        f(&s["arr"]),
        f(&s["arcr"]),
        s["relocalisations"],
        s["correct_relocalisations"],
        f(&s["energy_metric"]),
        s["arm_collisions"],
        s["base_collisions"],
        sw["decisions"],
        sw["on_walls"]["wall"],
        sw["on_walls"]["object"],
        sw["on_walls"]["undecided"],
        sw["on_objects"]["object"],
        sw["on_objects"]["wall"],
        sw["on_objects"]["undecided"],
        found,
    )
}
