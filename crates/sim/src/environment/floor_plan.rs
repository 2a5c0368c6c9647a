//! A floor plan: a flat floor with straight walls, doors cut into them, and posts — the
//! maze board of thesis §3.1 (Fig 3.1) and the office of its conclusions ("a uniformly
//! textured and flat ground ... and multiple rooms"; Fig 5.1, §7.1) are both one.
//!
//! Plan frame: the floor spans x ∈ [0, size.x], y ∈ [0, size.y], its top surface at
//! z = 0, a [`FLOOR_THICKNESS`] slab below it. A wall is a straight segment on the floor
//! (end points, height, thickness), extended by half its thickness at each end so that
//! walls meeting at a corner close it. A door is a gap of `width` centred `at` metres
//! along its wall from the wall's `from` end: the wall is built as the pieces between
//! its doors (extended only at the wall's own ends, so a door's opening is exactly its
//! width). Posts are upright cylinders or square boxes. Every part becomes a fixed
//! collider with a primitive shape (cuboid, cylinder).

use super::shapes::cuboid;
use super::{Environment, Piece};
use nalgebra::{Isometry3, Point2, Point3, Vector3};
use parry3d_f64::shape::SharedShape;
use serde::Deserialize;

/// Floor slab thickness (m).
pub const FLOOR_THICKNESS: f64 = 0.02;

/// A wall: a straight segment on the floor (scenario fields `from_m`, `to_m`,
/// `height_m`, `thickness_m`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Wall {
    /// Start point (x, y) on the floor (m).
    #[serde(rename = "from_m")]
    pub from: [f64; 2],
    /// End point (x, y) on the floor (m).
    #[serde(rename = "to_m")]
    pub to: [f64; 2],
    /// Height above the floor (m).
    #[serde(rename = "height_m")]
    pub height: f64,
    /// Thickness (m).
    #[serde(rename = "thickness_m")]
    pub thickness: f64,
}

/// Shape of a post.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum PostShape {
    /// Upright cylinder of diameter `size`.
    #[default]
    Cylinder,
    /// Square box of side `size`.
    Box,
}

/// A post (scenario fields `at_m`, `size_m`, `height_m`, `shape`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Post {
    /// Centre (x, y) on the floor (m).
    #[serde(rename = "at_m")]
    pub at: [f64; 2],
    /// Diameter (cylinder) or side (box) (m).
    #[serde(rename = "size_m")]
    pub size: f64,
    /// Height above the floor (m).
    #[serde(rename = "height_m")]
    pub height: f64,
    /// Cylinder (default) or box.
    #[serde(default)]
    pub shape: PostShape,
}

/// A door: a gap in a wall (scenario fields `wall`, `at_m`, `width_m`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Door {
    /// Index of the wall it is cut into.
    pub wall: usize,
    /// Distance of the door's centre from the wall's `from` end (m).
    #[serde(rename = "at_m")]
    pub at: f64,
    /// Width of the opening (m).
    #[serde(rename = "width_m")]
    pub width: f64,
}

/// A floor plan (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct FloorPlan {
    /// Floor size (x, y) (m).
    pub size: [f64; 2],
    /// The walls.
    pub walls: Vec<Wall>,
    /// Doors cut into the walls.
    pub doors: Vec<Door>,
    /// The posts.
    pub posts: Vec<Post>,
}

/// A field path and what is wrong with it.
pub type FieldError = (String, String);

pub(crate) fn positive(v: f64, field: &str) -> Result<(), FieldError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err((
            field.into(),
            format!("{v}: expected a positive length in metres"),
        ))
    }
}

/// One straight piece of a wall between its doors: arc lengths along the wall from its
/// `from` end (the ends of the wall itself extended by half the thickness).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallSpan {
    /// The wall's index.
    pub wall: usize,
    /// Start and end along the wall (m).
    pub along: [f64; 2],
}

impl FloorPlan {
    /// Checks sizes, that everything stands on the floor and that every door fits its
    /// wall without overlapping another; names the first bad field as (field path,
    /// message), `what` naming the floor ("board" for the maze).
    pub fn validate(&self, size_field: &str, what: &str) -> Result<(), FieldError> {
        positive(self.size[0], size_field)?;
        positive(self.size[1], size_field)?;
        let on_floor = |p: [f64; 2], field: String| match self.off_floor(p, what) {
            Some(msg) => Err((field, msg)),
            None => Ok(()),
        };
        for (i, w) in self.walls.iter().enumerate() {
            positive(w.height, &format!("walls[{i}].height_m"))?;
            positive(w.thickness, &format!("walls[{i}].thickness_m"))?;
            on_floor(w.from, format!("walls[{i}].from_m"))?;
            on_floor(w.to, format!("walls[{i}].to_m"))?;
            if w.from == w.to {
                return Err((
                    format!("walls[{i}]"),
                    "from and to are the same point".into(),
                ));
            }
        }
        for (i, p) in self.posts.iter().enumerate() {
            positive(p.size, &format!("posts[{i}].size_m"))?;
            positive(p.height, &format!("posts[{i}].height_m"))?;
            on_floor(p.at, format!("posts[{i}].at_m"))?;
        }
        for (i, d) in self.doors.iter().enumerate() {
            let Some(w) = self.walls.get(d.wall) else {
                return Err((
                    format!("doors[{i}].wall"),
                    format!(
                        "{}: expected the index of a wall, 0 to {}",
                        d.wall,
                        self.walls.len() as isize - 1
                    ),
                ));
            };
            positive(d.width, &format!("doors[{i}].width_m"))?;
            let length = wall_length(w);
            if !(d.at.is_finite() && d.at - d.width / 2.0 > 0.0 && d.at + d.width / 2.0 < length) {
                return Err((
                    format!("doors[{i}].at_m"),
                    format!(
                        "{}: a {} m door must lie inside wall {} ({:.3} m long): expected {} < at_m < {}",
                        d.at,
                        d.width,
                        d.wall,
                        length,
                        d.width / 2.0,
                        length - d.width / 2.0
                    ),
                ));
            }
            if let Some(j) = self.doors[..i]
                .iter()
                .position(|e| e.wall == d.wall && (e.at - d.at).abs() < (e.width + d.width) / 2.0)
            {
                return Err((
                    format!("doors[{i}]"),
                    format!("overlaps doors[{j}] in wall {}", d.wall),
                ));
            }
        }
        Ok(())
    }

    /// What is wrong with the point `p` (x, y) when it does not lie on the floor (NaN
    /// included), `what` naming the floor; None on it.
    pub fn off_floor(&self, p: [f64; 2], what: &str) -> Option<String> {
        let on = (0.0..=self.size[0]).contains(&p[0]) && (0.0..=self.size[1]).contains(&p[1]);
        (!on).then(|| {
            format!(
                "({}, {}) is off the {} × {} m {what}",
                p[0], p[1], self.size[0], self.size[1]
            )
        })
    }

    /// The walls' straight pieces between their doors, wall by wall.
    pub fn spans(&self) -> Vec<WallSpan> {
        let mut out = Vec::new();
        for (i, w) in self.walls.iter().enumerate() {
            let half = w.thickness / 2.0;
            let mut gaps: Vec<[f64; 2]> = self
                .doors
                .iter()
                .filter(|d| d.wall == i)
                .map(|d| [d.at - d.width / 2.0, d.at + d.width / 2.0])
                .collect();
            gaps.sort_by(|a, b| a[0].total_cmp(&b[0]));
            let mut start = -half;
            for g in gaps {
                out.push(WallSpan {
                    wall: i,
                    along: [start, g[0]],
                });
                start = g[1];
            }
            out.push(WallSpan {
                wall: i,
                along: [start, wall_length(w) + half],
            });
        }
        out
    }

    /// The plan-view centre line of a span (end points, m).
    pub fn span_line(&self, span: &WallSpan) -> [Point2<f64>; 2] {
        let w = &self.walls[span.wall];
        let (a, b) = (Point2::from(w.from), Point2::from(w.to));
        let dir = (b - a) / (b - a).norm();
        [a + dir * span.along[0], a + dir * span.along[1]]
    }

    /// The floor, walls and posts, the plan frame at `frame` in the world, named
    /// "`prefix` floor", "`prefix` wall i" (with ".k" for the k-th piece of a wall with
    /// doors) and "`prefix` post i".
    pub fn build(&self, frame: &Isometry3<f64>, prefix: &str) -> Environment {
        let frame = *frame;
        let mut pieces = Vec::new();
        let [w, d] = self.size;
        pieces.push(slab(
            format!("{prefix} floor"),
            Point3::new(0.0, 0.0, -FLOOR_THICKNESS),
            Point3::new(w, d, 0.0),
            frame,
        ));
        let spans = self.spans();
        for (i, wall) in self.walls.iter().enumerate() {
            let mine: Vec<&WallSpan> = spans.iter().filter(|s| s.wall == i).collect();
            for (k, span) in mine.iter().enumerate() {
                let (pose, length) = match mine.len() {
                    // Without doors, exactly the maze's construction (bit for bit).
                    1 => wall_frame(wall, &frame),
                    _ => {
                        let [a, b] = self.span_line(span);
                        let (pose, _) = wall_frame(
                            &Wall {
                                from: [a.x, a.y],
                                to: [b.x, b.y],
                                ..wall.clone()
                            },
                            &frame,
                        );
                        (pose, span.along[1] - span.along[0])
                    }
                };
                let name = match mine.len() {
                    1 => format!("{prefix} wall {i}"),
                    _ => format!("{prefix} wall {i}.{k}"),
                };
                let half = Vector3::new(length / 2.0, wall.thickness / 2.0, wall.height / 2.0);
                pieces.push(slab(
                    name,
                    Point3::new(-half.x, -half.y, 0.0),
                    Point3::new(half.x, half.y, wall.height),
                    pose,
                ));
            }
        }
        for (i, post) in self.posts.iter().enumerate() {
            let at = frame * Isometry3::translation(post.at[0], post.at[1], 0.0);
            let (h, r) = (post.height, post.size / 2.0);
            match post.shape {
                PostShape::Box => pieces.push(slab(
                    format!("{prefix} post {i}"),
                    Point3::new(-r, -r, 0.0),
                    Point3::new(r, r, h),
                    at,
                )),
                PostShape::Cylinder => pieces.push(Piece::cylinder(
                    format!("{prefix} post {i}"),
                    r,
                    h,
                    at * Isometry3::translation(0.0, 0.0, h / 2.0),
                )),
            }
        }
        Environment { pieces }
    }
}

/// The smallest distance between the segments `a`–`b` and `c`–`d` in the plan.
pub fn segment_distance(a: Point2<f64>, b: Point2<f64>, c: Point2<f64>, d: Point2<f64>) -> f64 {
    let (u, v) = (b - a, d - c);
    let cross = |p: nalgebra::Vector2<f64>, q: nalgebra::Vector2<f64>| p.perp(&q);
    // Proper crossing: the end points of each lie on opposite sides of the other.
    let (d1, d2) = (cross(u, c - a), cross(u, d - a));
    let (d3, d4) = (cross(v, a - c), cross(v, b - c));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    let to = |p: Point2<f64>, s: Point2<f64>, e: Point2<f64>| {
        let w = e - s;
        let t = ((p - s).dot(&w) / w.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        (p - (s + w * t)).norm()
    };
    to(a, c, d)
        .min(to(b, c, d))
        .min(to(c, a, b))
        .min(to(d, a, b))
}

impl FloorPlan {
    /// How close the segment `a`–`b` of the plan comes to a wall's or post's surface (m,
    /// 0 when it runs through one) and which ("wall i", "post i"); None without walls
    /// or posts. Walls are taken as capsules of their thickness round their centre lines
    /// (so at a wall's end, a door's jamb, up to half the thickness too close) and box
    /// posts as the circles round them: never more clearance than there is.
    pub fn clearance(&self, a: Point2<f64>, b: Point2<f64>) -> Option<(f64, String)> {
        let walls = self.spans().into_iter().map(|span| {
            let [c, d] = self.span_line(&span);
            let t = self.walls[span.wall].thickness / 2.0;
            (
                (segment_distance(a, b, c, d) - t).max(0.0),
                format!("wall {}", span.wall),
            )
        });
        let posts = self.posts.iter().enumerate().map(|(i, p)| {
            let c = Point2::from(p.at);
            // A box post's half diagonal: conservative.
            let r = match p.shape {
                PostShape::Cylinder => p.size / 2.0,
                PostShape::Box => p.size / 2.0 * std::f64::consts::SQRT_2,
            };
            (
                (segment_distance(a, b, c, c) - r).max(0.0),
                format!("post {i}"),
            )
        });
        walls.chain(posts).min_by(|x, y| x.0.total_cmp(&y.0))
    }
}

/// A wall's length between its end points (m).
pub fn wall_length(w: &Wall) -> f64 {
    (w.to[0] - w.from[0]).hypot(w.to[1] - w.from[1])
}

/// The pose (in the world, the plan frame at `frame`) of a wall's centre with x along it,
/// and its length with half its thickness added at each end.
pub fn wall_frame(wall: &Wall, frame: &Isometry3<f64>) -> (Isometry3<f64>, f64) {
    let a = Vector3::new(wall.from[0], wall.from[1], 0.0);
    let b = Vector3::new(wall.to[0], wall.to[1], 0.0);
    let yaw = (b.y - a.y).atan2(b.x - a.x);
    let along = Isometry3::new((a + b) / 2.0, Vector3::z() * yaw);
    (frame * along, (b - a).norm() + wall.thickness)
}

/// An axis-aligned box from `lo` to `hi` in the frame `pose`.
pub(crate) fn slab(name: String, lo: Point3<f64>, hi: Point3<f64>, pose: Isometry3<f64>) -> Piece {
    let half = (hi - lo) / 2.0;
    let centre = Isometry3::translation(lo.x + half.x, lo.y + half.y, lo.z + half.z);
    Piece {
        name,
        shape: SharedShape::cuboid(half.x, half.y, half.z),
        mesh: cuboid(Point3::from(-half), Point3::from(half)),
        pose: pose * centre,
        soup: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(from: [f64; 2], to: [f64; 2]) -> Wall {
        Wall {
            from,
            to,
            height: 0.5,
            thickness: 0.1,
        }
    }

    /// A 4 × 3 m room with a door in its south wall and one in a partition.
    fn room() -> FloorPlan {
        FloorPlan {
            size: [4.0, 3.0],
            walls: vec![
                wall([0.0, 0.0], [4.0, 0.0]),
                wall([4.0, 0.0], [4.0, 3.0]),
                wall([4.0, 3.0], [0.0, 3.0]),
                wall([0.0, 3.0], [0.0, 0.0]),
                wall([2.0, 0.0], [2.0, 3.0]),
            ],
            doors: vec![
                Door {
                    wall: 0,
                    at: 1.0,
                    width: 0.9,
                },
                Door {
                    wall: 4,
                    at: 1.5,
                    width: 0.8,
                },
            ],
            posts: Vec::new(),
        }
    }

    /// Whether the world point `p` lies inside any piece but the floor.
    fn blocked(env: &Environment, p: Point3<f64>) -> bool {
        env.pieces.iter().skip(1).any(|piece| {
            parry3d_f64::query::PointQuery::contains_point(
                piece.shape.as_ref(),
                &piece.pose.into(),
                p.coords.into(),
            )
        })
    }

    #[test]
    fn doors_are_openings_of_their_width_and_walls_close_their_corners() {
        let plan = room();
        plan.validate("size_m", "floor").unwrap();
        let env = plan.build(&Isometry3::identity(), "office");
        // 1 floor, wall 0 in two pieces, 3 whole walls, the partition in two pieces.
        assert_eq!(env.pieces.len(), 1 + 2 + 3 + 2);
        assert_eq!(env.pieces[1].name, "office wall 0.0");
        let at = |x: f64, y: f64| Point3::new(x, y, 0.25);
        // The south door spans x ∈ [0.55, 1.45] in the wall's centre line.
        for x in [0.56, 1.0, 1.44] {
            assert!(!blocked(&env, at(x, 0.0)), "{x}");
        }
        for x in [0.54, 1.46, 3.0] {
            assert!(blocked(&env, at(x, 0.0)), "{x}");
        }
        // The partition's door spans y ∈ [1.1, 1.9].
        assert!(!blocked(&env, at(2.0, 1.5)) && blocked(&env, at(2.0, 1.05)));
        assert!(!blocked(&env, at(2.0, 1.89)) && blocked(&env, at(2.0, 1.95)));
        // Corners are closed: the point just outside both walls' centre lines at a
        // corner lies inside the extension.
        assert!(blocked(&env, at(4.04, -0.04)) && blocked(&env, at(-0.04, 3.04)));
        // Above the walls is free.
        assert!(!blocked(&env, Point3::new(3.0, 0.0, 0.55)));
    }

    #[test]
    fn clearance_measures_to_the_wall_surfaces_and_through_doors() {
        let plan = room();
        let p = |x: f64, y: f64| Point2::new(x, y);
        // Along the middle of the west room, 1 m from its west wall's centre line.
        let (d, what) = plan.clearance(p(1.0, 0.8), p(1.0, 2.2)).unwrap();
        assert!((d - 0.75).abs() < 1e-12, "{d} {what}");
        // Through the partition's door (y ∈ [1.1, 1.9]) at its middle: 0.4 m to the
        // jambs, less half the wall's thickness (walls are taken as capsules).
        let (d, what) = plan.clearance(p(1.0, 1.5), p(3.0, 1.5)).unwrap();
        assert!((d - 0.35).abs() < 1e-12 && what == "wall 4", "{d} {what}");
        // Through the partition itself.
        assert_eq!(plan.clearance(p(1.0, 2.5), p(3.0, 2.5)).unwrap().0, 0.0);
        // Crossing, touching and parallel segments.
        assert_eq!(
            segment_distance(p(0., 0.), p(2., 2.), p(0., 2.), p(2., 0.)),
            0.0
        );
        assert_eq!(
            segment_distance(p(0., 0.), p(1., 0.), p(2., 1.), p(3., 1.)),
            2f64.sqrt()
        );
        assert_eq!(
            segment_distance(p(0., 0.), p(4., 0.), p(1., 0.5), p(3., 0.5)),
            0.5
        );
    }

    #[test]
    fn bad_doors_are_named() {
        let mut plan = room();
        plan.doors[1].at = 0.3;
        let (field, msg) = plan.validate("size_m", "floor").unwrap_err();
        assert_eq!(field, "doors[1].at_m", "{msg}");
        let mut plan = room();
        plan.doors[1].wall = 5;
        assert_eq!(
            plan.validate("size_m", "floor").unwrap_err().0,
            "doors[1].wall"
        );
        let mut plan = room();
        plan.doors.push(Door {
            wall: 0,
            at: 1.6,
            width: 0.5,
        });
        let (field, msg) = plan.validate("size_m", "floor").unwrap_err();
        assert_eq!(field, "doors[2]");
        assert!(msg.contains("doors[0]"), "{msg}");
        let mut plan = room();
        plan.walls[2].to = [5.0, 3.0];
        let (field, msg) = plan.validate("size_m", "floor").unwrap_err();
        assert_eq!(field, "walls[2].to_m");
        assert!(msg.contains("4 × 3 m floor"), "{msg}");
    }
}
