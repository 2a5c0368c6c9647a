//! The message definitions of the bag, in ROS 2's `.msg` text (MCAP schema encoding
//! `ros2msg`): the standard messages it uses, written out with their dependencies as
//! `ros2 bag record` stores them, and the whisker-slam messages (docs/dataset.md, "ROS 2
//! bags"): one sample of the array's Hall sensors, and one message type per CSV table whose
//! fields are the table's columns.

use super::table::{Column, Kind};

/// The separator between a definition and each of its dependencies.
const SEPARATOR: &str =
    "================================================================================";

const TIME: (&str, &str) = ("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n");
const HEADER: (&str, &str) = (
    "std_msgs/Header",
    "builtin_interfaces/Time stamp\nstring frame_id\n",
);
const POINT: (&str, &str) = ("geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n");
const VECTOR3: (&str, &str) = ("geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n");
const QUATERNION: (&str, &str) = (
    "geometry_msgs/Quaternion",
    "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
);
const POSE: (&str, &str) = (
    "geometry_msgs/Pose",
    "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
);
const TRANSFORM: (&str, &str) = (
    "geometry_msgs/Transform",
    "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
);
const TRANSFORM_STAMPED: (&str, &str) = (
    "geometry_msgs/TransformStamped",
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n",
);

/// A message type: its name as MCAP records it (`pkg/msg/Type`) and its schema text.
#[derive(Debug, Clone, PartialEq)]
pub struct Schema {
    pub name: String,
    pub text: String,
}

fn schema(name: &str, main: &str, deps: &[(&str, &str)]) -> Schema {
    let mut text = main.to_string();
    for (dep, def) in deps {
        text.push_str(&format!("{SEPARATOR}\nMSG: {dep}\n{def}"));
    }
    Schema {
        name: name.into(),
        text,
    }
}

/// `geometry_msgs/msg/PoseStamped`.
pub fn pose_stamped() -> Schema {
    schema(
        "geometry_msgs/msg/PoseStamped",
        "std_msgs/Header header\ngeometry_msgs/Pose pose\n",
        &[HEADER, TIME, POSE, POINT, QUATERNION],
    )
}

/// `tf2_msgs/msg/TFMessage`.
pub fn tf_message() -> Schema {
    schema(
        "tf2_msgs/msg/TFMessage",
        "geometry_msgs/TransformStamped[] transforms\n",
        &[
            TRANSFORM_STAMPED,
            HEADER,
            TIME,
            TRANSFORM,
            VECTOR3,
            QUATERNION,
        ],
    )
}

/// `sensor_msgs/msg/JointState`.
pub fn joint_state() -> Schema {
    schema(
        "sensor_msgs/msg/JointState",
        "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n",
        &[HEADER, TIME],
    )
}

/// `whisker_slam_msgs/msg/HallSample`: one 2 kHz sample of every whisker (one row of a
/// whisk file).
pub fn hall_sample() -> Schema {
    schema(
        "whisker_slam_msgs/msg/HallSample",
        "# One 2 kHz sample of every whisker's Hall-effect sensor: one row of a whisk file\n\
         # (docs/dataset.md). Arrays hold the whiskers in the manifest's order A1 B1 ... F3.\n\
         std_msgs/Header header\n\
         # The whisk cycle (whisk file whisk_NNNNNN.csv) and the sample (row) within it.\n\
         uint32 whisk\n\
         uint32 sample\n\
         # Whisk angle, counts of the manifest's sensor.angle_resolution_rad.\n\
         int32[] angle\n\
         # Deflection perpendicular to the sweep, ADC counts.\n\
         int32[] x\n\
         # Deflection along the sweep (positive: pushed back against protraction), ADC counts.\n\
         int32[] y\n\
         # The spare column (written 0).\n\
         int32[] spare\n",
        &[HEADER, TIME],
    )
}

/// A table's row message: `std_msgs/Header` (stamped with the row's `time_s` when it has
/// one) then one field per column — `int64`, `float64` or `string`.
pub fn row(name: &str, columns: &[Column]) -> Schema {
    let mut main = String::from(
        "# One row of a whisker-slam CSV table (docs/dataset.md): the header is stamped\n\
         # with the row's time_s (0 without one); the fields are the columns in order.\n\
         std_msgs/Header header\n",
    );
    for c in columns {
        let ty = match c.kind {
            Kind::Int => "int64",
            Kind::Debug | Kind::Display => "float64",
            Kind::Text => "string",
        };
        main.push_str(&format!("{ty} {}\n", c.field));
    }
    schema(
        &format!("whisker_slam_msgs/msg/{name}"),
        &main,
        &[HEADER, TIME],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every dependency a definition names is defined in the schema text, once.
    #[test]
    fn dependencies_are_complete() {
        for s in [pose_stamped(), tf_message(), joint_state(), hall_sample()] {
            let defined: Vec<&str> = s
                .text
                .lines()
                .filter_map(|l| l.strip_prefix("MSG: "))
                .collect();
            for line in s.text.lines() {
                let ty = line.split_whitespace().next().unwrap_or("");
                let ty = ty.trim_end_matches("[]");
                if ty.contains('/') {
                    assert_eq!(
                        defined.iter().filter(|d| **d == ty).count(),
                        1,
                        "{}: {ty}",
                        s.name
                    );
                }
            }
        }
    }
}
