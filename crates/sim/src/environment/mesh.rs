//! Object meshes: loading a file into a closed, outward-oriented triangle mesh in metres
//! with z up, and turning it into a Rapier/parry collision shape.
//!
//! Pipeline: read ([`super::mesh_io`]) → scale to metres (`units` × `scale`) → turn to
//! z up → fan-triangulate polygons → weld vertices closer than 1e-7 × the bounding-box
//! diagonal → repair or refuse ([`super::topology`]) as the [`Repair`] policy says. What
//! was repaired is reported so that `whisker check` can show it.

use super::fallback::{SAMPLES_PER_EDGE, convex_hull, deviation, distances, index_surface};
use super::mesh_io;
pub use super::mesh_io::MeshError;
use super::topology::{close_and_orient, weld};
pub use super::triangles::{Mesh, bounds};
use nalgebra::{Point3, Vector3};
use std::path::Path;

/// Length unit of a mesh file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Units {
    /// Metres.
    #[default]
    Metres,
    /// Centimetres.
    Centimetres,
    /// Millimetres (common in CAD/STL exports).
    Millimetres,
    /// Inches.
    Inches,
}

impl Units {
    /// Metres per file unit.
    pub fn metres(self) -> f64 {
        match self {
            Units::Metres => 1.0,
            Units::Centimetres => 0.01,
            Units::Millimetres => 0.001,
            Units::Inches => 0.0254,
        }
    }

    /// Parses "m", "cm", "mm" or "in".
    pub fn parse(s: &str) -> Option<Units> {
        Some(match s {
            "m" => Units::Metres,
            "cm" => Units::Centimetres,
            "mm" => Units::Millimetres,
            "in" => Units::Inches,
            _ => return None,
        })
    }
}

/// Which file axis points up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UpAxis {
    /// +z up (as in ROS and this project).
    #[default]
    Z,
    /// +y up (common in OBJ exports): turned by +90° about x.
    Y,
}

/// What to do with a mesh that is not a clean closed solid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Repair {
    /// Refuse any file that needs a repair (vertex welding of STL files aside).
    Strict,
    /// The repairs of [`super::topology`] that keep the shape; refuse the rest.
    #[default]
    Auto,
    /// The convex hull of the file's vertices, always a solid (unless they are coplanar);
    /// its deviation from the file's surface is reported.
    Hull,
    /// A watertight remesh of the file's surface at a stated voxel size
    /// ([`super::voxel`]), always a solid; its deviation from the file's surface is
    /// reported.
    Voxel,
    /// The triangles as they are (welded; degenerate and duplicate ones dropped), closed
    /// or not: enough for kinematic sensing, which only intersects triangles; physics
    /// sensing and depth checks refuse it.
    Soup,
}

impl Repair {
    /// The keywords, as a scenario writes them.
    pub const CHOICES: &str = "\"strict\", \"auto\", \"hull\", \"voxel\" or \"soup\"";

    /// Parses one of [`Repair::CHOICES`].
    pub fn parse(s: &str) -> Option<Repair> {
        Some(match s {
            "strict" => Repair::Strict,
            "auto" => Repair::Auto,
            "hull" => Repair::Hull,
            "voxel" => Repair::Voxel,
            "soup" => Repair::Soup,
            _ => return None,
        })
    }
}

/// How to interpret a mesh file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshOptions {
    /// The file's length unit.
    pub units: Units,
    /// An extra uniform scale factor (> 0).
    pub scale: f64,
    /// The file's up axis.
    pub up: UpAxis,
    /// What to do when the file is not a clean closed solid.
    pub repair: Repair,
    /// Where the mesh's origin goes.
    pub origin: Origin,
    /// Voxel size (m, after units and scale) of [`Repair::Voxel`]; None: the longest side
    /// of the bounding box / [`super::voxel::DEFAULT_DIVISIONS`].
    pub voxel_size: Option<f64>,
    /// Width (m) of the openings [`Repair::Voxel`] seals before filling (a morphological
    /// closing of ⌈width / 2 voxels⌉); None: none.
    pub voxel_closing: Option<f64>,
    /// Decimation of the solid ([`super::decimate`]); None: none.
    pub decimate: Option<Decimation>,
}

/// A decimation target: at most `triangles` triangles, no collapse whose quadric error
/// exceeds `tolerance` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decimation {
    /// Target number of triangles.
    pub triangles: usize,
    /// Largest quadric error of a collapse (m).
    pub tolerance: f64,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self {
            units: Units::Metres,
            scale: 1.0,
            up: UpAxis::Z,
            repair: Repair::Auto,
            origin: Origin::File,
            voxel_size: None,
            voxel_closing: None,
            decimate: None,
        }
    }
}

/// A loaded mesh and what was done to it.
#[derive(Debug, Clone)]
pub struct LoadedMesh {
    /// The closed, outward-oriented mesh (metres, z up), or with [`Repair::Soup`] the
    /// file's triangles as they are.
    pub mesh: Mesh,
    /// Whether `mesh` is a closed solid (false only for [`Repair::Soup`]).
    pub solid: bool,
    /// Repairs made, in words (empty for a clean file).
    pub repairs: Vec<String>,
    /// Objects/groups the file declared.
    pub objects: usize,
}

/// Where a loaded mesh's origin goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Origin {
    /// The file's own origin.
    #[default]
    File,
    /// The centre of the bottom of the bounding box: the mesh stands on z = 0, centred on
    /// the z axis (as the generated catalogue does).
    Base,
}

impl Origin {
    /// Parses "file" or "base".
    pub fn parse(s: &str) -> Option<Origin> {
        Some(match s {
            "file" => Origin::File,
            "base" => Origin::Base,
            _ => return None,
        })
    }
}

/// Loads a mesh file (see the module documentation), its origin moved as `options.origin`
/// says.
pub fn load(path: &Path, options: &MeshOptions) -> Result<LoadedMesh, MeshError> {
    let mut loaded = load_in_file_frame(path, options)?;
    if let Some(d) = options.decimate {
        decimate_loaded(path, &mut loaded, d)?;
    }
    if options.origin == Origin::Base {
        let (lo, hi) = bounds(&loaded.mesh.vertices);
        let shift = Vector3::new(-(lo.x + hi.x) / 2.0, -(lo.y + hi.y) / 2.0, -lo.z);
        for v in &mut loaded.mesh.vertices {
            *v += shift;
        }
    }
    Ok(loaded)
}

/// Decimates a loaded solid and reports how far the result lies from it, both ways.
fn decimate_loaded(path: &Path, loaded: &mut LoadedMesh, d: Decimation) -> Result<(), MeshError> {
    if !loaded.solid {
        return Err(MeshError::new(
            path,
            "decimate",
            "a triangle soup (repair = \"soup\") is kept as it is: expected a solid to decimate \
             (repair = \"auto\", \"hull\" or \"voxel\")",
        ));
    }
    let before = &loaded.mesh;
    if before.triangles.len() <= d.triangles {
        loaded.repairs.push(format!(
            "not decimated: {} triangles already, target {}",
            before.triangles.len(),
            d.triangles
        ));
        return Ok(());
    }
    let after = super::decimate::decimate(before, d.triangles, d.tolerance);
    let index = |m: &Mesh| {
        index_surface(&m.vertices, &m.triangles).map_err(|e| MeshError::new(path, "decimate", e))
    };
    let (out_max, out_mean) = deviation(&after, &index(before)?, SAMPLES_PER_EDGE);
    let (in_max, in_mean) = distances(&before.vertices, &index(&after)?);
    loaded.repairs.push(format!(
        "decimated from {} to {} triangles (target {}, quadric tolerance {:.2} mm): its \
         surface lies up to {:.2} mm (mean {:.3} mm) from the surface before, whose vertices \
         lie up to {:.2} mm (mean {:.3} mm) from it",
        before.triangles.len(),
        after.triangles.len(),
        d.triangles,
        d.tolerance * 1e3,
        out_max * 1e3,
        out_mean * 1e3,
        in_max * 1e3,
        in_mean * 1e3
    ));
    loaded.mesh = after;
    Ok(())
}

/// The largest distance of a used vertex from the file's origin along any axis (m, after
/// `units` and `scale`): beyond it geometry and contact queries lose their precision (a
/// whisker is millimetres thick), and near the f64 limit they fail.
pub const MAX_COORDINATE_M: f64 = 1e3;

/// The smallest bounding-box diagonal of a mesh (m, after `units` and `scale`).
pub const MIN_DIAGONAL_M: f64 = 1e-5;

fn load_in_file_frame(path: &Path, options: &MeshOptions) -> Result<LoadedMesh, MeshError> {
    if !(options.scale.is_finite() && options.scale > 0.0) {
        return Err(MeshError::new(
            path,
            "scale",
            format!("{}: expected a positive number", options.scale),
        ));
    }
    let soup = mesh_io::read(path)?;
    let factor = options.units.metres() * options.scale;
    let positions: Vec<Point3<f64>> = soup
        .positions
        .iter()
        .map(|&[x, y, z]| {
            let p = match options.up {
                UpAxis::Z => Point3::new(x, y, z),
                UpAxis::Y => Point3::new(x, -z, y),
            };
            p * factor
        })
        .collect();
    let mut triangles = Vec::new();
    let mut origins = Vec::new();
    for (poly, origin) in soup.polygons.iter().zip(&soup.origins) {
        for k in 1..poly.len() - 1 {
            triangles.push([poly[0], poly[k], poly[k + 1]]);
            origins.push(origin.clone());
        }
    }
    let used: Vec<Point3<f64>> = triangles
        .iter()
        .flatten()
        .map(|&i| positions[i as usize])
        .collect();
    let (lo, hi) = bounds(&used);
    let diagonal = (hi - lo).norm();
    if diagonal == 0.0 {
        return Err(MeshError::new(
            path,
            "mesh",
            "every vertex is at the same point: expected a solid",
        ));
    }
    let reach = lo.coords.amax().max(hi.coords.amax());
    if reach > MAX_COORDINATE_M || diagonal < MIN_DIAGONAL_M {
        return Err(MeshError::new(
            path,
            "mesh",
            format!(
                "its vertices reach {reach:.3e} m from the file's origin and its bounding box's \
                 diagonal is {diagonal:.3e} m (after units and scale): expected every vertex \
                 within {MAX_COORDINATE_M} m of the origin and a diagonal of at least \
                 {MIN_DIAGONAL_M} m (check `units` and `scale`)"
            ),
        ));
    }
    let (vertices, map) = weld(&positions, 1e-7 * diagonal);
    let welded = positions.len() - vertices.len();
    let triangles: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| t.map(|i| map[i as usize]))
        .collect();
    match options.repair {
        Repair::Hull | Repair::Voxel => {
            let surface = index_surface(&vertices, &triangles)
                .map_err(|e| MeshError::new(path, "mesh", e))?;
            let (mesh, what, subdivisions) = if options.repair == Repair::Hull {
                let hull = convex_hull(&vertices).map_err(|e| MeshError::new(path, "mesh", e))?;
                let what = format!(
                    "replaced by the convex hull of its {} vertices ({} triangles; repair = \"hull\")",
                    vertices.len(),
                    hull.triangles.len()
                );
                (hull, what, SAMPLES_PER_EDGE)
            } else {
                let size = options
                    .voxel_size
                    .unwrap_or_else(|| (hi - lo).max() / super::voxel::DEFAULT_DIVISIONS);
                let closing = options
                    .voxel_closing
                    .map_or(0, |w| (w / (2.0 * size)).ceil() as usize);
                let remeshed = super::voxel::remesh(&vertices, &triangles, &surface, size, closing)
                    .map_err(|e| MeshError::new(path, "voxel_size", e))?;
                let sealed = if closing > 0 {
                    format!(
                        ", openings up to {:.1} mm sealed",
                        2.0 * closing as f64 * size * 1e3
                    )
                } else {
                    String::new()
                };
                let what = format!(
                    "replaced by a watertight remesh on {:.2} mm voxels{sealed} ({} triangles; repair = \"voxel\")",
                    size * 1e3,
                    remeshed.triangles.len()
                );
                (remeshed, what, 1)
            };
            let (max, mean) = deviation(&mesh, &surface, subdivisions);
            let repairs = vec![format!(
                "{what}: its surface lies up to {:.1} mm (mean {:.2} mm) from the file's",
                max * 1e3,
                mean * 1e3
            )];
            return Ok(LoadedMesh {
                mesh,
                solid: true,
                repairs,
                objects: soup.objects,
            });
        }
        Repair::Soup => {
            let (mesh, repairs) = super::topology::clean_soup(vertices, triangles);
            return Ok(LoadedMesh {
                mesh,
                solid: false,
                repairs,
                objects: soup.objects,
            });
        }
        Repair::Strict | Repair::Auto => {}
    }
    let (mesh, mut repairs) = close_and_orient(vertices, triangles, origins).map_err(|e| {
        MeshError::new(
            path,
            &e.at,
            format!(
                "{} (repair = \"hull\" or \"voxel\" would replace it by a solid: its \
                 convex hull, or a watertight remesh; \"soup\" would keep its triangles \
                 for kinematic sensing only)",
                e.message
            ),
        )
    })?;
    if welded > 0 && !matches!(mesh_io::Format::from_path(path), Some(mesh_io::Format::Stl)) {
        repairs.insert(0, format!("welded {welded} duplicate vertices"));
    }
    if options.repair == Repair::Strict && !repairs.is_empty() {
        return Err(MeshError::new(
            path,
            "mesh",
            format!(
                "not a clean closed solid: it needs {} (repair = \"strict\"; \"auto\" would \
                 make these repairs)",
                repairs.join("; ")
            ),
        ));
    }
    Ok(LoadedMesh {
        mesh,
        solid: true,
        repairs,
        objects: soup.objects,
    })
}
