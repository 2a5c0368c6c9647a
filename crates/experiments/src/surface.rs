//! An object's outer surface as a ray and point query sees it: how far out along a ray
//! from inside it lies, and its point nearest a point outside — the stand-offs of the §5.2
//! trajectories and of the closed loop's goals at whisker reach (§6.1.3, issue #35).

use nalgebra::{Point3, Vector3};
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::query::Ray;
use parry3d_f64::shape::SharedShape;
use whisker_sim::environment::{Mesh, ShapeError};
use whisker_slam::exploration::goal_mesh::Surface;

/// How far out from `centre` (inside the solid `shape`) along `dir` its outermost
/// surface lies (m): a ray cast inwards from 2 m out. A ray through an edge or a vertex
/// can slip between the triangles, so a miss is retried from origins moved 1 µm sideways;
/// the last resort, the first exit from the inside, is exact for star-shaped solids.
pub fn distance_along(shape: &SharedShape, centre: Vector3<f64>, dir: Vector3<f64>) -> f64 {
    const FAR: f64 = 2.0;
    let side = dir
        .cross(&Vector3::z())
        .try_normalize(1e-9)
        .unwrap_or_else(Vector3::x);
    let other = dir.cross(&side);
    let nudges = [Vector3::zeros(), side, -side, other, -other].map(|v| v * 1e-6);
    let inward = PVector::new(-dir.x, -dir.y, -dir.z);
    nudges
        .iter()
        .find_map(|n| {
            let o = centre + dir * FAR + n;
            let ray = Ray::new(PVector::new(o.x, o.y, o.z), inward);
            shape.cast_local_ray(&ray, FAR, true).map(|t| FAR - t)
        })
        .unwrap_or_else(|| {
            let ray = Ray::new(PVector::new(centre.x, centre.y, centre.z), -inward);
            shape.cast_local_ray(&ray, FAR, false).unwrap_or(0.0)
        })
}

/// An object's mesh (in the world) seen from a point inside it.
pub struct MeshSurface {
    /// The object's triangles in the world.
    pub shape: SharedShape,
    /// Where the rays start.
    pub centre: Point3<f64>,
}

impl MeshSurface {
    /// The triangles of `mesh` (world) seen from `centre`, as a two-sided triangle mesh.
    pub fn new(mesh: &Mesh, centre: Point3<f64>) -> Result<Self, ShapeError> {
        Ok(Self {
            shape: whisker_sim::environment::solids::soup_shape(mesh)?,
            centre,
        })
    }
}

impl Surface for MeshSurface {
    fn centre(&self) -> Point3<f64> {
        self.centre
    }

    fn outermost(&self, direction: &Vector3<f64>) -> Point3<f64> {
        self.centre + direction * distance_along(&self.shape, self.centre.coords, *direction)
    }

    fn nearest(&self, p: &Point3<f64>) -> Point3<f64> {
        let q = self
            .shape
            .project_local_point(PVector::new(p.x, p.y, p.z), false)
            .point;
        Point3::new(q.x, q.y, q.z)
    }
}
