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

/// A 3 mm pole, `2·half_length` long, across `module`'s sweep plane at radial distance `r`
/// from the pivot along the shaft at whisk angle `theta`.
#[allow(dead_code)] // not every test binary uses every helper
pub fn pole(
    module: &whisker_sim::whisker::array::Module,
    r: f64,
    theta: f64,
    half_length: f64,
) -> whisker_sim::sensing::physics::EnvironmentPiece {
    use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
    let centre = module.whisker_pose(theta) * Point3::new(0.0, 0.0, r);
    let axis = module.pose.rotation * Vector3::x();
    let rotation = UnitQuaternion::rotation_between(&Vector3::y(), &axis).unwrap();
    (
        rapier3d_f64::prelude::SharedShape::cylinder(half_length, 0.003),
        Isometry3::from_parts(Translation3::from(centre.coords), rotation),
    )
}
