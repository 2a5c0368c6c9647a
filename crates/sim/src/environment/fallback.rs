//! Fallback solids for meshes that cannot be repaired into closed solids (issue #20): the
//! convex hull of the file's vertices, with how far it strays from the file's surface.

use super::shape_error::ShapeError;
use super::triangles::{Mesh, signed_volume};
use nalgebra::Point3;
use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::TriMesh;

/// Barycentric subdivisions per edge when sampling large triangles (a hull's, a decimated
/// mesh's); a voxel remesh's are about a voxel across and are sampled at their corners and
/// centroids.
pub const SAMPLES_PER_EDGE: usize = 4;

/// The convex hull of `points` as a closed, outward-oriented mesh.
pub fn convex_hull(points: &[Point3<f64>]) -> Result<Mesh, ShapeError> {
    let input: Vec<Vector> = points.iter().map(|p| Vector::new(p.x, p.y, p.z)).collect();
    let (vertices, mut triangles) =
        parry3d_f64::transformation::try_convex_hull(&input).map_err(ShapeError::Hull)?;
    let vertices: Vec<Point3<f64>> = vertices
        .iter()
        .map(|v| Point3::new(v.x, v.y, v.z))
        .collect();
    let volume = signed_volume(&vertices, &triangles);
    if triangles.len() < 4 || volume == 0.0 {
        return Err(ShapeError::Coplanar);
    }
    if volume < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    Ok(Mesh {
        vertices,
        triangles,
    })
}

/// How far the surface of `replacement` lies from `original` (any soup, indexed by
/// [`index_surface`]): (max, mean) distance (m) over points sampled on the replacement:
/// with `subdivisions` > 1, a barycentric grid of that many divisions per edge on every
/// triangle; otherwise every vertex and every triangle's centroid.
pub fn deviation(replacement: &Mesh, original: &TriMesh, subdivisions: usize) -> (f64, f64) {
    let mut samples: Vec<Point3<f64>> = Vec::new();
    if subdivisions > 1 {
        let n = subdivisions;
        for t in &replacement.triangles {
            let [a, b, c] = t.map(|i| replacement.vertices[i as usize].coords);
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    samples.push(Point3::from(a * (1.0 - u - v) + b * u + c * v));
                }
            }
        }
    } else {
        samples.extend(&replacement.vertices);
        samples.extend(replacement.triangles.iter().map(|t| {
            let [a, b, c] = t.map(|i| replacement.vertices[i as usize].coords);
            Point3::from((a + b + c) / 3.0)
        }));
    }
    distances(&samples, original)
}

/// Any triangle soup as a parry triangle mesh for nearest-point queries.
pub fn index_surface(
    vertices: &[Point3<f64>],
    triangles: &[[u32; 3]],
) -> Result<TriMesh, ShapeError> {
    TriMesh::new(
        vertices
            .iter()
            .map(|p| Vector::new(p.x, p.y, p.z))
            .collect(),
        triangles.to_vec(),
    )
    .map_err(ShapeError::Index)
}

/// The (max, mean) distance (m) from `points` to `surface`.
pub fn distances(points: &[Point3<f64>], surface: &TriMesh) -> (f64, f64) {
    let (mut max, mut sum) = (0.0f64, 0.0);
    for p in points {
        let q = Vector::new(p.x, p.y, p.z);
        let d = (surface.project_local_point(q, false).point - q).length();
        max = max.max(d);
        sum += d;
    }
    (max, sum / points.len().max(1) as f64)
}
