//! The office world and the navigation route (issue #36, Fig 5.1): `whisker check` of the
//! default office, bad `[office]` / `[navigate]` input (exit code 2, file and field named,
//! nothing written), and the terrain-mode run of `whisker run`.

use super::*;

/// scenarios/office.toml with `edit` applied, written into `dir` as `name.toml`.
pub(super) fn office(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
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

/// The office's objects: name and centre (x, y) on the floor.
pub(super) const OBJECTS: [(&str, f64, f64); 3] = [
    ("box", 6.15, 2.4),
    ("box_stack", 2.6, 3.95),
    ("barrel", 1.4, 3.95),
];

/// `whisker run` of scenarios/office.toml with `edit` applied (as [`office`]); must
/// succeed. Returns the output directory and its `summary.json`.
pub(super) fn office_run(
    dir: &Path,
    name: &str,
    edit: impl Fn(String) -> String,
) -> (PathBuf, serde_json::Value) {
    let path = office(dir, name, edit);
    let o = whisker(&["run", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join(format!("out-{name}"));
    let summary =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    (out, summary)
}

/// `s` with `old` (which must be in it) replaced by `new`.
pub(super) fn swap(s: String, old: &str, new: &str) -> String {
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
            Box::new(|s| {
                swap(
                    s,
                    "link_gap_m = 0.15",
                    "link_gap_m = 0.15\nmax_object_m = 0",
                )
            }),
            vec!["navigate.switch", "max_object_m"],
        ),
        (
            "no_sensing",
            Box::new(|s| swap(s, "sensing = \"kinematic\"", "sensing = \"none\"")),
            vec![
                "field `sensing`",
                "needs sensing = \"kinematic\" or \"physics\"",
            ],
        ),
        (
            "mount",
            Box::new(|s| s + "\n[navigate.terrain]\nmount_height_m = 0\n"),
            vec!["navigate.terrain.mount_height_m", "> 0"],
        ),
        (
            "posture_out_of_reach",
            Box::new(|s| s + "\n[navigate.terrain]\narray_position_m = [0.0, -1.5, 0.0]\n"),
            vec!["navigate.terrain.array_position_m", "cannot hold the array"],
        ),
        (
            "ratslam_value",
            Box::new(|s| s + "\n[navigate.ratslam.pose_cells]\ncell_size_m = -0.1\n"),
            vec!["navigate.ratslam", "cell_size_m"],
        ),
        (
            "ratslam_unknown_field",
            Box::new(|s| s + "\n[navigate.ratslam.local_view]\nthreshold = 3\n"),
            vec!["navigate.ratslam", "threshold"],
        ),
        (
            "object_mode_maps",
            Box::new(|s| swap(s, "task = \"recognise\"", "task = \"map\"")),
            vec!["navigate.object.explore.task", "recognise"],
        ),
        (
            "object_mode_object",
            Box::new(|s| {
                swap(
                    s,
                    "stop_on_identity = true",
                    "stop_on_identity = true\nobject = \"box\"",
                )
            }),
            vec!["navigate.object.explore.object", "expected none"],
        ),
        (
            "object_mode_missing_map",
            Box::new(|s| swap(s, "maps/box.json", "maps/no_such_box.json")),
            vec!["navigate.object.explore.maps.box", "no such file"],
        ),
        (
            "landmark_energy",
            Box::new(|s| s + "\n[navigate.object]\nlandmark_energy = 0.0\n"),
            vec!["navigate.object.landmark_energy", "expected a number > 0"],
        ),
        (
            "dock_by_wheels",
            Box::new(|s| s + "\n[navigate.object]\ndock = \"wheels\"\n"),
            vec!["dock = \"wheels\"", "expected `arm` or `base`"],
        ),
        (
            "kidnap_one_lap",
            Box::new(|s| swap(s, "laps = 2", "laps = 1\nkidnap = true")),
            vec!["navigate.kidnap", "laps ≥ 2"],
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
            for e in &expected {
                assert!(err.contains(e), "{name} {command}: expected {e:?} in {err}");
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
    use whisker_scenario::ScenarioFile;
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
        let file = ScenarioFile::load(&path).unwrap();
        let n = file.scenario.experiment.navigate().unwrap();
        let environment = file.environment().unwrap().environment;
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

/// `whisker run scenarios/office.toml` (terrain mode): every update's true pose follows the
/// route; whisks touch where the array is within whisker reach of a wall or an object and
/// (along the south wall, followed at 0.65 m) nearly always there; nothing collides; and the
/// map, after its best rigid fit, is closer to the truth than the odometry alone — both
/// errors re-computed here from `path.csv` with a fit of our own (by brute force over the
/// heading), not read from the summary.
#[test]
fn the_office_run_maps_the_route_closer_than_its_odometry() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, summary) = office_run(tmp.path(), "run", |s| s);
    // The recording: every entity documented, one tactile image per update.
    let chunks = recording::checked(
        &dir.join("run.rrd"),
        &[
            "slam/office/tactile_image",
            "slam/office/pose_cells",
            "world/runs/office/array",
            "world/runs/office/true",
            "world/runs/office/estimated",
            "world/runs/office/odometry",
            "world/runs/office/stops",
            "slam/office/map/landmarks",
            "events",
        ],
    );
    let entities = whisker_recording::decode::entities(&chunks);
    assert_eq!(summary["arm_collisions"], 0, "{summary}");
    assert_eq!(summary["base_collisions"], 0, "{summary}");
    assert_eq!(summary["collisions"], serde_json::json!([]), "{summary}");
    // The cue rarely calls a wall an object on this route (docs/navigation.md: the
    // office's end window trades a few such verdicts for finding the objects).
    let switch = &summary["switch"];
    let (on_wall, wall_object) = (
        switch["on_walls"]["wall"].as_u64().unwrap(),
        switch["on_walls"]["object"].as_u64().unwrap(),
    );
    assert!(wall_object * 10 < on_wall, "{switch}");
    let svg = std::fs::read_to_string(dir.join("path.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("map estimate"),
        "path.svg"
    );
    let csv = std::fs::read_to_string(dir.join("path.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').take(14).map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len() as u64, summary["updates"].as_u64().unwrap());
    assert_eq!(entities["/slam/office/tactile_image"].rows, rows.len());
    // Waypoints A, B, C, D, twice round, starting and ending at A.
    let (first, last) = (&rows[0], rows.last().unwrap());
    assert_eq!((first[2], first[3], last[2], last[3]), (0.7, 0.7, 0.7, 0.7));
    // The array's centre: 0.48 m to the base's right, from the truth columns.
    let array = |r: &Vec<f64>| (r[2] + 0.48 * r[4].sin(), r[3] - 0.48 * r[4].cos());
    // Whisker reach (0.19 m) plus the array's half width: a contact needs a wall's
    // surface or an object's side within 0.3 m of the array's centre.
    let walls: [(f64, f64, f64, f64); 6] = [
        (0.0, 0.0, 7.0, 0.0),
        (7.0, 0.0, 7.0, 4.5),
        (0.0, 4.5, 7.0, 4.5),
        (0.0, 0.0, 0.0, 4.5),
        (0.0, 1.5, 7.0, 1.5),
        (3.5, 1.5, 3.5, 4.5),
    ];

    let near = |(x, y): (f64, f64)| {
        let wall = walls.iter().any(|&(ax, ay, bx, by)| {
            let (cx, cy) = (
                x.clamp(ax.min(bx), ax.max(bx)),
                y.clamp(ay.min(by), ay.max(by)),
            );
            (x - cx).hypot(y - cy) < 0.05 + 0.3
        });
        wall || OBJECTS
            .iter()
            .any(|&(_, ox, oy)| (x - ox).hypot(y - oy) < 0.15 + 0.3)
    };
    // A verdict and the touched piece exactly where one of the latest 20 whisks (the
    // cue's window) touched.
    let mut last_touch = None;
    for (k, line) in csv.lines().skip(1).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        if f[11] != "0" {
            last_touch = Some(k);
        }
        let in_window = last_touch.is_some_and(|t| k - t < 20);
        assert_eq!(!f[15].is_empty(), in_window, "{line}");
        assert_eq!(!f[16].is_empty(), in_window, "{line}");
    }
    let touched: Vec<&Vec<f64>> = rows.iter().filter(|r| r[11] > 0.0).collect();
    assert!(!touched.is_empty());
    for r in &touched {
        assert!(
            near(array(r)),
            "update {} touched far from everything",
            r[0]
        );
    }
    let south: Vec<&Vec<f64>> = rows
        .iter()
        .filter(|r| r[3] == 0.7 && r[4] == 0.0 && r[2] > 1.0 && r[2] < 5.2)
        .collect();
    let hit = south.iter().filter(|r| r[11] > 0.0).count();
    assert!(
        hit * 10 >= south.len() * 9,
        "{hit} of {} along the south wall",
        south.len()
    );
    // Position error rms after the best rigid fit, the heading by brute force (0.01°).
    let truth: Vec<(f64, f64)> = rows.iter().map(|r| (r[2], r[3])).collect();
    let rms_after_fit = |est: Vec<(f64, f64)>| -> f64 {
        let n = est.len() as f64;
        let mean = |v: &[(f64, f64)]| {
            let (x, y) = v.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
            (x / n, y / n)
        };
        let (et, tt) = (mean(&est), mean(&truth));
        (0..36000)
            .map(|k| {
                let (s, c) = (k as f64 / 100.0).to_radians().sin_cos();
                let sq: f64 = est
                    .iter()
                    .zip(&truth)
                    .map(|(e, t)| {
                        let (dx, dy) = (e.0 - et.0, e.1 - et.1);
                        let (x, y) = (c * dx - s * dy + tt.0, s * dx + c * dy + tt.1);
                        (x - t.0).powi(2) + (y - t.1).powi(2)
                    })
                    .sum();
                (sq / n).sqrt()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let map = rms_after_fit(rows.iter().map(|r| (r[8], r[9])).collect());
    let odometry = rms_after_fit(rows.iter().map(|r| (r[5], r[6])).collect());
    let reported = summary["map_error"]["rms_m"].as_f64().unwrap();
    assert!(
        (map - reported).abs() < 1e-3,
        "{map} vs the summary's {reported}"
    );
    assert!(
        map < odometry,
        "map {map} m rms, odometry alone {odometry} m rms"
    );
    stop_recordings_agree(&dir);
}

/// Each stop's closed loops are recorded beside run.rrd (`stops/NNNNNN-<task>.rrd`)
/// exactly where stops.csv says loops ran: recognition at every object, map building where
/// nothing was identified, none at walls. A recognition's recording holds one integrated
/// confidence per whisk, its last value stops.csv's `ic` (which counts both loops'
/// whisks: recognition alone where nothing was mapped).
fn stop_recordings_agree(dir: &Path) {
    use whisker_recording::decode;
    let stops = rows(&dir.join("stops.csv"));
    let mut checked = 0;
    for s in &stops {
        let file = |task: &str| dir.join(format!("stops/{:0>6}-{task}.rrd", s[0]));
        assert_eq!(file("recognise").exists(), !s[7].is_empty(), "{s:?}");
        assert_eq!(file("map").exists(), !s[15].is_empty(), "{s:?}");
        if s[7].is_empty() || !s[15].is_empty() {
            continue;
        }
        let chunks = recording::checked(
            &file("recognise"),
            &[
                "world/arm/skeleton",
                "world/contacts/estimated",
                "recognition/integrated/box",
            ],
        );
        for pair in s[14].split(' ') {
            let (object, ic) = pair.split_once('=').unwrap();
            let ic: f64 = ic.parse().unwrap();
            let recorded = decode::scalars(&chunks, &format!("/recognition/integrated/{object}"));
            assert_eq!(recorded.len(), s[10].parse::<usize>().unwrap(), "{s:?}");
            let last = recorded.last().unwrap().1[0];
            assert!(
                (last - ic).abs() <= 0.5,
                "{object}: recorded {last}, stops.csv {ic}"
            );
        }
        checked += 1;
    }
    assert!(checked > 0, "no recognition to check: {stops:?}");
}
