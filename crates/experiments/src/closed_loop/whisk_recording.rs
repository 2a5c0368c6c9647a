//! What a closed loop puts in its recording per whisk (`docs/recording.md`): the goal and
//! the array, the shafts through the whisk, the contacts (ground truth and estimate), the
//! 2 kHz streams of physics whiskers, the 6-D pose cells, the object map with the current
//! experience and the strategy's target, re-localisations, and the raw and integrated
//! confidence in each object (§6.2).

use super::state::{Loop, Sensor, Whisk};
use crate::record::ContactKind;
use crate::record::Recorder;
use whisker_scenario::Result;

/// Instants per whisk at which the shafts are drawn.
const SHAFT_FRAMES: usize = 10;

impl Loop<'_> {
    /// Logs the final map and the outcome (a line of the event log) at the end of the run.
    pub(super) fn record_end(&mut self, rec: &dyn Recorder, summary: &serde_json::Value) -> Result {
        rec.at(self.time);
        // On the `whisk` timeline too: the state after the last whisk.
        let whisks = summary["iterations"].as_u64().unwrap_or(0);
        rec.at_step("whisk", whisks.saturating_sub(1));
        rec.object_map(
            "slam/map",
            &self.slam.map,
            self.slam.current,
            self.course.stepping_to(),
        )?;
        let text = match summary["recognition"].as_object() {
            Some(r) => format!(
                "outcome {}: identified {} (true object {}), SRT {}, IM {}",
                r["outcome"], r["identified"], summary["object"], r["srt"], r["im"]
            ),
            None => format!(
                "map built: {} experiences in {} whisks",
                summary["experiences"], summary["iterations"]
            ),
        };
        rec.event(&text)?;
        rec.checkpoint()
    }

    /// Logs whisk `w` to `rec`.
    pub(super) fn record(&mut self, rec: &dyn Recorder, w: &Whisk) -> Result {
        let t = w.start;
        let k = w.iteration as u64;
        rec.at(t);
        rec.at_step("whisk", k);
        if let Some((goal, kind)) = w.goal {
            rec.goal(goal, &kind.to_string())?;
        }
        rec.pose("world/array", w.pose)?;
        let (truth, shafts) = match &self.sensing {
            Sensor::Kinematic(a) => (crate::sensing::contact::intersects(a), Some(&**a)),
            Sensor::Physics(p) => (
                crate::sensing::contact::anticipated(&self.target, p.rigid(), w.pose),
                None,
            ),
        };
        rec.contacts_in("world/contacts", ContactKind::True, k, &truth)?;
        rec.contacts_in("world/contacts", ContactKind::Estimated, k, w.contacts)?;
        // The straight shafts through the whisk (on `sim_time` only).
        if let Some(a) = shafts {
            for f in 0..SHAFT_FRAMES {
                let tf = t + w.period * f as f64 / SHAFT_FRAMES as f64;
                rec.shafts(
                    tf,
                    &crate::sensing::contact::rigid_shafts(a, w.pose, tf - t),
                )?;
            }
        }
        if let (Some(streams), Some(cols)) = (w.streams, &mut self.records.columns) {
            cols.push_streams(rec, t, 0, streams, None)?;
            cols.send(rec)?;
        }
        // The SLAM state after the whisk.
        let te = t + w.period;
        rec.at(te);
        rec.at_step("whisk", k);
        rec.pose_cells("slam/pose_cells", &self.slam.cells.grid)?;
        if self
            .records
            .graph
            .due(self.slam.map.experiences.len(), false)
        {
            rec.object_map(
                "slam/map",
                &self.slam.map,
                w.step.map(|s| s.experience),
                self.course.stepping_to(),
            )?;
        }
        if let Some(step) = w.step.filter(|s| s.relocalised) {
            let onto = w.onto.map_or(String::new(), |o| format!(" ({o})"));
            rec.relocalisation(
                "world/relocalisations",
                w.pose,
                &format!(
                    "whisk {}: re-localised onto experience {}{onto}",
                    w.iteration, step.experience
                ),
            )?;
        }
        if w.spc.corrects() {
            rec.event(&format!("whisk {}: SPC {}", w.iteration, w.spc.name()))?;
        }
        if let Some(r) = &self.recognition {
            for (o, v) in &r.raw.confidence {
                rec.scalar(&format!("recognition/raw/{o}"), *v)?;
            }
            for (o, v) in &r.integrated {
                rec.scalar(&format!("recognition/integrated/{o}"), *v)?;
            }
            // Drawn beside the ICs: the threshold they race to (Fig 6.7).
            rec.scalar("recognition/integrated/threshold", r.params.threshold)?;
        }
        rec.step_done(w.iteration)
    }
}
