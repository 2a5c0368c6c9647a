//! What `whisker check` and `whisker run` say and write for an `[explore]` scenario.

use super::log::{CSV_NAME, SUMMARY_NAME};
use super::session::run_logged;
use crate::record::Context;
use std::path::Path;
use whisker_scenario::ScenarioFile;
use whisker_scenario::explore::{ExploreConfig, Task};
use whisker_scenario::plan::Plan;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::Environment;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// Whisks of tip path the recording draws behind the tip.
const TRAIL_WHISKS: usize = 10;

/// What `whisker check` says of an `[explore]` section: the task, the object, the
/// strategy, and each map loaded (a map that does not load is an input error).
pub fn describe(file: &ScenarioFile, e: &ExploreConfig) -> Result<String> {
    let scenario = &file.scenario;
    let object = e.object_name(&file.path, &scenario.object_names())?;
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
    for (name, path) in e.map_files(&file.path) {
        let m = ObjectMap::load(&path)
            .map_err(|err| Error::field(&file.path, &format!("explore.maps.{name}"), err))?;
        s.push_str(&format!(
            "map        {name}: {} ({} experiences, {} links)\n",
            path.display(),
            m.experiences.len(),
            m.links.len()
        ));
    }
    Ok(s)
}

/// `whisker run` of a scenario with `[explore]` (`config`): runs the loop and writes
/// `explore.csv`, `summary.json`, `contacts.csv` (every registered contact, in a kinematic
/// run's columns), the object map (`map.json`, map building) and `run.rrd` into `dir`.
pub fn write(
    file: &ScenarioFile,
    config: &ExploreConfig,
    plan: Plan,
    environment: &Environment,
    dir: &Path,
    rrd: &crate::record::Target,
    ctx: Context,
) -> Result {
    let scenario = &file.scenario;
    // The camera frames the object and the arm's base.
    let eye = crate::record::Eye::of(environment, &[[0.0; 3]]);
    let recording = ctx.scenario_recording(
        &file.path,
        scenario.seed,
        scenario.output.recording,
        dir,
        rrd,
        crate::record::Layout::ClosedLoop { eye },
    )?;
    if let Some(rec) = &recording {
        rec.environment(environment)?;
    }
    let frames = plan.clone();
    let started = std::time::Instant::now();
    let out = run_logged(
        file,
        config,
        plan,
        environment,
        (None, recording.as_deref()),
        ctx.reporter,
    )?;
    let wall = started.elapsed().as_secs_f64();
    whisker_scenario::files::write_atomic(&dir.join(CSV_NAME), out.csv.as_bytes())?;
    whisker_scenario::files::write_atomic(&dir.join("contacts.csv"), out.contacts_csv.as_bytes())?;
    let text = serde_json::to_string_pretty(&out.summary).expect("plain JSON") + "\n";
    whisker_scenario::files::write_atomic(&dir.join(SUMMARY_NAME), text.as_bytes())?;
    if let Some(map) = &out.map {
        whisker_scenario::files::write_json(&dir.join("map.json"), map)?;
    }
    if let Some(rec) = recording {
        record_arm(rec.as_ref(), &frames, &out)?;
        rec.finish()?;
    }
    ctx.say(&results(&out.summary, wall));
    Ok(())
}

/// The arm of `plan` at every whisk of the loop `out` into `rec` (its links, the tip and
/// the tip's recent trail), then the frame axes.
pub fn record_arm(rec: &dyn crate::record::Recorder, plan: &Plan, out: &super::Outcome) -> Result {
    let skeleton = plan.skeleton();
    let tips: Vec<_> = out.joints.iter().map(|q| plan.chain.fk(q)).collect();
    for (k, q) in out.joints.iter().enumerate() {
        let links = plan.link_frames(q, &skeleton);
        let recent = &tips[k.saturating_sub(TRAIL_WHISKS)..=k];
        rec.arm_at_whisk(out.times[k], k as u64, (&links, &tips[k]), recent)?;
    }
    rec.frame_axes()
}

/// The console account of a closed-loop run's `summary.json` (`wall`: seconds it took),
/// its lines explained below it.
fn results(s: &serde_json::Value, wall: f64) -> String {
    use std::fmt::Write as _;
    let mut out = format!(
        "explored   {} whisks ({:.0} s simulated, {wall:.1} s wall): {} experiences, {} re-localisations into the loaded maps\n",
        s["iterations"],
        s["simulated_time_s"].as_f64().unwrap_or(0.0),
        s["experiences"],
        s["relocalisations"]
    );
    if let Some(f) = s["fallbacks"].as_object() {
        let list: Vec<String> = f
            .iter()
            .filter(|(_, n)| n.as_u64().is_some_and(|n| n > 0))
            .map(|(k, n)| format!("{} {n}", k.replace('_', " ")))
            .collect();
        let list = match list.is_empty() {
            true => "none".to_owned(),
            false => list.join(", "),
        };
        let _ = writeln!(out, "fallbacks  {list}");
    }
    let mut legend = vec![
        (
            "whisks",
            "one whisk cycle = one WhiskerRatSLAM update (Alg 2); each whisk the arm moves to a new goal",
        ),
        (
            "fallbacks",
            "goals replaced: collision = the arm or array would have entered the object, unreachable = no IK solution, pushed back = a face goal moved 2 cm outward until clear, lost contact = a whisk touched nothing, SPC limit = the placement control (§6.1.1) gave up after its step limit",
        ),
    ];
    if let Some(r) = s["recognition"].as_object() {
        let text = |v: &serde_json::Value| v.as_str().map_or_else(|| v.to_string(), str::to_owned);
        // Null when nothing crossed the threshold: said in words, not as JSON's null.
        let whisks = |v: &serde_json::Value, none: &str| {
            if v.is_null() {
                none.to_string()
            } else {
                format!("{v} whisks")
            }
        };
        let identified = &r["identified"];
        let _ = writeln!(
            out,
            "recognised {} (the object is {}): {}; SRT {}, IM {}",
            if identified.is_null() {
                "nothing".to_string()
            } else {
                text(identified)
            },
            text(&s["object"]),
            text(&r["outcome"]),
            whisks(
                &r["srt"],
                "- (the true object's IC never reached the threshold)"
            ),
            whisks(&r["im"], "-")
        );
        legend.push(("recognised", "the first object whose integrated confidence IC (the raw confidence summed over whisks, §6.1.2.4, Fig 6.4) reached the threshold (300, Fig 6.7); correct / wrong / none"));
        legend.push(("SRT", "successful recognition time (§6.2, Fig 6.9): whisks until the true object's IC reached the threshold; lower is better"));
        legend.push(("IM", "identity margin (§6.2, Fig 6.8): whisks from the true object's crossing to the next object's (censored at the run's end); larger = a clearer decision"));
    }
    if let Some(m) = s["map_accuracy"].as_object() {
        let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
        let (a, r) = (&m["aligned"], &m["revisits"]);
        let _ = writeln!(
            out,
            "map error  {} experiences: median {:.3} m, max {:.3} m from the first experience; after a rigid fit median {:.3} m, max {:.3} m; {} over 2 cm",
            m["experiences_checked"],
            f(&m["median_error_m"]),
            f(&m["max_error_m"]),
            f(&a["median_error_m"]),
            f(&a["max_error_m"]),
            a["over_2cm"]
        );
        // Without revisits the medians are null: say so instead of printing NaN.
        let gap = match (
            r["median_distance_m"].as_f64(),
            r["median_angle_deg"].as_f64(),
        ) {
            (Some(d), Some(a)) => format!("median gap {d:.3} m, {a:.0}°"),
            _ => "no gap to measure".to_owned(),
        };
        let _ = writeln!(
            out,
            "revisits   {} re-localisations into this run's own experiences, {} true; {gap}",
            r["count"], r["true"]
        );
        legend.push(("map error", "how far each experience of this run sits in the map from where the array truly was (§6.1.3), laid on the truth at the first experience, then by the best rigid fit; a metric map keeps this within a few cm. Ch 6 judges recognition, not this: errors larger than the object mean the map joins views topologically (re-localisations pull distant views together), not metrically"));
        legend.push(("revisits", "true = the experience re-localised into was made within 2 cm and 10° of where the array is; gap = how far apart they are"));
    }
    out.push_str(&whisker_scenario::console::legend(
        "what the lines mean",
        &legend,
    ));
    out
}
