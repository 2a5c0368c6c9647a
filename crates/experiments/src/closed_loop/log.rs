//! What a closed-loop run writes: `explore.csv`, one row per iteration, and
//! `summary.json` (both documented in `scenarios/README.md`).

use super::goal::{Fallback, Fallbacks, GoalKind};
use nalgebra::Isometry3;
use serde_json::json;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use whisker_scenario::explore::{Strategy, Task};
use whisker_slam::pose;
use whisker_slam::recognition::Recognition;
use whisker_slam::whisker_ratslam::slam::Step;

/// File name of the per-iteration log.
pub const CSV_NAME: &str = "explore.csv";
/// File name of the run's summary.
pub const SUMMARY_NAME: &str = "summary.json";

/// The header of `explore.csv` for the loaded `objects` and `dof` joints.
pub fn header(objects: &[String], dof: usize) -> String {
    let mut h = String::from(
        "iteration,time_s,goal_kind,goal_x_m,goal_y_m,goal_z_m,goal_qx,goal_qy,goal_qz,goal_qw,ik_status,\
         x_m,y_m,z_m,qx,qy,qz,qw",
    );
    for j in 0..dof {
        let _ = write!(h, ",q{j}_rad");
    }
    h.push_str(",contacts,matched,experience,created,relocalised,relocalised_object");
    for o in objects {
        let _ = write!(h, ",rc_{o}");
    }
    for o in objects {
        let _ = write!(h, ",ic_{o}");
    }
    h.push_str(",strategy_state,spc\n");
    h
}

/// One iteration's record.
pub struct Row<'a> {
    pub iteration: usize,
    pub time: f64,
    pub goal: Option<&'a (Isometry3<f64>, GoalKind)>,
    pub status: &'a str,
    pub reached: &'a Isometry3<f64>,
    pub joints: &'a [f64],
    pub contacts: usize,
    pub step: Option<&'a Step>,
    pub onto: Option<&'a str>,
    pub recognition: Option<&'a Recognition>,
    pub heading: &'a str,
    pub spc: &'a str,
}

fn pose_columns(out: &mut String, p: &Isometry3<f64>) {
    let t = p.translation.vector;
    let [qx, qy, qz, qw] = pose::quaternion_xyzw(&p.rotation);
    let _ = write!(out, ",{},{},{},{qx},{qy},{qz},{qw}", t.x, t.y, t.z);
}

/// The columns `matched,experience,created,relocalised` of a whisk's SLAM `step`, all
/// empty while there is no experience.
pub fn step_columns(step: Option<&Step>) -> String {
    match step {
        Some(s) => format!(
            "{},{},{},{}",
            s.matched.map_or(String::new(), |m| m.to_string()),
            s.experience,
            u8::from(s.created),
            u8::from(s.relocalised)
        ),
        None => ",,,".into(),
    }
}

/// Appends one row.
pub fn row(out: &mut String, r: &Row, objects: &[String]) {
    let _ = write!(out, "{},{}", r.iteration, r.time);
    match r.goal {
        Some((g, kind)) => {
            let _ = write!(out, ",{kind}");
            pose_columns(out, g);
        }
        None => out.push_str(",none,,,,,,,"),
    }
    let _ = write!(out, ",{}", r.status);
    pose_columns(out, r.reached);
    for q in r.joints {
        let _ = write!(out, ",{q}");
    }
    let _ = write!(out, ",{},{}", r.contacts, step_columns(r.step));
    let _ = write!(out, ",{}", r.onto.unwrap_or(""));
    for o in objects {
        let _ = write!(
            out,
            ",{}",
            r.recognition.map_or(0.0, |c| c.raw.confidence[o])
        );
    }
    for o in objects {
        let _ = write!(out, ",{}", r.recognition.map_or(0.0, |c| c.integrated[o]));
    }
    let _ = writeln!(out, ",{},{}", r.heading, r.spc);
}

/// The figures of `summary.json`.
pub struct Summary<'a> {
    pub task: Task,
    pub truth: &'a str,
    pub strategy: Strategy,
    pub spc: bool,
    pub iterations: usize,
    pub relocalisations: usize,
    pub experiences: usize,
    pub faces_per_loop: usize,
    pub loops: usize,
    pub recognition: Option<&'a Recognition>,
    pub mean_rc: BTreeMap<String, f64>,
    pub fallbacks: &'a Fallbacks,
    pub map_accuracy: Option<super::map_accuracy::MapAccuracy>,
    pub time: f64,
    /// LSR runs: what its plans were like.
    pub lsr_plans: Option<super::strategy::LsrTally>,
}

impl Summary<'_> {
    /// The JSON value.
    pub fn json(&self) -> serde_json::Value {
        let mut fallbacks = serde_json::Map::new();
        for f in Fallback::ALL {
            fallbacks.insert(f.name().into(), json!(self.fallbacks.get(f)));
        }
        let recognition = self.recognition.map(|r| {
            let identified = r.identified();
            let srt = r.srt(self.truth);
            let im = r.identity_margin(self.truth);
            json!({
                "outcome": r.outcome(self.truth),
                "identified": identified.map(|(o, _)| o),
                "identified_at": identified.map(|(_, t)| t),
                "threshold": r.params.threshold,
                "srt": srt.ok(),
                "srt_censored_at": srt.err(),
                "im": im.map(|(v, _)| v),
                "im_censored": im.map(|(_, c)| c),
                "crossings": r.crossed,
                "final_rc": r.raw.confidence,
                "final_ic": r.integrated,
                "mean_rc": self.mean_rc,
                // The thesis' "mean RC of the correct object" (§6.3).
                "true_mean_rc": self.mean_rc.get(self.truth),
            })
        });
        let map = self.map_accuracy.as_ref().map(|m| m.json());
        let mut summary = json!({
            "task": match self.task { Task::Map => "map", Task::Recognise => "recognise" },
            "object": self.truth,
            "strategy": self.strategy.name(),
            "spc": self.spc,
            "iterations": self.iterations,
            "simulated_time_s": self.time,
            "relocalisations": self.relocalisations,
            "experiences": self.experiences,
            "goal_faces_per_loop": self.faces_per_loop,
            "loops_completed": self.loops,
            "fallbacks": fallbacks,
            "recognition": recognition,
            "map_accuracy": map,
        });
        if let Some(tally) = self.lsr_plans {
            summary["lsr"] = json!(tally);
        }
        summary
    }
}
