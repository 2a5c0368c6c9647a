//! RatSLAM's experience map (thesis §2.1.2, §3.2.1): a graph
//! of experiences — a pose (x, y, θ) in the map frame, the local-view template and the
//! pose cell they were made at — joined by links holding the odometric relative pose
//! (distance, direction of travel relative to the start's heading, change of heading).
//!
//! Each update the odometry (turn, then move: §3.1.2) is accumulated from the current
//! experience. When the template differs from the current experience's or the best pose
//! cell has moved more than `delta_pc_threshold` cells from it, the experience with that
//! template nearest in pose cells (within the threshold) becomes current — a
//! re-localisation, linked from the previous one if they were not linked — or else a new
//! experience is made at the accumulated pose and linked. Then the map is relaxed:
//! `loops` Jacobi passes, each experience moving by `correction` of the mean
//! disagreement between its pose and those its links predict from their other ends; on a
//! loop the odometric error ends up shared equally among the links. The first experience
//! is at the origin with heading 0.

use super::posecells3d::{Cell3, PoseCells3};
use crate::pose::{Pose2, wrap};
use serde::{Deserialize, Serialize};

/// Parameters of the experience map.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ExperienceMapParams {
    /// Pose-cell distance beyond which the current experience no longer holds (cells;
    /// Table 3.1: 1).
    pub delta_pc_threshold: f64,
    /// Fraction of the disagreement corrected per pass.
    pub correction: f64,
    /// Relaxation passes per update (Table 3.1: 10).
    pub loops: usize,
}

impl Default for ExperienceMapParams {
    fn default() -> Self {
        Self {
            delta_pc_threshold: 1.0,
            correction: 0.5,
            loops: 10,
        }
    }
}

/// An experience.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Experience {
    /// Pose in the map.
    pub pose: Pose2,
    /// Local-view template.
    pub template: usize,
    /// Pose cell.
    pub cell: Cell3,
}

/// A link: the odometry from one experience to another.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Link {
    /// Start experience.
    pub from: usize,
    /// End experience.
    pub to: usize,
    /// Distance travelled (m, straight line).
    pub d: f64,
    /// Direction of the displacement relative to the start's heading (rad).
    pub heading: f64,
    /// Change of heading (rad).
    pub facing: f64,
}

impl Link {
    /// Where the link puts its end, seen from `from`.
    pub fn predict_to(&self, from: &Pose2) -> Pose2 {
        let a = from.th + self.heading;
        Pose2 {
            x: from.x + self.d * a.cos(),
            y: from.y + self.d * a.sin(),
            th: wrap(from.th + self.facing),
        }
    }

    /// Where the link puts its start, seen from `to`.
    pub fn predict_from(&self, to: &Pose2) -> Pose2 {
        let th = wrap(to.th - self.facing);
        let a = th + self.heading;
        Pose2 {
            x: to.x - self.d * a.cos(),
            y: to.y - self.d * a.sin(),
            th,
        }
    }
}

/// What one map update did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapEvent {
    /// The current experience still holds.
    Stay,
    /// A new experience was made.
    Created,
    /// An existing experience became current (re-localisation).
    Relocalised,
}

/// The experience map.
#[derive(Debug, Clone, Default)]
pub struct ExperienceMap {
    /// Parameters.
    pub params: ExperienceMapParams,
    /// Experiences, in order of creation.
    pub experiences: Vec<Experience>,
    /// Links.
    pub links: Vec<Link>,
    /// The current experience.
    pub current: usize,
    /// Odometry accumulated since the current experience: displacement (map axes) and
    /// heading.
    accum: Pose2,
}

impl ExperienceMap {
    /// An empty map.
    pub fn new(params: ExperienceMapParams) -> Self {
        Self {
            params,
            ..Self::default()
        }
    }

    /// The map's pose of each experience in `log` (the current experience at each
    /// update), relative to the first one's and placed at `start`: relaxation moves the
    /// whole map (its links fix only relative poses), so a path read from it is anchored
    /// at its first update's experience. Empty for an empty log.
    pub fn placed(&self, log: &[usize], start: &Pose2) -> Vec<Pose2> {
        let Some(&first) = log.first() else {
            return Vec::new();
        };
        let anchor = self.experiences[first].pose;
        log.iter()
            .map(|&e| start.compose(&anchor.relative(&self.experiences[e].pose)))
            .collect()
    }

    /// The dead-reckoned pose: the current experience plus the odometry since.
    pub fn pose(&self) -> Pose2 {
        match self.experiences.get(self.current) {
            Some(e) => Pose2 {
                x: e.pose.x + self.accum.x,
                y: e.pose.y + self.accum.y,
                th: self.accum.th,
            },
            None => self.accum,
        }
    }

    fn link_to(&self, to: usize, end: &Pose2) -> Link {
        let from = &self.experiences[self.current].pose;
        let (dx, dy) = (end.x - from.x, end.y - from.y);
        Link {
            from: self.current,
            to,
            d: dx.hypot(dy),
            heading: wrap(dy.atan2(dx) - from.th),
            facing: wrap(end.th - from.th),
        }
    }

    /// One update: odometry `distance` (m) after turning `dtheta` (rad), the local view's
    /// template and the best cell of the pose cells `cells`.
    pub fn update(
        &mut self,
        distance: f64,
        dtheta: f64,
        template: usize,
        cell: &Cell3,
        cells: &PoseCells3,
    ) -> MapEvent {
        self.accum.th = wrap(self.accum.th + dtheta);
        self.accum.x += distance * self.accum.th.cos();
        self.accum.y += distance * self.accum.th.sin();
        if self.experiences.is_empty() {
            self.experiences.push(Experience {
                pose: Pose2::default(),
                template,
                cell: *cell,
            });
            self.accum = Pose2::default();
            return MapEvent::Created;
        }
        let cur = &self.experiences[self.current];
        let threshold = self.params.delta_pc_threshold;
        if cur.template == template && cells.distance(&cur.cell, cell) <= threshold {
            return MapEvent::Stay;
        }
        let end = self.pose();
        let matched = self
            .experiences
            .iter()
            .enumerate()
            .filter(|(_, e)| e.template == template)
            .map(|(i, e)| (i, cells.distance(&e.cell, cell)))
            .filter(|&(_, d)| d < threshold)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let event = match matched {
            Some((m, _)) if m != self.current => {
                let linked = self.links.iter().any(|l| {
                    (l.from, l.to) == (self.current, m) || (l.from, l.to) == (m, self.current)
                });
                if !linked {
                    let link = self.link_to(m, &end);
                    self.links.push(link);
                }
                self.current = m;
                MapEvent::Relocalised
            }
            Some(_) => MapEvent::Stay,
            None => {
                let id = self.experiences.len();
                let link = self.link_to(id, &end);
                self.links.push(link);
                self.experiences.push(Experience {
                    pose: end,
                    template,
                    cell: *cell,
                });
                self.current = id;
                MapEvent::Created
            }
        };
        if event != MapEvent::Stay {
            self.accum = Pose2 {
                x: 0.0,
                y: 0.0,
                th: self.experiences[self.current].pose.th,
            };
            self.relax(self.params.loops, self.params.correction);
        }
        event
    }

    /// `loops` Jacobi passes of relaxation (module documentation).
    pub fn relax(&mut self, loops: usize, correction: f64) {
        let n = self.experiences.len();
        for _ in 0..loops {
            let poses: Vec<Pose2> = self.experiences.iter().map(|e| e.pose).collect();
            let mut sum = vec![(0.0, 0.0, 0.0); n];
            let mut degree = vec![0usize; n];
            for l in &self.links {
                if l.from == l.to {
                    continue;
                }
                for (i, p) in [
                    (l.to, l.predict_to(&poses[l.from])),
                    (l.from, l.predict_from(&poses[l.to])),
                ] {
                    sum[i].0 += p.x - poses[i].x;
                    sum[i].1 += p.y - poses[i].y;
                    sum[i].2 += wrap(p.th - poses[i].th);
                    degree[i] += 1;
                }
            }
            for (i, e) in self.experiences.iter_mut().enumerate() {
                if degree[i] == 0 {
                    continue;
                }
                let k = correction / degree[i] as f64;
                e.pose.x += k * sum[i].0;
                e.pose.y += k * sum[i].1;
                e.pose.th = wrap(e.pose.th + k * sum[i].2);
            }
        }
    }
}
