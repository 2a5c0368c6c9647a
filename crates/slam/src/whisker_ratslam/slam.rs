//! The WhiskerRatSLAM main loop (thesis Alg 2, §5.1): per whisk, match the observed
//! features against the object map, excite the matched experience's pose cell
//! (Eq 5.8–5.9), run the pose cells and path integration, read the best pose, and update
//! the object map — create an experience, re-localise onto one, or stay.
//!
//! Order of the re-localisation test (`injection.test`): by default, as Alg 2 orders it,
//! the match is injected first, then the attractor and path integration run and the
//! experience rule tests the match against the decoded best pose — so the match pulls the
//! packet it is tested against, and the 1-cell test hardly ever rejects it. With
//! `independent` ([`Params::corrected`]) the pose cells are advanced and the best pose is
//! decoded *before* this whisk's match is injected; the match's activity is injected
//! afterwards, to be consolidated by the next update's attractor (which also places it at
//! the pose where the features were seen rather than one odometry step beyond it).
//!
//! Experience rule (§5.1.2.4.1.1, with RatSLAM's re-localisation test): when the features
//! match an experience whose recorded pose cell is within `threshold_cells` of the best
//! pose, that experience becomes current (a link from the previous one, holding the
//! accumulated odometry, closes the loop); otherwise, when the features are new or the
//! best pose has moved more than `threshold_cells` from the current experience's cell, a
//! new experience is created at the current experience's pose composed with the
//! accumulated odometry; otherwise the current experience stays.
//!
//! Odometry anchor (with robust relaxation on; an addition to the thesis): the last
//! experience *made* is the anchor, and the odometry since it is kept across
//! re-localisations. A new experience made after re-localisations is also linked from the
//! anchor by that odometry, and it is placed by it — at the anchor's pose composed with
//! the odometry since — when the re-localised estimate disagrees with it by more than the
//! robust scale (s > 1, `ObjectMap::relax_robust`). So a false re-localisation cannot
//! carry the experiences made after it to the far side of the object: their odometry link
//! holds them, and robust relaxation leaves the contradicting links little pull. When the
//! two agree (a true revisit after little drift), the experience is placed as in the
//! thesis, relative to the re-localised one.

use super::object_map::{HistoryEntry, Link, ObjectMap, standardised_residual};
use super::posecells6d::{Cell6, PoseCellParams, PoseCells6};
use super::relative_pose::Accumulator;
use crate::features::similarity::{Features, Matching};
use crate::sensor::Odometry;
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

/// How Ω is applied to the pose cells (Eq 5.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InjectionScale {
    /// Ω added to the matched cell as an absolute activity (Eq 5.9 as printed; default).
    #[default]
    Cell,
    /// Ω is a fraction of the packet's peak: a copy of the activity, its peak moved to the
    /// matched cell, scaled by Ω ([`PoseCells6::inject_packet`]). The thesis' 1-D example
    /// normalises activity to the maximum (§5.1.2.3.1), so ζ = 0.3 is 30 % of the peak;
    /// on the 5⁶ grid the stable packet (sum 1) has a peak of ~0.0024, and Ω added to one
    /// cell as printed is ~127× the peak, so one match moves the decoded pose by ~1.5 cells
    /// while it should need "the coordinated effort across multiple features" (§5.1.2.2).
    /// The bump has the packet's shape because on 5 cells per axis one cell's activity is
    /// spread over the whole axis by the next excitation anyway.
    Peak,
}

/// When the re-localisation test reads the pose cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RelocalisationTest {
    /// Before this whisk's match is injected (module documentation).
    Independent,
    /// After it, as Alg 2 orders the steps (injection, attractor, path integration, map):
    /// the match pulls the packet it is tested against (default).
    #[default]
    AfterInjection,
}

/// Feature injection (Eq 5.8): Ω = ζ/30·(30 − e^{1.2·decay}).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Injection {
    /// ζ, the largest activity one match injects (0.3, §5.1.2.2).
    pub zeta: f64,
    /// What Ω is relative to: `cell` (as printed, default) or `peak`.
    pub scale: InjectionScale,
    /// When the re-localisation test reads the pose cells: `after_injection` (Alg 2's
    /// order, default) or `independent` (before the injection).
    pub test: RelocalisationTest,
    /// Added to an experience's decay each time it is matched (OpenRatSLAM's 1.0).
    pub active_decay: f64,
    /// Taken off every experience's decay each update, down to 0 (OpenRatSLAM's 0.05).
    pub restore: f64,
}

impl Default for Injection {
    fn default() -> Self {
        Self {
            zeta: 0.3,
            scale: InjectionScale::Cell,
            test: RelocalisationTest::AfterInjection,
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
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
    /// The fewest contacts of a closed-loop whisk that enters matching and map building
    /// ([`WhiskerRatSlam::whisk`]); a whisk with fewer only moves the pose cells and the
    /// odometry on. 1 (the default): a new experience needs contact, and an empty whisk,
    /// whose features (a zero histogram, no slopes) match a stored empty experience
    /// perfectly (χ² = NMSE = 0), matches nothing — nothing in Ch 5–6 matches an empty
    /// whisk. 4 is Alg 7's μ (the SPC's); 0 sends every whisk to SLAM (before issue #35).
    pub min_contacts: usize,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            pose_cells: PoseCellParams::default(),
            matching: Matching::default(),
            injection: Injection::default(),
            experiences: ExperienceParams::default(),
            merge_features: false,
            min_contacts: 1,
        }
    }
}

impl Params {
    /// WhiskerRatSLAM with the corrections of issue #19, each measured on the §5.2
    /// experiments (`whisker object-slam` uses these): Ω relative to the packet's peak, the
    /// re-localisation test before the injection, phase-exact path-integration shifts and
    /// the odometry anchor. [`Params::default`] is Alg 2 as printed (plus robust
    /// relaxation), which the closed loop of Ch 6 keeps: its maps, built under
    /// Eq 6.4–6.11's odometry noise, hold pose cells too inconsistent for a corrected test
    /// to re-localise into, and nothing is recognised (scenarios/README.md).
    pub fn corrected() -> Self {
        let d = Self::default();
        Self {
            pose_cells: PoseCellParams::corrected(),
            injection: Injection {
                scale: InjectionScale::Peak,
                test: RelocalisationTest::Independent,
                ..d.injection
            },
            experiences: ExperienceParams {
                anchor: true,
                ..d.experiences
            },
            ..d
        }
    }
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
    /// The odometry anchor (module documentation; needs robust relaxation on).
    pub anchor: bool,
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
            anchor: false,
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
    /// The last experience made, and the odometry since (module documentation); None
    /// while the anchor is off.
    anchor: Option<(usize, Accumulator)>,
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
            anchor: None,
            samples: 0,
        }
    }

    /// The pose estimate: the current experience's pose composed with the odometry since.
    pub fn estimate(&self) -> Option<Isometry3<f64>> {
        self.current
            .map(|c| self.map.pose(c) * self.accumulated.pose)
    }

    /// One whisk of the closed loop (Ch 6): [`Self::step`] when it made at least
    /// `min_contacts` contacts, [`Self::idle`] otherwise.
    pub fn whisk(
        &mut self,
        features: &Features,
        contacts: usize,
        odometry: &Odometry,
    ) -> Option<Step> {
        if contacts < self.params.min_contacts {
            self.idle(odometry)
        } else {
            Some(self.step(features, odometry))
        }
    }

    /// An update without features: the pose cells' attractor and path integration on
    /// `odometry`, the odometry accumulated since the current experience, the experiences'
    /// decay restored; nothing matched, made or re-localised onto. The step stays at the
    /// current experience; none before the first (a new experience needs contact).
    pub fn idle(&mut self, odometry: &Odometry) -> Option<Step> {
        self.feature_excitation(None);
        let best = self.path_integration(odometry);
        let sample = self.samples;
        self.samples += 1;
        let experience = self.current?;
        self.map.history.push(HistoryEntry {
            sample,
            experience,
            relocalised: false,
        });
        Some(Step {
            matched: None,
            experience,
            created: false,
            relocalised: false,
            best,
        })
    }

    /// One iteration of Alg 2 for a whisk's `features` and the `odometry` since the last.
    pub fn step(&mut self, features: &Features, odometry: &Odometry) -> Step {
        let p = self.params;
        // match_features
        let matched = p
            .matching
            .best(features, self.map.experiences.iter().map(|e| &e.features))
            .map(|(i, _)| i);
        let order = p.injection.test;
        if order == RelocalisationTest::AfterInjection {
            self.feature_excitation(matched);
        }
        // path_integration (an earlier injection is consolidated here)
        let best = self.path_integration(odometry);
        // process_object_map
        let (experience, created, relocalised) = self.process_map(features, matched, best);
        if order == RelocalisationTest::Independent {
            self.feature_excitation(matched);
        }
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

    /// Alg 2's path integration: the pose cells' attractor, then their shift by
    /// `odometry`, accumulated since the current experience (and the anchor); returns the
    /// best pose cell.
    fn path_integration(&mut self, odometry: &Odometry) -> Cell6 {
        self.cells.excite_inhibit();
        self.cells
            .path_integrate(&odometry.translation(), &odometry.rotation());
        self.accumulated.add(odometry);
        if let Some((_, since)) = &mut self.anchor {
            since.add(odometry);
        }
        self.cells.best()
    }

    /// Whether the odometry anchor is on (it needs robust relaxation).
    fn anchoring(&self) -> bool {
        let e = &self.params.experiences;
        e.anchor && e.robust_scale().is_some()
    }

    /// Feature excitation (Eq 5.8–5.9) of the `matched` experience's cell, with the
    /// per-experience decay.
    fn feature_excitation(&mut self, matched: Option<usize>) {
        let p = self.params.injection;
        for e in &mut self.map.experiences {
            e.decay = (e.decay - p.restore).max(0.0);
        }
        if let Some(m) = matched {
            let e = &mut self.map.experiences[m];
            let omega = p.energy(e.decay);
            let cells = e.cells;
            e.decay += p.active_decay;
            if omega > 0.0 {
                match p.scale {
                    InjectionScale::Peak => self.cells.inject_packet(&cells, omega),
                    InjectionScale::Cell => self.cells.inject(&cells, omega),
                }
            }
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
            self.anchor = self.anchoring().then(|| (id, Accumulator::default()));
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
            let mut pose = self.map.pose(current) * relative;
            let anchored = self
                .anchor
                .take()
                .filter(|(a, _)| *a != current)
                .map(|(a, mut since)| (a, since.take()));
            if let (Some((a, since)), Some(scale)) =
                (&anchored, self.params.experiences.robust_scale())
            {
                let by_odometry = self.map.pose(*a) * since;
                let (dt, dr) = crate::pose::distance(&by_odometry, &pose);
                if standardised_residual(dt, dr, scale) > 1.0 {
                    pose = by_odometry;
                }
            }
            let id = self.map.add(features.clone(), best, &pose, None);
            self.map.links.push(Link::new(current, id, &relative));
            if let Some((a, since)) = anchored {
                self.map.links.push(Link::new(a, id, &since));
            }
            self.current = Some(id);
            self.anchor = self.anchoring().then(|| (id, Accumulator::default()));
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
