//! The environment as solids: what is inside an object, and how the physics sees parts
//! that overlap.
//!
//! A mesh may hold several closed components that overlap (a mug's handle sunk into its
//! wall, a kettle's spout into its belly): the solid is their union. The part of one
//! component's surface that lies inside another is not surface of the union, and a
//! triangle-mesh collider must not keep it: a whisker tip sliding along a handle's
//! underside into the crease meets those buried triangles, which push it *into* the wall
//! behind them, and the wall's own face, a surface without thickness, no longer holds it
//! once the tip is behind (`whisker soak --objects mug --whiskers E1` put the tip 3.9 mm
//! inside the Mug's wall at 0.34 s before buried triangles were dropped).
//! [`outer_surface`] drops every triangle buried inside another component; the few
//! triangles that straddle the intersection curve stay.
//!
//! [`Solids`] answers "how deep inside the environment is this point", per closed
//! component, for tunnelling checks (`whisker soak`, tests).

use super::Environment;
use super::edges::components;
use super::shape_error::ShapeError;
use super::triangles::Mesh;
use nalgebra::{Isometry3, Point3};
use parry3d_f64::math::Vector;
use parry3d_f64::shape::{SharedShape, TriMeshFlags};

/// Tolerance (m) within which a vertex on another component's surface counts as on it,
/// not inside: triangles touching another part keep their place in the outer surface.
const ON_SURFACE: f64 = 1e-7;

/// The mesh's connected components, each as its own mesh (same vertex list).
pub fn component_meshes(mesh: &Mesh) -> Vec<Mesh> {
    components(&mesh.triangles)
        .into_iter()
        .map(|c| Mesh {
            vertices: mesh.vertices.clone(),
            triangles: c.iter().map(|&t| mesh.triangles[t]).collect(),
        })
        .collect()
}

/// A mesh as a parry `ORIENTED` triangle mesh (one-sided contacts; an inside for point
/// queries when the mesh is closed and outward-oriented).
fn oriented_trimesh(mesh: &Mesh) -> Result<SharedShape, ShapeError> {
    trimesh(mesh, TriMeshFlags::ORIENTED)
}

/// `mesh` as a parry shape for fixed colliders: the surface of the union of its
/// components ([`outer_surface`]: triangles buried inside another component dropped),
/// `ORIENTED` so that contacts are one-sided. Not `FIX_INTERNAL_EDGES`: with it, a
/// whisker tip pressed into a concave crease (the Barrel's hoops) wedges ~2 mm into the
/// solid within half a minute of whisking (`whisker soak --objects barrel --whiskers D1`:
/// 1.9 mm at 27 s with 2 substeps); without it (2 substeps per step), the centre line
/// stayed within 0.12 mm over 60 s. Point queries on this shape are not inside tests for
/// meshes of several components; use [`Solids`].
pub fn shape(mesh: &Mesh) -> Result<SharedShape, ShapeError> {
    oriented_trimesh(&outer_surface(mesh)?)
}

/// A triangle soup as a plain, two-sided parry triangle mesh (for the arm's collision
/// checks; no inside, so no depth queries).
pub fn soup_shape(mesh: &Mesh) -> Result<SharedShape, ShapeError> {
    trimesh(mesh, TriMeshFlags::empty())
}

fn trimesh(mesh: &Mesh, flags: TriMeshFlags) -> Result<SharedShape, ShapeError> {
    let vertices = mesh
        .vertices
        .iter()
        .map(|p| Vector::new(p.x, p.y, p.z))
        .collect();
    SharedShape::trimesh_with_flags(vertices, mesh.triangles.clone(), flags)
        .map_err(ShapeError::Collider)
}

/// Depth (m) of `p` inside the closed solid `shape` at `pose`; 0 outside.
fn depth_in(shape: &SharedShape, pose: &Isometry3<f64>, p: &Point3<f64>) -> f64 {
    let local = pose.inverse() * p;
    let q = Vector::new(local.x, local.y, local.z);
    let proj = shape.project_local_point(q, false);
    if proj.is_inside {
        (proj.point - q).length()
    } else {
        0.0
    }
}

/// The surface of the union of a mesh's closed components: the mesh without the
/// triangles whose three vertices and centroid all lie inside another component.
/// A mesh of one component is returned as it is.
pub fn outer_surface(mesh: &Mesh) -> Result<Mesh, ShapeError> {
    let parts = components(&mesh.triangles);
    if parts.len() < 2 {
        return Ok(mesh.clone());
    }
    let solids = component_meshes(mesh)
        .iter()
        .map(oriented_trimesh)
        .collect::<Result<Vec<_>, _>>()?;
    let identity = Isometry3::identity();
    let mut keep = vec![true; mesh.triangles.len()];
    for (own, part) in parts.iter().enumerate() {
        for &t in part {
            let corners = mesh.triangles[t].map(|i| mesh.vertices[i as usize]);
            let centroid =
                Point3::from((corners[0].coords + corners[1].coords + corners[2].coords) / 3.0);
            let buried = solids.iter().enumerate().any(|(other, s)| {
                other != own
                    && corners
                        .iter()
                        .chain([&centroid])
                        .all(|p| depth_in(s, &identity, p) > ON_SURFACE)
            });
            keep[t] = !buried;
        }
    }
    Ok(Mesh {
        vertices: mesh.vertices.clone(),
        triangles: mesh
            .triangles
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(t, _)| *t)
            .collect(),
    })
}

/// The environment's closed solids in the world frame, for depth queries.
pub struct Solids {
    parts: Vec<(SharedShape, Isometry3<f64>)>,
}

impl Solids {
    /// One solid per closed component of every piece (primitive pieces — the maze's boxes
    /// and cylinders — as their exact shapes).
    pub fn new(environment: &Environment) -> Result<Self, ShapeError> {
        environment.require_solids("a depth check")?;
        let mut parts = Vec::new();
        for piece in &environment.pieces {
            if piece.shape.as_trimesh().is_none() {
                parts.push((piece.shape.clone(), piece.pose));
                continue;
            }
            for component in component_meshes(&piece.mesh) {
                parts.push((oriented_trimesh(&component)?, piece.pose));
            }
        }
        Ok(Self { parts })
    }

    /// How deep `p` (world) lies inside the environment (m, ≥ 0): the largest depth inside
    /// any one solid. Inside overlapping solids this is a lower bound on the depth inside
    /// their union.
    pub fn depth(&self, p: &Point3<f64>) -> f64 {
        self.parts
            .iter()
            .map(|(s, pose)| depth_in(s, pose, p))
            .fold(0.0, f64::max)
    }

    /// Whether `shape` at `pose` (world) touches or enters any solid: its surface meets
    /// a solid's, or its local origin lies inside one (a shape wholly inside a solid
    /// crosses no surface).
    pub fn overlaps(&self, shape: &dyn parry3d_f64::shape::Shape, pose: &Isometry3<f64>) -> bool {
        if self.depth(&Point3::from(pose.translation.vector)) > 0.0 {
            return true;
        }
        self.parts.iter().any(|(s, p)| {
            parry3d_f64::query::intersection_test(&(*p).into(), s.as_ref(), &(*pose).into(), shape)
                .is_ok_and(|i| i.intersecting)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::environment::Piece;
    use crate::environment::shapes::{cuboid, merge};

    /// A 2 m cube and a small box sunk into its +x face: the small box's face at x = 1.5
    /// lies inside the cube (both of its triangles go); every other triangle touches the
    /// outside of the union and stays.
    fn sunk_boxes() -> Mesh {
        merge(&[
            cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(2.0, 2.0, 2.0)),
            cuboid(Point3::new(1.5, 0.5, 0.5), Point3::new(2.5, 1.0, 1.0)),
        ])
    }

    #[test]
    fn buried_faces_leave_the_outer_surface() {
        let mesh = sunk_boxes();
        let surface = outer_surface(&mesh).unwrap();
        assert_eq!(surface.triangles.len(), mesh.triangles.len() - 2);
        let dropped: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .filter(|t| !surface.triangles.contains(t))
            .copied()
            .collect();
        for t in dropped {
            for i in t {
                assert!((mesh.vertices[i as usize].x - 1.5).abs() < 1e-12);
            }
        }
        // One component: nothing to drop.
        let cube = cuboid(Point3::origin(), Point3::new(1.0, 1.0, 1.0));
        assert_eq!(outer_surface(&cube).unwrap().triangles, cube.triangles);
    }

    #[test]
    fn depth_is_the_distance_to_the_nearest_face_of_the_containing_solid() {
        let mesh = sunk_boxes();
        let pose = Isometry3::translation(10.0, 0.0, 0.0);
        let environment = Environment {
            pieces: vec![Piece {
                name: "boxes".into(),
                shape: shape(&mesh).unwrap(),
                mesh,
                pose,
                soup: false,
            }],
        };
        let solids = Solids::new(&environment).unwrap();
        let at = |x: f64, y: f64, z: f64| solids.depth(&(pose * Point3::new(x, y, z)));
        assert!((at(1.0, 1.0, 0.3) - 0.3).abs() < 1e-12);
        // In the small box outside the cube: 0.2 from its top face (z = 1).
        assert!((at(2.3, 0.75, 0.8) - 0.2).abs() < 1e-12);
        // In both: the deeper of the two (0.25 inside the small box; 0.1 inside the cube).
        assert!((at(1.9, 0.75, 0.75) - 0.25).abs() < 1e-12);
        assert_eq!(at(3.0, 1.0, 1.0), 0.0);
        assert_eq!(at(2.3, 1.5, 1.5), 0.0);
    }
}
