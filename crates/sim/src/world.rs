//! One simulated world: the Rapier physics state with the arm and the fixed environment.
//!
//! Later parts add the whisker array and environments; this holds what they share: the
//! integration step, the arm driven from joint positions, and arm–environment contact
//! detection (the thesis relied on MoveIt to keep the arm clear of objects, §2.2.1; here
//! a collision is detected and reported).

use crate::arm::{Arm, groups};
use crate::environment::Environment;
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

    /// Adds every piece of `environment` as a fixed collider at its pose.
    pub fn add_environment(&mut self, environment: &Environment) {
        for piece in &environment.pieces {
            self.add_fixed(ColliderBuilder::new(piece.shape.clone()).position(piece.pose.into()));
        }
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
