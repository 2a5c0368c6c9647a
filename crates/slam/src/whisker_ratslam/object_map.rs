//! The object map (thesis §5.1.2.4): complex experience nodes — the features of a surface
//! region, the best pose cell when it was recorded, and a 6-D pose (position and unit
//! quaternion) relative to the first experience — joined by links holding the odometric
//! relative pose between them; the experience history; graph relaxation; and the file
//! format maps are saved in.
//!
//! # File format
//! JSON (one object), written atomically (temporary file, then rename):
//! ```text
//! { "format": "whisker-slam object map", "version": 2,
//!   "sensing": { "mode": "kinematic" | "physics", "array": "<the array, one line>" },
//!   "experiences": [ { "id": 0, "object": "kettle" | null,
//!                      "features": { "pfh": [..d⁴ numbers..], "sda": [slope | null, ..18..] },
//!                      "cells": [x, y, z, roll, pitch, yaw],        // pose cells
//!                      "position_m": [x, y, z], "orientation_wxyz": [w, x, y, z],
//!                      "decay": 0.0 }, .. ],
//!   "links": [ { "from": 0, "to": 1, "translation_m": [..], "rotation_wxyz": [..] }, .. ],
//!   "history": [ { "sample": 0, "experience": 0, "relocalised": false }, .. ] }
//! ```
//! Experience ids are their positions in the list. A link's relative pose T satisfies
//! pose(to) ≈ pose(from)·T. `sensing` says how the map's contacts were sensed (version 2;
//! version 1 files, which have no `sensing`, are still read: their sensing is unknown).

use super::posecells6d::Cell6;
use crate::features::pfh::PfhParams;
use crate::features::similarity::Features;
use crate::invalid::Invalid;
use crate::sensor::WHISKERS;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The `format` tag of object map files.
pub const FORMAT: &str = "whisker-slam object map";
/// The file format version written (1: no `sensing`, still read).
pub const VERSION: u32 = 2;

/// How a map's contacts were sensed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SensedBy {
    /// Anticipated intersections of straight whiskers, with noise.
    Kinematic,
    /// Simulated compliant whiskers and the signal front end.
    Physics,
}

impl SensedBy {
    /// The name written in map files and scenarios.
    pub fn name(self) -> &'static str {
        match self {
            Self::Kinematic => "kinematic",
            Self::Physics => "physics",
        }
    }
}

/// The sensing a map was built with (version 2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapSensing {
    /// Kinematic or physics.
    pub mode: SensedBy,
    /// The array and front end, one line (as `whisker check` describes them).
    pub array: String,
}

/// A complex experience node (§5.1.2.4.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Experience {
    /// Its index in the map.
    pub id: usize,
    /// The object it was recorded on, when known (appended maps, §5.2.2.2).
    pub object: Option<String>,
    /// The surface region's features.
    pub features: Features,
    /// The best pose cell when it was recorded.
    pub cells: Cell6,
    /// Position in the map frame (m).
    pub position_m: [f64; 3],
    /// Orientation in the map frame, unit quaternion (w, x, y, z).
    pub orientation_wxyz: [f64; 4],
    /// Feature-injection decay (Eq 5.8).
    pub decay: f64,
}

/// A link between two experiences with the relative pose from one to the other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Link {
    /// Source experience.
    pub from: usize,
    /// Target experience.
    pub to: usize,
    /// Translation of the target in the source's frame (m).
    pub translation_m: [f64; 3],
    /// Rotation of the target relative to the source, (w, x, y, z).
    pub rotation_wxyz: [f64; 4],
}

/// One entry of the experience history: which experience was current after a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HistoryEntry {
    /// Sample (whisk) number.
    pub sample: u64,
    /// The current experience after it.
    pub experience: usize,
    /// Whether the sample re-localised onto an existing experience.
    pub relocalised: bool,
}

/// An object map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectMap {
    /// Always [`FORMAT`].
    pub format: String,
    /// File format version.
    pub version: u32,
    /// How the contacts were sensed (None: unknown, a version 1 file, or a map not built
    /// by one run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensing: Option<MapSensing>,
    /// Experiences, by id.
    pub experiences: Vec<Experience>,
    /// Links.
    pub links: Vec<Link>,
    /// Experience history, in sample order.
    pub history: Vec<HistoryEntry>,
}

impl Default for ObjectMap {
    fn default() -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            sensing: None,
            experiences: Vec::new(),
            links: Vec::new(),
            history: Vec::new(),
        }
    }
}

fn quaternion(wxyz: &[f64; 4]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_normalize(Quaternion::new(wxyz[0], wxyz[1], wxyz[2], wxyz[3]))
}

fn wxyz(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

fn isometry(t: &[f64; 3], q: &[f64; 4]) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::new(t[0], t[1], t[2]), quaternion(q))
}

impl Link {
    /// A link from `from` to `to` with relative pose `relative`.
    pub fn new(from: usize, to: usize, relative: &Isometry3<f64>) -> Self {
        let t = relative.translation.vector;
        Self {
            from,
            to,
            translation_m: [t.x, t.y, t.z],
            rotation_wxyz: wxyz(&relative.rotation),
        }
    }

    /// The relative pose.
    pub fn relative(&self) -> Isometry3<f64> {
        isometry(&self.translation_m, &self.rotation_wxyz)
    }
}

impl ObjectMap {
    /// Pose of experience `id` in the map frame.
    pub fn pose(&self, id: usize) -> Isometry3<f64> {
        let e = &self.experiences[id];
        isometry(&e.position_m, &e.orientation_wxyz)
    }

    /// Sets the pose of experience `id`.
    pub fn set_pose(&mut self, id: usize, pose: &Isometry3<f64>) {
        let t = pose.translation.vector;
        let e = &mut self.experiences[id];
        e.position_m = [t.x, t.y, t.z];
        e.orientation_wxyz = wxyz(&pose.rotation);
    }

    /// Adds an experience at `pose`; returns its id.
    pub fn add(
        &mut self,
        features: Features,
        cells: Cell6,
        pose: &Isometry3<f64>,
        object: Option<String>,
    ) -> usize {
        let id = self.experiences.len();
        self.experiences.push(Experience {
            id,
            object,
            features,
            cells,
            position_m: [0.0; 3],
            orientation_wxyz: [1.0, 0.0, 0.0, 0.0],
            decay: 0.0,
        });
        self.set_pose(id, pose);
        id
    }

    /// Graph relaxation in 6-D: `loops` passes; in each, every experience moves by
    /// `correction` of the mean disagreement between its pose and the poses its links
    /// predict from their other ends (position: the mean offset; orientation: the mean
    /// rotation vector, applied in the map frame). All moves of a pass are computed from
    /// the poses before it (a Jacobi sweep): on a loop the residual odometry error ends
    /// up shared equally among its links. Experiences without links do not move.
    pub fn relax(&mut self, loops: usize, correction: f64) {
        self.relax_robust(loops, correction, None);
    }

    /// [`ObjectMap::relax`] with each link's pull weighted by how well it agrees with the
    /// map — an addition to the thesis, whose relaxation trusts every link equally, so that
    /// one false loop closure (a link whose relative pose contradicts the many links around
    /// it, e.g. a match on the far side of a symmetric object) cannot fold a map. A link's
    /// residual at the poses of the pass, the translation r_t and rotation angle r_θ between
    /// the pose its far end has and the one the link predicts, gives
    /// s = (r_t/σ_t)² + (r_θ/σ_θ)² and the Geman–McClure weight w = 1/(1 + s)², which
    /// falls off as s⁻² and so leaves a contradicting link almost no pull (a 180° false link
    /// at σ_θ = 20°: w ≈ 1.5·10⁻⁴), while a link within σ pulls with at least ¼. Each
    /// experience then moves by `correction` of the weighted mean disagreement (divided by the
    /// total weight, or by 1 when that is smaller). `scale`:
    /// (σ_t in m, σ_θ in rad); None is the thesis' relaxation.
    pub fn relax_robust(&mut self, loops: usize, correction: f64, scale: Option<(f64, f64)>) {
        let n = self.experiences.len();
        for _ in 0..loops {
            let poses: Vec<Isometry3<f64>> = (0..n).map(|i| self.pose(i)).collect();
            let mut dp = vec![Vector3::zeros(); n];
            let mut dr = vec![Vector3::zeros(); n];
            let mut degree = vec![0.0f64; n];
            for link in &self.links {
                let (a, b) = (link.from, link.to);
                if a == b {
                    continue;
                }
                let t = link.relative();
                let predicted_b = poses[a] * t;
                let predicted_a = poses[b] * t.inverse();
                let (offset_b, turn_b) = (
                    predicted_b.translation.vector - poses[b].translation.vector,
                    (predicted_b.rotation * poses[b].rotation.inverse()).scaled_axis(),
                );
                let w = match scale {
                    None => 1.0,
                    Some(scale) => {
                        let s = standardised_residual(offset_b.norm(), turn_b.norm(), scale);
                        1.0 / ((1.0 + s) * (1.0 + s))
                    }
                };
                dp[b] += offset_b * w;
                dp[a] += (predicted_a.translation.vector - poses[a].translation.vector) * w;
                dr[b] += turn_b * w;
                dr[a] += (predicted_a.rotation * poses[a].rotation.inverse()).scaled_axis() * w;
                degree[a] += w;
                degree[b] += w;
            }
            for i in 0..n {
                if degree[i] <= 0.0 {
                    continue;
                }
                // The weighted mean, but never amplified: links that together weigh less
                // than one (all of them contradicting) move the experience only as much.
                let k = correction / degree[i].max(1.0);
                let pose = Isometry3::from_parts(
                    Translation3::from(poses[i].translation.vector + dp[i] * k),
                    UnitQuaternion::from_scaled_axis(dr[i] * k) * poses[i].rotation,
                );
                self.set_pose(i, &pose);
            }
        }
    }

    /// Appends `other`'s experiences, links and history (ids shifted past this map's),
    /// labelling its experiences `object` (§5.2.2.2: object maps appended with no
    /// connection between them).
    pub fn append(&mut self, other: &ObjectMap, object: &str) {
        let offset = self.experiences.len();
        for e in &other.experiences {
            let mut e = e.clone();
            e.id += offset;
            e.object = Some(object.to_string());
            // Prior knowledge starts unexcited (see [`ObjectMap::rested`]).
            e.decay = 0.0;
            self.experiences.push(e);
        }
        for l in &other.links {
            let mut l = l.clone();
            l.from += offset;
            l.to += offset;
            self.links.push(l);
        }
        for h in &other.history {
            self.history.push(HistoryEntry {
                experience: h.experience + offset,
                ..*h
            });
        }
    }

    /// Checks the map's consistency; the message names the first problem.
    pub fn validate(&self) -> Result<(), Invalid> {
        if self.format != FORMAT {
            return Err(format!("format {:?}: expected {FORMAT:?}", self.format).into());
        }
        if !(1..=VERSION).contains(&self.version) {
            return Err(format!("version {}: expected 1 to {VERSION}", self.version).into());
        }
        if self.version == 1 && self.sensing.is_some() {
            return Err("sensing: not a field of version 1 (expected version 2)"
                .to_string()
                .into());
        }
        let n = self.experiences.len();
        for (i, e) in self.experiences.iter().enumerate() {
            let at = format!("experiences[{i}]");
            if e.id != i {
                return Err(format!("{at}.id {}: expected {i} (its position)", e.id).into());
            }
            let numbers = e
                .cells
                .iter()
                .chain(&e.position_m)
                .chain(&e.orientation_wxyz);
            if numbers.chain([&e.decay]).any(|x| !x.is_finite()) {
                return Err(format!("{at}: non-finite number").into());
            }
            let norm = e.orientation_wxyz.iter().map(|x| x * x).sum::<f64>().sqrt();
            if (norm - 1.0).abs() > 1e-6 {
                return Err(format!(
                    "{at}.orientation_wxyz: norm {norm}, expected a unit quaternion"
                )
                .into());
            }
            check_features(&e.features, &at)?;
        }
        for (i, l) in self.links.iter().enumerate() {
            if l.translation_m
                .iter()
                .chain(&l.rotation_wxyz)
                .any(|x| !x.is_finite())
            {
                return Err(format!("links[{i}]: non-finite number").into());
            }
            if l.from >= n || l.to >= n {
                return Err(format!(
                    "links[{i}]: {} -> {} but there are {n} experiences",
                    l.from, l.to
                )
                .into());
            }
        }
        for (i, h) in self.history.iter().enumerate() {
            if h.experience >= n {
                return Err(format!(
                    "history[{i}].experience {}: there are {n} experiences",
                    h.experience
                )
                .into());
            }
        }
        Ok(())
    }

    /// The map as it is saved: every experience's decay back to 0. Decay (Eq 5.8) is the
    /// state of one run's feature injections, not of the map: a map saved mid-run would
    /// otherwise inject less into the experiences its builder matched last.
    pub fn rested(&self) -> Self {
        let mut map = self.clone();
        for e in &mut map.experiences {
            e.decay = 0.0;
        }
        map
    }

    /// Writes the map to `path` (atomically: a temporary file beside it, then renamed).
    pub fn save(&self, path: &Path) -> Result<(), MapFileError> {
        let text = serde_json::to_string(self).map_err(MapFileError::Encode)?;
        let tmp = path.with_extension("json.part");
        std::fs::write(&tmp, text)
            .and_then(|_| std::fs::rename(&tmp, path))
            .map_err(|source| MapFileError::Write {
                path: path.to_path_buf(),
                source,
            })
    }

    /// Reads a map written by [`ObjectMap::save`]; errors name the file, and the line and
    /// column or the field at fault.
    pub fn load(path: &Path) -> Result<Self, MapFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| MapFileError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let map: Self = serde_json::from_str(&text).map_err(|source| MapFileError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        map.validate().map_err(|invalid| MapFileError::Invalid {
            path: path.to_path_buf(),
            invalid,
        })?;
        Ok(map)
    }
}

/// Why an object map file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum MapFileError {
    /// The file could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file is not the map's JSON (serde names the line and column).
    #[error("{}: line {} column {}: {source}", path.display(), source.line(), source.column())]
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },
    /// The JSON is a map, but not a consistent one.
    #[error("{}: {invalid}", path.display())]
    Invalid { path: PathBuf, invalid: Invalid },
    /// The map could not be encoded (non-finite numbers).
    #[error("{0}")]
    Encode(serde_json::Error),
}

/// s = (r_t/σ_t)² + (r_θ/σ_θ)² of a residual of `translation` (m) and `rotation` (rad) at
/// `scale` = (σ_t, σ_θ): the argument of robust relaxation's weight.
pub fn standardised_residual(
    translation: f64,
    rotation: f64,
    (sigma_t, sigma_r): (f64, f64),
) -> f64 {
    (translation / sigma_t).powi(2) + (rotation / sigma_r).powi(2)
}

/// Checks one experience's features against what this code computes and compares
/// (`whisk_features`): a PFH of d⁴ finite, non-negative bins (d = 3: 81), an SDA of one
/// finite slope or null per whisker (18). `at` names the experience.
fn check_features(features: &Features, at: &str) -> Result<(), Invalid> {
    let bins = PfhParams::default().divisions.pow(4);
    let pfh = &features.pfh;
    if pfh.len() != bins {
        return Err(format!(
            "{at}.features.pfh: {} bins, expected {bins} (d = {} divisions per feature, d⁴)",
            pfh.len(),
            PfhParams::default().divisions
        )
        .into());
    }
    if let Some(k) = pfh.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
        return Err(format!(
            "{at}.features.pfh[{k}]: {}, expected a finite number ≥ 0",
            pfh[k]
        )
        .into());
    }
    let sda = &features.sda.0;
    if sda.len() != WHISKERS {
        return Err(format!(
            "{at}.features.sda: {} slopes, expected {WHISKERS} (one per whisker, null without contact)",
            sda.len()
        ).into());
    }
    if let Some(k) = sda.iter().position(|x| x.is_some_and(|x| !x.is_finite())) {
        return Err(format!("{at}.features.sda[{k}]: expected a finite slope or null").into());
    }
    Ok(())
}
