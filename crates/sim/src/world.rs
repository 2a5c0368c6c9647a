//! One simulated world: the Rapier physics state with the arm and the fixed environment.
//!
//! Later parts add the whisker array and environments; this holds what they share: the
//! integration step, the arm driven from joint positions, and arm–environment contact
//! detection (the thesis relied on MoveIt to keep the arm clear of objects, §2.2.1; here
//! a collision is detected and reported).

use crate::arm::{Arm, groups};
use crate::kinematics::urdf::RobotModel;
use nalgebra::Isometry3;
use rapier3d_f64::prelude::*;

/// A Rapier world holding the arm of a robot model.
pub struct World {
    /// The physics state.
    pub physics: PhysicsWorld,
    /// The robot model the arm was built from.
    pub model: RobotModel,
    /// The arm's bodies.
    pub arm: Arm,
    /// Model joint positions the arm is at (one per model joint).
    pub q: Vec<f64>,
    /// Simulated time (s).
    pub time: f64,
}

impl World {
    /// A world stepping at `dt` seconds, with the arm of `model` rooted at the world
    /// origin at model joint positions `q`.
    pub fn new(model: RobotModel, q: Vec<f64>, dt: f64) -> Self {
        let mut physics = PhysicsWorld::new();
        physics.gravity = Vector::new(0.0, 0.0, -9.81);
        physics.integration_parameters.dt = dt;
        let arm = Arm::build(&model, &mut physics, Isometry3::identity(), &q);
        Self {
            physics,
            model,
            arm,
            q,
            time: 0.0,
        }
    }

    /// Adds a fixed environment collider (objects, walls, floor).
    pub fn add_fixed(&mut self, collider: ColliderBuilder) -> ColliderHandle {
        let body = self.physics.insert_body(RigidBodyBuilder::fixed());
        let collider = collider.collision_groups(InteractionGroups::new(
            groups::ENVIRONMENT,
            Group::ALL,
            InteractionTestMode::And,
        ));
        self.physics.insert_collider(collider, Some(body))
    }

    /// Moves the arm to model joint positions `q` over one step and advances time by dt.
    pub fn step(&mut self, q: &[f64]) {
        self.arm.drive(&self.model, &mut self.physics, q);
        self.physics.step();
        self.q.copy_from_slice(q);
        self.time += self.physics.integration_parameters.dt;
    }

    /// Names of arm links touching or penetrating the environment after the last step
    /// (geometric contact: solver contacts are not generated between a kinematic and a
    /// fixed body).
    pub fn arm_collisions(&self) -> Vec<String> {
        let mut hits = Vec::new();
        for &(link, handle) in &self.arm.bodies {
            let touching = self.physics.bodies[handle].colliders().iter().any(|&c| {
                self.physics.narrow_phase.contact_pairs_with(c).any(|pair| {
                    pair.find_deepest_contact()
                        .is_some_and(|(_, c)| c.dist <= 0.0)
                })
            });
            if touching {
                hits.push(self.model.links[link].name.clone());
            }
        }
        hits
    }
}

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
