//! The dataset's own tables as fixed message types — the `.msg` files of the ROS 2 package
//! `ros2/whisker_slam_msgs` (build it to play the bags with `ros2 bag play`): each known
//! header has one definition, its columns typed by name (`whisk`, `update`, `whisker` and
//! `…_whisks` `int64`; `label`, `whisk_file`, `object` `string`; every other `float64`).
//! Any other table, or a known one whose values do not fit (an empty field), is typed
//! from its values and named after its file (`explore.csv` → `ExploreRow`).

use super::table::{Kind, Table};
use crate::dataset_format::records::{CONTACT_COLUMNS, POSE_COLUMNS, TRUTH_POSE_COLUMNS};

/// The known tables: (header, message type).
pub const TYPES: [(&str, &str); 9] = [
    (CONTACT_COLUMNS, "Contact"),
    (POSE_COLUMNS, "PoseLogEntry"),
    (TRUTH_POSE_COLUMNS, "TruePose"),
    (
        crate::maze_slam::dataset::ODOMETRY_COLUMNS,
        "PlanarOdometry",
    ),
    (
        crate::object_slam::dataset::ODOMETRY_COLUMNS,
        "BodyOdometry",
    ),
    (crate::navigation::dataset::ODOMETRY_COLUMNS, "BaseOdometry"),
    (crate::navigation::dataset::TRUTH_COLUMNS, "PlanarPose"),
    (crate::navigation::dataset::STOPS_COLUMNS, "Stop"),
    (crate::navigation::dataset::TRUTH_STOPS_COLUMNS, "TrueStop"),
];

/// A known column's declared kind: integer, number (written by `{:?}`) or text.
pub fn declared(column: &str) -> Kind {
    match column {
        "whisk" | "update" | "whisker" => Kind::Int,
        c if c.ends_with("_whisks") => Kind::Int,
        "label" | "whisk_file" | "object" => Kind::Text,
        _ => Kind::Debug,
    }
}

/// Gives `t` (read from `path`, header `header`) its message type: the known one, its
/// columns set to their declared kinds, when every value fits; else its file's.
pub fn type_of(path: &str, header: &str, t: &mut Table) -> String {
    if let Some((_, name)) = TYPES.iter().find(|(h, _)| *h == header) {
        let kinds: Option<Vec<Kind>> = t
            .columns
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let fits = |k: Kind| t.rows.iter().all(|r| k.fits(&r[i]));
                match declared(&c.name) {
                    Kind::Debug | Kind::Display => {
                        [Kind::Debug, Kind::Display].into_iter().find(|&k| fits(k))
                    }
                    k => fits(k).then_some(k),
                }
            })
            .collect();
        if let Some(kinds) = kinds {
            for (c, k) in t.columns.iter_mut().zip(kinds) {
                c.kind = k;
            }
            return name.to_string();
        }
    }
    file_type(path)
}

/// `<FileName>Row` for a table's path.
fn file_type(path: &str) -> String {
    let stem = path.rsplit('/').next().unwrap_or(path);
    let stem = stem.strip_suffix(".csv").unwrap_or(stem);
    let mut name = String::new();
    let mut upper = true;
    for ch in stem.chars() {
        if ch.is_ascii_alphanumeric() {
            name.push(if upper { ch.to_ascii_uppercase() } else { ch });
            upper = false;
        } else {
            upper = true;
        }
    }
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name.insert_str(0, "Table");
    }
    name + "Row"
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros2_bag::schema;

    fn package() -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../ros2/whisker_slam_msgs")
    }

    /// The shipped `.msg` files are the definitions the bags carry: one per known table
    /// (typed by the declared rule, even with no rows) and the Hall sample; the package's
    /// CMakeLists lists exactly them. `WHISKER_BLESS_MSGS=1` writes them first (after a
    /// change of the definitions).
    #[test]
    fn shipped_messages_are_the_bags_definitions() {
        let main = |text: &str| text.split("====").next().unwrap().to_string();
        if std::env::var_os("WHISKER_BLESS_MSGS").is_some() {
            let write = |name: &str, text: String| {
                std::fs::write(package().join(format!("msg/{name}.msg")), main(&text)).unwrap()
            };
            write("HallSample", schema::hall_sample().text);
            for (header, name) in TYPES {
                let mut t = Table::parse(&format!("{header}\n")).unwrap();
                type_of("x.csv", header, &mut t);
                write(name, schema::row(name, &t.columns).text);
            }
        }
        let mut listed = vec!["HallSample".to_string()];
        let hall = std::fs::read_to_string(package().join("msg/HallSample.msg")).unwrap();
        assert_eq!(hall, main(&schema::hall_sample().text));
        for (header, name) in TYPES {
            let mut t = Table::parse(&format!("{header}\n")).unwrap();
            assert_eq!(type_of("x.csv", header, &mut t), name);
            let shipped = std::fs::read_to_string(package().join(format!("msg/{name}.msg")))
                .unwrap_or_else(|e| panic!("{name}.msg: {e}"));
            assert_eq!(shipped, main(&schema::row(name, &t.columns).text), "{name}");
            listed.push(name.to_string());
        }
        let cmake = std::fs::read_to_string(package().join("CMakeLists.txt")).unwrap();
        let mut in_cmake: Vec<String> = cmake
            .lines()
            .filter_map(|l| l.trim().strip_prefix("\"msg/"))
            .map(|l| l.trim_end_matches('"').trim_end_matches(".msg").to_string())
            .collect();
        in_cmake.sort();
        listed.sort();
        assert_eq!(in_cmake, listed);
    }

    /// A contacts table with an empty slope is no `Contact`: it keeps its values' types
    /// under its file's name.
    #[test]
    fn a_known_table_that_does_not_fit_is_typed_by_its_values() {
        let text = format!("{CONTACT_COLUMNS}\n0,0.5,3,D1,1.0,0.05,0.1,0.0,0.2,\n");
        let mut t = Table::parse(&text).unwrap();
        assert_eq!(
            type_of("log/contacts.csv", CONTACT_COLUMNS, &mut t),
            "ContactsRow"
        );
        let mut t = Table::parse(&format!(
            "{CONTACT_COLUMNS}\n0,1,3,D1,1.0,0.05,0.1,0.0,0.2,inf\n"
        ))
        .unwrap();
        assert_eq!(
            type_of("log/contacts.csv", CONTACT_COLUMNS, &mut t),
            "Contact"
        );
        assert_eq!(t.columns[1].kind, Kind::Display);
    }
}
