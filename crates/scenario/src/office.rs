//! `[office]` of a scenario (documented in `scenarios/README.md`): the office of the
//! thesis' conclusions — "a uniformly textured and flat ground ... and multiple rooms"
//! (Fig 5.1, §7.1) — as a floor plan of wall segments with doors cut into them
//! ([`whisker_sim::environment::floor_plan`]). The office's plan frame is the world: the
//! floor's top at z = 0, x and y from its corner. Objects stand on the floor as
//! `[[objects]]` placed in the same frame.

use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::Path;
use whisker_sim::environment::Piece;
use whisker_sim::environment::floor_plan::{Door, FloorPlan};
use whisker_sim::environment::maze::{Post, Wall};

/// `[office]`: the floor, its walls and doors.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OfficeConfig {
    /// Floor size x, y (m).
    pub floor_m: [f64; 2],
    /// Height of every wall that does not give its own (m) [0.5].
    #[serde(default = "wall_height")]
    pub wall_height_m: f64,
    /// Thickness of every wall that does not give its own (m) [0.1].
    #[serde(default = "wall_thickness")]
    pub wall_thickness_m: f64,
    /// `[[office.walls]]`.
    #[serde(default)]
    pub walls: Vec<OfficeWall>,
    /// `[[office.doors]]`: gaps cut into the walls.
    #[serde(default)]
    pub doors: Vec<Door>,
    /// `[[office.posts]]`: pillars.
    #[serde(default)]
    pub posts: Vec<Post>,
}

/// `[[office.walls]]`: a straight wall on the floor.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OfficeWall {
    /// Start point (x, y) (m).
    pub from_m: [f64; 2],
    /// End point (x, y) (m).
    pub to_m: [f64; 2],
    /// Height (m) [`office.wall_height_m`].
    pub height_m: Option<f64>,
    /// Thickness (m) [`office.wall_thickness_m`].
    pub thickness_m: Option<f64>,
}

fn wall_height() -> f64 {
    0.5
}
fn wall_thickness() -> f64 {
    0.1
}

impl OfficeConfig {
    /// The floor plan, each wall's missing height and thickness the office's.
    pub fn floor_plan(&self) -> FloorPlan {
        FloorPlan {
            size: self.floor_m,
            walls: self
                .walls
                .iter()
                .map(|w| Wall {
                    from: w.from_m,
                    to: w.to_m,
                    height: w.height_m.unwrap_or(self.wall_height_m),
                    thickness: w.thickness_m.unwrap_or(self.wall_thickness_m),
                })
                .collect(),
            doors: self.doors.clone(),
            posts: self.posts.clone(),
        }
    }

    /// The floor plan, checked: every problem names its `office.` field.
    pub fn checked_plan(&self, file: &Path) -> Result<FloorPlan> {
        for (name, v) in [
            ("wall_height_m", self.wall_height_m),
            ("wall_thickness_m", self.wall_thickness_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::field(
                    file,
                    &format!("office.{name}"),
                    format!("{v}: expected a positive length in metres"),
                ));
            }
        }
        let plan = self.floor_plan();
        plan.validate("floor_m", "floor")
            .map_err(|(f, msg)| Error::field(file, &format!("office.{f}"), msg))?;
        Ok(plan)
    }
}

/// The `[office]` built (floor, walls between their doors, posts) and its report line.
pub fn load(file: &Path, o: &OfficeConfig) -> Result<(Vec<Piece>, String)> {
    let plan = o.checked_plan(file)?;
    let built = plan.build(&nalgebra::Isometry3::identity(), "office");
    let line = format!(
        "office     {} x {} m floor, {} walls ({} pieces), {} doors, {} posts",
        o.floor_m[0],
        o.floor_m[1],
        o.walls.len(),
        plan.spans().len(),
        o.doors.len(),
        o.posts.len()
    );
    Ok((built.pieces, line))
}
