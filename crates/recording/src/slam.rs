//! The SLAM state and the closed loop's decisions in a recording (`slam/…`,
//! `recognition/…`, `world/explore/…`; `docs/recording.md`): per SLAM update the tactile
//! image (Ch 3), a readable projection of the pose-cell activity (planar: the maximum over
//! θ; 6-D: the six maximum projections onto pairs of axes), the experience or object map
//! as a graph drawn at its map positions (points and links in a 2-D view: Rerun's graph
//! view lays nodes out by a force simulation, which would move them off their map poses;
//! current experience red, the strategy's target blue), and the
//! re-localisations; per whisk of a closed loop the goal and its kind, the raw and
//! integrated confidence in each object (§6.2) and the outcome.

use super::Recording;
use nalgebra::Isometry3;
use whisker_experiments::record::Graph;
use whisker_scenario::Result;
use whisker_slam::pose_grid::PoseGrid;
use whisker_slam::ratslam::local_view::{COLUMNS, ROWS, TactileImage};

/// The maxima of `grid` over every axis but each pair (a, b) of `pairs`: per pair a
/// `dims[a]` × `dims[b]` image (a across, b down, row-major), scaled to its own maximum
/// (0–1). One pass over the cells, their coordinates counted up as the index runs (the
/// first axis fastest).
pub fn projections(grid: &PoseGrid, pairs: &[(usize, usize)]) -> Vec<Vec<f32>> {
    let dims = grid.dims();
    let mut out: Vec<Vec<f32>> = pairs
        .iter()
        .map(|&(a, b)| vec![0f32; dims[a] * dims[b]])
        .collect();
    let mut c = vec![0usize; dims.len()];
    for &v in &grid.cells {
        for (tile, &(a, b)) in out.iter_mut().zip(pairs) {
            let p = &mut tile[c[b] * dims[a] + c[a]];
            *p = p.max(v as f32);
        }
        for (ci, &n) in c.iter_mut().zip(dims) {
            *ci += 1;
            if *ci < n {
                break;
            }
            *ci = 0;
        }
    }
    for tile in &mut out {
        let max = tile.iter().cloned().fold(0f32, f32::max);
        if max > 0.0 {
            tile.iter_mut().for_each(|v| *v /= max);
        }
    }
    out
}

/// The maximum of `grid` over every axis but `a` and `b` ([`projections`]): (width,
/// height, pixels).
pub fn max_projection(grid: &PoseGrid, a: usize, b: usize) -> (usize, usize, Vec<f32>) {
    let dims = grid.dims();
    let tile = projections(grid, &[(a, b)]).remove(0);
    (dims[a], dims[b], tile)
}

/// The six projections of a 6-D grid onto pairs of axes, tiled with a 1-pixel gap: top
/// row (x,y) (x,z) (y,z), bottom row (α,β) (α,γ) (β,γ), each tile scaled to its maximum.
pub fn tiles6(grid: &PoseGrid) -> (usize, usize, Vec<f32>) {
    const PAIRS: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 2), (3, 4), (3, 5), (4, 5)];
    let n = grid.dims()[0];
    let (w, h) = (3 * n + 2, 2 * n + 1);
    let mut out = vec![0f32; w * h];
    for (k, tile) in projections(grid, &PAIRS).iter().enumerate() {
        let (row, col) = (k / 3, k % 3);
        for y in 0..n {
            for x in 0..n {
                out[(row * (n + 1) + y) * w + col * (n + 1) + x] = tile[y * n + x];
            }
        }
    }
    (w, h, out)
}

impl Recording {
    /// Logs a tactile image (6 × 3, intensities 0–255) at `entity`.
    pub fn tactile_image(&self, entity: &str, image: &TactileImage) -> Result {
        self.log(
            entity,
            &rerun::Image::from_elements(
                &image.pixels,
                [COLUMNS as u32, ROWS as u32],
                rerun::ColorModel::L,
            ),
        )
    }

    /// Logs the pose cells of `grid` at `entity` as an image: planar (3-D) grids the
    /// maximum over θ, 6-D grids the six projections onto pairs of axes ([`tiles6`]).
    pub fn pose_cells(&self, entity: &str, grid: &PoseGrid) -> Result {
        let (w, h, v) = match grid.dims().len() {
            6 => tiles6(grid),
            _ => max_projection(grid, 0, 1),
        };
        self.log(
            entity,
            &rerun::Image::from_elements(&v, [w as u32, h as u32], rerun::ColorModel::L),
        )
    }

    /// Logs an experience graph under `entity`, in map space (x, y in metres, a 2-D view):
    /// `<entity>/experiences` (points labelled with their index, and object in appended
    /// maps; the current experience red and large, the strategy's target blue) and
    /// `<entity>/links` (a 2-point strip per link).
    pub fn graph(&self, entity: &str, g: &Graph) -> Result {
        let n = g.positions.len();
        let colours = (0..n).map(|k| {
            if Some(k) == g.current {
                rerun::Color::from_rgb(230, 40, 40)
            } else if Some(k) == g.target {
                rerun::Color::from_rgb(40, 90, 230)
            } else {
                rerun::Color::from_rgb(170, 170, 170)
            }
        });
        let labels = (0..n).map(|k| match g.objects.and_then(|o| o[k].as_deref()) {
            Some(o) => format!("{o}:{k}"),
            None => k.to_string(),
        });
        let radii = (0..n).map(|k| {
            if Some(k) == g.current || Some(k) == g.target {
                rerun::Radius::new_ui_points(7.0)
            } else {
                rerun::Radius::new_ui_points(2.5)
            }
        });
        let point = |p: &[f64; 2]| [p[0] as f32, p[1] as f32];
        self.log(
            format!("{entity}/experiences"),
            &rerun::Points2D::new(g.positions.iter().map(point))
                .with_colors(colours)
                .with_labels(labels)
                .with_radii(radii)
                .with_show_labels(false),
        )?;
        self.log(
            format!("{entity}/links"),
            &rerun::LineStrips2D::new(
                g.links
                    .iter()
                    .map(|&(a, b)| [point(&g.positions[a]), point(&g.positions[b])]),
            )
            .with_radii([rerun::Radius::new_ui_points(0.75)])
            .with_colors([rerun::Color::from_rgb(110, 110, 110)]),
        )
    }

    /// Logs a whole path (world) as a static line strip at `entity`.
    pub fn trajectory(&self, entity: &str, points: &[[f64; 3]], colour: [u8; 3]) -> Result {
        let strip: Vec<[f32; 3]> = points.iter().map(|p| p.map(|v| v as f32)).collect();
        let [r, g, b] = colour;
        self.log_static(
            entity,
            &rerun::LineStrips3D::new([strip])
                .with_colors([rerun::Color::from_rgb(r, g, b)])
                .with_radii([rerun::Radius::new_ui_points(1.5)]),
        )
    }

    /// Marks a re-localisation at the current time: a point at the true pose (at
    /// `entity`) and a line of the event log.
    pub fn relocalisation(&self, entity: &str, at: &Isometry3<f64>, text: &str) -> Result {
        let p = at.translation.vector;
        self.log(
            entity,
            &rerun::Points3D::new([[p.x as f32, p.y as f32, p.z as f32]])
                .with_radii([0.008])
                .with_colors([rerun::Color::from_rgb(230, 40, 200)]),
        )?;
        self.event(text)
    }

    /// Logs one scalar at `entity` at the current time.
    pub fn scalar(&self, entity: &str, value: f64) -> Result {
        self.log(entity, &rerun::Scalars::single(value))
    }

    /// Logs a closed loop's goal of kind `kind` (`face:<k>`, `spc`, `step:<e>`) at the
    /// current time (`world/explore/goal`: a point labelled with its kind, blue for the
    /// strategy's goals, orange for the SPC's corrections).
    pub fn goal(&self, pose: &Isometry3<f64>, kind: &str) -> Result {
        let p = pose.translation.vector;
        let colour = if kind == "spc" {
            rerun::Color::from_rgb(255, 140, 0)
        } else {
            rerun::Color::from_rgb(40, 90, 230)
        };
        self.log(
            "world/explore/goal",
            &rerun::Points3D::new([[p.x as f32, p.y as f32, p.z as f32]])
                .with_radii([0.006])
                .with_colors([colour])
                .with_labels([kind]),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass projection equals the definition: the maximum over every cell whose
    /// coordinates (by the grid's own `coords`) on the two axes are the pixel's.
    #[test]
    fn projections_are_the_maxima_over_the_other_axes() {
        let mut grid = PoseGrid::new(&[3, 4, 2, 5]);
        for (k, v) in grid.cells.iter_mut().enumerate() {
            *v = ((k * 7919) % 97) as f64;
        }
        for (a, b) in [(0, 1), (1, 0), (2, 3), (0, 3)] {
            let (w, h, got) = max_projection(&grid, a, b);
            let mut want = vec![0.0f64; w * h];
            for (k, &v) in grid.cells.iter().enumerate() {
                let c = grid.coords(k);
                want[c[b] * w + c[a]] = want[c[b] * w + c[a]].max(v);
            }
            let max = want.iter().cloned().fold(0.0, f64::max);
            for (g, x) in got.iter().zip(&want) {
                assert!((*g as f64 - x / max).abs() < 1e-6, "axes {a},{b}");
            }
        }
    }
}
