//! The scene of a recording (`world/…`, frame `world` = the arm's base link, metres, z
//! up; `docs/recording.md`): the environment's meshes, the arm and the array, the whisker
//! shafts, the contacts — ground truth (the anticipated intersect, without noise) and the
//! estimate (the front end with the radial model, or the noisy kinematic contact) — and the
//! error between them.

use super::{Recording, f32x3};
use nalgebra::Isometry3;
use std::collections::BTreeMap;
use whisker_experiments::record::{Contact, ContactKind};
use whisker_scenario::Result;
use whisker_sim::environment::Environment;

/// Colour of the ground-truth contacts (green).
const TRUE_COLOUR: [u8; 3] = [40, 200, 80];
/// Colour of the estimated contacts (orange).
const ESTIMATED_COLOUR: [u8; 3] = [255, 140, 0];
/// Colours of the environment's pieces, in turn.
const PIECE_COLOURS: [[u8; 3]; 4] = [
    [150, 150, 170],
    [170, 140, 110],
    [120, 160, 190],
    [190, 170, 120],
];

/// The contacts of the cycles whose other half has not been logged yet, for the error
/// arrows: (prefix, cycle) → (time of the first half, truth, estimate).
pub(crate) type Pending =
    BTreeMap<(String, u64), (rerun::TimePoint, Option<Vec<Contact>>, Option<Vec<Contact>>)>;

pub(crate) fn point(p: &Isometry3<f64>) -> [f32; 3] {
    f32x3(&p.translation.vector)
}

fn quaternion(p: &Isometry3<f64>) -> rerun::Quaternion {
    let q = p.rotation.quaternion();
    rerun::Quaternion::from_xyzw([q.i as f32, q.j as f32, q.k as f32, q.w as f32])
}

/// The transform of a pose.
pub fn transform(p: &Isometry3<f64>) -> rerun::Transform3D {
    rerun::Transform3D::from_translation_rotation(point(p), quaternion(p))
}

impl Recording {
    /// Logs the environment's pieces as static meshes at `<prefix>/<piece>`.
    pub fn environment_in(&self, prefix: &str, environment: &Environment) -> Result {
        for (k, piece) in environment.pieces.iter().enumerate() {
            let positions: Vec<[f32; 3]> = piece
                .mesh
                .vertices
                .iter()
                .map(|v| f32x3(&(piece.pose * v).coords))
                .collect();
            let [r, g, b] = PIECE_COLOURS[k % PIECE_COLOURS.len()];
            let mesh = rerun::Mesh3D::new(positions)
                .with_triangle_indices(piece.mesh.triangles.iter().copied())
                .with_albedo_factor(rerun::Rgba32::from_unmultiplied_rgba(r, g, b, 255));
            self.log_static(
                format!(
                    "{prefix}/{}",
                    whisker_experiments::record::entity_name(&piece.name)
                ),
                &mesh,
            )?;
        }
        Ok(())
    }

    /// Logs the tip positions at the waypoints (`world/waypoints`, static), blue as the
    /// goals of a closed loop are (the legend's colours), each labelled with its number.
    pub fn waypoints(&self, tips: &[Isometry3<f64>]) -> Result {
        let points: Vec<[f32; 3]> = tips.iter().map(point).collect();
        let labels: Vec<String> = (0..tips.len()).map(|k| format!("#{k}")).collect();
        self.log_static(
            "world/waypoints",
            &rerun::Points3D::new(points)
                .with_radii([0.01])
                .with_colors([rerun::Color::from_rgb(40, 90, 230)])
                .with_labels(labels),
        )
    }

    /// Logs the arm at time `t`: its link frames along the chain from the root
    /// (`world/arm/links/<k>`), a line through their origins (`world/arm/skeleton`) and
    /// the tip frame (`world/arm/tip`).
    pub fn arm(&self, t: f64, links: &[Isometry3<f64>], tip: &Isometry3<f64>) -> Result {
        self.at(t);
        self.arm_now(links, tip)
    }

    /// Logs the arm at the current time (see [`Self::arm`]).
    pub(crate) fn arm_now(&self, links: &[Isometry3<f64>], tip: &Isometry3<f64>) -> Result {
        let strip: Vec<[f32; 3]> = links.iter().map(point).collect();
        self.log(
            "world/arm/skeleton",
            &rerun::LineStrips3D::new([strip]).with_radii([0.004]),
        )?;
        for (k, link) in links.iter().enumerate() {
            self.log(format!("world/arm/links/{k}"), &transform(link))?;
        }
        self.links
            .store(links.len(), std::sync::atomic::Ordering::Relaxed);
        self.log("world/arm/tip", &transform(tip))
    }

    /// Logs the whole tip path (`world/arm/tip_path`, static) and the axes of the tip and
    /// array frames (static: their length does not change).
    pub fn tip_path(&self, path: &[Isometry3<f64>]) -> Result {
        let strip: Vec<[f32; 3]> = path.iter().map(point).collect();
        self.log_static(
            "world/arm/tip_path",
            &rerun::LineStrips3D::new([strip]).with_radii([rerun::Radius::new_ui_points(1.0)]),
        )?;
        self.frame_axes()
    }

    /// Logs the axes of the tip, link and array frames (static: their length does not
    /// change).
    pub fn frame_axes(&self) -> Result {
        self.log_static("world/arm/tip", &rerun::TransformAxes3D::new(0.05))?;
        for k in 0..self.links.load(std::sync::atomic::Ordering::Relaxed) {
            self.log_static(
                format!("world/arm/links/{k}"),
                &rerun::TransformAxes3D::new(0.03),
            )?;
        }
        self.log_static("world/array", &rerun::TransformAxes3D::new(0.03))
    }

    /// Logs whisker shafts at `entity` at time `t`.
    pub fn shafts_at(&self, entity: &str, t: f64, shafts: &[Vec<[f64; 3]>]) -> Result {
        self.at(t);
        let strips: Vec<Vec<[f32; 3]>> = shafts
            .iter()
            .map(|s| {
                s.iter()
                    .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
                    .collect()
            })
            .collect();
        self.log(
            entity,
            &rerun::LineStrips3D::new(strips)
                .with_radii([0.0006])
                .with_colors([rerun::Color::from_rgb(230, 230, 230)]),
        )
    }

    /// Logs the contacts of whisk cycle `cycle` of one kind at the current time, labelled
    /// by whisker, at `<prefix>/true` or `<prefix>/estimated`; once both kinds of a cycle
    /// are in, the error from each true contact to its whisker's estimate
    /// (`<prefix>/error`, arrows, at the time of the cycle's first half).
    pub fn contacts_in(
        &self,
        prefix: &str,
        kind: ContactKind,
        cycle: u64,
        contacts: &[Contact],
    ) -> Result {
        let labels = whisker_sim::whisker::array::labels();
        let (name, [r, g, b]) = match kind {
            ContactKind::True => ("true", TRUE_COLOUR),
            ContactKind::Estimated => ("estimated", ESTIMATED_COLOUR),
        };
        let points: Vec<[f32; 3]> = contacts.iter().map(|c| c.point.map(|v| v as f32)).collect();
        self.log(
            format!("{prefix}/{name}"),
            &rerun::Points3D::new(points)
                .with_radii([0.003])
                .with_colors([rerun::Color::from_rgb(r, g, b)])
                .with_labels(contacts.iter().map(|c| labels[c.whisker].clone())),
        )?;
        let key = (prefix.to_string(), cycle);
        let pair = {
            let mut pending = self.pending.lock().unwrap_or_else(|e| e.into_inner());
            let entry = pending
                .entry(key.clone())
                .or_insert_with(|| (self.now(), None, None));
            match kind {
                ContactKind::True => entry.1 = Some(contacts.to_vec()),
                ContactKind::Estimated => entry.2 = Some(contacts.to_vec()),
            }
            if entry.1.is_some() && entry.2.is_some() {
                pending.remove(&key)
            } else {
                None
            }
        };
        if let Some((when, Some(truth), Some(estimate))) = pair {
            let (origins, vectors): (Vec<[f32; 3]>, Vec<[f32; 3]>) = truth
                .iter()
                .filter_map(|c| {
                    let e = estimate.iter().find(|e| e.whisker == c.whisker)?;
                    Some((
                        c.point.map(|v| v as f32),
                        [0, 1, 2].map(|i| (e.point[i] - c.point[i]) as f32),
                    ))
                })
                .unzip();
            self.at_timepoint(when, || {
                self.log(
                    format!("{prefix}/error"),
                    &rerun::Arrows3D::from_vectors(vectors)
                        .with_origins(origins)
                        .with_radii([0.0008]),
                )
            })?;
        }
        Ok(())
    }
}
