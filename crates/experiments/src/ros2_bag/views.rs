//! The standard ROS 2 messages the bag derives from its tables, for the ROS tools (`ros2
//! bag play`, RViz, Foxglove): poses as `geometry_msgs/PoseStamped` and `/tf`, joints as
//! `sensor_msgs/JointState`, the array's follicles on `/tf_static`. They are views: the
//! replay reads the tables' own messages, never these.

use super::cdr::Encoder;
use super::table::Table;
use nalgebra::Isometry3;

/// A pose as a message carries it: position, orientation (x, y, z, w) — the table's own
/// numbers, not renormalised.
pub type Pose = ([f64; 3], [f64; 4]);

/// A table's pose columns: for each prefix `p` (`""`, `true_`, `est_`, `goal_`, …) the
/// 6-D group `p`+`x_m,y_m,z_m,qx,qy,qz,qw` or the planar `p`+`x_m,y_m,heading_rad` (z 0,
/// turned by the heading about the vertical) — (prefix, stamped poses) per group, when the
/// table has `time_s`. Rows whose group is empty (no goal, no ground truth) are left out.
pub fn poses(t: &Table) -> Vec<(String, Vec<(u64, Pose)>)> {
    if t.time.is_none() {
        return Vec::new();
    }
    let col = |name: String| t.columns.iter().position(|c| c.name == name);
    let mut out = Vec::new();
    for c in &t.columns {
        let Some(p) = c.name.strip_suffix("x_m") else {
            continue;
        };
        let group = |names: &[&str]| -> Option<Vec<usize>> {
            names.iter().map(|n| col(format!("{p}{n}"))).collect()
        };
        let six = group(&["x_m", "y_m", "z_m", "qx", "qy", "qz", "qw"]);
        let planar = group(&["x_m", "y_m", "heading_rad"]);
        let pose = |r: &[String]| -> Option<Pose> {
            let v = |i: usize| r[i].parse::<f64>().ok().filter(|v| v.is_finite());
            match (&six, &planar) {
                (Some(c), _) => Some((
                    [v(c[0])?, v(c[1])?, v(c[2])?],
                    [v(c[3])?, v(c[4])?, v(c[5])?, v(c[6])?],
                )),
                (None, Some(c)) => {
                    let half = v(c[2])? / 2.0;
                    Some((
                        [v(c[0])?, v(c[1])?, 0.0],
                        [0.0, 0.0, half.sin(), half.cos()],
                    ))
                }
                (None, None) => None,
            }
        };
        if six.is_none() && planar.is_none() {
            continue;
        }
        let rows: Vec<(u64, Pose)> = t
            .rows
            .iter()
            .enumerate()
            .filter_map(|(i, r)| Some((t.stamp(i), pose(r)?)))
            .collect();
        if !rows.is_empty() {
            out.push((p.to_string(), rows));
        }
    }
    out
}

/// A module's pose in the array frame as a message carries it.
fn of_isometry(p: &Isometry3<f64>) -> Pose {
    let (t, q) = (p.translation.vector, p.rotation.coords);
    ([t.x, t.y, t.z], [q.x, q.y, q.z, q.w])
}

/// The arm's joints of a table with `time_s` and `q0_rad`…`q5_rad` (explore.csv): (stamp,
/// joints) per row; rows whose joints are empty are left out.
pub fn arm_joints(t: &Table) -> Option<Vec<(u64, Vec<f64>)>> {
    t.time?;
    let cols: Vec<usize> = (0..ARM_JOINTS.len())
        .map(|j| t.columns.iter().position(|c| c.name == format!("q{j}_rad")))
        .collect::<Option<_>>()?;
    Some(
        t.rows
            .iter()
            .enumerate()
            .filter_map(|(i, r)| {
                let q: Option<Vec<f64>> = cols.iter().map(|&c| r[c].parse().ok()).collect();
                Some((t.stamp(i), q?))
            })
            .collect(),
    )
}

/// The UR5's joints, in the order of `q0_rad`…`q5_rad` (assets/urdf).
pub const ARM_JOINTS: [&str; 6] = [
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
];

/// `geometry_msgs/PoseStamped`.
pub fn pose_stamped(stamp: u64, frame: &str, p: &Pose) -> Vec<u8> {
    let mut e = Encoder::new();
    e.header(stamp, frame);
    pose(&mut e, p);
    e.finish()
}

fn pose(e: &mut Encoder, (t, q): &Pose) {
    for &v in t.iter().chain(q) {
        e.f64(v);
    }
}

/// `tf2_msgs/TFMessage` of transforms (parent, child, pose of child in parent).
pub fn tf(stamp: u64, transforms: &[(&str, String, Pose)]) -> Vec<u8> {
    let mut e = Encoder::new();
    e.count(transforms.len());
    for (parent, child, p) in transforms {
        e.header(stamp, parent);
        e.string(child);
        pose(&mut e, p);
    }
    e.finish()
}

/// `sensor_msgs/JointState` with positions only.
pub fn joint_state(stamp: u64, names: &[String], positions: &[f64]) -> Vec<u8> {
    let mut e = Encoder::new();
    e.header(stamp, "");
    e.count(names.len());
    for n in names {
        e.string(n);
    }
    e.count(positions.len());
    for &p in positions {
        e.f64(p);
    }
    e.count(0);
    e.count(0);
    e.finish()
}

/// The static transforms of the array: each whisker's module frame (at its pivot) in the
/// array frame, child frames `follicle_<label>`.
pub fn follicles(array_frame: &str) -> Vec<u8> {
    let transforms: Vec<_> = whisker_sim::whisker::array::modules()
        .iter()
        .map(|m| {
            (
                array_frame,
                format!("follicle_{}", m.pixel()),
                of_isometry(&m.pose),
            )
        })
        .collect();
    tf(0, &transforms)
}
