//! Local view cells on tactile images (thesis §3.1.1, §3.2.1, Eq 3.1; injection as in
//! Eq 5.8).
//!
//! A tactile image is 6 × 3 8-bit pixels, columns A–F and rows 1–3 (Fig 3.2), pixel
//! (row r, column c) being whisker 6·(r − 1) + c; its intensity is proportional to the
//! height of the obstacle the whisker touched (0: no contact). Images are compared with
//! Eq 3.1, S(A, B) = Σᵢⱼ √|aᵢⱼ − bᵢⱼ|, over all pixels; an image matches the stored
//! template of least S if that S is below the threshold, else it becomes a new template
//! (stored with the pose cell it was first seen at).
//!
//! A matched template injects E = e/30·(30 − exp(1.2·decay)) at its pose cell if E > 0
//! (Eq 5.8), its decay then growing by `active_decay`; every template's decay relaxes by
//! `restore` per update, down to `active_decay`. Templates among the `skip_recent` most
//! recent do not inject (the reference implementation's gate, there 10, which underflows
//! with fewer templates; here with fewer templates none is skipped wrongly: a template
//! injects when at least `skip_recent` templates were created after it).
//!
//! **Landmark templates** (issue #36, thesis Fig 5.1): a template keyed by an object's
//! identity (what the Ch 6 closed loop recognised) instead of an image
//! ([`LocalView::observe_landmark`]). It is never compared with images; re-observing the
//! same identity matches it and injects at the pose cell where it was first seen, with
//! its own energy in place of e and the same decay, so a recognised object closes the
//! loop where a tactile image would.

use super::posecells3d::Cell3;
use serde::{Deserialize, Serialize};

/// Pixels of a tactile image: 3 rows of 6 (Fig 3.2).
pub const ROWS: usize = 3;
/// Columns of a tactile image.
pub const COLUMNS: usize = 6;

/// A 6 × 3 tactile image; `pixels[6·row + column]`, the whisker index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct TactileImage {
    /// Intensities 0–255.
    pub pixels: [u8; ROWS * COLUMNS],
}

impl TactileImage {
    /// The image of per-whisker contact heights (m; None: no contact), intensity
    /// 255·h/`full_scale` rounded and clamped to 0–255 (§3.1.1).
    pub fn from_heights(heights: &[Option<f64>], full_scale: f64) -> Self {
        let mut pixels = [0u8; ROWS * COLUMNS];
        for (p, h) in pixels.iter_mut().zip(heights) {
            if let Some(h) = h {
                *p = (255.0 * h / full_scale).round().clamp(0.0, 255.0) as u8;
            }
        }
        Self { pixels }
    }
}

/// The largest value of Eq 3.1: every pixel 255 apart, 18 · √255 ≈ 287.4.
pub const MAX_SIMILARITY: f64 = (ROWS * COLUMNS) as f64 * 15.968_719_422_671_311;

/// Eq 3.1: S(A, B) = Σ √|a − b| over all pixels.
pub fn similarity(a: &TactileImage, b: &TactileImage) -> f64 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .map(|(&x, &y)| f64::from(x.abs_diff(y)).sqrt())
        .sum()
}

/// Parameters of the local view.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LocalViewParams {
    /// Matching threshold on Eq 3.1.
    pub match_threshold: f64,
    /// Injection energy e of Eq 5.8.
    pub inject_energy: f64,
    /// Decay added when a template is matched (vt_active_decay, Table 3.1: 1).
    pub active_decay: f64,
    /// Decay restored per update.
    pub restore: f64,
    /// The most recent templates that do not inject.
    pub skip_recent: usize,
}

impl Default for LocalViewParams {
    fn default() -> Self {
        Self {
            match_threshold: 20.0,
            inject_energy: 0.1,
            active_decay: 1.0,
            restore: 0.05,
            skip_recent: 0,
        }
    }
}

/// One stored template.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Template {
    /// The image.
    pub image: TactileImage,
    /// Pose cell where it was first seen.
    pub cell: Cell3,
    /// Its decay.
    pub decay: f64,
    /// The identity of a landmark template (none for an image's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub landmark: Option<String>,
}

/// What one observation gave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// The template matched or created.
    pub template: usize,
    /// Whether it was created now.
    pub new: bool,
    /// Energy to inject at `cell` (0 if none).
    pub energy: f64,
    /// Where to inject.
    pub cell: Cell3,
}

/// The local view cells.
#[derive(Debug, Clone, Default)]
pub struct LocalView {
    /// Parameters.
    pub params: LocalViewParams,
    /// The templates, in order of creation.
    pub templates: Vec<Template>,
}

impl LocalView {
    /// An empty local view.
    pub fn new(params: LocalViewParams) -> Self {
        Self {
            params,
            templates: Vec::new(),
        }
    }

    /// Observes `image` with the pose cells' best pose at `cell`.
    pub fn observe(&mut self, image: &TactileImage, cell: &Cell3) -> Observation {
        self.restore();
        let best = self
            .templates
            .iter()
            .enumerate()
            .filter(|(_, t)| t.landmark.is_none())
            .map(|(i, t)| (i, similarity(&t.image, image)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match best {
            Some((i, s)) if s < self.params.match_threshold => {
                self.matched(i, self.params.inject_energy)
            }
            _ => self.create(*image, None, cell),
        }
    }

    /// Observes the landmark `identity` (a landmark template, module documentation) with
    /// the pose cells' best pose at `cell`; a re-observation injects from `energy` (in
    /// place of e).
    pub fn observe_landmark(&mut self, identity: &str, cell: &Cell3, energy: f64) -> Observation {
        self.restore();
        let known = self
            .templates
            .iter()
            .position(|t| t.landmark.as_deref() == Some(identity));
        match known {
            Some(i) => self.matched(i, energy),
            None => self.create(TactileImage::default(), Some(identity.to_string()), cell),
        }
    }

    /// Every template's decay relaxes by `restore`, down to `active_decay` (one update).
    fn restore(&mut self) {
        let p = self.params;
        for t in &mut self.templates {
            t.decay = (t.decay - p.restore).max(p.active_decay);
        }
    }

    /// Template `i` matched: Eq 5.8's energy from `e` (none for one of the
    /// `skip_recent` most recent), its decay grown.
    fn matched(&mut self, i: usize, e: f64) -> Observation {
        let p = self.params;
        let n = self.templates.len();
        let t = &mut self.templates[i];
        let energy = if i + p.skip_recent < n {
            (e / 30.0 * (30.0 - (1.2 * t.decay).exp())).max(0.0)
        } else {
            0.0
        };
        t.decay += p.active_decay;
        Observation {
            template: i,
            new: false,
            energy,
            cell: t.cell,
        }
    }

    /// A new template, first seen at `cell`.
    fn create(
        &mut self,
        image: TactileImage,
        landmark: Option<String>,
        cell: &Cell3,
    ) -> Observation {
        self.templates.push(Template {
            image,
            cell: *cell,
            decay: self.params.active_decay,
            landmark,
        });
        Observation {
            template: self.templates.len() - 1,
            new: true,
            energy: 0.0,
            cell: *cell,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq_3_1_sums_square_roots_of_pixel_differences() {
        let mut a = TactileImage::default();
        let mut b = TactileImage::default();
        a.pixels[0] = 16; // √16 = 4
        b.pixels[5] = 9; // √9 = 3
        a.pixels[17] = 200;
        b.pixels[17] = 199; // √1 = 1
        assert_eq!(similarity(&a, &b), 8.0);
        assert_eq!(similarity(&a, &a), 0.0);
        let img = TactileImage::from_heights(&[Some(0.05), None, Some(0.2), Some(-1.0)], 0.1);
        assert_eq!(&img.pixels[..4], &[128, 0, 255, 0]);
    }

    #[test]
    fn the_largest_difference_is_black_against_white() {
        let white = TactileImage {
            pixels: [255; ROWS * COLUMNS],
        };
        let d = similarity(&TactileImage::default(), &white);
        assert!(
            (d - MAX_SIMILARITY).abs() < 1e-12,
            "{d} vs {MAX_SIMILARITY}"
        );
        assert!((MAX_SIMILARITY - 18.0 * 255f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn injection_follows_eq_5_8_and_decays() {
        let params = LocalViewParams {
            inject_energy: 0.3,
            match_threshold: 5.0,
            ..LocalViewParams::default()
        };
        let mut view = LocalView::new(params);
        let mut img = TactileImage::default();
        img.pixels[3] = 100;
        let first = view.observe(&img, &[1.0, 2.0, 3.0]);
        assert!(first.new && first.energy == 0.0);
        // Re-seen: decay 1 − 0.05 restored back to its floor 1: E = 0.3/30·(30 − e^1.2).
        let again = view.observe(&img, &[9.0, 9.0, 9.0]);
        assert!(!again.new && again.template == 0 && again.cell == [1.0, 2.0, 3.0]);
        assert!((again.energy - 0.01 * (30.0 - 1.2f64.exp())).abs() < 1e-15);
        // Decay is now 2; next update restores 0.05: E = 0.01·(30 − e^(1.2·1.95)).
        let third = view.observe(&img, &[0.0; 3]);
        assert!((third.energy - 0.01 * (30.0 - (1.2f64 * 1.95).exp())).abs() < 1e-15);
        // Repeated matching exhausts it (decay ≥ ln 30 / 1.2 ≈ 2.83): no more energy.
        let mut e = 1.0;
        for _ in 0..5 {
            e = view.observe(&img, &[0.0; 3]).energy;
        }
        assert_eq!(e, 0.0);
        // A different image (S = √100 = 10 > 5) is a new template.
        let mut other = img;
        other.pixels[3] = 0;
        assert!(view.observe(&other, &[0.0; 3]).new);
    }
}
