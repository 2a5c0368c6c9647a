//! Fuzzing the files a scenario points at: meshes in all six encodings (OBJ, STL ASCII
//! and binary, PLY ASCII, binary little- and big-endian) under every repair mode, the URDF,
//! object maps, and radial-distance models with their validation set.

use super::mutate::*;
use super::{Case, absolute_assets, config, run, s};
use crate::repo;
use proptest::prelude::*;
use std::path::Path;

/// The Box of `assets/meshes` as triangles.
fn box_triangles() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let soup = whisker_sim::environment::mesh_io::read(&repo("assets/meshes/box.obj")).unwrap();
    let tris = soup
        .polygons
        .iter()
        .flat_map(|p| (1..p.len() - 1).map(move |i| [p[0], p[i], p[i + 1]]))
        .collect();
    (soup.positions, tris)
}

/// The Box in `encoding` (file extension, bytes).
fn encoded(encoding: &str) -> (&'static str, Vec<u8>) {
    let (v, t) = box_triangles();
    let f32s = |x: f64, big: bool| {
        let x = x as f32;
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    match encoding {
        "obj" => ("obj", std::fs::read(repo("assets/meshes/box.obj")).unwrap()),
        "stl-ascii" => {
            let mut s = String::from("solid box\n");
            for tri in &t {
                s += "facet normal 0 0 0\nouter loop\n";
                for &i in tri {
                    let p = v[i as usize];
                    s += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
                }
                s += "endloop\nendfacet\n";
            }
            ("stl", (s + "endsolid box\n").into_bytes())
        }
        "stl-binary" => {
            let mut b = vec![0u8; 80];
            b.extend((t.len() as u32).to_le_bytes());
            for tri in &t {
                b.extend([0u8; 12]);
                for &i in tri {
                    v[i as usize].iter().for_each(|&x| b.extend(f32s(x, false)));
                }
                b.extend([0u8; 2]);
            }
            ("stl", b)
        }
        ply => {
            let mut b = format!(
                "ply\nformat {ply} 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
                 property float z\nelement face {}\nproperty list uchar int vertex_indices\n\
                 end_header\n",
                v.len(),
                t.len()
            )
            .into_bytes();
            let big = ply == "binary_big_endian";
            for p in &v {
                if ply == "ascii" {
                    b.extend(format!("{} {} {}\n", p[0], p[1], p[2]).bytes());
                } else {
                    p.iter().for_each(|&x| b.extend(f32s(x, big)));
                }
            }
            for tri in &t {
                if ply == "ascii" {
                    b.extend(format!("3 {} {} {}\n", tri[0], tri[1], tri[2]).bytes());
                } else {
                    b.push(3);
                    for &i in tri {
                        let i = i as i32;
                        b.extend(if big {
                            i.to_be_bytes()
                        } else {
                            i.to_le_bytes()
                        });
                    }
                }
            }
            ("ply", b)
        }
    }
}

const ENCODINGS: &[&str] = &[
    "obj",
    "stl-ascii",
    "stl-binary",
    "ascii",
    "binary_little_endian",
    "binary_big_endian",
];

/// A kinematic scenario in `dir` with one object from `mesh`, repaired as `repair`.
fn object_scenario(dir: &Path, mesh: &Path, repair: &str) -> std::path::PathBuf {
    let text = super::super::with_urdf(&format!(
        "version = 1\nsensing = \"kinematic\"\n{}[[objects]]\nmesh = {:?}\nname = \"box\"\n\
         position_m = [0.55, 0, 0]\nrepair = \"{repair}\"\n{}[output]\ndir = \"out\"\n",
        super::super::ARM,
        s(mesh),
        super::super::WAYPOINT
    ));
    let p = dir.join("scenario.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// Either byte edits or number replacements.
fn file_edits() -> impl Strategy<Value = (Vec<ByteEdit>, Vec<(usize, &'static str)>, bool)> {
    (byte_edits(), number_edits(), any::<bool>())
}

fn mutated(bytes: &[u8], edits: &(Vec<ByteEdit>, Vec<(usize, &'static str)>, bool)) -> Vec<u8> {
    let (bytes_edits, numbers, by_number) = edits;
    match std::str::from_utf8(bytes) {
        Ok(text) if *by_number => apply_numbers(text, numbers).into_bytes(),
        _ => apply_bytes(bytes, bytes_edits),
    }
}

proptest! {
    #![proptest_config(config(200))]

    /// Meshes: `whisker check` of a scenario holding the mutated Box.
    #[test]
    fn fuzz_meshes(
        encoding in prop::sample::select(ENCODINGS),
        repair in prop::sample::select(&["auto", "hull", "voxel", "soup"][..]),
        edits in file_edits(),
    ) {
        let tmp = tempfile::tempdir().unwrap();
        let (ext, bytes) = encoded(encoding);
        let mesh = tmp.path().join(format!("fuzzed.{ext}"));
        std::fs::write(&mesh, mutated(&bytes, &edits)).unwrap();
        let scenario = object_scenario(tmp.path(), &mesh, repair);
        run(&Case {
            args: vec!["check".into(), s(&scenario)],
            cwd: tmp.path(),
            names: vec!["fuzzed.".into(), "scenario.toml".into()],
            watch: vec![],
        })?;
    }

    /// The URDF: `whisker check` of a scenario on the mutated arm, and `urdf fk`.
    #[test]
    fn fuzz_urdf(edits in file_edits(), nest in prop::sample::select(&[0usize, 0, 0, 63, 64, 20000][..])) {
        let tmp = tempfile::tempdir().unwrap();
        let text = std::fs::read(repo("assets/urdf/ur5_whisker_array.urdf")).unwrap();
        let mut bytes = mutated(&text, &edits);
        if nest > 0 {
            // Elements nested `nest` deep inside the robot (the URDF's own depth is ~4).
            let t = String::from_utf8_lossy(&bytes).into_owned();
            let deep = format!("{}{}", "<visual>".repeat(nest), "</visual>".repeat(nest));
            bytes = t.replacen("</robot>", &format!("<link name=\"deep\">{deep}</link></robot>"), 1).into_bytes();
        }
        let urdf = tmp.path().join("fuzzed.urdf");
        std::fs::write(&urdf, &bytes).unwrap();
        let scenario = tmp.path().join("scenario.toml");
        std::fs::write(&scenario, format!(
            "[arm]\nurdf = {:?}\ninitial_joints_deg = [0, -90, 90, -90, -90, 0]\n{}",
            s(&urdf), super::super::WAYPOINT
        )).unwrap();
        let names = vec!["fuzzed.urdf".to_string(), "scenario.toml".into()];
        run(&Case { args: vec!["check".into(), s(&scenario)], cwd: tmp.path(), names: names.clone(), watch: vec![] })?;
        run(&Case {
            args: vec!["urdf".into(), "fk".into(), s(&urdf), "--joints".into(), "0,0,0,0,0,0".into()],
            cwd: tmp.path(), names, watch: vec![],
        })?;
    }

    /// Object maps: the closed loop of `scenarios/quickstart.toml` knowing a mutated Box map.
    #[test]
    fn fuzz_object_maps(edits in tree_edits()) {
        let tmp = tempfile::tempdir().unwrap();
        let map: serde_json::Value = serde_json::from_slice(&std::fs::read(repo("assets/maps/box.json")).unwrap()).unwrap();
        let path = tmp.path().join("fuzzed_map.json");
        std::fs::write(&path, apply_tree(&map, &edits).to_string()).unwrap();
        let text = absolute_assets(&std::fs::read_to_string(repo("scenarios/quickstart.toml")).unwrap())
            .replace(&format!("{:?}", s(&repo("assets/maps/box.json"))), &format!("{:?}", s(&path)));
        let scenario = tmp.path().join("scenario.toml");
        std::fs::write(&scenario, text).unwrap();
        run(&Case {
            args: vec!["check".into(), s(&scenario)],
            cwd: tmp.path(),
            names: vec!["fuzzed_map.json".into(), "scenario.toml".into()],
            watch: vec![],
        })?;
    }

    /// Radial-distance models (tree edits of svr10) and the validation set (text edits),
    /// through `whisker radial eval`.
    #[test]
    fn fuzz_radial_models(edits in tree_edits(), data_edits in file_edits(), which in any::<bool>()) {
        let tmp = tempfile::tempdir().unwrap();
        let models = tmp.path().join("models");
        std::fs::create_dir(&models).unwrap();
        let model: serde_json::Value = serde_json::from_slice(&std::fs::read(repo("assets/models/svr10.json")).unwrap()).unwrap();
        let data = tmp.path().join("validation.csv");
        let good_data = std::fs::read(repo("assets/radial/validation.csv")).unwrap();
        if which {
            std::fs::write(models.join("svr10.json"), apply_tree(&model, &edits).to_string()).unwrap();
            std::fs::write(&data, &good_data).unwrap();
        } else {
            std::fs::write(models.join("svr10.json"), model.to_string()).unwrap();
            std::fs::write(&data, mutated(&good_data, &data_edits)).unwrap();
        }
        run(&Case {
            args: vec!["radial".into(), "eval".into(), "--data".into(), s(&data), "--models".into(), s(&models)],
            cwd: tmp.path(),
            names: vec!["svr10.json".into(), "validation.csv".into()],
            watch: vec![],
        })?;
    }
}
