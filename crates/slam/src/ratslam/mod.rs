//! Planar RatSLAM on tactile images (thesis Chapter 3, §2.1.2): local view cells on 6 × 3
//! tactile images ([`local_view`], Eq 3.1), an (x, y, θ) pose-cell network
//! ([`posecells3d`]), the experience map ([`experience_map`]), the odometry error model of
//! §3.1.2 ([`odometry`]) and the Experience and Energy Metrics ([`metrics`], Algorithm 1,
//! Eq 3.2–3.3).
//!
//! One update ([`RatSlam::step`]) per tactile image and odometry reading (1.5 Hz in the
//! thesis): the image is matched against the templates (a new one is stored at the
//! current best pose cell); a matched template injects its Eq 5.8 energy at its pose
//! cell; the pose cells excite, inhibit and normalise, then integrate the odometry (turn,
//! then move); the experience map takes the odometry, the template and the new best cell.

pub mod experience_map;
pub mod local_view;
pub mod metrics;
pub mod odometry;
pub mod posecells3d;

use crate::invalid::Invalid;
use crate::message::short;
use experience_map::{ExperienceMap, ExperienceMapParams, MapEvent};
use local_view::{LocalView, LocalViewParams, TactileImage};
use posecells3d::{Cell3, PlanarCellParams, PoseCells3};
use serde::{Deserialize, Serialize};

/// All parameters (Table 3.1 where the thesis gives them).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RatSlamParams {
    /// Pose cells.
    pub pose_cells: PlanarCellParams,
    /// Local view.
    pub local_view: LocalViewParams,
    /// Experience map.
    pub experience_map: ExperienceMapParams,
}

impl RatSlamParams {
    /// Checks every parameter; the message names the field (`pose_cells.dim_xy`, …).
    pub fn validate(&self) -> Result<(), Invalid> {
        self.pose_cells
            .validate()
            .map_err(|e| format!("pose_cells: {e}"))?;
        let lv = &self.local_view;
        let em = &self.experience_map;
        let checks = [
            ("local_view.match_threshold", lv.match_threshold, false),
            ("local_view.inject_energy", lv.inject_energy, true),
            ("local_view.active_decay", lv.active_decay, false),
            ("local_view.restore", lv.restore, true),
            (
                "experience_map.delta_pc_threshold",
                em.delta_pc_threshold,
                false,
            ),
        ];
        for (name, v, zero_ok) in checks {
            if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) {
                let want = if zero_ok { "≥ 0" } else { "> 0" };
                return Err(format!("{name} {}: expected a number {want}", short(v)).into());
            }
        }
        let most = local_view::MAX_SIMILARITY;
        if lv.match_threshold > most {
            return Err(format!(
                "local_view.match_threshold {}: expected at most {most:.1}, the largest \
                 difference of two images (Eq 3.1: 18 pixels · √255)",
                short(lv.match_threshold)
            )
            .into());
        }
        if !(em.correction > 0.0 && em.correction <= 1.0) {
            return Err(format!(
                "experience_map.correction {}: expected a fraction in (0, 1]",
                em.correction
            )
            .into());
        }
        Ok(())
    }
}

/// What one update did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// The template matched or made.
    pub template: usize,
    /// Whether the template is new.
    pub new_template: bool,
    /// The current experience after the update.
    pub experience: usize,
    /// What the experience map did.
    pub event: MapEvent,
    /// The best pose cell.
    pub cell: Cell3,
}

/// Planar RatSLAM.
#[derive(Debug, Clone)]
pub struct RatSlam {
    /// Local view cells.
    pub view: LocalView,
    /// Pose cells.
    pub cells: PoseCells3,
    /// Experience map.
    pub map: ExperienceMap,
}

impl RatSlam {
    /// A fresh system, its activity packet in the middle of the x/y plane at heading 0.
    pub fn new(params: RatSlamParams) -> Self {
        let p = params.pose_cells;
        let mid = (p.dim_xy / 2) as f64;
        Self {
            view: LocalView::new(params.local_view),
            cells: PoseCells3::new(p, &[mid, mid, 0.0]),
            map: ExperienceMap::new(params.experience_map),
        }
    }

    /// One update with a tactile image and odometry (`distance` m after a turn of
    /// `dtheta` rad).
    pub fn step(&mut self, image: &TactileImage, distance: f64, dtheta: f64) -> Step {
        self.step_gated(image, distance, dtheta, true)
    }

    /// [`step`](Self::step) where a matched template injects only if `inject` (false for
    /// an image that holds no evidence of the place, e.g. a whisk that touched nothing:
    /// the pose cells then only integrate the odometry).
    pub fn step_gated(
        &mut self,
        image: &TactileImage,
        distance: f64,
        dtheta: f64,
        inject: bool,
    ) -> Step {
        let seen = self.view.observe(image, &self.cells.best());
        self.advance(seen, inject, distance, dtheta)
    }

    /// One update on a landmark (a recognised object's `identity`, issue #36) instead of
    /// an image: its landmark template ([`LocalView::observe_landmark`]) injects from
    /// `energy` when re-observed; then as [`step`](Self::step).
    pub fn step_landmark(
        &mut self,
        identity: &str,
        energy: f64,
        distance: f64,
        dtheta: f64,
    ) -> Step {
        let seen = self
            .view
            .observe_landmark(identity, &self.cells.best(), energy);
        self.advance(seen, true, distance, dtheta)
    }

    /// The rest of an update after the local view saw `seen`.
    fn advance(
        &mut self,
        seen: local_view::Observation,
        inject: bool,
        distance: f64,
        dtheta: f64,
    ) -> Step {
        if inject && seen.energy > 0.0 {
            self.cells.inject(&seen.cell, seen.energy);
        }
        self.cells.update(distance, dtheta);
        let cell = self.cells.best();
        let event = self
            .map
            .update(distance, dtheta, seen.template, &cell, &self.cells);
        Step {
            template: seen.template,
            new_template: seen.new,
            experience: self.map.current,
            event,
            cell,
        }
    }
}
