//! Decimation of large closed meshes (issue #20, scans of a million triangles): edge
//! collapses ordered by the quadric error metric (Garland & Heckbert, "Surface
//! simplification using quadric error metrics", 1997).
//!
//! Each vertex carries the quadric of the planes of its original triangles; collapsing an
//! edge moves the merged vertex to the point that minimises the sum of the two quadrics
//! (or the better end point or midpoint when that point is ill-determined), and costs
//! that minimum: the sum of squared distances to the planes around. Collapses run
//! cheapest first until the mesh has at most the target number of triangles or the next
//! collapse would cost more than the tolerance squared. A collapse is skipped when it
//! would change the topology (the two end points must share exactly the two neighbours
//! opposite the edge, and those must keep at least three neighbours) or turn a triangle
//! over, so a closed, consistently wound mesh stays one. The quadric error bounds the
//! distance to the planes, not to the triangles: the caller measures and reports the
//! result's real deviation.

use super::edges::EdgeMap;
use super::triangles::Mesh;
use nalgebra::{Matrix3, Matrix4, Point3, Vector3, Vector4};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A candidate collapse, cheapest first in the heap.
struct Candidate {
    cost: f64,
    a: u32,
    b: u32,
    /// The end points' versions when the cost was computed (stale if either changed).
    stamp: (u32, u32),
    target: Point3<f64>,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: the heap pops the smallest cost; ties by vertex indices, so that the
        // order (and the result) never depends on anything but the mesh.
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| (other.a, other.b).cmp(&(self.a, self.b)))
    }
}

struct Decimator {
    positions: Vec<Point3<f64>>,
    quadrics: Vec<Matrix4<f64>>,
    triangles: Vec<[u32; 3]>,
    alive: Vec<bool>,
    /// Triangles around each vertex (alive or not; filtered when read).
    around: Vec<Vec<u32>>,
    version: Vec<u32>,
    live_triangles: usize,
}

impl Decimator {
    fn new(mesh: &Mesh) -> Self {
        let n = mesh.vertices.len();
        let mut quadrics = vec![Matrix4::zeros(); n];
        let mut around = vec![Vec::new(); n];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| mesh.vertices[i as usize]);
            if let Some(normal) = (b - a).cross(&(c - a)).try_normalize(0.0) {
                let plane = Vector4::new(normal.x, normal.y, normal.z, -normal.dot(&a.coords));
                let k = plane * plane.transpose();
                for &v in tri {
                    quadrics[v as usize] += k;
                }
            }
            for &v in tri {
                around[v as usize].push(t as u32);
            }
        }
        Self {
            positions: mesh.vertices.clone(),
            quadrics,
            triangles: mesh.triangles.clone(),
            alive: vec![true; mesh.triangles.len()],
            around,
            version: vec![0; n],
            live_triangles: mesh.triangles.len(),
        }
    }

    fn live_around(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.around[v as usize]
            .iter()
            .copied()
            .filter(|&t| self.alive[t as usize])
    }

    fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut out: Vec<u32> = self
            .live_around(v)
            .flat_map(|t| self.triangles[t as usize])
            .filter(|&w| w != v)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    fn candidate(&self, a: u32, b: u32) -> Candidate {
        let (a, b) = (a.min(b), a.max(b));
        let q = self.quadrics[a as usize] + self.quadrics[b as usize];
        let cost = |p: &Point3<f64>| {
            let h = Vector4::new(p.x, p.y, p.z, 1.0);
            (h.transpose() * q * h)[0].max(0.0)
        };
        let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
        let mid = nalgebra::center(&pa, &pb);
        let a3 = Matrix3::from_fn(|i, j| q[(i, j)]);
        let rhs = -Vector3::new(q[(0, 3)], q[(1, 3)], q[(2, 3)]);
        let scale = a3.norm();
        let optimum = (scale > 0.0 && a3.determinant().abs() > 1e-9 * scale.powi(3))
            .then(|| a3.try_inverse().map(|inv| Point3::from(inv * rhs)))
            .flatten()
            // Only trusted near the edge: far-off optima come from near-singular systems.
            .filter(|p| (p - mid).norm() <= 2.0 * (pb - pa).norm());
        let target = optimum
            .into_iter()
            .chain([pa, pb, mid])
            .min_by(|x, y| cost(x).total_cmp(&cost(y)))
            .expect("candidates");
        Candidate {
            cost: cost(&target),
            a,
            b,
            stamp: (self.version[a as usize], self.version[b as usize]),
            target,
        }
    }

    /// Whether collapsing (a, b) to `target` keeps the mesh a closed manifold without
    /// turning any triangle over.
    fn allowed(&self, a: u32, b: u32, target: &Point3<f64>) -> bool {
        let shared: Vec<u32> = self
            .live_around(a)
            .filter(|&t| self.triangles[t as usize].contains(&b))
            .collect();
        if shared.len() != 2 {
            return false;
        }
        let opposite: Vec<u32> = shared
            .iter()
            .flat_map(|&t| self.triangles[t as usize])
            .filter(|&w| w != a && w != b)
            .collect();
        let (na, nb) = (self.neighbours(a), self.neighbours(b));
        let common: Vec<u32> = na.iter().copied().filter(|w| nb.contains(w)).collect();
        if common.len() != 2 || !opposite.iter().all(|w| common.contains(w)) {
            return false;
        }
        if opposite.iter().any(|&w| self.neighbours(w).len() <= 3) {
            return false;
        }
        for v in [a, b] {
            for t in self.live_around(v) {
                let tri = self.triangles[t as usize];
                if tri.contains(&a) && tri.contains(&b) {
                    continue;
                }
                let p = tri.map(|i| self.positions[i as usize]);
                let moved = tri.map(|i| {
                    if i == a || i == b {
                        *target
                    } else {
                        self.positions[i as usize]
                    }
                });
                let before = (p[1] - p[0]).cross(&(p[2] - p[0]));
                let after = (moved[1] - moved[0]).cross(&(moved[2] - moved[0]));
                if after.dot(&before) <= 0.0 || after.norm() <= 1e-12 * before.norm() {
                    return false;
                }
            }
        }
        true
    }

    /// Collapses b into a at `target`.
    fn collapse(&mut self, a: u32, b: u32, target: Point3<f64>) {
        let moved: Vec<u32> = self.live_around(b).collect();
        for t in moved {
            let tri = &mut self.triangles[t as usize];
            if tri.contains(&a) {
                self.alive[t as usize] = false;
                self.live_triangles -= 1;
            } else {
                for c in tri.iter_mut() {
                    if *c == b {
                        *c = a;
                    }
                }
                self.around[a as usize].push(t);
            }
        }
        self.around[b as usize].clear();
        self.positions[a as usize] = target;
        let qb = self.quadrics[b as usize];
        self.quadrics[a as usize] += qb;
        self.version[a as usize] += 1;
        self.version[b as usize] += 1;
        let a_list: Vec<u32> = self.live_around(a).collect();
        self.around[a as usize] = a_list;
    }
}

/// Decimates a closed, consistently wound mesh to at most `target` triangles, never
/// making a collapse whose quadric error exceeds `tolerance` (m). Returns the new mesh
/// (unused vertices dropped).
pub fn decimate(mesh: &Mesh, target: usize, tolerance: f64) -> Mesh {
    let mut d = Decimator::new(mesh);
    let mut heap: BinaryHeap<Candidate> = EdgeMap::new(&mesh.triangles)
        .iter()
        .map(|((a, b), _)| d.candidate(a, b))
        .collect();
    let limit = tolerance * tolerance;
    while d.live_triangles > target {
        let Some(c) = heap.pop() else { break };
        if c.stamp != (d.version[c.a as usize], d.version[c.b as usize]) {
            continue;
        }
        if c.cost > limit {
            break;
        }
        if !d.allowed(c.a, c.b, &c.target) {
            continue;
        }
        d.collapse(c.a, c.b, c.target);
        for w in d.neighbours(c.a) {
            heap.push(d.candidate(c.a, w));
        }
    }
    // Compact.
    let mut index = vec![u32::MAX; d.positions.len()];
    let mut out = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for (t, tri) in d.triangles.iter().enumerate() {
        if !d.alive[t] {
            continue;
        }
        out.triangles.push(tri.map(|v| {
            if index[v as usize] == u32::MAX {
                index[v as usize] = out.vertices.len() as u32;
                out.vertices.push(d.positions[v as usize]);
            }
            index[v as usize]
        }));
    }
    out
}
