//! Mesh connectivity over edges: which triangles share each edge, connected parts, and
//! the splitting of vertices where separate sheets meet.
//!
//! Keys are vertex indices; maps use foldhash's fixed-seed hasher (deterministic, and
//! several times faster than the standard SipHash on these keys: checking a
//! 1-million-triangle scan spent a quarter of its time hashing and allocating per-edge
//! lists before).

use nalgebra::Point3;
use std::collections::{HashMap, VecDeque};

/// A hash map with foldhash's fixed-seed hasher.
pub type FastMap<K, V> = HashMap<K, V, foldhash::fast::FixedState>;

/// Undirected edge key.
pub fn edge(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The triangles around each undirected edge, in flat storage: edges in ascending order,
/// each with its triangles in ascending order.
pub struct EdgeMap {
    keys: Vec<(u32, u32)>,
    offsets: Vec<u32>,
    triangles: Vec<u32>,
    index: FastMap<(u32, u32), u32>,
}

impl EdgeMap {
    /// The edges of `triangles`.
    pub fn new(triangles: &[[u32; 3]]) -> Self {
        let mut pairs: Vec<((u32, u32), u32)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                pairs.push((edge(tri[k], tri[(k + 1) % 3]), t as u32));
            }
        }
        pairs.sort_unstable();
        let mut map = Self {
            keys: Vec::with_capacity(pairs.len() / 2 + 1),
            offsets: Vec::with_capacity(pairs.len() / 2 + 2),
            triangles: Vec::with_capacity(pairs.len()),
            index: FastMap::with_capacity_and_hasher(pairs.len() / 2 + 1, Default::default()),
        };
        for (key, t) in pairs {
            if map.keys.last() != Some(&key) {
                map.index.insert(key, map.keys.len() as u32);
                map.keys.push(key);
                map.offsets.push(map.triangles.len() as u32);
            }
            map.triangles.push(t);
        }
        map.offsets.push(map.triangles.len() as u32);
        map
    }

    /// The triangles around the edge (a, b) (either direction); empty if it is none.
    pub fn get(&self, a: u32, b: u32) -> &[u32] {
        match self.index.get(&edge(a, b)) {
            Some(&i) => self.at(i as usize),
            None => &[],
        }
    }

    fn at(&self, i: usize) -> &[u32] {
        &self.triangles[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Every edge with its triangles, edges in ascending order.
    pub fn iter(&self) -> impl Iterator<Item = ((u32, u32), &[u32])> {
        self.keys.iter().enumerate().map(|(i, &k)| (k, self.at(i)))
    }
}

/// Connected components (triangle indices) over shared edges.
pub fn components(triangles: &[[u32; 3]]) -> Vec<Vec<usize>> {
    let by_edge = EdgeMap::new(triangles);
    let mut seen = vec![false; triangles.len()];
    let mut out = Vec::new();
    for start in 0..triangles.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut comp = vec![start];
        let mut queue = VecDeque::from([start]);
        while let Some(t) = queue.pop_front() {
            let tri = triangles[t];
            for k in 0..3 {
                for &n in by_edge.get(tri[k], tri[(k + 1) % 3]) {
                    let n = n as usize;
                    if !seen[n] {
                        seen[n] = true;
                        comp.push(n);
                        queue.push_back(n);
                    }
                }
            }
        }
        out.push(comp);
    }
    out
}

/// Splits every vertex whose incident triangles form more than one fan — triangles joined
/// through edges at the vertex that lie in at most two triangles — into one copy per fan
/// (the first fan keeps the vertex). Returns the number of copies made.
pub(crate) fn split_sheets(vertices: &mut Vec<Point3<f64>>, triangles: &mut [[u32; 3]]) -> usize {
    let by_edge = EdgeMap::new(triangles);
    let original = triangles.to_vec();
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for (t, tri) in triangles.iter().enumerate() {
        for &v in tri {
            incident[v as usize].push(t);
        }
    }
    let mut copies = 0;
    for v in 0..incident.len() {
        let around = &incident[v];
        if around.len() < 2 {
            continue;
        }
        // Fans: connected components of `around` over manifold edges (v, w).
        let mut fan = vec![usize::MAX; around.len()];
        let mut fans = 0;
        for start in 0..around.len() {
            if fan[start] != usize::MAX {
                continue;
            }
            fan[start] = fans;
            let mut queue = VecDeque::from([start]);
            while let Some(i) = queue.pop_front() {
                let tri = original[around[i]];
                for &w in tri.iter().filter(|&&w| w as usize != v) {
                    let shared = by_edge.get(v as u32, w);
                    if shared.len() > 2 {
                        continue;
                    }
                    for &n in shared {
                        if let Some(j) = around.iter().position(|&t| t == n as usize)
                            && fan[j] == usize::MAX
                        {
                            fan[j] = fans;
                            queue.push_back(j);
                        }
                    }
                }
            }
            fans += 1;
        }
        for f in 1..fans {
            vertices.push(vertices[v]);
            let copy = (vertices.len() - 1) as u32;
            for (i, &t) in around.iter().enumerate() {
                if fan[i] == f {
                    for corner in triangles[t].iter_mut() {
                        if *corner as usize == v {
                            *corner = copy;
                        }
                    }
                }
            }
            copies += 1;
        }
    }
    copies
}

/// A topology problem that cannot be repaired: what, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct TopologyError {
    /// Where (a polygon origin, or a position).
    pub at: String,
    /// What is wrong.
    pub message: String,
}

/// Where a problem is, for messages.
pub(crate) fn point_at(p: &Point3<f64>) -> String {
    format!("near ({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
}
