//! Environments the whiskers touch: object meshes (thesis §5.2.1, Fig 5.13; §6.1.3,
//! Fig 6.5) and the maze (§3.1, Fig 3.1).
//!
//! - [`mesh_io`] reads OBJ, STL and PLY files; [`topology`] welds, orients and closes
//!   them ([`edges`]: connectivity; [`cracks`]: T-junctions and holes); [`fallback`] and
//!   [`voxel`] replace what cannot be closed by its convex hull or a watertight remesh;
//!   [`decimate`] thins large solids; [`mesh`] ties them together with units, up axis,
//!   the repair policy and decimation, and builds the collision shape.
//! - [`shapes`] builds closed meshes from primitives (boxes, lathes, swept tubes, star
//!   surfaces); [`assets`] uses it to generate the object catalogue of `assets/meshes`.
//! - [`maze`] builds the re-configurable maze board.
//!
//! An [`Environment`] is a list of fixed [`Piece`]s in the world frame: each has the
//! collision shape the physics uses and a triangle mesh for the kinematic sweep (which
//! prepares its target from it: `SweepTarget::of`).

pub mod assets;
pub mod cracks;
pub mod decimate;
pub mod edges;
pub mod fallback;
pub mod floor_plan;
pub mod maze;
pub mod mesh;
pub mod mesh_io;
pub mod shape_error;
pub mod shapes;
pub mod solids;
pub mod topology;
pub mod triangles;
pub mod voxel;

use nalgebra::Isometry3;
use parry3d_f64::shape::SharedShape;
pub use shape_error::ShapeError;
pub use triangles::Mesh;

/// A fixed piece of the environment as the physics worlds hold it: a shape and its pose
/// in the world.
pub type EnvironmentPiece = (SharedShape, Isometry3<f64>);

/// One fixed piece of the environment.
#[derive(Clone)]
pub struct Piece {
    /// A name for messages and recordings (e.g. "object mug", "maze wall 3").
    pub name: String,
    /// Collision shape for the physics (in the piece frame).
    pub shape: SharedShape,
    /// Closed triangle mesh of the same solid (piece frame), for the kinematic sweep;
    /// exact for meshes and boxes, a 64-sided prism for cylinders.
    pub mesh: Mesh,
    /// Pose of the piece frame in the world.
    pub pose: Isometry3<f64>,
    /// Whether `mesh` is a triangle soup kept as loaded (`repair = "soup"`, #20) rather
    /// than a closed solid: the kinematic sweep takes its triangles as two-sided (the
    /// contact normal turned towards the whisker); physics and depth checks refuse it.
    pub soup: bool,
}

impl Piece {
    /// A solid cylinder of `radius` and `length` whose axis is the z axis of `pose`
    /// (centred on its origin): exact in the physics (parry's cylinder, which stands along
    /// its own y axis, turned to z), a 64-sided prism for the kinematic sweep.
    pub fn cylinder(name: String, radius: f64, length: f64, pose: Isometry3<f64>) -> Self {
        let h = length / 2.0;
        let along_z = shapes::lathe(&[(0.0, -h), (radius, -h), (radius, h), (0.0, h)], 64);
        let y_to_z = shapes::rotation(nalgebra::Vector3::x(), std::f64::consts::FRAC_PI_2);
        Self {
            name,
            shape: SharedShape::cylinder(h, radius),
            mesh: shapes::transformed(&along_z, &y_to_z.inverse()),
            pose: pose * y_to_z,
            soup: false,
        }
    }
}

impl std::fmt::Debug for Piece {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Piece")
            .field("name", &self.name)
            .field("triangles", &self.mesh.triangles.len())
            .field("pose", &self.pose)
            .finish()
    }
}

/// The fixed environment of a scenario.
#[derive(Debug, Clone, Default)]
pub struct Environment {
    /// Its pieces.
    pub pieces: Vec<Piece>,
}

impl Environment {
    /// The pieces as (shape, pose) pairs for the physics worlds.
    pub fn physics_pieces(&self) -> Vec<EnvironmentPiece> {
        self.pieces
            .iter()
            .map(|p| (p.shape.clone(), p.pose))
            .collect()
    }

    /// An error naming the first piece that is a triangle soup, for what needs solids.
    pub fn require_solids(&self, what: &str) -> Result<(), ShapeError> {
        match self.pieces.iter().find(|p| p.soup) {
            Some(p) => Err(ShapeError::Soup {
                piece: p.name.clone(),
                what: what.to_string(),
            }),
            None => Ok(()),
        }
    }

    /// All pieces' triangles in the world frame, one mesh (for the kinematic sweep).
    pub fn world_mesh(&self) -> Mesh {
        let mut out = Mesh {
            vertices: Vec::new(),
            triangles: Vec::new(),
        };
        for p in &self.pieces {
            let base = out.vertices.len() as u32;
            out.vertices
                .extend(p.mesh.vertices.iter().map(|v| p.pose * v));
            out.triangles
                .extend(p.mesh.triangles.iter().map(|t| t.map(|i| i + base)));
        }
        out
    }
}
