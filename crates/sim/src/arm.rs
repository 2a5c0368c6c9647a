//! The arm's links as kinematic, position-based Rapier bodies (thesis §2.2.1).
//!
//! Every link that has collision geometry becomes one kinematic body whose next pose is
//! set from forward kinematics before each physics step, so the solver sees the link
//! velocities implied by consecutive poses. Its colliders are the link's URDF collision
//! primitives. Arm colliders belong to the [`groups::ARM`] interaction group and interact
//! only with the environment ([`groups::ENVIRONMENT`]): adjacent links overlap at their
//! joints and are never tested against each other. Because arm bodies are kinematic and
//! environment bodies fixed, the kinematic–fixed collision type is switched on so that
//! arm–object contacts are detected.
//!
//! Collision meshes (OBJ, STL or PLY files, scaled as the URDF says) become the convex
//! hull of their vertices: arm links are nearly convex, a hull needs no closed mesh, and
//! hull–environment contacts are robust. Mesh files that are missing or in another format
//! (e.g. Collada) give no collider; [`Arm::skipped`] lists those links so callers can warn.

use crate::kinematics::urdf::{Geometry, RobotModel};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use rapier3d_f64::prelude::*;

/// Interaction groups of the simulated world.
pub mod groups {
    use rapier3d_f64::prelude::Group;
    /// The arm's links.
    pub const ARM: Group = Group::GROUP_1;
    /// Fixed environment: objects, maze walls, floor.
    pub const ENVIRONMENT: Group = Group::GROUP_2;
}

/// The arm's bodies in a Rapier world.
#[derive(Debug, Clone)]
pub struct Arm {
    /// (link index in the model, body handle) for every link with a collider.
    pub bodies: Vec<(usize, RigidBodyHandle)>,
    /// Link names whose mesh collision geometry was not turned into a collider.
    pub skipped: Vec<String>,
    /// Pose of the model's root link in the world frame.
    pub root_pose: Isometry3<f64>,
}

/// The convex hull of a collision mesh file's vertices, scaled per axis (None if the file
/// is missing, unreadable or not OBJ, STL or PLY).
fn mesh_hull(resolved: Option<&std::path::Path>, scale: &Vector3<f64>) -> Option<SharedShape> {
    let soup = crate::environment::mesh_io::read(resolved?).ok()?;
    let points: Vec<Vector> = soup
        .positions
        .iter()
        .map(|p| Vector::new(p[0] * scale.x, p[1] * scale.y, p[2] * scale.z))
        .collect();
    SharedShape::convex_hull(&points)
}

/// Rapier's shape and its pose in the link frame for a URDF collision element (None for
/// a mesh file that cannot be read).
fn collider_for(geometry: &Geometry, origin: &Isometry3<f64>) -> Option<ColliderBuilder> {
    // URDF cylinders and capsules run along z; Rapier's along y.
    let z_to_y = Isometry3::from_parts(
        Default::default(),
        UnitQuaternion::rotation_between(&Vector3::y(), &Vector3::z()).expect("not opposite"),
    );
    let (builder, local) = match geometry {
        Geometry::Box { size } => (
            ColliderBuilder::cuboid(size.x / 2.0, size.y / 2.0, size.z / 2.0),
            *origin,
        ),
        Geometry::Sphere { radius } => (ColliderBuilder::ball(*radius), *origin),
        Geometry::Cylinder { radius, length } => (
            ColliderBuilder::cylinder(length / 2.0, *radius),
            origin * z_to_y,
        ),
        Geometry::Capsule { radius, length } => (
            ColliderBuilder::capsule_y(length / 2.0, *radius),
            origin * z_to_y,
        ),
        Geometry::Mesh {
            resolved, scale, ..
        } => (
            ColliderBuilder::new(mesh_hull(resolved.as_deref(), scale)?),
            *origin,
        ),
    };
    Some(builder.position(local.into()))
}

/// Names of the links of `model` with collision geometry that cannot be turned into
/// colliders (mesh files missing or in an unsupported format): such geometry is left out
/// of [`Arm::build`].
pub fn links_without_colliders(model: &RobotModel) -> Vec<String> {
    model
        .links
        .iter()
        .filter(|l| {
            l.collisions
                .iter()
                .any(|c| collider_for(&c.geometry, &c.origin).is_none())
        })
        .map(|l| l.name.clone())
        .collect()
}

impl Arm {
    /// Adds the arm of `model` to `world`, its root at `root_pose`, posed at model joint
    /// positions `q` (one per model joint).
    pub fn build(
        model: &RobotModel,
        world: &mut PhysicsWorld,
        root_pose: Isometry3<f64>,
        q: &[f64],
    ) -> Self {
        let poses = model.link_poses(q);
        let mut arm = Self {
            bodies: Vec::new(),
            skipped: Vec::new(),
            root_pose,
        };
        for (i, link) in model.links.iter().enumerate() {
            // Each mesh file is read once here (`links_without_colliders` would read it again).
            let built: Vec<_> = link
                .collisions
                .iter()
                .map(|c| collider_for(&c.geometry, &c.origin))
                .collect();
            if built.iter().any(Option::is_none) {
                arm.skipped.push(link.name.clone());
            }
            let shapes: Vec<_> = built.into_iter().flatten().collect();
            if shapes.is_empty() {
                continue;
            }
            let body = world.insert_body(
                RigidBodyBuilder::kinematic_position_based().pose((root_pose * poses[i]).into()),
            );
            for shape in shapes {
                let collider = shape
                    .collision_groups(InteractionGroups::new(
                        groups::ARM,
                        groups::ENVIRONMENT,
                        InteractionTestMode::And,
                    ))
                    .active_collision_types(
                        ActiveCollisionTypes::default() | ActiveCollisionTypes::KINEMATIC_FIXED,
                    );
                world.insert_collider(collider, Some(body));
            }
            arm.bodies.push((i, body));
        }
        arm
    }

    /// Sets the pose each link body moves to during the next step, for model joint
    /// positions `q`.
    pub fn drive(&self, model: &RobotModel, world: &mut PhysicsWorld, q: &[f64]) {
        let poses = model.link_poses(q);
        for &(link, handle) in &self.bodies {
            crate::kinematic_body::set_next_kinematic_pose(
                &mut world.bodies[handle],
                self.root_pose * poses[link],
            );
        }
    }

    /// The current world pose of link `link`'s body, if it has one.
    pub fn link_pose(&self, world: &PhysicsWorld, link: usize) -> Option<Isometry3<f64>> {
        let (_, handle) = self.bodies.iter().find(|(l, _)| *l == link)?;
        Some((*world.bodies[*handle].position()).into())
    }
}

/// The arm's collision shapes in their link frames, for clearance checks without a
/// physics world (the closed loop checks each goal configuration and the path to it).
#[derive(Clone)]
pub struct LinkShapes {
    /// (link index, shape, pose in the link frame).
    pub shapes: Vec<(usize, SharedShape, Isometry3<f64>)>,
}

impl LinkShapes {
    /// Every collision shape of `model` that can be built (as [`Arm::build`] does).
    pub fn new(model: &RobotModel) -> Self {
        let mut shapes = Vec::new();
        for (i, link) in model.links.iter().enumerate() {
            for c in &link.collisions {
                if let Some(b) = collider_for(&c.geometry, &c.origin) {
                    shapes.push((i, b.shape.clone(), b.position.into()));
                }
            }
        }
        Self { shapes }
    }

    /// Names of the links that overlap `solids` with the arm at model joint positions
    /// `q` (its root at the world origin), each once, in link order.
    pub fn colliding(
        &self,
        model: &RobotModel,
        q: &[f64],
        solids: &crate::environment::solids::Solids,
    ) -> Vec<String> {
        self.colliding_at(model, q, &Isometry3::identity(), solids)
    }

    /// [`colliding`](Self::colliding) with the arm's root at `root` in the world (an
    /// arm on a mobile base).
    pub fn colliding_at(
        &self,
        model: &RobotModel,
        q: &[f64],
        root: &Isometry3<f64>,
        solids: &crate::environment::solids::Solids,
    ) -> Vec<String> {
        let poses = model.link_poses(q);
        let mut out: Vec<String> = Vec::new();
        for (link, shape, local) in &self.shapes {
            let name = &model.links[*link].name;
            let pose = root * poses[*link] * local;
            if !out.contains(name) && solids.overlaps(shape.as_ref(), &pose) {
                out.push(name.clone());
            }
        }
        out
    }
}
