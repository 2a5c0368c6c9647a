//! What `whisker maze-slam` puts in its recording (`docs/recording.md`): the maze, and per
//! RatSLAM run (`slam/<run>`, `world/runs/<run>`; a run is one seed, variant, image set and
//! tuning) at every update the tactile image, the pose cells (maximum over θ), the
//! experience map, the true position and the re-localisations; at its end the true and
//! estimated trajectories. Timelines `update` and `sim_time` (update / `hz`: the maze's
//! 1.5 Hz, the office's 1 Hz).

use super::path::Sample;
use crate::record::{Graph, GraphSchedule, Recorder};
use nalgebra::{Isometry3, Translation3};
use whisker_scenario::Result;
use whisker_slam::pose::Pose2;
use whisker_slam::ratslam::experience_map::MapEvent;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::{RatSlam, Step};

/// The recording of one run.
pub struct RunRecording<'a> {
    pub rec: &'a dyn Recorder,
    /// The run's name (`<images>-<variant>[-t<threshold>-e<energy>]-s<seed>`).
    pub name: String,
    /// Height at which paths are drawn (the array's plane, m).
    pub z: f64,
    /// Updates per second (timeline `sim_time`).
    pub hz: f64,
    pub graph: GraphSchedule,
    /// The office's object landmarks: each one's experience and label (`box#0`), drawn
    /// over the map (`slam/<run>/map/landmarks`).
    pub landmarks: Vec<(usize, String)>,
}

/// A run's name as an entity path segment.
pub fn run_name(images: &str, variant: &str, tuning: &str, seed: u64) -> String {
    crate::record::entity_name(&format!("{images}-{variant}{tuning}-s{seed}"))
}

impl RunRecording<'_> {
    fn at(&self, k: usize) {
        self.rec.at(k as f64 / self.hz);
        self.rec.at_step("update", k as u64);
    }

    fn point(&self, p: &Sample) -> [f64; 3] {
        [p.x, p.y, self.z]
    }

    /// Logs update `k`: its image, the state after it, and the true pose.
    pub fn update(
        &mut self,
        k: usize,
        image: &TactileImage,
        slam: &RatSlam,
        step: &Step,
        truth: Option<&Sample>,
        last: bool,
    ) -> Result {
        let (rec, run) = (self.rec, self.name.as_str());
        self.at(k);
        rec.tactile_image(&format!("slam/{run}/tactile_image"), image)?;
        rec.pose_cells(&format!("slam/{run}/pose_cells"), &slam.cells.grid)?;
        if self.graph.due(slam.map.experiences.len(), last) {
            rec.graph(
                &format!("slam/{run}/map"),
                &Graph {
                    positions: slam
                        .map
                        .experiences
                        .iter()
                        .map(|e| [e.pose.x, e.pose.y])
                        .collect(),
                    links: slam.map.links.iter().map(|l| (l.from, l.to)).collect(),
                    current: Some(step.experience),
                    target: None,
                    objects: None,
                },
            )?;
            if !self.landmarks.is_empty() {
                let e = &slam.map.experiences;
                let (points, labels): (Vec<[f64; 2]>, Vec<String>) = self
                    .landmarks
                    .iter()
                    .map(|(x, l)| ([e[*x].pose.x, e[*x].pose.y], l.clone()))
                    .unzip();
                rec.labelled_2d(
                    &format!("slam/{run}/map/landmarks"),
                    &points,
                    &labels,
                    [40, 170, 60],
                )?;
            }
        }
        if let Some(t) = truth {
            let p = self.point(t);
            rec.marker(&format!("world/runs/{run}/array"), p, 0.006, None)?;
            if step.event == MapEvent::Relocalised {
                let at =
                    Isometry3::from_parts(Translation3::new(p[0], p[1], p[2]), Default::default());
                rec.relocalisation(
                    &format!("world/runs/{run}/relocalisations"),
                    &at,
                    &format!(
                        "{run} update {k}: re-localised onto experience {}",
                        step.experience
                    ),
                )?;
            }
        }
        rec.step_done(k)
    }

    /// Logs the run's true and estimated trajectories (static).
    pub fn finish(&self, truth: Option<&[Sample]>, estimate: &[Pose2]) -> Result {
        let run = &self.name;
        if let Some(t) = truth {
            let points: Vec<[f64; 3]> = t.iter().map(|p| self.point(p)).collect();
            self.rec
                .trajectory(&format!("world/runs/{run}/true"), &points, [40, 200, 80])?;
        }
        let points: Vec<[f64; 3]> = estimate.iter().map(|p| self.point(p)).collect();
        self.rec.trajectory(
            &format!("world/runs/{run}/estimated"),
            &points,
            [255, 140, 0],
        )?;
        self.rec.checkpoint()
    }
}
