//! Loading and validating URDF robot descriptions into a [`RobotModel`].
//!
//! Parsing is done by `urdf-rs`; this module adds what a simulator needs on top of it and
//! what ROS tools would otherwise check: a single rooted tree of links (no missing parent
//! or child, no cycle, no second root), finite numbers everywhere, usable joint axes and
//! limits, and mesh file names resolved without ROS ([`PackagePaths`]). Elements that do
//! not matter here (`<gazebo>`, `<transmission>`, `<material>`, inertials of massless
//! links, a `world` link above the robot) are accepted and ignored.
//!
//! Every error names the file and the element it is about ([`UrdfError`]).

use super::package_path::PackagePaths;
use nalgebra::{Isometry3, Unit, Vector3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use whisker_slam::invalid::Invalid;
use whisker_slam::pose;

/// A problem with a URDF file: which file, which element, what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {element}: {message}", file.display())]
pub struct UrdfError {
    /// The URDF file (or a stand-in name for a string).
    pub file: PathBuf,
    /// The element concerned, e.g. `<joint name="elbow_joint">`, or `<robot>`.
    pub element: String,
    /// What is wrong and what was expected.
    pub message: String,
}

/// Kind of a joint, as in URDF.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rigid connection.
    Fixed,
    /// Rotation about the axis within limits.
    Revolute,
    /// Rotation about the axis without limits.
    Continuous,
    /// Translation along the axis within limits.
    Prismatic,
    /// Six free DoF (not supported in kinematic chains).
    Floating,
    /// Planar motion (not supported in kinematic chains).
    Planar,
    /// Three rotational DoF (not supported in kinematic chains).
    Spherical,
}

impl JointKind {
    /// Whether the joint has exactly one degree of freedom (a chain coordinate).
    pub fn is_single_dof(self) -> bool {
        matches!(self, Self::Revolute | Self::Continuous | Self::Prismatic)
    }

    /// The URDF name of the kind.
    pub fn name(self) -> &'static str {
        match self {
            Self::Fixed => "fixed",
            Self::Revolute => "revolute",
            Self::Continuous => "continuous",
            Self::Prismatic => "prismatic",
            Self::Floating => "floating",
            Self::Planar => "planar",
            Self::Spherical => "spherical",
        }
    }
}

/// Position (or displacement) and velocity limits of a joint (rad, m, rad/s, m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLimits {
    /// Lower position limit (−∞ for continuous joints).
    pub lower: f64,
    /// Upper position limit (+∞ for continuous joints).
    pub upper: f64,
    /// Maximum speed; +∞ when the URDF gives none (0 in URDF means "unspecified").
    pub velocity: f64,
}

/// One joint of the model.
#[derive(Debug, Clone)]
pub struct Joint {
    /// Joint name.
    pub name: String,
    /// Joint kind.
    pub kind: JointKind,
    /// Index of the parent link in [`RobotModel::links`].
    pub parent: usize,
    /// Index of the child link in [`RobotModel::links`].
    pub child: usize,
    /// Pose of the joint frame in the parent link frame (`<origin>`).
    pub origin: Isometry3<f64>,
    /// Joint axis in the joint frame (unit; x for fixed joints without an axis).
    pub axis: Unit<Vector3<f64>>,
    /// Limits.
    pub limits: JointLimits,
}

/// Collision geometry of a link, in the link frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    /// Box with full side lengths (m).
    Box { size: Vector3<f64> },
    /// Cylinder along the local z axis.
    Cylinder { radius: f64, length: f64 },
    /// Capsule along the local z axis (`length` between the cap centres).
    Capsule { radius: f64, length: f64 },
    /// Sphere.
    Sphere { radius: f64 },
    /// Triangle mesh file; `resolved` is the file found on disk, if any.
    Mesh {
        filename: String,
        resolved: Option<PathBuf>,
        scale: Vector3<f64>,
    },
}

/// A collision element of a link.
#[derive(Debug, Clone)]
pub struct CollisionShape {
    /// Pose of the geometry in the link frame.
    pub origin: Isometry3<f64>,
    /// The geometry.
    pub geometry: Geometry,
}

/// One link of the model.
#[derive(Debug, Clone)]
pub struct Link {
    /// Link name.
    pub name: String,
    /// Collision elements.
    pub collisions: Vec<CollisionShape>,
}

/// A validated robot: a tree of links joined by joints, rooted at [`RobotModel::root`].
#[derive(Debug, Clone)]
pub struct RobotModel {
    /// Robot name.
    pub name: String,
    /// The file it was read from.
    pub source: PathBuf,
    /// Links, in file order.
    pub links: Vec<Link>,
    /// Joints, in file order.
    pub joints: Vec<Joint>,
    /// Index of the root link.
    pub root: usize,
    /// For each link, the index of the joint whose child it is (None for the root).
    pub parent_joint: Vec<Option<usize>>,
    link_index: HashMap<String, usize>,
}

impl RobotModel {
    /// Read and validate a URDF file, resolving mesh references with `packages`.
    pub fn load(path: &Path, packages: &PackagePaths) -> Result<Self, UrdfError> {
        let text = std::fs::read_to_string(path).map_err(|e| UrdfError {
            file: path.to_path_buf(),
            element: "file".into(),
            message: format!("cannot read: {e}"),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        Self::parse(&text, path, dir, packages)
    }

    /// Parse and validate URDF text. `source` names it in errors; relative mesh paths are
    /// resolved against `dir`.
    pub fn parse(
        text: &str,
        source: &Path,
        dir: &Path,
        packages: &PackagePaths,
    ) -> Result<Self, UrdfError> {
        let err = |element: &str, message: String| UrdfError {
            file: source.to_path_buf(),
            element: element.to_string(),
            message,
        };
        if let Some((line, depth)) = super::urdf_nesting::too_deep(text) {
            return Err(err(
                "<robot>",
                format!(
                    "line {line}: elements nested {depth} deep: expected at most {}",
                    super::urdf_nesting::MAX_DEPTH
                ),
            ));
        }
        let robot =
            urdf_rs::read_from_string(text).map_err(
                |e| match super::urdf_numbers::find_bad_number(text) {
                    Some((element, message)) => err(&element, message),
                    None => err("<robot>", format!("not a valid URDF document: {e}")),
                },
            )?;
        if robot.links.is_empty() {
            return Err(err("<robot>", "no <link> elements".into()));
        }

        let mut link_index = HashMap::new();
        let mut links = Vec::with_capacity(robot.links.len());
        for l in &robot.links {
            let element = format!("<link name=\"{}\">", l.name);
            if link_index.insert(l.name.clone(), links.len()).is_some() {
                return Err(err(&element, "a second link of the same name".into()));
            }
            let collisions = l
                .collision
                .iter()
                .map(|c| {
                    let origin = origin_pose(&c.origin)
                        .ok_or_else(|| err(&element, "non-finite <collision><origin>".into()))?;
                    let geometry = geometry(&c.geometry, dir, packages)
                        .map_err(|m| err(&element, format!("<collision><geometry>: {m}")))?;
                    Ok(CollisionShape { origin, geometry })
                })
                .collect::<Result<Vec<_>, UrdfError>>()?;
            links.push(Link {
                name: l.name.clone(),
                collisions,
            });
        }

        let mut joints = Vec::with_capacity(robot.joints.len());
        let mut parent_joint: Vec<Option<usize>> = vec![None; links.len()];
        let mut joint_names = HashMap::new();
        for j in &robot.joints {
            let element = format!("<joint name=\"{}\">", j.name);
            if joint_names.insert(j.name.clone(), ()).is_some() {
                return Err(err(&element, "a second joint of the same name".into()));
            }
            let find = |role: &str, name: &str| {
                link_index.get(name).copied().ok_or_else(|| {
                    err(
                        &element,
                        format!("<{role} link=\"{name}\">: no link of that name is defined"),
                    )
                })
            };
            let parent = find("parent", &j.parent.link)?;
            let child = find("child", &j.child.link)?;
            if parent == child {
                return Err(err(&element, "parent and child are the same link".into()));
            }
            if let Some(other) = parent_joint[child] {
                return Err(err(
                    &element,
                    format!(
                        "link \"{}\" is already the child of joint \"{}\": a link has one parent",
                        j.child.link, robot.joints[other].name
                    ),
                ));
            }
            parent_joint[child] = Some(joints.len());
            joints.push(joint(j, parent, child).map_err(|m| err(&element, m.to_string()))?);
        }

        let roots: Vec<usize> = (0..links.len())
            .filter(|&i| parent_joint[i].is_none())
            .collect();
        // Every link reaches a root by walking up, unless it sits on a cycle.
        // Each walk stops at a link an earlier walk finished from (linear in all).
        let mut done = vec![false; links.len()];
        let mut seen = vec![usize::MAX; links.len()];
        for start in 0..links.len() {
            let mut at = start;
            while let Some(j) = parent_joint[at] {
                if done[at] {
                    break;
                }
                if seen[at] == start {
                    return Err(err(
                        &format!("<joint name=\"{}\">", joints[j].name),
                        format!(
                            "the joints form a cycle through link \"{}\"",
                            links[at].name
                        ),
                    ));
                }
                seen[at] = start;
                at = joints[j].parent;
            }
            let mut at = start;
            while !done[at] {
                done[at] = true;
                match parent_joint[at] {
                    Some(j) => at = joints[j].parent,
                    None => break,
                }
            }
        }
        let root = match roots.as_slice() {
            [r] => *r,
            [] => {
                return Err(err(
                    "<robot>",
                    "no root link (every link has a parent)".into(),
                ));
            }
            many => {
                let names: Vec<_> = many.iter().map(|&i| links[i].name.as_str()).collect();
                return Err(err(
                    "<robot>",
                    format!(
                        "{} root links ({}): expected one tree; join them with a fixed joint",
                        many.len(),
                        names.join(", ")
                    ),
                ));
            }
        };

        Ok(Self {
            name: robot.name,
            source: source.to_path_buf(),
            links,
            joints,
            root,
            parent_joint,
            link_index,
        })
    }

    /// Index of the link called `name`.
    pub fn link(&self, name: &str) -> Option<usize> {
        self.link_index.get(name).copied()
    }

    /// Index of the joint called `name`.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Indices of the joints from the root down to `link`, root first.
    pub fn path_from_root(&self, link: usize) -> Vec<usize> {
        let mut path = Vec::new();
        let mut at = link;
        while let Some(j) = self.parent_joint[at] {
            path.push(j);
            at = self.joints[j].parent;
        }
        path.reverse();
        path
    }

    /// Poses of every link in the root frame for joint positions `q` indexed like
    /// [`RobotModel::joints`] (entries of fixed joints are ignored).
    pub fn link_poses(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        assert_eq!(q.len(), self.joints.len(), "one position per joint");
        let mut poses: Vec<Option<Isometry3<f64>>> = vec![None; self.links.len()];
        poses[self.root] = Some(Isometry3::identity());
        // Resolve each link by walking up to the nearest posed ancestor.
        for link in 0..self.links.len() {
            let mut stack = Vec::new();
            let mut at = link;
            while poses[at].is_none() {
                let j = self.parent_joint[at].expect("validated tree");
                stack.push(j);
                at = self.joints[j].parent;
            }
            let mut pose = poses[at].expect("posed ancestor");
            while let Some(j) = stack.pop() {
                let joint = &self.joints[j];
                pose *= joint.transform(q[j]);
                poses[joint.child] = Some(pose);
            }
        }
        poses.into_iter().map(|p| p.expect("all posed")).collect()
    }
}

impl Joint {
    /// Pose of the child link in the parent link frame at joint position `q`.
    pub fn transform(&self, q: f64) -> Isometry3<f64> {
        self.origin * self.motion(q)
    }

    /// The joint's own motion at position `q` (identity for fixed joints).
    pub fn motion(&self, q: f64) -> Isometry3<f64> {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => {
                Isometry3::rotation(self.axis.into_inner() * q)
            }
            JointKind::Prismatic => {
                Isometry3::translation(self.axis.x * q, self.axis.y * q, self.axis.z * q)
            }
            _ => Isometry3::identity(),
        }
    }
}

fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

fn origin_pose(p: &urdf_rs::Pose) -> Option<Isometry3<f64>> {
    (finite(&p.xyz.0) && finite(&p.rpy.0)).then(|| pose::from_xyz_rpy(p.xyz.0, p.rpy.0))
}

fn positive(name: &str, v: f64) -> Result<f64, Invalid> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{name} must be a positive finite number, got {v}").into())
    }
}

fn geometry(
    g: &urdf_rs::Geometry,
    dir: &Path,
    packages: &PackagePaths,
) -> Result<Geometry, Invalid> {
    Ok(match g {
        urdf_rs::Geometry::Box { size } => {
            for (axis, &s) in ["x", "y", "z"].iter().zip(size.0.iter()) {
                positive(&format!("<box size> {axis}"), s)?;
            }
            Geometry::Box {
                size: Vector3::from(size.0),
            }
        }
        urdf_rs::Geometry::Cylinder { radius, length } => Geometry::Cylinder {
            radius: positive("<cylinder radius>", *radius)?,
            length: positive("<cylinder length>", *length)?,
        },
        urdf_rs::Geometry::Capsule { radius, length } => Geometry::Capsule {
            radius: positive("<capsule radius>", *radius)?,
            length: positive("<capsule length>", *length)?,
        },
        urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere {
            radius: positive("<sphere radius>", *radius)?,
        },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map(|s| s.0).unwrap_or([1.0; 3]);
            for &s in &scale {
                positive("<mesh scale>", s)?;
            }
            Geometry::Mesh {
                filename: filename.clone(),
                resolved: packages.resolve(filename, dir),
                scale: Vector3::from(scale),
            }
        }
    })
}

fn joint(j: &urdf_rs::Joint, parent: usize, child: usize) -> Result<Joint, Invalid> {
    use urdf_rs::JointType as T;
    let kind = match j.joint_type {
        T::Fixed => JointKind::Fixed,
        T::Revolute => JointKind::Revolute,
        T::Continuous => JointKind::Continuous,
        T::Prismatic => JointKind::Prismatic,
        T::Floating => JointKind::Floating,
        T::Planar => JointKind::Planar,
        T::Spherical => JointKind::Spherical,
    };
    let origin = origin_pose(&j.origin).ok_or("<origin> has a non-finite xyz or rpy value")?;
    let axis = Vector3::from(j.axis.xyz.0);
    if !finite(axis.as_slice()) {
        return Err(format!("<axis xyz> has a non-finite value: {axis:?}").into());
    }
    let axis = match Unit::try_new(axis, 1e-9) {
        Some(a) => a,
        None if kind == JointKind::Fixed => Vector3::x_axis(),
        None => return Err("<axis xyz> is the zero vector: expected a direction".into()),
    };
    let l = &j.limit;
    let velocity = if l.velocity > 0.0 {
        l.velocity
    } else {
        f64::INFINITY
    };
    if l.velocity.is_nan() || l.velocity < 0.0 {
        return Err(format!(
            "<limit velocity> must be a non-negative number, got {}",
            l.velocity
        )
        .into());
    }
    let limits = match kind {
        JointKind::Revolute | JointKind::Prismatic => {
            if l.lower.is_nan() || l.upper.is_nan() {
                return Err("<limit> lower/upper must be numbers, got NaN".into());
            }
            if l.lower > l.upper {
                return Err(
                    format!("<limit> lower ({}) is above upper ({})", l.lower, l.upper).into(),
                );
            }
            JointLimits {
                lower: l.lower,
                upper: l.upper,
                velocity,
            }
        }
        _ => JointLimits {
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            velocity,
        },
    };
    Ok(Joint {
        name: j.name.clone(),
        kind,
        parent,
        child,
        origin,
        axis,
        limits,
    })
}
