//! Robot kinematics from URDF (thesis §2.2.1, §5.1.1.1.2: the transform chain
//! base → end effector → whisker).
//!
//! - [`urdf`]: loading and validating a URDF into a [`RobotModel`] (no ROS needed),
//! - [`package_path`]: resolving `package://` and relative mesh file names,
//! - [`chain`]: forward kinematics and Jacobians of the serial chain between two links,
//! - [`ik`]: inverse kinematics (damped least squares with joint limits),
//! - [`trajectory`]: joint-space trajectories under a joint-speed limit.

pub mod chain;
pub mod ik;
pub mod package_path;
pub mod trajectory;
pub mod urdf;
pub mod urdf_nesting;
mod urdf_numbers;

pub use chain::Chain;
pub use ik::{IkError, IkOptions};
pub use package_path::PackagePaths;
pub use trajectory::JointTrajectory;
pub use urdf::{Geometry, JointKind, RobotModel, UrdfError};
