//! Environments in scenarios: `[[objects]]`, `[maze]`, kinematic sensing runs and their
//! bad inputs.

use super::*;
use nalgebra::Point3;
use parry3d_f64::math::Vector as PVector;
use whisker_sim::environment::mesh::{MeshOptions, Repair, load};

/// The objects scenario with noise off, written into `dir`.
fn quiet_objects(dir: &Path, seed: u64) -> PathBuf {
    let text = std::fs::read_to_string(repo("scenarios/objects.toml"))
        .unwrap()
        .replace("noise = true", "noise = false")
        .replace("seed = 5", &format!("seed = {seed}"))
        .replace("\"../assets/", &format!("\"{}/", repo("assets").display()));
    let path = dir.join(format!("objects-{seed}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn noise_free_contacts_lie_on_the_object_and_on_the_shaft() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run_into(&quiet_objects(tmp.path(), 5), &tmp.path().join("out"));
    let contacts = rows(&out.join("contacts.csv"));
    assert!(contacts.len() > 20, "{} contacts", contacts.len());
    // The kettle as placed by the scenario: at (0.5, 0, 0), turned 90° about z.
    let mesh = load(&repo("assets/meshes/kettle.obj"), &MeshOptions::default())
        .unwrap()
        .mesh;
    let shape = whisker_sim::environment::solids::shape(&mesh).unwrap();
    let pose = whisker_slam::pose::from_xyz_rpy([0.5, 0.0, 0.0], [0.0, 0.0, 90f64.to_radians()]);
    let lengths = [0.060, 0.100, 0.160];
    for c in &contacts {
        let f = |k: usize| c[k].parse::<f64>().unwrap();
        let world = Point3::new(f(10), f(11), f(12));
        let local = pose.inverse_transform_point(&world);
        let d = shape.distance_to_local_point(PVector::new(local.x, local.y, local.z), true);
        assert!(d < 1e-9, "contact {c:?} is {d} m off the surface");
        let whisker: usize = c[2].parse().unwrap();
        let r = f(6);
        assert!(
            (0.0..=lengths[whisker / 6] + 1e-12).contains(&r),
            "radial distance {r}"
        );
        let angle = f(5);
        assert!((40.0..=140.0).contains(&angle) && (angle - angle.round()).abs() < 1e-9);
        // Contact time lies in the protraction half of its cycle.
        let (t0, t) = (f(1), f(4));
        assert!(
            (t0..=t0 + 0.5 + 1e-9).contains(&t),
            "t {t} in cycle from {t0}"
        );
    }
}

#[test]
fn kinematic_runs_are_reproducible_per_seed() {
    let tmp = tempfile::tempdir().unwrap();
    let maze = repo("scenarios/maze_kinematic.toml");
    let a = std::fs::read(run_into(&maze, &tmp.path().join("a")).join("contacts.csv")).unwrap();
    let b = std::fs::read(run_into(&maze, &tmp.path().join("b")).join("contacts.csv")).unwrap();
    assert_eq!(a, b, "same seed, same bytes");
    // The same maze (a copy of the base, assets found by absolute path) with another seed,
    // written as changes to it.
    let text = std::fs::read_to_string(repo("scenarios/maze.toml"))
        .unwrap()
        .replace("\"../assets/", &format!("\"{}/", repo("assets").display()));
    std::fs::write(tmp.path().join("maze.toml"), text).unwrap();
    let other = tmp.path().join("maze4.toml");
    std::fs::write(
        &other,
        "base = \"maze.toml\"\nseed = 4\nsensing = \"kinematic\"\n",
    )
    .unwrap();
    let c = std::fs::read(run_into(&other, &tmp.path().join("c")).join("contacts.csv")).unwrap();
    assert_ne!(a, c, "another seed draws other noise and deformities");
    assert!(rows(&tmp.path().join("a/contacts.csv")).len() > 10);
}

#[test]
fn check_reports_mesh_repairs() {
    let tmp = tempfile::tempdir().unwrap();
    // A unit cube written inside out, in millimetres.
    let mut obj = String::new();
    for i in 0..8 {
        obj += &format!(
            "v {} {} {}\n",
            100 * (i & 1),
            100 * ((i >> 1) & 1),
            100 * ((i >> 2) & 1)
        );
    }
    for q in [
        [1, 2, 4, 3],
        [5, 7, 8, 6],
        [1, 5, 6, 2],
        [3, 4, 8, 7],
        [1, 3, 7, 5],
        [2, 6, 8, 4],
    ] {
        obj += &format!("f {} {} {} {}\n", q[0], q[1], q[2], q[3]);
    }
    std::fs::write(tmp.path().join("cube.obj"), obj).unwrap();
    let body = with_urdf(&format!(
        "{ARM}[[objects]]\nmesh = \"cube.obj\"\nunits = \"mm\"\nposition_m = [0.5, 0, 0]\n{WAYPOINT}{OUTPUT}"
    ))
    .replace("OUT", "\"out\"");
    let path = tmp.path().join("cube.toml");
    std::fs::write(&path, body).unwrap();
    let o = whisker(&["check", path.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("0.100 x 0.100 x 0.100 m"), "{text}");
    assert!(
        text.contains("mesh repaired") && text.contains("inside-out"),
        "{text}"
    );
}

#[test]
fn bad_environments_exit_2_naming_the_field_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("nan.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n",
    )
    .unwrap();
    let object = |extra: &str| format!("{ARM}[[objects]]\n{extra}\n{WAYPOINT}{OUTPUT}");
    let maze = |extra: &str| format!("{ARM}[maze]\n{extra}\n{WAYPOINT}{OUTPUT}");
    let wall = "[[maze.walls]]\nfrom_m = [0.1, 0.1]\nto_m = [0.5, 0.1]\nheight_m = 0.05\nthickness_m = 0.01";
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "no_mesh",
            object("mesh = \"missing.obj\""),
            vec!["objects[0].mesh", "missing.obj", "cannot read"],
        ),
        (
            "nan_mesh",
            object("mesh = \"nan.obj\""),
            vec!["objects[0].mesh", "nan.obj", "line 3"],
        ),
        (
            "units",
            object("mesh = \"nan.obj\"\nunits = \"furlong\""),
            vec!["objects[0].units"],
        ),
        (
            "up",
            object("mesh = \"nan.obj\"\nup = \"x\""),
            vec!["objects[0].up"],
        ),
        (
            "scale",
            object("mesh = \"nan.obj\"\nscale = 0"),
            vec!["objects[0].scale"],
        ),
        (
            "repair",
            object("mesh = \"nan.obj\"\nrepair = \"melt\""),
            vec![
                "objects[0].repair",
                "\"strict\", \"auto\", \"hull\", \"voxel\" or \"soup\"",
            ],
        ),
        (
            "voxel_size_without_voxel",
            object("mesh = \"nan.obj\"\nvoxel_size_m = 0.002"),
            vec!["objects[0].voxel_size_m", "\"voxel\" only"],
        ),
        (
            "voxel_size",
            object("mesh = \"nan.obj\"\nrepair = \"voxel\"\nvoxel_size_m = -1"),
            vec!["objects[0].voxel_size_m", "positive"],
        ),
        (
            "decimate_soup",
            object("mesh = \"nan.obj\"\nrepair = \"soup\"\ndecimate = 1000"),
            vec!["objects[0].decimate", "kept as it is"],
        ),
        (
            "decimate_tolerance_alone",
            object("mesh = \"nan.obj\"\ndecimate_tolerance_m = 0.001"),
            vec!["objects[0].decimate_tolerance_m", "decimate"],
        ),
        (
            "decimate_too_few",
            object("mesh = \"nan.obj\"\ndecimate = 2"),
            vec!["objects[0].decimate", "at least 4"],
        ),
        (
            "soup_physics",
            format!(
                "sensing = \"physics\"\n{ARM}[[objects]]\nmesh = \"nan.obj\"\nrepair = \"soup\"\n{WAYPOINT}{OUTPUT}"
            ),
            vec![
                "objects[0].repair",
                "kinematic sensing only",
                "sensing = \"physics\"",
            ],
        ),
        (
            "origin",
            object("mesh = \"nan.obj\"\norigin = \"centre\""),
            vec!["objects[0].origin", "\"file\" or \"base\""],
        ),
        (
            "off_board",
            maze(&wall.replace("[0.5, 0.1]", "[2.5, 0.1]")),
            vec!["maze.walls[0].to_m", "off the"],
        ),
        (
            "thin_wall",
            maze(&wall.replace("thickness_m = 0.01", "thickness_m = -1")),
            vec!["maze.walls[0].thickness_m"],
        ),
        (
            "post",
            maze(
                "[[maze.posts]]\nat_m = [0.2, 0.2]\nsize_m = 0.03\nheight_m = 0.05\nshape = \"cone\"",
            ),
            vec!["cone"],
        ),
        (
            "deform",
            maze(&format!(
                "{wall}\n[maze.deformities]\ncount = 3\nsize_m = [0.02, 0.01]"
            )),
            vec!["maze.deformities.size_m"],
        ),
        (
            "wall_field",
            maze(&format!("{wall}\ncolour = 1")),
            vec!["colour"],
        ),
        (
            "detection",
            format!(
                "sensing = \"kinematic\"\n{ARM}[kinematic]\ndetection_probability = 1.5\n{WAYPOINT}{OUTPUT}"
            ),
            vec!["kinematic.detection_probability"],
        ),
        (
            "slope_noise",
            format!(
                "sensing = \"kinematic\"\n{ARM}[kinematic]\nslope_noise = -0.3\n{WAYPOINT}{OUTPUT}"
            ),
            vec!["kinematic.slope_noise"],
        ),
    ];
    for (name, body, expected) in cases {
        let (o, path) = run_bad(tmp.path(), name, &body);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains(path.to_str().unwrap()), "{name}: {err}");
        for e in expected {
            assert!(err.contains(e), "{name}: expected {e:?} in {err}");
        }
        assert!(!err.contains("panicked"), "{name}: {err}");
        let out = tmp.path().join(format!("out-{name}"));
        assert!(
            !out.exists() || std::fs::read_dir(&out).unwrap().next().is_none(),
            "{name} wrote output"
        );
    }
}

/// The Kettle with a fin on one of its edges (a third triangle on the edge 1–3, as in
/// exported models with stray geometry): auto refuses it. Written into `dir` with the
/// objects scenario (noise off) using it under `repair`.
fn finned_kettle(dir: &Path, repair: &str) -> PathBuf {
    let mut obj = std::fs::read_to_string(repo("assets/meshes/kettle.obj")).unwrap();
    let v1: Vec<f64> = obj
        .lines()
        .find(|l| l.starts_with("v "))
        .unwrap()
        .split_whitespace()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let n = obj.lines().filter(|l| l.starts_with("v ")).count();
    obj += &format!(
        "v {} {} {}\nf 1 3 {}\n",
        v1[0] + 0.02,
        v1[1] + 0.03,
        v1[2] + 0.01,
        n + 1
    );
    std::fs::write(dir.join("finned.obj"), obj).unwrap();
    let text = std::fs::read_to_string(quiet_objects(dir, 5))
        .unwrap()
        .replace(
            &format!(
                "{:?}",
                repo("assets/meshes/kettle.obj").display().to_string()
            ),
            &format!("\"finned.obj\"\nrepair = \"{repair}\""),
        );
    let path = dir.join(format!("finned-{repair}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Noise-free contacts of a run, as world points.
fn contact_points(out: &Path) -> Vec<Point3<f64>> {
    rows(&out.join("contacts.csv"))
        .iter()
        .map(|c| {
            let f = |k: usize| c[k].parse::<f64>().unwrap();
            Point3::new(f(10), f(11), f(12))
        })
        .collect()
}

#[test]
fn a_mesh_auto_refuses_runs_as_a_soup_or_a_voxel_remesh() {
    let tmp = tempfile::tempdir().unwrap();
    let o = whisker(&["check", finned_kettle(tmp.path(), "auto").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("finned.obj") && err.contains("\"soup\""),
        "{err}"
    );
    let pose = whisker_slam::pose::from_xyz_rpy([0.5, 0.0, 0.0], [0.0, 0.0, 90f64.to_radians()]);
    let file = tmp.path().join("finned.obj");
    for repair in ["soup", "voxel"] {
        let scenario = finned_kettle(tmp.path(), repair);
        let written = tmp.path().join(format!("meshes-{repair}"));
        let o = whisker(&[
            "check",
            scenario.to_str().unwrap(),
            "--meshes",
            written.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{repair}: {}", stderr(&o));
        let text = stdout(&o);
        assert!(text.contains("triangles"), "{text}");
        // What the sweep touches: the soup itself, or the remesh (a solid, within its
        // reported deviation of the file's surface).
        let options = MeshOptions {
            repair: if repair == "soup" {
                Repair::Soup
            } else {
                Repair::Voxel
            },
            ..Default::default()
        };
        let loaded = load(&file, &options).unwrap();
        let allowed = if repair == "soup" {
            assert!(text.contains("triangle soup"), "{text}");
            1e-9
        } else {
            assert!(
                text.contains("solid part") && text.contains("voxels"),
                "{text}"
            );
            // The remesh, written out and read back strictly, is a clean closed solid.
            let again = load(
                &written.join("finned.obj"),
                &MeshOptions {
                    repair: Repair::Strict,
                    ..Default::default()
                },
            )
            .unwrap_or_else(|e| panic!("{e}"));
            assert!(again.repairs.is_empty(), "{:?}", again.repairs);
            let mm: f64 = text
                .split("up to ")
                .nth(1)
                .and_then(|r| r.split(" mm").next())
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("{text}"));
            mm * 1e-3 + 1e-4
        };
        let points = contact_points(&run_into(&scenario, &tmp.path().join(repair)));
        assert!(points.len() > 20, "{repair}: {} contacts", points.len());
        let soup = whisker_sim::environment::solids::soup_shape(
            &load(
                &file,
                &MeshOptions {
                    repair: Repair::Soup,
                    ..Default::default()
                },
            )
            .unwrap()
            .mesh,
        )
        .unwrap();
        let surface = whisker_sim::environment::solids::soup_shape(&loaded.mesh).unwrap();
        for p in &points {
            let local = pose.inverse_transform_point(p);
            let q = PVector::new(local.x, local.y, local.z);
            // On the surface swept, and that surface is the file's (or near it).
            assert!(
                surface.distance_to_local_point(q, true) < 1e-9,
                "{repair}: {p}"
            );
            let d = soup.distance_to_local_point(q, true);
            assert!(
                d <= allowed,
                "{repair}: contact {p} is {d} m off the file's surface"
            );
        }
    }
}

/// A physics run over the kettle: the anticipated contacts (ground truth) and the signal
/// front end's contacts. Once the arm has stopped, the front end detects exactly the
/// whiskers the rigid sweep says touch, at onset angles within a few degrees of the
/// anticipated contact angles, and localises them (built-in svr10) within half a whisker
/// length of the anticipated point.
#[test]
fn physics_runs_with_an_object_write_the_anticipated_and_detected_contacts() {
    let tmp = tempfile::tempdir().unwrap();
    // Down over the kettle (as in scenarios/objects.toml), in physics mode with light whiskers.
    let kettle = repo("assets/meshes/kettle.obj");
    let body = format!(
        "sensing = \"physics\"\n{ARM}[array]\nsegments = 8\nbending = \"sweep-plane\"\n\
         [[objects]]\nmesh = {:?}\nposition_m = [0.5, 0.0, 0.0]\nrpy_deg = [0, 0, 90]\n\
         [[trajectory.waypoints]]\nposition_m = [0.50, -0.12, 0.25]\nrpy_deg = [180.0, 0.0, -90.0]\n\
         hold_s = 2.05\n{OUTPUT}",
        kettle.display().to_string()
    );
    let (o, _) = run_bad(tmp.path(), "physics_kettle", &body);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.path().join("out-physics_kettle");
    assert!(out.join("whiskers.csv").exists());
    let anticipated = rows(&out.join("anticipated.csv"));
    assert!(!anticipated.is_empty(), "no anticipated contacts");
    // Noise-free anticipated intersects: every contact angle is a whole sweep step.
    for c in &anticipated {
        let angle: f64 = c[5].parse().unwrap();
        assert!((angle - angle.round()).abs() < 1e-9);
    }
    // The last whisk cycle the front end processed is one with the arm at rest.
    let detected = rows(&out.join("frontend.csv"));
    let last = detected.last().expect("front-end contacts")[0].clone();
    let cycle = |rows: &[Vec<String>]| -> Vec<Vec<f64>> {
        rows.iter()
            .filter(|r| r[0] == last)
            .map(|r| {
                r.iter()
                    .enumerate()
                    .map(|(k, v)| if k == 3 { 0.0 } else { v.parse().unwrap() })
                    .collect()
            })
            .collect()
    };
    let (front, truth) = (cycle(&detected), cycle(&anticipated));
    let whiskers = |c: &[Vec<f64>]| c.iter().map(|r| r[2] as usize).collect::<Vec<_>>();
    assert_eq!(whiskers(&front), whiskers(&truth), "cycle {last}");
    let lengths = [
        0.06, 0.06, 0.06, 0.06, 0.06, 0.06, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1,
    ];
    for (f, t) in front.iter().zip(&truth) {
        let length = *lengths.get(f[2] as usize).unwrap_or(&0.16);
        assert!((f[5] - t[5]).abs() < 3.0, "onset {}° vs {}°", f[5], t[5]);
        assert!((0.0..=length).contains(&f[6]));
        let d =
            ((f[10] - t[10]).powi(2) + (f[11] - t[11]).powi(2) + (f[12] - t[12]).powi(2)).sqrt();
        assert!(
            d < 0.5 * length,
            "whisker {}: {d} m from the anticipated point",
            f[2]
        );
    }
}

#[test]
fn check_writes_one_mesh_file_per_object_even_when_names_repeat() {
    // The objects scenario with a second Kettle: both are written, as kettle-0 and
    // kettle-1, each the Kettle as loaded (same triangle count as the catalogue file).
    let tmp = tempfile::tempdir().unwrap();
    let path = quiet_objects(tmp.path(), 5);
    let kettle = repo("assets/meshes/kettle.obj");
    let mut text = std::fs::read_to_string(&path).unwrap();
    text += &format!(
        "\n[[objects]]\nmesh = {:?}\nposition_m = [0.9, 0.0, 0.0]\n",
        kettle.display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    let dir = tmp.path().join("meshes");
    let o = whisker(&[
        "check",
        path.to_str().unwrap(),
        "--meshes",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let triangles = load(&kettle, &MeshOptions::default())
        .unwrap()
        .mesh
        .triangles
        .len();
    for name in ["kettle-0.obj", "kettle-1.obj"] {
        let written =
            load(&dir.join(name), &MeshOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(written.mesh.triangles.len(), triangles, "{name}");
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
}
