//! Shared helpers of the sim crate's integration tests.

use std::path::PathBuf;
use whisker_sim::kinematics::{PackagePaths, RobotModel};

/// A path inside the repository.
#[allow(dead_code)] // not every test binary uses every helper
pub fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// The project's arm description.
#[allow(dead_code)] // not every test binary uses every helper
pub fn ur5_array() -> RobotModel {
    RobotModel::load(
        &repo("assets/urdf/ur5_whisker_array.urdf"),
        &PackagePaths::default(),
    )
    .expect("asset URDF loads")
}

/// A UR5 description in the layout of the ROS packages (meshes, transmissions, gazebo, world).
#[allow(dead_code)] // not every test binary uses every helper
pub fn ur5_ros_style() -> RobotModel {
    RobotModel::load(
        &repo("tests/fixtures/ur5_ros_style.urdf"),
        &PackagePaths::default(),
    )
    .expect("ROS-style fixture loads")
}
