//! Kinematic Rapier bodies driven along prescribed poses: the arm's links and each
//! whisker's driver (the follicle's root, moved by the array pose × the whisk angle).

use nalgebra::Isometry3;
use rapier3d_f64::prelude::*;

/// Sets the pose a kinematic body reaches at the end of the next step, its rotation
/// quaternion taken on the same hemisphere as the body's current one. q and −q are one
/// rotation, but Rapier 0.36 derives a kinematic body's velocity from the quaternion
/// difference's `to_scaled_axis`, which reads a sign flip as a turn of nearly 2π within
/// one step: every whisker of the maze run blew up (saturated, then NaN) the moment the
/// array's heading crossed ±180°, whose quaternion flips sign there.
pub fn set_next_kinematic_pose(body: &mut RigidBody, pose: Isometry3<f64>) {
    let mut next: Pose = pose.into();
    if body.position().rotation.dot(next.rotation) < 0.0 {
        next.rotation = -next.rotation;
    }
    body.set_next_kinematic_position(next);
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{UnitQuaternion, Vector3};

    /// A kinematic body turned from 179.9° to −179.9° about z (0.2°, across the sign flip
    /// of the quaternion) gets the angular velocity of 0.2° per step, not of ~2π.
    #[test]
    fn a_turn_across_180_degrees_is_a_small_turn() {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::ZERO;
        let at = |deg: f64| {
            Isometry3::from_parts(
                Vector3::zeros().into(),
                UnitQuaternion::from_axis_angle(&Vector3::z_axis(), deg.to_radians()),
            )
        };
        let h = world.insert_body(
            RigidBodyBuilder::kinematic_position_based()
                .pose(at(179.9).into())
                .build(),
        );
        let dt = 0.01;
        world.integration_parameters.dt = dt;
        let naive: Pose = at(-179.9).into();
        assert!(
            world.bodies[h].position().rotation.dot(naive.rotation) < 0.0,
            "the case flips sign"
        );
        set_next_kinematic_pose(&mut world.bodies[h], at(-179.9));
        world.step();
        let bodies = &world.bodies;
        let w = bodies[h].angvel();
        let want = 0.2f64.to_radians() / dt;
        assert!(
            (w.z - want).abs() < 1e-6 * want && w.x.abs() + w.y.abs() < 1e-9,
            "{w:?}"
        );
        let reached: Isometry3<f64> = (*bodies[h].position()).into();
        let turned = reached.rotation.angle_to(&at(-179.9).rotation);
        assert!(turned < 1e-9, "{turned}");
    }
}
