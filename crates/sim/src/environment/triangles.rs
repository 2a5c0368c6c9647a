//! The triangle mesh every environment piece is made of: closed, consistently wound,
//! metres, z up — its type, bounds, volume, components and normals. The repairs that make
//! a file's soup into one are `topology` and the loaders `mesh`; the physics' shapes of
//! it are `solids`.

use super::edges::components;
use nalgebra::{Point3, Vector3};

/// A closed, consistently wound triangle mesh (metres, z up).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<Point3<f64>>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// Signed volume of a set of triangles (positive for a closed outward-wound surface).
pub fn signed_volume(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize].coords);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum()
}

/// Axis-aligned bounds of points.
pub fn bounds(points: &[Point3<f64>]) -> (Point3<f64>, Point3<f64>) {
    let mut lo = Point3::from(Vector3::repeat(f64::INFINITY));
    let mut hi = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}

impl Mesh {
    /// Bounding-box size (m).
    pub fn size(&self) -> Vector3<f64> {
        let (lo, hi) = bounds(&self.vertices);
        hi - lo
    }

    /// Enclosed volume (m³); components counted separately.
    pub fn volume(&self) -> f64 {
        signed_volume(&self.vertices, &self.triangles)
    }

    /// Each connected component's signed volume (all positive for a valid mesh).
    pub fn component_volumes(&self) -> Vec<f64> {
        components(&self.triangles)
            .iter()
            .map(|c| {
                let sub: Vec<[u32; 3]> = c.iter().map(|&t| self.triangles[t]).collect();
                signed_volume(&self.vertices, &sub)
            })
            .collect()
    }

    /// Whether every edge is shared by exactly two triangles in opposite directions.
    pub fn is_closed_and_consistent(&self) -> bool {
        let mut directed = std::collections::HashMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        directed
            .iter()
            .all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1))
    }

    /// Outward unit normal of triangle `t`.
    pub fn normal(&self, t: usize) -> Vector3<f64> {
        let [a, b, c] = self.triangles[t].map(|i| self.vertices[i as usize]);
        (b - a).cross(&(c - a)).normalize()
    }
}
