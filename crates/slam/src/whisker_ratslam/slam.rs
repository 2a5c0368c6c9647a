//! The WhiskerRatSLAM main loop (thesis Alg 2, §5.1): per whisk, match the observed
//! features against the object map, excite the matched experience's pose cell
//! (Eq 5.8–5.9), run the pose cells and path integration, read the best pose, and update
//! the object map — create an experience, re-localise onto one, or stay.
//!
//! Experience rule (§5.1.2.4.1.1, with RatSLAM's re-localisation test): when the features
//! match an experience whose recorded pose cell is within `threshold_cells` of the best
//! pose, that experience becomes current (a link from the previous one, holding the
//! accumulated odometry, closes the loop); otherwise, when the features are new or the
//! best pose has moved more than `threshold_cells` from the current experience's cell, a
//! new experience is created at the current experience's pose composed with the
//! accumulated odometry; otherwise the current experience stays.

use super::object_map::{HistoryEntry, Link, ObjectMap};
use super::posecells6d::{Cell6, PoseCellParams, PoseCells6};
use super::relative_pose::Accumulator;
use crate::features::similarity::{Features, Matching};
use crate::sensor::Odometry;
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

/// Feature injection (Eq 5.8): Ω = ζ/30·(30 − e^{1.2·decay}).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Injection {
    /// ζ, the largest activity one match injects (0.3, §5.1.2.2).
    pub zeta: f64,
    /// Added to an experience's decay each time it is matched (OpenRatSLAM's 1.0).
    pub active_decay: f64,
    /// Taken off every experience's decay each update, down to 0 (OpenRatSLAM's 0.05).
    pub restore: f64,
}

impl Default for Injection {
    fn default() -> Self {
        Self {
            zeta: 0.3,
            active_decay: 1.0,
            restore: 0.05,
        }
    }
}

impl Injection {
    /// Ω for a decay (Eq 5.8); may be negative (then nothing is injected).
    pub fn energy(&self, decay: f64) -> f64 {
        self.zeta / 30.0 * (30.0 - (1.2 * decay).exp())
    }
}

/// WhiskerRatSLAM parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// Pose cells.
    pub pose_cells: PoseCellParams,
    /// Feature matching (Eq 5.5).
    pub matching: Matching,
    /// Feature injection (Eq 5.8).
    pub injection: Injection,
    /// Experience creation and relaxation.
    pub experiences: ExperienceParams,
    /// Feature merging (Table 5.1 "feature update"): a re-localisation averages the
    /// matched experience's features with the observed ones.
    pub merge_features: bool,
}

/// Experience creation and relaxation parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ExperienceParams {
    /// Pose-cell distance (cells) beyond which a new experience is made.
    pub threshold_cells: f64,
    /// Relaxation correction (0.5).
    pub correction: f64,
    /// Relaxation passes per update.
    pub loops: usize,
    /// Robust relaxation's translation scale σ_t (m; an addition to the thesis, see
    /// `ObjectMap::relax_robust`); 0 turns robust weighting off (the thesis' relaxation).
    pub robust_position_m: f64,
    /// Robust relaxation's rotation scale σ_θ (degrees).
    pub robust_rotation_deg: f64,
}

impl ExperienceParams {
    /// (σ_t, σ_θ in rad) of robust relaxation, or None when it is off.
    pub fn robust_scale(&self) -> Option<(f64, f64)> {
        (self.robust_position_m > 0.0 && self.robust_rotation_deg > 0.0).then(|| {
            (
                self.robust_position_m,
                self.robust_rotation_deg.to_radians(),
            )
        })
    }
}

impl Default for ExperienceParams {
    fn default() -> Self {
        Self {
            threshold_cells: 1.0,
            correction: 0.5,
            loops: 10,
            robust_position_m: 0.05,
            robust_rotation_deg: 20.0,
        }
    }
}

/// What one update did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// The experience the features matched (before the pose check), if any.
    pub matched: Option<usize>,
    /// The current experience after the update.
    pub experience: usize,
    /// Whether a new experience was made.
    pub created: bool,
    /// Whether the update re-localised onto an existing experience other than the
    /// previous one.
    pub relocalised: bool,
    /// The best pose cell.
    pub best: Cell6,
}

/// The WhiskerRatSLAM state.
#[derive(Debug, Clone)]
pub struct WhiskerRatSlam {
    /// Parameters.
    pub params: Params,
    /// Pose cells.
    pub cells: PoseCells6,
    /// The object map.
    pub map: ObjectMap,
    /// The current experience.
    pub current: Option<usize>,
    /// Odometry since the current experience.
    pub accumulated: Accumulator,
    samples: u64,
}

impl WhiskerRatSlam {
    /// A new run with `map` as prior knowledge (empty for a new object; appended object
    /// maps for identification). The pose cells start at the middle of the translation
    /// axes and at cell 0 (0°) of the rotation axes: the start orientation is the map
    /// frame's, so that each voxel's orientation (which rotates the body velocity) is the
    /// orientation relative to the start, and the body rotation rates drive the Euler axes
    /// near where that is exact. (The thesis starts every axis mid-grid, Fig 5.4, which
    /// turns the first velocities by 144° about every axis.)
    pub fn new(params: Params, map: ObjectMap) -> Self {
        let n = params.pose_cells.cells;
        let centre = [
            (n[0] / 2) as f64,
            (n[1] / 2) as f64,
            (n[2] / 2) as f64,
            0.0,
            0.0,
            0.0,
        ];
        Self {
            params,
            cells: PoseCells6::new(params.pose_cells, &centre),
            map,
            current: None,
            accumulated: Accumulator::default(),
            samples: 0,
        }
    }

    /// The pose estimate: the current experience's pose composed with the odometry since.
    pub fn estimate(&self) -> Option<Isometry3<f64>> {
        self.current
            .map(|c| self.map.pose(c) * self.accumulated.pose)
    }

    /// One iteration of Alg 2 for a whisk's `features` and the `odometry` since the last.
    pub fn step(&mut self, features: &Features, odometry: &Odometry) -> Step {
        let p = self.params;
        // match_features
        let matched = p
            .matching
            .best(features, self.map.experiences.iter().map(|e| &e.features))
            .map(|(i, _)| i);
        // feature_excitation (Eq 5.8–5.9) with per-experience decay
        for e in &mut self.map.experiences {
            e.decay = (e.decay - p.injection.restore).max(0.0);
        }
        if let Some(m) = matched {
            let e = &mut self.map.experiences[m];
            let omega = p.injection.energy(e.decay);
            let cells = e.cells;
            e.decay += p.injection.active_decay;
            if omega > 0.0 {
                self.cells.inject(&cells, omega);
            }
        }
        // path_integration
        self.cells.excite_inhibit();
        self.cells
            .path_integrate(&odometry.translation(), &odometry.rotation());
        let best = self.cells.best();
        self.accumulated.add(odometry);
        // process_object_map
        let (experience, created, relocalised) = self.process_map(features, matched, best);
        self.map.relax_robust(
            p.experiences.loops,
            p.experiences.correction,
            p.experiences.robust_scale(),
        );
        self.map.history.push(HistoryEntry {
            sample: self.samples,
            experience,
            relocalised,
        });
        self.samples += 1;
        Step {
            matched,
            experience,
            created,
            relocalised,
            best,
        }
    }

    /// The experience rule (module documentation); returns (current, created, relocalised).
    fn process_map(
        &mut self,
        features: &Features,
        matched: Option<usize>,
        best: Cell6,
    ) -> (usize, bool, bool) {
        let threshold = self.params.experiences.threshold_cells;
        let Some(current) = self.current else {
            let id = self
                .map
                .add(features.clone(), best, &Isometry3::identity(), None);
            self.current = Some(id);
            self.accumulated = Accumulator::default();
            return (id, true, false);
        };
        if let Some(m) = matched
            && self.cells.distance(&best, &self.map.experiences[m].cells) < threshold
        {
            if m == current {
                return (current, false, false);
            }
            let relative = self.accumulated.take();
            self.map.links.push(Link::new(current, m, &relative));
            if self.params.merge_features {
                merge(&mut self.map.experiences[m].features, features);
            }
            self.current = Some(m);
            return (m, false, true);
        }
        let moved = self
            .cells
            .distance(&best, &self.map.experiences[current].cells);
        if matched.is_none() || moved > threshold {
            let relative = self.accumulated.take();
            let pose = self.map.pose(current) * relative;
            let id = self.map.add(features.clone(), best, &pose, None);
            self.map.links.push(Link::new(current, id, &relative));
            self.current = Some(id);
            return (id, true, false);
        }
        (current, false, false)
    }
}

/// Feature merging: the stored features become the mean of themselves and the observed
/// ones (a slope missing on one side keeps the other's).
fn merge(stored: &mut Features, seen: &Features) {
    for (a, b) in stored.pfh.iter_mut().zip(&seen.pfh) {
        *a = (*a + b) / 2.0;
    }
    for (a, b) in stored.sda.0.iter_mut().zip(&seen.sda.0) {
        *a = match (*a, *b) {
            (Some(x), Some(y)) => Some((x + y) / 2.0),
            (x, y) => x.or(y),
        };
    }
}
