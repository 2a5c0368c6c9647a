//! Repairs of meshes from the wild (#20), on meshes generated here: T-junctions, slits,
//! open cylinders, parts sharing a face, double-sided files, holes that cannot be closed
//! honestly. Every repaired result must be a closed, consistently oriented solid of the
//! intended volume (computed independently from the shape's dimensions). The fallbacks
//! (`voxel`, `hull`, `soup`) and decimation: `mesh_fallbacks.rs`.

mod mesh_gen;

use mesh_gen::*;
use std::f64::consts::PI;
use whisker_sim::environment::mesh::{MeshOptions, load};

#[test]
fn a_t_junction_is_split_without_moving_the_surface() {
    // A 0.2 × 0.3 × 0.5 box whose top face is cut into three triangles at the midpoint
    // m of its edge y = 0; the side face y = 0 does not have m.
    let dir = tempfile::tempdir().unwrap();
    let mut v = box_corners(0.2, 0.3, 0.5);
    v.push([0.1, 0.0, 0.5]); // m = 8
    let faces = vec![
        vec![0, 2, 3, 1],
        vec![4, 8, 6],
        vec![8, 7, 6],
        vec![8, 5, 7],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
    ];
    let loaded = auto(&obj(dir.path(), "t.obj", &v, &faces));
    assert_solid("t-junction", &loaded, 0.03, 1e-12, "1 T-junction");
    // Nothing else was needed: no hole filled with slivers.
    assert!(
        !loaded.repairs.iter().any(|r| r.contains("hole")),
        "{:?}",
        loaded.repairs
    );
}

#[test]
fn a_zero_width_slit_is_closed_up() {
    // A box a × b × c with a saw cut of zero width across it at y = y0, from the top
    // down to depth d: the two cut walls coincide with opposite windings, and each end
    // face is three rectangles whose lower one has a T-junction at (y0, c − d).
    let (a, b, c, y0, d) = (0.2, 0.3, 0.5, 0.1, 0.2);
    let dir = tempfile::tempdir().unwrap();
    let mut v: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<Vec<u32>> = Vec::new();
    // An axis-aligned rectangle as a quad wound so that its normal is `normal`.
    let mut rect = |corners: [[f64; 3]; 4], normal: [f64; 3]| {
        let n = v.len() as u32;
        v.extend(corners);
        let e1: Vec<f64> = (0..3).map(|k| corners[1][k] - corners[0][k]).collect();
        let e2: Vec<f64> = (0..3).map(|k| corners[2][k] - corners[0][k]).collect();
        let cross = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let dot: f64 = (0..3).map(|k| cross[k] * normal[k]).sum();
        faces.push(if dot > 0.0 {
            vec![n, n + 1, n + 2, n + 3]
        } else {
            vec![n, n + 3, n + 2, n + 1]
        });
    };
    let (t, m) = (c, c - d);
    rect(
        [[0., 0., 0.], [a, 0., 0.], [a, b, 0.], [0., b, 0.]],
        [0., 0., -1.],
    );
    rect(
        [[0., 0., t], [a, 0., t], [a, y0, t], [0., y0, t]],
        [0., 0., 1.],
    );
    rect(
        [[0., y0, t], [a, y0, t], [a, b, t], [0., b, t]],
        [0., 0., 1.],
    );
    rect(
        [[0., 0., 0.], [a, 0., 0.], [a, 0., t], [0., 0., t]],
        [0., -1., 0.],
    );
    rect(
        [[0., b, 0.], [a, b, 0.], [a, b, t], [0., b, t]],
        [0., 1., 0.],
    );
    rect(
        [[0., y0, m], [a, y0, m], [a, y0, t], [0., y0, t]],
        [0., 1., 0.],
    ); // left wall
    rect(
        [[0., y0, m], [a, y0, m], [a, y0, t], [0., y0, t]],
        [0., -1., 0.],
    ); // right wall
    for (x, nx) in [(0.0, -1.0), (a, 1.0)] {
        rect(
            [[x, 0., 0.], [x, b, 0.], [x, b, m], [x, 0., m]],
            [nx, 0., 0.],
        );
        rect(
            [[x, 0., m], [x, y0, m], [x, y0, t], [x, 0., t]],
            [nx, 0., 0.],
        );
        rect([[x, y0, m], [x, b, m], [x, b, t], [x, y0, t]], [nx, 0., 0.]);
    }
    let loaded = auto(&obj(dir.path(), "slit.obj", &v, &faces));
    assert_solid(
        "slit",
        &loaded,
        a * b * c,
        1e-12,
        "4 coincident triangle(s) wound oppositely",
    );
    assert!(
        loaded.repairs.iter().any(|r| r.contains("T-junction")),
        "{:?}",
        loaded.repairs
    );
    assert_eq!(loaded.mesh.component_volumes().len(), 1);
}

#[test]
fn parts_sharing_a_face_become_their_union() {
    // Two boxes stacked, each closed, so their common face is there twice, wound
    // oppositely: the union, one solid of twice the volume.
    let dir = tempfile::tempdir().unwrap();
    let mut v = box_corners(0.2, 0.3, 0.5);
    v.extend(
        box_corners(0.2, 0.3, 0.5)
            .iter()
            .map(|p| [p[0], p[1], p[2] + 0.5]),
    );
    let quads = BOX_QUADS;
    let faces: Vec<Vec<u32>> = [0u32, 8]
        .iter()
        .flat_map(|&o| {
            quads.iter().flat_map(move |q| {
                [
                    vec![q[0] + o, q[1] + o, q[2] + o],
                    vec![q[0] + o, q[2] + o, q[3] + o],
                ]
            })
        })
        .collect();
    let loaded = auto(&obj(dir.path(), "stack.obj", &v, &faces));
    assert_solid("stack", &loaded, 0.06, 1e-12, "wound oppositely");
    assert_eq!(loaded.mesh.component_volumes().len(), 1);
}

#[test]
fn an_open_cylinder_gets_its_caps() {
    // Both open ends are planar: closed whatever their number of edges, giving the
    // prism n/2 · r² · sin(2π/n) · h exactly.
    let dir = tempfile::tempdir().unwrap();
    let (r, h) = (0.05, 0.12);
    for n in [24, 64, 200] {
        let (v, faces) = tube(n, r, |_| h);
        let loaded = auto(&obj(dir.path(), &format!("tube{n}.obj"), &v, &faces));
        let prism = n as f64 / 2.0 * r * r * (2.0 * PI / n as f64).sin() * h;
        assert_solid(
            &format!("tube {n}"),
            &loaded,
            prism,
            1e-9,
            "closed 2 hole(s)",
        );
        assert_eq!(
            loaded
                .repairs
                .iter()
                .any(|r| r.contains("planar with more than")),
            n > 32,
            "{:?}",
            loaded.repairs
        );
    }
}

#[test]
fn a_large_hole_that_is_not_planar_is_refused_naming_the_fallbacks() {
    // A 64-sided tube whose upper rim is a saddle (z = h + 0.3 r sin 2θ): capping it
    // would invent a surface.
    let dir = tempfile::tempdir().unwrap();
    let path = saddle_tube(dir.path());
    let e = load(&path, &MeshOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("saddle.obj") && e.contains("64 boundary edges"),
        "{e}"
    );
    assert!(e.contains("repair = \"hull\""), "{e}");
}

#[test]
fn a_double_sided_surface_keeps_each_face_once() {
    // Render models often carry every face twice, once per side: cancelling the pairs
    // would leave nothing, so one of each is kept.
    let dir = tempfile::tempdir().unwrap();
    let v = box_corners(0.2, 0.3, 0.5);
    let quads = BOX_QUADS;
    let faces: Vec<Vec<u32>> = quads
        .iter()
        .flat_map(|q| {
            let front = vec![q[0], q[1], q[2], q[3]];
            let back = vec![q[0], q[3], q[2], q[1]];
            [front, back]
        })
        .collect();
    let loaded = auto(&obj(dir.path(), "two_sided.obj", &v, &faces));
    assert_solid("two-sided", &loaded, 0.03, 1e-12, "double-sided");
}

#[test]
fn large_planar_holes_that_no_centre_sees_whole_are_capped_by_ear_clipping() {
    // A C-shaped prism (the 3 × 3 square without the 2 × 1 notch on its right, in 2 cm
    // units), open at both ends, its outline cut into 48 edges: the centre of the outline
    // lies in the notch, so no fan from it could cap the ends; clipping ears in the plane
    // does, giving the prism of area 7 × (2 cm)² and height 5 cm exactly.
    let dir = tempfile::tempdir().unwrap();
    let corners = [
        (0.0, 0.0),
        (3.0, 0.0),
        (3.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (3.0, 2.0),
        (3.0, 3.0),
        (0.0, 3.0),
    ];
    let (unit, h, cuts) = (0.02, 0.05, 6);
    let mut outline = Vec::new();
    for k in 0..corners.len() {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        for j in 0..cuts {
            let t = j as f64 / cuts as f64;
            outline.push((
                unit * (a.0 + (b.0 - a.0) * t),
                unit * (a.1 + (b.1 - a.1) * t),
            ));
        }
    }
    let n = outline.len() as u32;
    let mut v = Vec::new();
    for &(x, y) in &outline {
        v.push([x, y, 0.0]);
        v.push([x, y, h]);
    }
    let faces: Vec<Vec<u32>> = (0..n)
        .map(|k| {
            let j = (k + 1) % n;
            vec![2 * k, 2 * j, 2 * j + 1, 2 * k + 1]
        })
        .collect();
    let loaded = auto(&obj(dir.path(), "c_prism.obj", &v, &faces));
    let volume = 7.0 * unit * unit * h;
    assert_solid("C prism", &loaded, volume, 1e-9, "2 of them planar");
}
