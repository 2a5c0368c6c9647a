//! Environments in scenarios: `[[objects]]`, `[maze]`, kinematic sensing runs and their
//! bad inputs.

use super::*;
use nalgebra::Point3;
use parry3d_f64::math::Vector as PVector;
use whisker_sim::environment::mesh::{MeshOptions, load};

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
    let shape = mesh.shape().unwrap();
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
            object("mesh = \"nan.obj\"\nrepair = \"voxel\""),
            vec!["objects[0].repair", "\"strict\", \"auto\" or \"hull\""],
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
