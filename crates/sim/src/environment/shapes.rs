//! Closed triangle meshes built from primitives, for the generated object catalogue
//! ([`super::assets`]) and the maze ([`super::maze`]).
//!
//! Most shapes are a [`stack`] of cross-sections joined in order: a lathe (profile
//! revolved about z), a tube swept along a path, a star-shaped surface (latitude rings
//! of a radius function), a prism. A stack that starts and ends with a single point is
//! closed by construction. Unions of axis-aligned boxes are meshed on the grid of their
//! corner coordinates ([`box_union`]), so faces meet without T-junctions.

use super::triangles::{Mesh, signed_volume};
use nalgebra::{Isometry3, Point3, Unit, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::f64::consts::{PI, TAU};

/// A cross-section of a [`stack`]: a single point (a pole or cap centre) or a closed
/// loop of points (all loops of one stack have the same count).
#[derive(Debug, Clone)]
pub enum Section {
    /// A single point.
    Point(Point3<f64>),
    /// A closed loop.
    Loop(Vec<Point3<f64>>),
}

/// Joins cross-sections in order into one surface, consecutive loops by quads (two
/// triangles) and points by fans, then orients it outward. Closed when the first and
/// last sections are points.
pub fn stack(sections: &[Section]) -> Mesh {
    let mut vertices = Vec::new();
    let mut ids: Vec<Vec<u32>> = Vec::new();
    for s in sections {
        let start = vertices.len() as u32;
        match s {
            Section::Point(p) => {
                vertices.push(*p);
                ids.push(vec![start]);
            }
            Section::Loop(l) => {
                vertices.extend(l.iter().copied());
                ids.push((start..start + l.len() as u32).collect());
            }
        }
    }
    let n = ids.iter().map(Vec::len).max().unwrap_or(1);
    let at = |ring: &Vec<u32>, j: usize| ring[if ring.len() == 1 { 0 } else { j % n }];
    let mut triangles = Vec::new();
    for w in ids.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        for j in 0..n {
            let (a0, a1, b0, b1) = (at(a, j), at(a, j + 1), at(b, j), at(b, j + 1));
            if a0 != a1 {
                triangles.push([a0, a1, b1]);
            }
            if b0 != b1 {
                triangles.push([a0, b1, b0]);
            }
        }
    }
    outward(Mesh {
        vertices,
        triangles,
    })
}

/// Flips a single-component mesh whose signed volume is negative.
pub fn outward(mut mesh: Mesh) -> Mesh {
    if signed_volume(&mesh.vertices, &mesh.triangles) < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    mesh
}

/// A circle of `n` points of radius `r` about `centre` in the plane spanned by `u`, `v`.
fn circle(
    centre: Point3<f64>,
    u: Vector3<f64>,
    v: Vector3<f64>,
    r: f64,
    n: usize,
) -> Vec<Point3<f64>> {
    (0..n)
        .map(|j| {
            let a = TAU * j as f64 / n as f64;
            centre + (u * a.cos() + v * a.sin()) * r
        })
        .collect()
}

/// Surface of revolution about z of a profile `(r, z)` that starts and ends on the axis
/// (r = 0), with `n` segments around.
pub fn lathe(profile: &[(f64, f64)], n: usize) -> Mesh {
    let sections: Vec<Section> = profile
        .iter()
        .map(|&(r, z)| {
            if r == 0.0 {
                Section::Point(Point3::new(0.0, 0.0, z))
            } else {
                Section::Loop(circle(
                    Point3::new(0.0, 0.0, z),
                    Vector3::x(),
                    Vector3::y(),
                    r,
                    n,
                ))
            }
        })
        .collect();
    stack(&sections)
}

/// A closed tube of circular section swept along `path` with radius `radius(k)` at path
/// point k (`n` sides; section frames by parallel transport; flat end caps).
pub fn tube(path: &[Point3<f64>], radius: impl Fn(usize) -> f64, n: usize) -> Mesh {
    let m = path.len();
    let tangent = |k: usize| (path[(k + 1).min(m - 1)] - path[k.saturating_sub(1)]).normalize();
    let t0 = tangent(0);
    let seed = if t0.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let mut u = (seed - t0 * seed.dot(&t0)).normalize();
    let mut sections = vec![Section::Point(path[0])];
    let mut previous = t0;
    for (k, p) in path.iter().enumerate() {
        let t = tangent(k);
        if let Some(q) = UnitQuaternion::rotation_between(&previous, &t) {
            u = q * u;
        }
        u = (u - t * u.dot(&t)).normalize();
        previous = t;
        sections.push(Section::Loop(circle(*p, u, t.cross(&u), radius(k), n)));
    }
    sections.push(Section::Point(path[m - 1]));
    stack(&sections)
}

/// A star-shaped closed surface about the origin: the point in unit direction d is at
/// distance `radius(d)`; `rings` latitude rings of `n` points between the poles.
pub fn star(radius: impl Fn(Vector3<f64>) -> f64, rings: usize, n: usize) -> Mesh {
    let mut sections = vec![Section::Point(Point3::from(
        -Vector3::z() * radius(-Vector3::z()),
    ))];
    for i in 1..=rings {
        let polar = PI * i as f64 / (rings + 1) as f64;
        let ring = (0..n)
            .map(|j| {
                let a = TAU * j as f64 / n as f64;
                let d = Vector3::new(polar.sin() * a.cos(), polar.sin() * a.sin(), -polar.cos());
                Point3::from(d * radius(d))
            })
            .collect();
        sections.push(Section::Loop(ring));
    }
    sections.push(Section::Point(Point3::from(
        Vector3::z() * radius(Vector3::z()),
    )));
    stack(&sections)
}

/// A prism: the convex outline (x, y) extruded along z from `z0` to `z1`.
pub fn prism(outline: &[(f64, f64)], z0: f64, z1: f64) -> Mesh {
    let centre = outline
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let c = (
        centre.0 / outline.len() as f64,
        centre.1 / outline.len() as f64,
    );
    let ring = |z: f64| Section::Loop(outline.iter().map(|&(x, y)| Point3::new(x, y, z)).collect());
    stack(&[
        Section::Point(Point3::new(c.0, c.1, z0)),
        ring(z0),
        ring(z1),
        Section::Point(Point3::new(c.0, c.1, z1)),
    ])
}

/// An axis-aligned box from `lo` to `hi`.
pub fn cuboid(lo: Point3<f64>, hi: Point3<f64>) -> Mesh {
    box_union(&[(lo, hi)])
}

/// The union of axis-aligned boxes `(lo, hi)` as one closed mesh: the boxes' corner
/// coordinates cut space into cells; the faces between inside and outside cells are the
/// surface. Closed and manifold unless two boxes touch only along an edge.
pub fn box_union(boxes: &[(Point3<f64>, Point3<f64>)]) -> Mesh {
    let axis = |k: usize| {
        let mut c: Vec<f64> = boxes.iter().flat_map(|(lo, hi)| [lo[k], hi[k]]).collect();
        c.sort_by(f64::total_cmp);
        c.dedup();
        c
    };
    let grid = [axis(0), axis(1), axis(2)];
    let dims = [grid[0].len() - 1, grid[1].len() - 1, grid[2].len() - 1];
    let inside = |c: [i64; 3]| -> bool {
        if (0..3).any(|k| c[k] < 0 || c[k] >= dims[k] as i64) {
            return false;
        }
        let centre: Vec<f64> = (0..3)
            .map(|k| 0.5 * (grid[k][c[k] as usize] + grid[k][c[k] as usize + 1]))
            .collect();
        boxes
            .iter()
            .any(|(lo, hi)| (0..3).all(|k| lo[k] < centre[k] && centre[k] < hi[k]))
    };
    let mut index: HashMap<[usize; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut vertex = |g: [usize; 3]| -> u32 {
        *index.entry(g).or_insert_with(|| {
            vertices.push(Point3::new(grid[0][g[0]], grid[1][g[1]], grid[2][g[2]]));
            (vertices.len() - 1) as u32
        })
    };
    let mut triangles = Vec::new();
    for i in 0..dims[0] {
        for j in 0..dims[1] {
            for k in 0..dims[2] {
                let c = [i as i64, j as i64, k as i64];
                if !inside(c) {
                    continue;
                }
                for axis in 0..3 {
                    for side in [0usize, 1] {
                        let mut n = c;
                        n[axis] += if side == 1 { 1 } else { -1 };
                        if inside(n) {
                            continue;
                        }
                        // The face's four grid corners, counter-clockwise about +axis.
                        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
                        let corner = |d1: usize, d2: usize| {
                            let mut g = [i, j, k];
                            g[axis] += side;
                            g[a1] += d1;
                            g[a2] += d2;
                            g
                        };
                        let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                            .map(&mut vertex);
                        if side == 1 {
                            triangles.push([q[0], q[1], q[2]]);
                            triangles.push([q[0], q[2], q[3]]);
                        } else {
                            triangles.push([q[0], q[2], q[1]]);
                            triangles.push([q[0], q[3], q[2]]);
                        }
                    }
                }
            }
        }
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// Several meshes as one (each stays its own component).
pub fn merge(parts: &[Mesh]) -> Mesh {
    let mut out = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for p in parts {
        let base = out.vertices.len() as u32;
        out.vertices.extend(p.vertices.iter().copied());
        out.triangles
            .extend(p.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    out
}

/// A mesh moved by a rigid transform.
pub fn transformed(mesh: &Mesh, pose: &Isometry3<f64>) -> Mesh {
    Mesh {
        vertices: mesh.vertices.iter().map(|v| pose * v).collect(),
        triangles: mesh.triangles.clone(),
    }
}

/// A mesh scaled per axis about the origin (positive factors keep the winding).
pub fn scaled(mesh: &Mesh, s: Vector3<f64>) -> Mesh {
    Mesh {
        vertices: mesh
            .vertices
            .iter()
            .map(|v| Point3::from(v.coords.component_mul(&s)))
            .collect(),
        triangles: mesh.triangles.clone(),
    }
}

/// A rotation about an axis.
pub fn rotation(axis: Vector3<f64>, angle: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Vector3::zeros().into(),
        UnitQuaternion::from_axis_angle(&Unit::new_normalize(axis), angle),
    )
}
