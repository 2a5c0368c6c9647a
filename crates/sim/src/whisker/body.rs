//! One whisker built in Rapier: whisking driver, follicle, bulb and shaft segments.
//!
//! Frames: the whisker frame F has its origin where the shaft leaves the bulb, the shaft
//! along +Z, the whisk (rotation) axis along X and Y in the sweep plane, so that the
//! sensor's y deflection is parallel to the sweep and x perpendicular to it (Fig 2.7).
//!
//! Bodies (docs/physics.md, "The model"):
//! - the **driver**, a kinematic position-based body posed at the module mount turned by
//!   the whisk angle (a kinematic body cannot be a multibody root),
//! - the **follicle**, root of the whisker's multibody: a light dynamic body welded to
//!   the driver by an impulse fixed joint ([`RootDrive::Welded`]), or a heavy one pushed
//!   onto the driver's pose by a force held over each step ([`RootDrive::Driven`]),
//! - the **bulb**, joined to the follicle by a spherical joint at the pivot with the
//!   follicle's rotational spring (omitted for a rigid follicle, `follicle = None`),
//! - the **segments**, joined by spherical joints with implicit bending springs
//!   ([`BeamDesign::joint_stiffness`]) and a stiff twist spring.
//!
//! Multibody joint springs are implicit, which is what makes a 0.5 ms step stable for
//! these light, stiff chains; joint damping is set explicitly (Rapier's default of
//! 0.1 N·m·s/rad per angular DoF would dwarf the whisker's stiffness). Self-contacts and
//! joint contacts are off. Every body index and handle is public for readouts.

use super::beam::{BeamDesign, Bending};
use super::follicle::FollicleDesign;
use nalgebra::{Isometry3, Point3, Vector3};
use rapier3d_f64::prelude::*;

/// Mass of the welded follicle body (kg): light, it only carries the weld.
const FOLLICLE_MASS: f64 = 1.0e-3;

/// Mass (kg) and isotropic rotational inertia (kg·m²) of the driven follicle body: ~10⁵
/// times the bulb's (0.3 g) and the shaft's, so that their reactions within a step move it
/// by ~0.2 nm and ~1e-7 rad (1 kg: 12 nm and 1e-6 rad; `tests/root_drive.rs`), and
/// isotropic, so that it has no gyroscopic torque. A numerical device for a prescribed
/// motion, not a model of tissue.
const DRIVEN_ROOT_MASS: f64 = 100.0;
const DRIVEN_ROOT_INERTIA: f64 = 100.0;

/// How the follicle's root follows the whisking driver (#34, deliverable 2: "the follicle's
/// root driven along its prescribed path, no 6-row weld").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RootDrive {
    /// A light root welded to the kinematic driver by an impulse fixed joint: six
    /// constraint rows, solved at every substep with the shaft's contacts.
    #[default]
    Welded,
    /// A heavy root without a weld ([`DRIVEN_ROOT_MASS`]), pushed by a force and torque
    /// held over the step that land it on the driver's pose at the step's end
    /// ([`Whisker::drive`]). The root's free motion still carries the shaft's inertia, so
    /// the base's acceleration loads the shaft as it does through the weld.
    Driven,
}

/// A whisker in a Rapier world.
#[derive(Debug, Clone)]
pub struct Whisker {
    /// The shaft's design.
    pub beam: BeamDesign,
    /// The follicle's design (None: the shaft is clamped rigidly in the follicle).
    pub follicle: Option<FollicleDesign>,
    /// Kinematic driver body.
    pub driver: RigidBodyHandle,
    /// Follicle body (multibody root).
    pub root: RigidBodyHandle,
    /// Bulb body, when the follicle is compliant.
    pub bulb: Option<RigidBodyHandle>,
    /// Shaft segments, base first.
    pub segments: Vec<RigidBodyHandle>,
    /// Multibody joints: follicle→bulb (if any), then the shaft joints, base first.
    pub joints: Vec<MultibodyJointHandle>,
    /// How the root follows the driver.
    pub root_drive: RootDrive,
    /// Current damping scale (1 = the design's damping).
    damping_scale: f64,
}

fn glam(v: Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn mass_props(com_z: f64, mass: f64, transverse: f64, axial: f64) -> MassProperties {
    MassProperties::new(
        Vector::new(0.0, 0.0, com_z),
        mass,
        AngVector::new(transverse, transverse, axial),
    )
}

impl Whisker {
    /// Builds a whisker whose frame F is at `pose` (world), colliding as `groups`, its
    /// root following the driver as `root_drive` says.
    pub fn build(
        world: &mut PhysicsWorld,
        pose: Isometry3<f64>,
        beam: BeamDesign,
        follicle: Option<FollicleDesign>,
        groups: InteractionGroups,
        root_drive: RootDrive,
    ) -> Self {
        let at = |offset: f64| -> Pose { (pose * Isometry3::translation(0.0, 0.0, offset)).into() };
        let driver =
            world.insert_body(RigidBodyBuilder::kinematic_position_based().pose(pose.into()));
        // The root: light and welded to the driver, or heavy, unweighted and driven.
        let (mass, inertia, gravity_scale) = match root_drive {
            RootDrive::Welded => (FOLLICLE_MASS, 1e-8, 1.0),
            RootDrive::Driven => (DRIVEN_ROOT_MASS, DRIVEN_ROOT_INERTIA, 0.0),
        };
        let root = world.insert_body(
            RigidBodyBuilder::dynamic()
                .pose(pose.into())
                .additional_mass_properties(mass_props(0.0, mass, inertia, inertia))
                .gravity_scale(gravity_scale)
                .can_sleep(false),
        );
        if root_drive == RootDrive::Welded {
            world.insert_impulse_joint(
                driver,
                root,
                FixedJointBuilder::new().contacts_enabled(false),
            );
        }

        let mut joints = Vec::new();
        let spherical = |anchor1: f64| -> GenericJoint {
            SphericalJointBuilder::new()
                .local_anchor1(Vector::new(0.0, 0.0, anchor1))
                .local_anchor2(Vector::ZERO)
                .contacts_enabled(false)
                .into()
        };
        let shaft_joint = |anchor1: f64| -> GenericJoint {
            match beam.bending {
                Bending::Spatial => spherical(anchor1),
                Bending::SweepPlane => RevoluteJointBuilder::new(Vector::X)
                    .local_anchor1(Vector::new(0.0, 0.0, anchor1))
                    .local_anchor2(Vector::ZERO)
                    .contacts_enabled(false)
                    .into(),
            }
        };
        // The body the shaft's base joint hangs on, and that joint's anchor in it.
        let (mut parent, mut anchor) = (root, 0.0);
        let bulb = follicle.map(|f| {
            let (transverse, axial) = f.bulb_inertia();
            let bulb = world.insert_body(
                RigidBodyBuilder::dynamic()
                    .pose(at(-f.pivot_depth))
                    .additional_mass_properties(mass_props(
                        f.bulb_com(),
                        f.bulb_mass,
                        transverse,
                        axial,
                    ))
                    .can_sleep(false),
            );
            joints.push(
                world
                    .insert_multibody_joint(root, bulb, spherical(-f.pivot_depth))
                    .expect("a tree"),
            );
            (parent, anchor) = (bulb, f.pivot_depth);
            bulb
        });

        let l = beam.segment_length();
        let mut segments = Vec::with_capacity(beam.segments);
        for j in 0..beam.segments {
            let (mass, com, transverse, axial) = beam.segment_mass(j);
            let radius = (beam.radius(j as f64 * l) + beam.radius((j + 1) as f64 * l)) / 2.0;
            let body = world.insert_body(
                RigidBodyBuilder::dynamic()
                    .pose(at(j as f64 * l))
                    .additional_mass_properties(mass_props(com, mass, transverse, axial))
                    .can_sleep(false),
            );
            world.insert_collider(
                ColliderBuilder::capsule_from_endpoints(
                    Vector::ZERO,
                    Vector::new(0.0, 0.0, l),
                    radius,
                )
                .density(0.0)
                .collision_groups(groups)
                .active_collision_types(ActiveCollisionTypes::default()),
                Some(body),
            );
            joints.push(
                world
                    .insert_multibody_joint(parent, body, shaft_joint(anchor))
                    .expect("a tree"),
            );
            segments.push(body);
            (parent, anchor) = (body, l);
        }

        let mut whisker = Self {
            beam,
            follicle,
            driver,
            root,
            bulb,
            segments,
            joints,
            root_drive,
            damping_scale: 1.0,
        };
        whisker.set_springs(world);
        whisker
    }

    /// Stiffness (bending, twist) of each multibody joint, in `joints` order.
    fn joint_stiffnesses(&self) -> Vec<(f64, f64)> {
        let follicle = self.follicle.map(|f| (f.stiffness, 100.0 * f.stiffness));
        follicle
            .into_iter()
            .chain(
                (0..self.beam.segments)
                    .map(|j| (self.beam.joint_stiffness(j), self.beam.twist_stiffness(j))),
            )
            .collect()
    }

    /// Writes springs and damping into the multibody joints: bending about X and Y (the
    /// two first angular DoFs) and twist about Z for spherical joints; bending about X
    /// alone for revolute ones.
    fn set_springs(&mut self, world: &mut PhysicsWorld) {
        let beta = self.beam.rayleigh_beta() * self.damping_scale;
        for (&handle, (bend, twist)) in self.joints.iter().zip(self.joint_stiffnesses()) {
            let (multibody, link_id) = world
                .multibody_joints
                .get_mut(handle)
                .expect("joint exists");
            let link = multibody.link_mut(link_id).expect("link exists");
            let dofs = link.joint.ndofs();
            let first = link.assembly_id();
            let per_dof: &[(usize, f64)] = if dofs == 3 {
                &[(3, bend), (4, bend), (5, twist)]
            } else {
                &[(3, bend)]
            };
            for &(axis, k) in per_dof {
                link.joint.set_spring(axis, k, 0.0);
            }
            for (i, &(_, k)) in per_dof.iter().enumerate() {
                multibody.damping_mut()[first + i] = beta * k;
            }
        }
    }

    /// Scales every joint's damping by `scale` relative to the design's (e.g. a large
    /// value to settle a static load quickly); 1 restores the design.
    pub fn set_damping_scale(&mut self, world: &mut PhysicsWorld, scale: f64) {
        self.damping_scale = scale;
        self.set_springs(world);
    }

    /// Pose of a body (world).
    pub fn pose(world: &PhysicsWorld, body: RigidBodyHandle) -> Isometry3<f64> {
        (*world.bodies[body].position()).into()
    }

    /// Pose of the shaft's base frame (where the shaft leaves the bulb; world).
    pub fn base_pose(&self, world: &PhysicsWorld) -> Isometry3<f64> {
        match (self.bulb, self.follicle) {
            (Some(b), Some(f)) => {
                Self::pose(world, b) * Isometry3::translation(0.0, 0.0, f.pivot_depth)
            }
            _ => Self::pose(world, self.root),
        }
    }

    /// World position of the material point at arc length `s` along the shaft.
    pub fn point_at(&self, world: &PhysicsWorld, s: f64) -> Point3<f64> {
        let l = self.beam.segment_length();
        let j = ((s / l).floor() as usize).min(self.beam.segments - 1);
        Self::pose(world, self.segments[j]) * Point3::new(0.0, 0.0, s - j as f64 * l)
    }

    /// The shaft's largest curvature (1/m): over every joint of the chain (base joint
    /// included) the bending angle between its two bodies over the segment length — the
    /// discretised beam's κ = dθ/ds (Eq 2.33).
    pub fn max_curvature(&self, world: &PhysicsWorld) -> f64 {
        let l = self.beam.segment_length();
        let mut previous = self.base_pose(world).rotation;
        let mut most: f64 = 0.0;
        for &s in &self.segments {
            let r = Self::pose(world, s).rotation;
            most = most.max((previous.inverse() * r).angle() / l);
            previous = r;
        }
        most
    }

    /// Bending moment the shaft's base joint carries (N·m, in the base frame, x and y
    /// components): its spring stiffness times the rotation of the first segment
    /// relative to the base frame.
    pub fn base_moment(&self, world: &PhysicsWorld) -> Vector3<f64> {
        let rel = self.base_pose(world).inverse() * Self::pose(world, self.segments[0]);
        let phi = rel.rotation.scaled_axis();
        let k = self.beam.joint_stiffness(0);
        Vector3::new(k * phi.x, k * phi.y, 0.0)
    }

    /// Rotation of the bulb relative to the follicle (rotation vector, rad, follicle
    /// frame); zero for a rigid follicle.
    pub fn follicle_rotation(&self, world: &PhysicsWorld) -> Vector3<f64> {
        match self.bulb {
            Some(b) => (Self::pose(world, self.root).inverse() * Self::pose(world, b))
                .rotation
                .scaled_axis(),
            None => Vector3::zeros(),
        }
    }

    /// Displacement of the magnet in the follicle frame (m, x and y): what the
    /// Hall-effect sensor reads. The magnet sits `magnet_lever` below the pivot, so it
    /// moves opposite to the shaft's base.
    pub fn magnet_displacement(&self, world: &PhysicsWorld) -> (f64, f64) {
        let h = self.follicle.map_or(0.0, |f| f.magnet_lever);
        let r = self.follicle_rotation(world);
        // Rotation about X by φ moves (0, 0, −h) to (0, h·φ, ·); about Y to (−h·φ, 0, ·).
        (-h * r.y, h * r.x)
    }

    /// Applies `force` (N, world) at the material point at arc length `s` for the next
    /// step, replacing any force applied before.
    ///
    /// The load is split between the centres of mass of the two segments around `s`
    /// by the lever rule (weights interpolating linearly in arc length), so that the
    /// resultant force and its moment about every joint inboard of the load are exact.
    /// Forces are applied at centres of mass only: in Rapier 0.36 user torques on
    /// multibody links are not integrated consistently (a 1 µN·m torque on a whisker
    /// segment drifts without bound), and `add_force_at_point` uses a centre of mass that
    /// multibody links do not keep up to date.
    pub fn apply_force(&self, world: &mut PhysicsWorld, s: f64, force: Vector3<f64>) {
        self.clear_forces(world);
        let l = self.beam.segment_length();
        let com = |j: usize| j as f64 * l + self.beam.segment_mass(j).1;
        let last = self.beam.segments - 1;
        let j = (0..last).find(|&j| s <= com(j + 1)).unwrap_or(last - 1);
        let w1 = (com(j + 1) - s) / (com(j + 1) - com(j));
        world.bodies[self.segments[j]].add_force(glam(force * w1), true);
        world.bodies[self.segments[j + 1]].add_force(glam(force * (1.0 - w1)), true);
    }

    /// Removes applied forces.
    pub fn clear_forces(&self, world: &mut PhysicsWorld) {
        for &seg in &self.segments {
            world.bodies[seg].reset_forces(true);
        }
    }

    /// Poses the driver (and so the follicle) at `pose` for the next step, of
    /// `world.integration_parameters.dt` (set it first).
    ///
    /// A [`RootDrive::Driven`] root gets the force and torque, held over the step's n
    /// substeps of h, that land it on `pose`: Rapier's substeps integrate v ← v + a·h,
    /// x ← x + v·h, so after n of them x = x₀ + n·h·v₀ + n(n+1)/2·h²·a, solved for a, per
    /// axis, with the rotation's error as a rotation vector (world frame, as the free
    /// root's angular DoFs). The position lands exactly but for the shaft's reaction; the
    /// velocity's error e becomes −e·(n−1)/(n+1) (−e/2 at n = 3), so it dies out within
    /// a few steps of any jerk in the path.
    pub fn drive(&self, world: &mut PhysicsWorld, pose: Isometry3<f64>) {
        crate::kinematic_body::set_next_kinematic_pose(&mut world.bodies[self.driver], pose);
        if self.root_drive == RootDrive::Driven {
            self.push_root(world, pose);
        }
    }

    /// The force and torque of [`Self::drive`] for a driven root.
    fn push_root(&self, world: &mut PhysicsWorld, target: Isometry3<f64>) {
        let params = &world.integration_parameters;
        let n = params.num_solver_iterations.max(1) as f64;
        let h = params.dt / n;
        let (multibody, _) = world
            .multibody_joints
            .get(self.joints[0])
            .expect("joint exists");
        let v = multibody.generalized_velocity();
        let (linvel, angvel) = (
            Vector3::new(v[0], v[1], v[2]),
            Vector3::new(v[3], v[4], v[5]),
        );
        let now = Self::pose(world, self.root);
        let mut turn = target.rotation * now.rotation.inverse();
        if turn.w < 0.0 {
            turn = nalgebra::UnitQuaternion::new_unchecked(-turn.into_inner());
        }
        let gain = 1.0 / (n * (n + 1.0) / 2.0 * h * h);
        let a_lin = (target.translation.vector - now.translation.vector - n * h * linvel) * gain;
        let a_ang = (turn.scaled_axis() - n * h * angvel) * gain;
        let root = &mut world.bodies[self.root];
        root.reset_forces(true);
        root.reset_torques(true);
        root.add_force(glam(a_lin * DRIVEN_ROOT_MASS), true);
        root.add_torque(glam(a_ang * DRIVEN_ROOT_INERTIA), true);
    }
}
