//! Meshes generated for the mesh tests (#20) and assertions on what loading makes of
//! them, shared by `mesh_repair.rs` and `mesh_fallbacks.rs`.
#![allow(dead_code)] // not every test binary uses every helper

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use whisker_sim::environment::mesh::{LoadedMesh, MeshOptions, load};
use whisker_sim::environment::topology;

/// An OBJ file of `vertices` and polygons (0-based indices).
pub fn obj(dir: &Path, name: &str, vertices: &[[f64; 3]], faces: &[Vec<u32>]) -> PathBuf {
    let mut s = String::new();
    for v in vertices {
        s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
    }
    for f in faces {
        s += "f";
        for i in f {
            s += &format!(" {}", i + 1);
        }
        s += "\n";
    }
    let path = dir.join(name);
    std::fs::write(&path, s).unwrap();
    path
}

/// Loads with the default policy (auto), panicking with the error.
pub fn auto(path: &Path) -> LoadedMesh {
    load(path, &MeshOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Asserts a closed, consistently wound solid of `volume` (relative tolerance `rel`),
/// every component outward and no triangle degenerate, and a repair containing `repair`.
pub fn assert_solid(name: &str, loaded: &LoadedMesh, volume: f64, rel: f64, repair: &str) {
    let mesh = &loaded.mesh;
    assert!(mesh.is_closed_and_consistent(), "{name}: not closed");
    assert!(
        mesh.component_volumes().iter().all(|&v| v > 0.0),
        "{name}: {:?}",
        mesh.component_volumes()
    );
    for t in 0..mesh.triangles.len() {
        assert!(
            mesh.normal(t).norm() > 0.5,
            "{name}: triangle {t} degenerate"
        );
    }
    assert!(
        (mesh.volume() - volume).abs() <= rel * volume,
        "{name}: volume {} against {volume}",
        mesh.volume()
    );
    assert!(
        loaded.repairs.iter().any(|r| r.contains(repair)),
        "{name}: {:?}",
        loaded.repairs
    );
}

/// The faces of [`box_corners`] as outward counter-clockwise quads.
pub const BOX_QUADS: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

/// The corners of an a × b × c box from the origin, indexed by bits (x, y, z).
pub fn box_corners(a: f64, b: f64, c: f64) -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| {
            [
                a * (i & 1) as f64,
                b * ((i >> 1) & 1) as f64,
                c * ((i >> 2) & 1) as f64,
            ]
        })
        .collect()
}

/// A tube of `n` sides, radius r, from z = 0 to the rim z = top(θ), no caps.
pub fn tube(n: usize, r: f64, top: impl Fn(f64) -> f64) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let mut v = Vec::new();
    for k in 0..n {
        let th = 2.0 * PI * k as f64 / n as f64;
        v.push([r * th.cos(), r * th.sin(), 0.0]);
        v.push([r * th.cos(), r * th.sin(), top(th)]);
    }
    let faces = (0..n as u32)
        .map(|k| {
            let j = (k + 1) % n as u32;
            vec![2 * k, 2 * j, 2 * j + 1, 2 * k + 1]
        })
        .collect();
    (v, faces)
}

/// Radius and height of [`saddle_tube`].
pub const SADDLE_R: f64 = 0.05;
pub const SADDLE_H: f64 = 0.12;

/// A 64-sided open tube whose upper rim is a saddle (z = h + 0.3 r sin 2θ), written
/// into `dir`.
pub fn saddle_tube(dir: &Path) -> PathBuf {
    let (v, faces) = tube(64, SADDLE_R, |th| {
        SADDLE_H + 0.3 * SADDLE_R * (2.0 * th).sin()
    });
    obj(dir, "saddle.obj", &v, &faces)
}

/// The "up to X mm (mean Y mm)" deviation a fallback reports, in metres.
pub fn reported_deviation(loaded: &LoadedMesh) -> (f64, f64) {
    let report = loaded.repairs.join("; ");
    let number = |after: &str| -> f64 {
        report
            .split(after)
            .nth(1)
            .and_then(|r| r.split(" mm").next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{report}"))
    };
    (number("up to ") * 1e-3, number("(mean ") * 1e-3)
}

/// Surface area of a mesh.
pub fn area(mesh: &whisker_sim::environment::Mesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            (b - a).cross(&(c - a)).norm() / 2.0
        })
        .sum()
}

/// Asserts that a fallback result is a closed 2-manifold solid that the repairs of
/// `auto` leave alone, and that its volume differs from `volume` by no more than a shell
/// of the reported maximum deviation over the surface `surface` would allow.
pub fn assert_fallback(name: &str, loaded: &LoadedMesh, volume: f64, surface: f64) {
    let mesh = &loaded.mesh;
    assert!(loaded.solid, "{name}");
    assert!(mesh.is_closed_and_consistent(), "{name}: not closed");
    let (again, repairs) = topology::close_and_orient(
        mesh.vertices.clone(),
        mesh.triangles.clone(),
        vec![String::new(); mesh.triangles.len()],
    )
    .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    assert!(repairs.is_empty(), "{name}: {repairs:?}");
    assert_eq!(again.triangles.len(), mesh.triangles.len());
    let (max, mean) = reported_deviation(loaded);
    assert!(mean <= max, "{name}");
    assert!(
        (mesh.volume() - volume).abs() <= surface * max,
        "{name}: volume {} against {volume}, deviation {max}",
        mesh.volume()
    );
}

/// A 0.2 × 0.3 × 0.5 box whose faces are each an n × n grid of quads (vertices shared).
pub fn grid_box(n: usize) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let size = [0.2, 0.3, 0.5];
    let mut index = std::collections::HashMap::new();
    let mut v: Vec<[f64; 3]> = Vec::new();
    let mut at = |p: [usize; 3]| {
        *index.entry(p).or_insert_with(|| {
            v.push([0, 1, 2].map(|k| size[k] * p[k] as f64 / n as f64));
            (v.len() - 1) as u32
        })
    };
    let mut faces = Vec::new();
    for a in 0..3 {
        let (u, w) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: usize, dj: usize| {
                        let mut p = [0; 3];
                        p[a] = side;
                        p[u] = i + di;
                        p[w] = j + dj;
                        p
                    };
                    let mut q =
                        [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)].map(&mut at);
                    if side == 0 {
                        q.swap(1, 3);
                    }
                    faces.push(q.to_vec());
                }
            }
        }
    }
    (v, faces)
}
