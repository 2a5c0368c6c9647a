//! Mesh loading and repair (issue: environments; #20). The generated catalogue:
//! `catalogue.rs`.
//!
//! Round trips check the loaders against a solid of known volume written in every
//! format; repairs check that damaged copies come back closed, outward and with the same
//! volume; malformed files must give an error naming the file and place, never a panic.

use std::path::{Path, PathBuf};
use whisker_sim::environment::mesh::{MeshOptions, Origin, Repair, Units, UpAxis, bounds, load};

/// The reference solid: a 0.2 × 0.3 × 0.5 box from the origin, volume 0.03.
const SIZE: [f64; 3] = [0.2, 0.3, 0.5];
const VOLUME: f64 = 0.2 * 0.3 * 0.5;

fn corners() -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| {
            [
                SIZE[0] * (i & 1) as f64,
                SIZE[1] * ((i >> 1) & 1) as f64,
                SIZE[2] * ((i >> 2) & 1) as f64,
            ]
        })
        .collect()
}

/// The six faces as outward counter-clockwise quads of `corners()` (0-based).
const QUADS: [[u32; 4]; 6] = [
    [0, 2, 3, 1], // z = 0, normal −z
    [4, 5, 7, 6], // z = top
    [0, 1, 5, 4], // y = 0
    [2, 6, 7, 3], // y = top
    [0, 4, 6, 2], // x = 0
    [1, 3, 7, 5], // x = top
];

fn triangles() -> Vec<[u32; 3]> {
    QUADS
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn obj_quads(scale: f64) -> String {
    let mut s = String::from("# quads\no box\n");
    for c in corners() {
        s += &format!("v {} {} {}\n", c[0] * scale, c[1] * scale, c[2] * scale);
    }
    for q in QUADS {
        s += &format!(
            "f {}/1/1 {}//2 {} {}\n",
            q[0] + 1,
            q[1] + 1,
            q[2] + 1,
            q[3] + 1
        );
    }
    s
}

fn stl_binary(header: &[u8; 80]) -> Vec<u8> {
    let c = corners();
    let t = triangles();
    let mut b = header.to_vec();
    b.extend((t.len() as u32).to_le_bytes());
    for tri in t {
        b.extend([0u8; 12]);
        for i in tri {
            for x in c[i as usize] {
                b.extend((x as f32).to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

fn stl_ascii() -> String {
    let c = corners();
    let mut s = String::from("solid box\n");
    for tri in triangles() {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for i in tri {
            let v = c[i as usize];
            s += &format!("      vertex {} {} {}\n", v[0], v[1], v[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + "endsolid box\n"
}

fn ply(format: &str) -> Vec<u8> {
    let c = corners();
    let mut b = format!(
        "ply\nformat {format} 1.0\ncomment test\nelement vertex 8\nproperty float x\n\
         property float y\nproperty float z\nproperty uchar red\nelement face 6\n\
         property list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    let big = format == "binary_big_endian";
    for v in &c {
        match format {
            "ascii" => b.extend(format!("{} {} {} 255\n", v[0], v[1], v[2]).bytes()),
            _ => {
                for x in v {
                    let f = *x as f32;
                    b.extend(if big {
                        f.to_be_bytes()
                    } else {
                        f.to_le_bytes()
                    });
                }
                b.push(255);
            }
        }
    }
    for q in QUADS {
        match format {
            "ascii" => b.extend(format!("4 {} {} {} {}\n", q[0], q[1], q[2], q[3]).bytes()),
            _ => {
                b.push(4);
                for i in q {
                    let i = i as i32;
                    b.extend(if big {
                        i.to_be_bytes()
                    } else {
                        i.to_le_bytes()
                    });
                }
            }
        }
    }
    b
}

fn assert_box(path: &Path, options: &MeshOptions, size: [f64; 3]) {
    let loaded = load(path, options).unwrap_or_else(|e| panic!("{e}"));
    let m = &loaded.mesh;
    assert!(m.is_closed_and_consistent(), "{}", path.display());
    assert!(
        (m.volume() - size.iter().product::<f64>()).abs() < 1e-7,
        "{}: volume {}",
        path.display(),
        m.volume()
    );
    let s = m.size();
    for k in 0..3 {
        assert!(
            (s[k] - size[k]).abs() < 1e-7,
            "{}: size {s:?}",
            path.display()
        );
    }
    assert_eq!(
        m.vertices.len(),
        8,
        "{}: welded to the 8 corners",
        path.display()
    );
}

#[test]
fn every_format_reads_the_same_solid() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let opts = MeshOptions::default();
    assert_box(
        &write(d, "quads.obj", obj_quads(1.0).as_bytes()),
        &opts,
        SIZE,
    );
    assert_box(&write(d, "ascii.stl", stl_ascii().as_bytes()), &opts, SIZE);
    assert_box(
        &write(d, "binary.stl", &stl_binary(&[b' '; 80])),
        &opts,
        SIZE,
    );
    // A binary STL whose header begins with "solid" (many exporters write that).
    let mut header = [b' '; 80];
    header[..11].copy_from_slice(b"solid box  ");
    assert_box(
        &write(d, "solid_header.stl", &stl_binary(&header)),
        &opts,
        SIZE,
    );
    for f in ["ascii", "binary_little_endian", "binary_big_endian"] {
        assert_box(&write(d, &format!("{f}.ply"), &ply(f)), &opts, SIZE);
    }
}

#[test]
fn units_scale_and_up_axis() {
    let dir = tempfile::tempdir().unwrap();
    let mm = write(dir.path(), "mm.obj", obj_quads(1000.0).as_bytes());
    let options = MeshOptions {
        units: Units::Millimetres,
        ..Default::default()
    };
    assert_box(&mm, &options, SIZE);
    let doubled = MeshOptions {
        scale: 2.0,
        ..options
    };
    let m = load(&mm, &doubled).unwrap().mesh;
    assert!((m.volume() - 8.0 * VOLUME).abs() < 1e-7);
    // Y up: the file's y (0.3) becomes z, its z (0.5) becomes y.
    let y_up = MeshOptions {
        up: UpAxis::Y,
        ..options
    };
    assert_box(&mm, &y_up, [SIZE[0], SIZE[2], SIZE[1]]);
}

#[test]
fn repairs_restore_a_closed_outward_solid() {
    let dir = tempfile::tempdir().unwrap();
    let c = corners();
    let text = |tris: &[[u32; 3]], header: &str| {
        let mut s = String::from(header);
        for v in &c {
            s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
        }
        for t in tris {
            s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    };
    let cases: Vec<(&str, Vec<[u32; 3]>, &str)> = vec![
        (
            "one_flipped",
            {
                let mut t = triangles();
                t[5].swap(1, 2);
                t
            },
            "re-wound",
        ),
        (
            "inside_out",
            triangles().iter().map(|t| [t[0], t[2], t[1]]).collect(),
            "inside-out",
        ),
        ("missing_face", triangles()[2..].to_vec(), "closed 1 hole"),
        (
            "duplicated_face",
            {
                let mut t = triangles();
                t.push(t[4]);
                t
            },
            "dropped 1 duplicate",
        ),
        (
            "duplicated_face_reversed",
            {
                let mut t = triangles();
                t.push([t[7][0], t[7][2], t[7][1]]);
                t
            },
            // The face and its reverse cancel; the hole left is closed again.
            "wound oppositely",
        ),
    ];
    for (name, tris, repair) in cases {
        let path = write(
            dir.path(),
            &format!("{name}.obj"),
            text(&tris, "").as_bytes(),
        );
        let loaded = load(&path, &MeshOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(loaded.mesh.is_closed_and_consistent(), "{name}");
        assert!(
            (loaded.mesh.volume() - VOLUME).abs() < 1e-12,
            "{name}: {}",
            loaded.mesh.volume()
        );
        assert!(
            loaded.repairs.iter().any(|r| r.contains(repair)),
            "{name}: {:?}",
            loaded.repairs
        );
    }
    // Two objects in one file, one of them inside-out: two outward components.
    let mut s = obj_quads(1.0);
    s += "o second\n";
    for v in &c {
        s += &format!("v {} {} {}\n", v[0] + 1.0, v[1], v[2]);
    }
    for t in triangles() {
        s += &format!("f {} {} {}\n", t[0] + 9, t[2] + 9, t[1] + 9);
    }
    let loaded = load(
        &write(dir.path(), "two.obj", s.as_bytes()),
        &MeshOptions::default(),
    )
    .unwrap();
    assert_eq!(loaded.objects, 2);
    let volumes = loaded.mesh.component_volumes();
    assert_eq!(volumes.len(), 2);
    assert!(
        volumes.iter().all(|v| (v - VOLUME).abs() < 1e-12),
        "{volumes:?}"
    );
}

#[test]
fn malformed_files_are_refused_with_their_place() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "nan.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n".to_vec(),
            "line 3",
        ),
        (
            "index.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n".to_vec(),
            "line 4",
        ),
        (
            "two_corners.obj",
            b"v 0 0 0\nv 1 0 0\nf 1 2\n".to_vec(),
            "line 3",
        ),
        ("word.obj", b"v 0 0 zero\n".to_vec(), "line 1"),
        ("empty.obj", b"# nothing\n".to_vec(), "empty mesh"),
        ("short.stl", vec![0u8; 40], "too short"),
        (
            "truncated.stl",
            stl_binary(&[b' '; 80])[..300].to_vec(),
            "header",
        ),
        (
            "bad_format.ply",
            b"ply\nformat binary_middle_endian 1.0\nend_header\n".to_vec(),
            "format",
        ),
        (
            "no_end.ply",
            b"ply\nformat ascii 1.0\nelement vertex 3\n".to_vec(),
            "end_header",
        ),
        (
            "truncated.ply",
            {
                let b = ply("binary_little_endian");
                b[..b.len() - 10].to_vec()
            },
            "truncated",
        ),
        (
            "nonmanifold.obj",
            // Three sheets on one edge: split apart, each encloses nothing.
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n".to_vec(),
            "no volume",
        ),
        ("cube.dae", b"<COLLADA/>".to_vec(), "unknown mesh format"),
    ];
    for (name, bytes, expected) in cases {
        let path = write(dir.path(), name, &bytes);
        let err = load(&path, &MeshOptions::default()).expect_err(name);
        let text = err.to_string();
        assert!(text.contains(name), "{name}: {text}");
        assert!(
            text.contains(expected),
            "{name}: expected {expected:?} in {text}"
        );
    }
    let missing = load(&dir.path().join("missing.obj"), &MeshOptions::default()).unwrap_err();
    assert!(missing.to_string().contains("cannot read"), "{missing}");
    let bad_scale = MeshOptions {
        scale: -1.0,
        ..Default::default()
    };
    let p = write(dir.path(), "ok.obj", obj_quads(1.0).as_bytes());
    assert!(
        load(&p, &bad_scale)
            .unwrap_err()
            .to_string()
            .contains("scale")
    );
}

/// An OBJ of boxes (the reference box moved by each offset), each with its own vertices.
fn boxes_obj(offsets: &[[f64; 3]], extra: &str) -> String {
    let mut s = String::new();
    for (k, o) in offsets.iter().enumerate() {
        s += &format!("o box{k}\n");
        for c in corners() {
            s += &format!("v {} {} {}\n", c[0] + o[0], c[1] + o[1], c[2] + o[2]);
        }
        for t in triangles() {
            let b = 8 * k as u32 + 1;
            s += &format!("f {} {} {}\n", t[0] + b, t[1] + b, t[2] + b);
        }
    }
    s + extra
}

#[test]
fn solids_sharing_an_edge_or_a_corner_are_split_and_sheets_refused() {
    let dir = tempfile::tempdir().unwrap();
    // Two boxes sharing the vertical edge x = 0.2, y = 0.3 (four triangles on it once
    // welded), and two touching at the corner (0.2, 0.3, 0.5) only.
    for (name, offset, split) in [
        ("edge", [SIZE[0], SIZE[1], 0.0], 2),
        ("corner", [SIZE[0], SIZE[1], SIZE[2]], 1),
    ] {
        let path = write(
            dir.path(),
            &format!("{name}.obj"),
            boxes_obj(&[[0.0; 3], offset], "").as_bytes(),
        );
        let loaded = load(&path, &MeshOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(loaded.mesh.is_closed_and_consistent(), "{name}");
        let volumes = loaded.mesh.component_volumes();
        assert_eq!(volumes.len(), 2, "{name}");
        assert!(
            volumes.iter().all(|v| (v - VOLUME).abs() < 1e-12),
            "{name}: {volumes:?}"
        );
        let expect = format!("split {split} vertex");
        assert!(
            loaded.repairs.iter().any(|r| r.contains(&expect)),
            "{name}: {:?}",
            loaded.repairs
        );
    }
    // A fin: one triangle on the box's edge x = 0.2, y = 0.3 (a 3-way edge), sticking out.
    // Split off, it is a sheet with no volume: refused, naming the file.
    let fin = "o fin\nv 0.2 0.3 0\nv 0.2 0.3 0.5\nv 0.4 0.5 0.25\nf 9 10 11\n";
    let path = write(
        dir.path(),
        "fin.obj",
        boxes_obj(&[[0.0; 3]], fin).as_bytes(),
    );
    let e = load(&path, &MeshOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("fin.obj") && e.contains("no volume"), "{e}");
    assert!(e.contains("repair = \"hull\""), "{e}");
    // repair = "hull": the convex hull of the box and the fin's apex (0.4, 0.5, 0.25) is
    // the box plus the pyramids from the apex over the two faces it sees, x = 0.2 (area
    // 0.15, height 0.2) and y = 0.3 (area 0.1, height 0.2).
    let hull = MeshOptions {
        repair: Repair::Hull,
        ..Default::default()
    };
    let loaded = load(&path, &hull).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.mesh.is_closed_and_consistent());
    let expected = VOLUME + 0.15 * 0.2 / 3.0 + 0.1 * 0.2 / 3.0;
    assert!(
        (loaded.mesh.volume() - expected).abs() < 1e-12,
        "{}",
        loaded.mesh.volume()
    );
    // Its reported deviation: positive (the pyramids' faces leave the fin's triangle),
    // below the apex's distance from the box's corner edge (0.2·√2 m).
    let report = loaded.repairs.join("; ");
    let max_mm: f64 = report
        .split("up to ")
        .nth(1)
        .and_then(|r| r.split(" mm").next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{report}"));
    assert!(max_mm > 1.0 && max_mm < 200.0 * 2f64.sqrt(), "{report}");
    // And the hull of a clean box is the box, 0 mm from it.
    let clean = write(dir.path(), "clean.obj", obj_quads(1.0).as_bytes());
    let loaded = load(&clean, &hull).unwrap();
    assert!((loaded.mesh.volume() - VOLUME).abs() < 1e-12);
    assert!(
        loaded.repairs[0].contains("up to 0.0 mm"),
        "{:?}",
        loaded.repairs
    );
}

#[test]
fn strict_refuses_what_auto_repairs_and_accepts_a_clean_solid() {
    let dir = tempfile::tempdir().unwrap();
    let strict = MeshOptions {
        repair: Repair::Strict,
        ..Default::default()
    };
    let clean = write(dir.path(), "clean.obj", obj_quads(1.0).as_bytes());
    assert!(load(&clean, &strict).unwrap().repairs.is_empty());
    let mut s = obj_quads(1.0);
    s += "f 1 3 4\n"; // the first face's first triangle again, as a separate polygon
    let damaged = write(dir.path(), "damaged.obj", s.as_bytes());
    let e = load(&damaged, &strict).unwrap_err().to_string();
    assert!(
        e.contains("damaged.obj") && e.contains("duplicate") && e.contains("\"auto\" would"),
        "{e}"
    );
    assert!(load(&damaged, &MeshOptions::default()).is_ok());
}

#[test]
fn origin_base_stands_the_mesh_on_z_0_centred() {
    // The reference box moved to (5, −3, 2) in its file: with origin = "base" its bounding
    // box runs from (−0.1, −0.15, 0) to (0.1, 0.15, 0.5), after the scale too.
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "far.obj",
        boxes_obj(&[[5.0, -3.0, 2.0]], "").as_bytes(),
    );
    let options = MeshOptions {
        origin: Origin::Base,
        scale: 2.0,
        ..Default::default()
    };
    let mesh = load(&path, &options).unwrap().mesh;
    let (lo, hi) = bounds(&mesh.vertices);
    let want_lo = [-SIZE[0], -SIZE[1], 0.0];
    let want_hi = [SIZE[0], SIZE[1], 2.0 * SIZE[2]];
    for k in 0..3 {
        assert!((lo[k] - want_lo[k]).abs() < 1e-9, "{lo}");
        assert!((hi[k] - want_hi[k]).abs() < 1e-9, "{hi}");
    }
    assert!((mesh.volume() - 8.0 * VOLUME).abs() < 1e-9);
}
