//! The office world and the navigation route (issue #36, Fig 5.1): `whisker check` of the
//! default office, and bad `[office]` / `[navigate]` input (exit code 2, file and field
//! named, nothing written).

use super::*;

/// scenarios/office.toml with `edit` applied, written into `dir` as `name.toml`.
fn office(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(repo("scenarios/office.toml"))
        .unwrap()
        .replace("\"../assets/", &format!("\"{}/", repo("assets").display()))
        .replace(
            "dir = \"out/office\"",
            &format!(
                "dir = {:?}",
                dir.join(format!("out-{name}")).display().to_string()
            ),
        );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// `s` with `old` (which must be in it) replaced by `new`.
fn swap(s: String, old: &str, new: &str) -> String {
    assert!(s.contains(old), "{old:?} not in the office scenario");
    s.replacen(old, new, 1)
}

#[test]
fn the_default_office_checks_with_its_route_clear_of_walls_and_objects() {
    let o = whisker(&["check", repo("scenarios/office.toml").to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("office     7 x 4.5 m floor, 6 walls (9 pieces), 3 doors"),
        "{out}"
    );
    // 4.8 + 2.6 + 4.8 + 2.6 m a lap.
    assert!(
        out.contains("route of 4 waypoints, 14.80 m a lap, 2 laps"),
        "{out}"
    );
}

#[test]
fn bad_offices_and_routes_exit_2_naming_the_field_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    type Edit = Box<dyn Fn(String) -> String>;
    let cases: Vec<(&str, Edit, Vec<&str>)> = vec![
        (
            "door_off_wall",
            Box::new(|s| swap(s, "at_m = 0.7", "at_m = 0.2")),
            vec!["office.doors[0].at_m", "inside wall 4"],
        ),
        (
            "wall_off_floor",
            Box::new(|s| swap(s, "to_m = [7.0, 0.0]", "to_m = [7.5, 0.0]")),
            vec!["office.walls[0].to_m", "off the 7 × 4.5 m floor"],
        ),
        (
            "no_such_wall",
            Box::new(|s| swap(s, "wall = 5", "wall = 9")),
            vec!["office.doors[2].wall", "0 to 5"],
        ),
        (
            // The west room's door moved away from the route's leg D -> A.
            "route_through_wall",
            Box::new(|s| swap(s, "at_m = 0.7", "at_m = 2.0")),
            vec!["navigate.route_m[3]", "from waypoint 3 to 0", "wall 4"],
        ),
        (
            // The Box moved onto the leg B -> C.
            "route_through_object",
            Box::new(|s| {
                swap(
                    s,
                    "position_m = [6.15, 2.4, 0.0]",
                    "position_m = [5.6, 2.4, 0.0]",
                )
            }),
            vec!["navigate.route_m[1]", "object box"],
        ),
        (
            "route_off_floor",
            Box::new(|s| swap(s, "[5.5, 0.7]", "[8.5, 0.7]")),
            vec!["navigate.route_m[1]", "off the 7 × 4.5 m floor"],
        ),
        (
            "one_waypoint",
            Box::new(|s| {
                swap(
                    s,
                    "[[0.7, 0.7], [5.5, 0.7], [5.5, 3.3], [0.7, 3.3]]",
                    "[[0.7, 0.7]]",
                )
            }),
            vec!["navigate.route_m", "at least 2"],
        ),
        (
            "laps",
            Box::new(|s| swap(s, "laps = 2", "laps = 0")),
            vec!["navigate.laps", "1 to 100"],
        ),
        (
            "radius",
            Box::new(|s| swap(s, "radius_m = 0.3", "radius_m = -0.3")),
            vec!["navigate.base.radius_m"],
        ),
        (
            "unknown_base_field",
            Box::new(|s| swap(s, "radius_m = 0.3", "radius_m = 0.3\nwheels = 4")),
            vec!["wheels"],
        ),
        (
            "odometry",
            Box::new(|s| s + "\n[navigate.odometry]\nalpha = [0.1, -1.0, 0.0, 0.0]\n"),
            vec!["navigate.odometry", "alpha"],
        ),
        (
            "switch",
            Box::new(|s| s + "\n[navigate.switch]\nmax_object_m = 0\n"),
            vec!["navigate.switch", "max_object_m"],
        ),
        (
            "maze_and_office",
            Box::new(|s| s + "\n[maze]\n"),
            vec!["field `office`", "not both"],
        ),
        (
            "waypoints_too",
            Box::new(|s| {
                s + "\n[[trajectory.waypoints]]\njoints_deg = [0, -80, 80, -90, -90, 0]\n"
            }),
            vec!["trajectory.waypoints", "navigate.route_m"],
        ),
    ];
    for (name, edit, expected) in cases {
        let path = office(tmp.path(), name, edit);
        for command in ["check", "run"] {
            let o = whisker(&[command, path.to_str().unwrap()]);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{name} {command}: {err}");
            assert!(err.contains(path.to_str().unwrap()), "{name}: {err}");
            // `run` refuses a route it has not built (#36) before checking the legs.
            if command == "check" || !name.starts_with("route_through") {
                for e in &expected {
                    assert!(err.contains(e), "{name} {command}: expected {e:?} in {err}");
                }
            }
            assert!(!err.contains("panicked"), "{name}: {err}");
        }
        assert!(
            !tmp.path().join(format!("out-{name}")).exists(),
            "{name} wrote output"
        );
    }
}

/// The base's footprint along the default office's route, sampled as a run drives it,
/// tested against the office's solids by parry: no collision. This check shares nothing with
/// `whisker check`'s plan-view route check, which the route passes too. With the Box moved
/// onto the leg B -> C both see it.
#[test]
fn the_default_route_is_collision_free_by_an_independent_check() {
    use whisker_experiments::navigation::{footprint, route};
    use whisker_experiments::scenario::Scenario;
    let tmp = tempfile::tempdir().unwrap();
    for (name, moved) in [("as_is", false), ("box_on_route", true)] {
        let path = office(tmp.path(), name, |s| match moved {
            true => swap(
                s,
                "position_m = [6.15, 2.4, 0.0]",
                "position_m = [5.6, 2.4, 0.0]",
            ),
            false => s,
        });
        let scenario = Scenario::load(&path).unwrap();
        let n = scenario.navigate.as_ref().unwrap();
        let environment = scenario.environment(&path).unwrap().environment;
        let poses = route::poses(n, 1.0);
        let hits = footprint::collisions(&environment, &poses, n.base.radius_m, 0.3).unwrap();
        let checked = whisker(&["check", path.to_str().unwrap()]);
        if moved {
            assert!(!hits.is_empty() && hits.iter().all(|(_, what)| what == "object box"));
            assert_eq!(checked.status.code(), Some(2));
        } else {
            assert_eq!(hits, vec![]);
            assert!(checked.status.success(), "{}", stderr(&checked));
        }
    }
}
