//! Forward kinematics and geometric Jacobians of the serial chain between two links
//! (thesis §5.1.1.1.2: T_BE from the arm's joint positions).
//!
//! The chain from `base` to `tip` follows the tree up from `base` to the closest common
//! ancestor and down to `tip`; joints walked upwards contribute their inverse transform.
//! Its coordinates are the single-DoF joints on that path, in order from `base` to `tip`.
//! Fixed joints are folded into constant transforms when the chain is built.

use super::urdf::{JointKind, RobotModel};
use nalgebra::{Isometry3, Matrix6xX, Unit, Vector3};

/// Why a chain cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ChainError {
    /// A link name that the model does not have.
    #[error("no link named \"{name}\" in {robot} (links: {known})")]
    UnknownLink {
        name: String,
        robot: String,
        known: String,
    },
    /// A joint kind with several DoF on the path.
    #[error(
        "joint \"{joint}\" on the chain is {kind}: only fixed, revolute, continuous and prismatic joints can be chained"
    )]
    UnsupportedJoint { joint: String, kind: &'static str },
}

#[derive(Debug, Clone, Copy)]
enum Motion {
    Rotation,
    Translation,
}

/// One movable joint of the chain: `pose = pose · before · motion(sign·q)`.
#[derive(Debug, Clone)]
struct Step {
    before: Isometry3<f64>,
    motion: Motion,
    axis: Unit<Vector3<f64>>,
    sign: f64,
}

/// The serial chain between two links of a [`RobotModel`].
#[derive(Debug, Clone)]
pub struct Chain {
    /// Name of the base link (the frame poses are expressed in).
    pub base: String,
    /// Name of the tip link (the frame whose pose is computed).
    pub tip: String,
    /// Names of the chain's coordinates (movable joints), base to tip.
    pub joint_names: Vec<String>,
    /// Indices of those joints in [`RobotModel::joints`].
    pub joint_indices: Vec<usize>,
    /// Lower position limits of the coordinates.
    pub lower: Vec<f64>,
    /// Upper position limits of the coordinates.
    pub upper: Vec<f64>,
    /// Velocity limits of the coordinates (+∞ where the URDF gives none).
    pub velocity: Vec<f64>,
    /// Whether each coordinate is an angle (revolute or continuous).
    pub angular: Vec<bool>,
    steps: Vec<Step>,
    after: Isometry3<f64>,
}

impl Chain {
    /// The chain of `model` from link `base` to link `tip`.
    pub fn new(model: &RobotModel, base: &str, tip: &str) -> Result<Self, ChainError> {
        let find = |name: &str| {
            model.link(name).ok_or_else(|| ChainError::UnknownLink {
                name: name.to_string(),
                robot: model.source.display().to_string(),
                known: model
                    .links
                    .iter()
                    .map(|l| l.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
        };
        let (b, t) = (find(base)?, find(tip)?);
        let up = model.path_from_root(b);
        let down = model.path_from_root(t);
        let common = up.iter().zip(&down).take_while(|(x, y)| x == y).count();
        // Joints walked upwards from base (reversed), then downwards to tip.
        let walk = up[common..]
            .iter()
            .rev()
            .map(|&j| (j, true))
            .chain(down[common..].iter().map(|&j| (j, false)));

        let mut chain = Self {
            base: base.to_string(),
            tip: tip.to_string(),
            joint_names: Vec::new(),
            joint_indices: Vec::new(),
            lower: Vec::new(),
            upper: Vec::new(),
            velocity: Vec::new(),
            angular: Vec::new(),
            steps: Vec::new(),
            after: Isometry3::identity(),
        };
        let mut pending = Isometry3::identity();
        for (j, reversed) in walk {
            let joint = &model.joints[j];
            let motion = match joint.kind {
                JointKind::Fixed => {
                    pending *= if reversed {
                        joint.origin.inverse()
                    } else {
                        joint.origin
                    };
                    continue;
                }
                JointKind::Revolute | JointKind::Continuous => Motion::Rotation,
                JointKind::Prismatic => Motion::Translation,
                kind => {
                    return Err(ChainError::UnsupportedJoint {
                        joint: joint.name.clone(),
                        kind: kind.name(),
                    });
                }
            };
            // Forward: pose·origin·motion(q). Reversed: pose·motion(−q)·origin⁻¹.
            let (before, sign) = if reversed {
                (pending, -1.0)
            } else {
                (pending * joint.origin, 1.0)
            };
            chain.steps.push(Step {
                before,
                motion,
                axis: joint.axis,
                sign,
            });
            pending = if reversed {
                joint.origin.inverse()
            } else {
                Isometry3::identity()
            };
            chain.joint_names.push(joint.name.clone());
            chain.joint_indices.push(j);
            chain.lower.push(joint.limits.lower);
            chain.upper.push(joint.limits.upper);
            chain.velocity.push(joint.limits.velocity);
            chain.angular.push(matches!(motion, Motion::Rotation));
        }
        chain.after = pending;
        Ok(chain)
    }

    /// Number of coordinates.
    pub fn dof(&self) -> usize {
        self.steps.len()
    }

    /// Pose of the tip link in the base link frame.
    pub fn fk(&self, q: &[f64]) -> Isometry3<f64> {
        self.walk(q, |_, _, _| {})
    }

    /// The origins of the joints' frames in the base frame, from the base outward (the
    /// points a view must hold to show the whole arm).
    pub fn joint_origins(&self, q: &[f64]) -> Vec<[f64; 3]> {
        let mut out = Vec::with_capacity(self.dof());
        self.walk(q, |_, pose, _| out.push(pose.translation.vector.into()));
        out
    }

    /// Pose of the tip and the geometric Jacobian in the base frame: rows 0–2 map joint
    /// velocities to the tip's linear velocity, rows 3–5 to its angular velocity.
    pub fn fk_jacobian(&self, q: &[f64]) -> (Isometry3<f64>, Matrix6xX<f64>) {
        let mut axes = Vec::with_capacity(self.dof());
        let tip = self.walk(q, |i, pose, step| {
            let axis = pose.rotation * step.axis.into_inner() * step.sign;
            axes.push((i, axis, pose.translation.vector, step.motion));
        });
        let mut jac = Matrix6xX::zeros(self.dof());
        for (i, axis, at, motion) in axes {
            match motion {
                Motion::Rotation => {
                    let lin = axis.cross(&(tip.translation.vector - at));
                    jac.fixed_view_mut::<3, 1>(0, i).copy_from(&lin);
                    jac.fixed_view_mut::<3, 1>(3, i).copy_from(&axis);
                }
                Motion::Translation => jac.fixed_view_mut::<3, 1>(0, i).copy_from(&axis),
            }
        }
        (tip, jac)
    }

    /// Applies the chain, calling `visit(index, pose_after_motion, step)` at each joint:
    /// the joint axis passes through that pose's origin along `pose.rotation · axis`.
    fn walk(
        &self,
        q: &[f64],
        mut visit: impl FnMut(usize, &Isometry3<f64>, &Step),
    ) -> Isometry3<f64> {
        assert_eq!(q.len(), self.dof(), "one position per chain coordinate");
        let mut pose = Isometry3::identity();
        for (i, step) in self.steps.iter().enumerate() {
            let v = step.axis.into_inner() * (step.sign * q[i]);
            let motion = match step.motion {
                Motion::Rotation => Isometry3::rotation(v),
                Motion::Translation => Isometry3::translation(v.x, v.y, v.z),
            };
            pose = pose * step.before * motion;
            visit(i, &pose, step);
        }
        pose * self.after
    }

    /// Whether `q` lies within the position limits (with tolerance `tol`).
    pub fn within_limits(&self, q: &[f64], tol: f64) -> bool {
        q.iter()
            .zip(self.lower.iter().zip(&self.upper))
            .all(|(v, (lo, hi))| *v >= lo - tol && *v <= hi + tol)
    }

    /// `q` clamped into the position limits.
    pub fn clamp(&self, q: &mut [f64]) {
        for (v, (lo, hi)) in q.iter_mut().zip(self.lower.iter().zip(&self.upper)) {
            *v = v.clamp(*lo, *hi);
        }
    }
}
