//! What `whisker object-slam` puts in its recording (`docs/recording.md`): each object in a
//! frame of its own (`world/objects/<object>`, placed side by side 0.4 m apart along y),
//! and for the best parameter set's walks A (two laps, building the map) and B (one lap
//! in A's map) at every whisk (timeline `whisk`): the array, the estimated position (the
//! current experience's map pose relative to the first, placed at A's first true pose), the
//! contacts — ground truth (the anticipated intersect) and estimate —, the 6-D pose
//! cells, the object map, the re-localisations; then the identification runs' confidence
//! per mapped object.
//!
//! The localisation runs are parallel; the recorded walks are run again, one after the
//! other on this thread, with the same parameters and data (WhiskerRatSLAM is
//! deterministic), so that the recording does not depend on the thread count.

use super::results::IdentificationRun;
use super::settings::{Combo, Settings, params};
use super::walk::{Sensed, Walk, anticipated, features};
use crate::record::{Contact, ContactKind, Context, GraphSchedule, Layout, Recorder};
use nalgebra::Isometry3;
use whisker_scenario::Result;
use whisker_sim::environment::assets::generate;
use whisker_sim::sensing::kinematic::SweepTarget;
use whisker_sim::whisker::array::{self, Module};
use whisker_slam::whisker_ratslam::object_map::ObjectMap;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

/// Spacing of the objects' frames along y (m).
const SPACING_M: f64 = 0.4;

/// Writes the recording of an object-slam run (`--rrd`, else `run.rrd` in `--out`).
pub(super) fn write(
    o: &Settings,
    data: &[Sensed],
    identification: &[IdentificationRun],
    ctx: Context,
) -> Result {
    let Some(path) = o.rrd.path(o.out.as_deref(), true) else {
        return Ok(());
    };
    let runs: Vec<String> = data
        .iter()
        .flat_map(|s| [format!("{}-A", s.asset.name), format!("{}-B", s.asset.name)])
        .collect();
    let layout = Layout::SlamRuns {
        runs,
        images: false,
        timeline: "whisk",
        // The first object and the walks around it (within ~0.3 m of it).
        eye: data.first().map(|s| {
            let (lo, hi) = whisker_sim::environment::mesh::bounds(&generate(s.asset).vertices);
            crate::record::Eye::framing(
                [lo.x - 0.3, lo.y - 0.3, lo.z],
                [hi.x + 0.3, hi.y + 0.3, hi.z + 0.3],
            )
        }),
    };
    let rec = ctx
        .recordings
        .create(&path, &crate::record::id("object-slam", o.seed), layout)?;
    let modules = array::modules();
    for (k, Sensed { asset, a, b, .. }) in data.iter().enumerate() {
        let frame = format!("world/objects/{}", asset.name);
        rec.frame(&frame, [0.0, SPACING_M * k as f64, 0.0])?;
        let mesh = generate(asset);
        rec.mesh(&format!("{frame}/mesh"), &mesh, [150, 150, 170])?;
        let target = SweepTarget::new(mesh);
        let walk = Walked {
            rec: rec.as_ref(),
            frame: &frame,
            target: &target,
            modules: &modules,
            origin: a.truth.as_ref().map(|t| t[0]),
        };
        let mut slam = WhiskerRatSlam::new(params(Combo::BEST, o.slam), ObjectMap::default());
        walk.replay(&format!("{}-A", asset.name), "A", &mut slam, a)?;
        let mut slam_b = WhiskerRatSlam::new(params(Combo::BEST, o.slam), slam.map.clone());
        walk.replay(&format!("{}-B", asset.name), "B", &mut slam_b, b)?;
    }
    for IdentificationRun {
        object,
        which,
        series,
        ..
    } in identification
    {
        let run = format!("{}-{}", data[*object].asset.name, which.name());
        for (k, confidence) in series.iter().enumerate() {
            rec.at_step("whisk", k as u64);
            for (object, v) in confidence {
                rec.scalar(&format!("recognition/{run}/{object}"), *v)?;
            }
        }
        rec.checkpoint()?;
    }
    rec.finish()
}

/// The recording of one object's walks.
struct Walked<'a> {
    rec: &'a dyn Recorder,
    frame: &'a str,
    target: &'a SweepTarget,
    modules: &'a [Module],
    /// A's first true pose: where the estimate (the map relative to its first
    /// experience) is placed.
    origin: Option<Isometry3<f64>>,
}

impl Walked<'_> {
    /// Runs `walk` through `slam` again, logging every whisk (run `run`, walk `which`).
    fn replay(&self, run: &str, which: &str, slam: &mut WhiskerRatSlam, walk: &Walk) -> Result {
        let (rec, frame) = (self.rec, self.frame);
        let mut graph = GraphSchedule::default();
        let truth_cycles = walk.truth.as_ref().map(|t| anticipated(self.target, t));
        let n = walk.cycles.len();
        for (k, (cycle, odo)) in walk.cycles.iter().zip(&walk.odometry).enumerate() {
            let step = slam.step(&features(cycle, Combo::BEST.contact, self.modules), odo);
            rec.at_step("whisk", k as u64);
            rec.pose_cells(&format!("slam/{run}/pose_cells"), &slam.cells.grid)?;
            if graph.due(slam.map.experiences.len(), k + 1 == n) {
                rec.object_map(
                    &format!("slam/{run}/map"),
                    &slam.map,
                    Some(step.experience),
                    None,
                )?;
            }
            if let Some(origin) = &self.origin {
                // The estimate: the current experience's map pose relative to the first.
                let estimate = origin * slam.map.pose(0).inverse() * slam.map.pose(step.experience);
                rec.marker(
                    &format!("{frame}/{which}/estimated"),
                    estimate.translation.vector.into(),
                    0.004,
                    Some([255, 140, 0]),
                )?;
            }
            if let (Some(truth), Some(anticipated)) = (&walk.truth, &truth_cycles) {
                let pose = &truth[k];
                rec.pose(&format!("{frame}/{which}/array"), pose)?;
                let world = |c: &whisker_slam::contact::ContactCycle| -> Vec<Contact> {
                    c.contacts
                        .iter()
                        .map(|c| {
                            let p = pose * c.point;
                            Contact {
                                whisker: c.whisker,
                                point: [p.x, p.y, p.z],
                            }
                        })
                        .collect()
                };
                rec.contacts_in(
                    &format!("{frame}/{which}/contacts"),
                    ContactKind::True,
                    k as u64,
                    &world(&anticipated[k]),
                )?;
                rec.contacts_in(
                    &format!("{frame}/{which}/contacts"),
                    ContactKind::Estimated,
                    k as u64,
                    &world(cycle),
                )?;
                if step.relocalised {
                    rec.relocalisation(
                        &format!("{frame}/{which}/relocalisations"),
                        pose,
                        &format!(
                            "{run} whisk {k}: re-localised onto experience {}",
                            step.experience
                        ),
                    )?;
                }
            }
            rec.step_done(k)?;
        }
        rec.checkpoint()?;
        if let Some(t) = &walk.truth {
            let points: Vec<[f64; 3]> = t.iter().map(|p| p.translation.vector.into()).collect();
            rec.trajectory(&format!("{frame}/{which}/true"), &points, [40, 200, 80])?;
        }
        Ok(())
    }
}
