//! ROS 2 interchange: a dataset or a run's output as a ROS 2 bag in MCAP (`whisker export
//! --mcap`), and a dataset's bag back to the dataset for a replay (`whisker slam --mcap`).
//! The layout — topics, message types, frames, units — is specified in docs/dataset.md,
//! "ROS 2 bags (MCAP)"; in short:
//!
//! ```text
//! /<path of a CSV table>                whisker_slam_msgs/msg/<Table>: one message per row,
//!                                       a field per column, stamped with its time_s
//! /<whisk folder>/hall                  whisker_slam_msgs/msg/HallSample: one per 2 kHz sample
//! /<whisk folder>/joint_states          sensor_msgs/JointState: the whisk angles (view)
//! /<pose table>/pose, /tf               geometry_msgs/PoseStamped, tf2_msgs/TFMessage (views)
//! /<table with q0_rad…>/joint_states    sensor_msgs/JointState: the UR5's joints (view)
//! /tf_static                            the array's follicles
//! attachments                           dataset.json and every file that is not a table
//! ```
//!
//! Messages are CDR-encoded ([`cdr`]) with `ros2msg` schemas ([`schema`]); tables travel
//! exactly ([`table`]); a damaged file is refused naming its byte ([`scan`]).

mod bag;
pub mod cdr;
mod export;
mod hall;
mod import;
pub mod known;
mod scan;
pub mod schema;
pub mod table;
mod views;

pub use export::{Exported, export};
pub use import::{Unpacked, import, unpack};
pub use views::ARM_JOINTS;

/// The topic of a file or folder: its path without `.csv`, each name made a ROS 2 name
/// token (letters, digits and `_`, not starting with a digit: `000012` → `n000012`).
pub fn topic(path: &str) -> String {
    let path = path.strip_suffix(".csv").unwrap_or(path);
    let tokens: Vec<String> = path
        .split('/')
        .map(|t| {
            let mut s: String = t
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            while s.contains("__") {
                s = s.replace("__", "_");
            }
            if !s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
                s.insert(0, 'n');
            }
            s
        })
        .collect();
    format!("/{}", tokens.join("/"))
}

/// A whisk file's folder and number (`log/whisks/whisk_000012.csv` → (`log/whisks`, 12)).
pub fn whisk_file(path: &str) -> Option<(&str, usize)> {
    let (folder, name) = path.rsplit_once('/')?;
    let k = name.strip_prefix("whisk_")?.strip_suffix(".csv")?;
    (folder.ends_with("whisks") && k.len() == 6 && k.bytes().all(|b| b.is_ascii_digit()))
        .then(|| (folder, k.parse().expect("digits")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topics_are_ros_names() {
        assert_eq!(topic("log/contacts.csv"), "/log/contacts");
        assert_eq!(
            topic("log/stops/000012/recognise/contacts.csv"),
            "/log/stops/n000012/recognise/contacts"
        );
        assert_eq!(
            topic("trajectory-max_angle-open-0.csv"),
            "/trajectory_max_angle_open_0"
        );
        assert_eq!(
            whisk_file("log/box/A/whisks/whisk_000012.csv"),
            Some(("log/box/A/whisks", 12))
        );
        assert_eq!(whisk_file("log/whisks/whisk_12.csv"), None);
    }
}
