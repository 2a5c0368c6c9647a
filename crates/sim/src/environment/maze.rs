//! The re-configurable maze (thesis §3.1, Fig 3.1): a 1.35 × 1 m board of plastic walls
//! and posts on a floor, over which the array moves in a plane 77 mm above it.
//!
//! Maze frame: the board spans x ∈ [0, width], y ∈ [0, depth], its top surface at z = 0;
//! the floor is a 20 mm slab below it. Walls are straight segments (end points on the
//! board, height, thickness; extended by half their thickness at each end so that walls
//! meeting at a corner close it); posts are upright cylinders or square boxes. Optional
//! deformities are small boxes stuck to the walls' sides at seeded random places (the
//! `maze/deformities` sub-stream of the scenario seed), to make places distinguishable.
//! Every part becomes a fixed collider with a primitive shape (cuboid, cylinder). The
//! board, walls and posts are a [`FloorPlan`] without doors.

use super::Environment;
use super::floor_plan::{FieldError, FloorPlan, positive, slab, wall_frame};
use nalgebra::{Isometry3, Point3};
use rand::RngExt;
use serde::Deserialize;

pub use super::floor_plan::{FLOOR_THICKNESS, Post, PostShape, Wall};

/// The most deformities of a maze (each is one more collider).
pub const MAX_DEFORMITIES: usize = 1000;

/// Seeded random bumps on the walls' sides (scenario fields `count`, `size_m`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Deformities {
    /// How many.
    pub count: usize,
    /// Smallest and largest edge length of a bump (m).
    #[serde(rename = "size_m")]
    pub size: [f64; 2],
}

/// A maze layout (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MazeLayout {
    /// Board size (x, y) (m); the thesis' board is 1.35 × 1 m.
    pub board: [f64; 2],
    /// The walls.
    pub walls: Vec<Wall>,
    /// The posts.
    pub posts: Vec<Post>,
    /// Optional deformities.
    pub deformities: Option<Deformities>,
}

impl MazeLayout {
    /// The board, walls and posts as a floor plan (no doors).
    pub fn floor_plan(&self) -> FloorPlan {
        FloorPlan {
            size: self.board,
            walls: self.walls.clone(),
            doors: Vec::new(),
            posts: self.posts.clone(),
        }
    }

    /// Checks sizes and that everything stands on the board; names the first bad field
    /// as (field path, message).
    pub fn validate(&self) -> Result<(), FieldError> {
        self.floor_plan().validate("board_m", "board")?;
        if let Some(d) = &self.deformities {
            positive(d.size[0], "deformities.size_m")?;
            if d.size[1] < d.size[0] || !d.size[1].is_finite() {
                return Err((
                    "deformities.size_m".into(),
                    "expected [smallest, largest]".into(),
                ));
            }
            if d.count > MAX_DEFORMITIES {
                return Err((
                    "deformities.count".into(),
                    format!("expected 0 to {MAX_DEFORMITIES}, got {}", d.count),
                ));
            }
            if d.count > 0 && self.walls.is_empty() {
                return Err((
                    "deformities".into(),
                    "deformities need at least one wall".into(),
                ));
            }
        }
        Ok(())
    }

    /// Builds the maze's pieces with the maze frame at `frame` in the world (call
    /// [`MazeLayout::validate`] first); deformities are drawn from the
    /// `maze/deformities` sub-stream of `seed`.
    pub fn build(&self, frame: &Isometry3<f64>, seed: u64) -> Environment {
        let mut pieces = self.floor_plan().build(frame, "maze").pieces;
        let wall_frames: Vec<(Isometry3<f64>, f64)> =
            self.walls.iter().map(|w| wall_frame(w, frame)).collect();
        if let Some(def) = &self.deformities {
            let mut rng = whisker_slam::rng::substream(seed, "maze/deformities");
            for k in 0..def.count {
                let i = rng.random_range(0..self.walls.len());
                let (pose, length) = wall_frames[i];
                let wall = &self.walls[i];
                let s = rng.random_range(def.size[0]..=def.size[1]);
                let x = rng.random_range(-0.5..0.5) * (length - s).max(0.0);
                let z = rng.random_range(0.0..(wall.height - s).max(0.0) + f64::EPSILON);
                let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                // Half a bump's depth is sunk into the wall so that the two overlap.
                let y = side * (wall.thickness / 2.0);
                pieces.push(slab(
                    format!("maze deformity {k} (wall {i})"),
                    Point3::new(x - s / 2.0, y - s / 2.0, z),
                    Point3::new(x + s / 2.0, y + s / 2.0, z + s),
                    pose,
                ));
            }
        }
        Environment { pieces }
    }
}
