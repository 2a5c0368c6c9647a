//! What `whisker check` and `whisker run` say and write for an `[explore]` scenario.

use super::log::{CSV_NAME, SUMMARY_NAME};
use super::session::run_logged;
use crate::error::{Error, Result};
use crate::plan::Plan;
use crate::record::Context;
use crate::scenario::Scenario;
use crate::scenario::explore::{ExploreConfig, Task};
use std::path::Path;
use whisker_sim::environment::Environment;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// What `whisker check` says of an `[explore]` section: the task, the object, the
/// strategy, and each map loaded (a map that does not load is an input error).
pub fn describe(file: &Path, scenario: &Scenario, e: &ExploreConfig) -> Result<String> {
    let object = e.object_name(file, &scenario.object_names())?;
    let mut s = match e.task {
        Task::Map => format!(
            "explore    build the object map of {object}: {} loops over a {n}×{n} ellipsoid, SPC {}, at most {} whisks\n",
            e.map_loops,
            if e.spc { "on" } else { "off" },
            e.max_iterations,
            n = e.mesh_faces
        ),
        Task::Recognise => format!(
            "explore    recognise {object} with the {} strategy, SPC {}, IC threshold {}, until every IC ≥ {} or {} whisks\n",
            e.strategy.name(),
            if e.spc { "on" } else { "off" },
            e.recognition.threshold,
            e.stop_ic,
            e.max_iterations
        ),
    };
    for (name, path) in e.map_files(file) {
        let m = ObjectMap::load(&path)
            .map_err(|err| Error::field(file, &format!("explore.maps.{name}"), err))?;
        s.push_str(&format!(
            "map        {name}: {} ({} experiences, {} links)\n",
            path.display(),
            m.experiences.len(),
            m.links.len()
        ));
    }
    Ok(s)
}

/// `whisker run` of a scenario with `[explore]`: runs the loop and writes `explore.csv`,
/// `summary.json`, `contacts.csv` (every registered contact, in a kinematic run's columns),
/// the object map (`map.json`, map building) and `run.rrd` into `dir`.
pub fn write(
    file: &Path,
    scenario: &Scenario,
    plan: Plan,
    environment: &Environment,
    dir: &Path,
    rrd: &crate::record::Target,
    ctx: Context,
) -> Result {
    let recording = ctx.scenario_recording(
        file,
        scenario.seed,
        scenario.output.recording,
        dir,
        rrd,
        crate::record::Layout::ClosedLoop,
    )?;
    if let Some(rec) = &recording {
        rec.environment(environment)?;
    }
    let skeleton = plan.skeleton();
    let frames = plan.clone();
    let started = std::time::Instant::now();
    let out = run_logged(
        scenario,
        file,
        plan,
        environment,
        None,
        recording.as_deref(),
        ctx.reporter,
    )?;
    let wall = started.elapsed().as_secs_f64();
    crate::output::write_atomic(&dir.join(CSV_NAME), out.csv.as_bytes())?;
    crate::output::write_atomic(&dir.join("contacts.csv"), out.contacts_csv.as_bytes())?;
    let text = serde_json::to_string_pretty(&out.summary).expect("plain JSON") + "\n";
    crate::output::write_atomic(&dir.join(SUMMARY_NAME), text.as_bytes())?;
    if let Some(map) = &out.map {
        map.save(&dir.join("map.json")).map_err(Error::Failure)?;
    }
    if let Some(rec) = recording {
        for (k, q) in out.joints.iter().enumerate() {
            let tip = frames.chain.fk(q);
            rec.arm(out.times[k], &frames.link_frames(q, &skeleton), &tip)?;
        }
        let tips: Vec<_> = out.joints.iter().map(|q| frames.chain.fk(q)).collect();
        rec.tip_path(&tips)?;
        rec.finish()?;
    }
    let s = &out.summary;
    ctx.say(&format!("explored   {} whisks ({:.0} s simulated, {wall:.1} s wall): {} experiences, {} re-localisations into the loaded maps",
        s["iterations"],
        s["simulated_time_s"].as_f64().unwrap_or(0.0),
        s["experiences"],
        s["relocalisations"]
    ));
    ctx.say(&format!("fallbacks  {}", s["fallbacks"]));
    if let Some(r) = s["recognition"].as_object() {
        ctx.say(&format!(
            "recognised {} (true object {}): outcome {}, SRT {}, IM {}",
            r["identified"], s["object"], r["outcome"], r["srt"], r["im"]
        ));
    }
    if let Some(m) = s["map_accuracy"].as_object() {
        let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
        let (a, r) = (&m["aligned"], &m["revisits"]);
        ctx.say(&format!(
            "map        {} experiences checked: max error {:.4} m, median {:.4} m, {} over 2 cm \
             (from the first); after a rigid fit {:.4} / {:.4} m, {} over 2 cm",
            m["experiences_checked"],
            f(&m["max_error_m"]),
            f(&m["median_error_m"]),
            m["over_2cm"],
            f(&a["max_error_m"]),
            f(&a["median_error_m"]),
            a["over_2cm"]
        ));
        // Without revisits the medians are null: say so instead of printing NaN.
        let gap = match (
            r["median_distance_m"].as_f64(),
            r["median_angle_deg"].as_f64(),
        ) {
            (Some(d), Some(a)) => format!("median gap {d:.3} m, {a:.0}°"),
            _ => "no gap to measure".to_owned(),
        };
        ctx.say(&format!(
            "revisits   {} re-localisations into this run's experiences, {} true (within 2 cm and \
             10° of where it was made); {gap}",
            r["count"], r["true"]
        ));
    }
    let map = if out.map.is_some() { ", map.json" } else { "" };
    let rrd = rrd.wrote(dir, scenario.output.recording);
    ctx.say(&format!(
        "wrote      {}/{{{CSV_NAME}, {SUMMARY_NAME}, contacts.csv{map}{rrd}}}",
        dir.display()
    ));
    Ok(())
}
