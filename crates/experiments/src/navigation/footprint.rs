//! The base's footprint against the environment: an independent collision check of the
//! base's poses (a solid upright cylinder, the base's disc, `height` tall, 1 mm above the
//! floor) against every piece's own collision shape, by parry's intersection test. It
//! shares nothing with `[navigate]`'s plan-view route check (segments, capsules,
//! rectangles), so each checks the other.

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::shape::Cylinder;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::Environment;
use whisker_slam::pose::Pose2;

/// Gap left under the footprint so that the floor slab it stands on does not count (m).
const ABOVE_FLOOR_M: f64 = 1e-3;

/// Every (update, piece name) where the base at `poses` (disc of `radius`, `height` tall)
/// touches or enters a piece of `environment`; pieces whose collision shapes parry cannot
/// test against a cylinder are named in the error.
pub fn collisions(
    environment: &Environment,
    poses: &[Pose2],
    radius: f64,
    height: f64,
) -> Result<Vec<(usize, String)>> {
    let disc = Cylinder::new(height / 2.0, radius);
    // Parry's cylinder stands along its own y axis: turned to stand along z.
    let upright =
        nalgebra::UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
    let mut hits = Vec::new();
    for (k, p) in poses.iter().enumerate() {
        let pose = Isometry3::from_parts(
            nalgebra::Translation3::new(p.x, p.y, ABOVE_FLOOR_M + height / 2.0),
            upright,
        );
        for piece in &environment.pieces {
            let test = parry3d_f64::query::intersection_test(
                &piece.pose.into(),
                piece.shape.as_ref(),
                &pose.into(),
                &disc,
            )
            .map_err(|_| {
                Error::Failure(format!(
                    "{}: its shape cannot be tested against the base",
                    piece.name
                ))
            })?;
            if test.intersecting {
                hits.push((k, piece.name.clone()));
            }
        }
    }
    Ok(hits)
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_sim::environment::floor_plan::{Door, FloorPlan};
    use whisker_sim::environment::maze::Wall;

    /// A south wall along y = 0 and a partition at x = 2 with a 1 m door (y from 1 to 2).
    fn room() -> Environment {
        let walls = [([0.0, 0.0], [4.0, 0.0]), ([2.0, 0.0], [2.0, 3.0])];
        FloorPlan {
            size: [4.0, 3.0],
            walls: walls
                .map(|(from, to)| Wall {
                    from,
                    to,
                    height: 0.5,
                    thickness: 0.1,
                })
                .to_vec(),
            doors: vec![Door {
                wall: 1,
                at: 1.5,
                width: 1.0,
            }],
            posts: Vec::new(),
        }
        .build(&Isometry3::identity(), "office")
    }

    fn at(x: f64, y: f64) -> Pose2 {
        Pose2 { x, y, th: 0.0 }
    }

    #[test]
    fn the_base_passes_a_door_wider_than_itself_and_touches_what_it_reaches() {
        let env = room();
        // Through the door's middle (jambs at y = 1 and 2) with a 0.3 m disc: clear; the
        // floor it stands on is not a collision.
        let through: Vec<Pose2> = (0..=20).map(|i| at(1.0 + i as f64 * 0.1, 1.5)).collect();
        assert_eq!(collisions(&env, &through, 0.3, 0.3).unwrap(), vec![]);
        // 0.6 m off the door's middle the disc reaches 0.1 m past the jamb: a hit on the
        // partition's lower piece, at the update in the doorway only.
        let off: Vec<Pose2> = [1.0, 2.0, 3.0].iter().map(|&x| at(x, 0.9)).collect();
        assert_eq!(
            collisions(&env, &off, 0.3, 0.3).unwrap(),
            vec![(1, "office wall 1.0".to_string())]
        );
        // 0.36 m from the south wall's surface (y = 0.05): clear; 0.34 m with a 0.35 m
        // disc: a hit.
        assert!(
            collisions(&env, &[at(1.0, 0.41)], 0.35, 0.3)
                .unwrap()
                .is_empty()
        );
        assert_eq!(
            collisions(&env, &[at(1.0, 0.39)], 0.35, 0.3).unwrap().len(),
            1
        );
    }
}
