//! Why a mesh could not become the shape something needs: a collider, a convex hull, an
//! index for nearest-point queries, or a solid where a triangle soup was given.

use parry3d_f64::shape::TriMeshBuilderError;
use parry3d_f64::transformation::ConvexHullError;

/// A mesh that cannot be the shape asked for.
#[derive(Debug, thiserror::Error)]
pub enum ShapeError {
    /// parry refused the triangles as a collision mesh.
    #[error("cannot build a collision mesh: {0}")]
    Collider(TriMeshBuilderError),
    /// parry found no convex hull of the points.
    #[error("no convex hull of the vertices ({0:?})")]
    Hull(ConvexHullError),
    /// The points lie in a plane: their hull has no volume.
    #[error("the vertices are coplanar: their convex hull has no volume")]
    Coplanar,
    /// parry refused the triangles as a surface for nearest-point queries.
    #[error("cannot index the surface: {0}")]
    Index(TriMeshBuilderError),
    /// A piece is a triangle soup where `what` needs closed solids.
    #[error(
        "{piece} is a triangle soup (repair = \"soup\"): {what} needs closed solids \
         (repair = \"auto\", \"hull\" or \"voxel\")"
    )]
    Soup { piece: String, what: String },
}
