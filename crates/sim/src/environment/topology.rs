//! Making a polygon soup into the closed, outward-oriented triangle mesh the physics needs
//! (`shared/notes/physics.md`: open or zero-thickness walls are tunnelled through).
//!
//! Steps, each reported when it changed something: weld coincident vertices (STL stores
//! every triangle's corners separately), drop degenerate triangles, drop duplicate
//! triangles (the same three corners in either winding; the first is kept), split every
//! vertex where separate sheets meet into one copy per sheet (its fans of triangles joined
//! through edges in at most two triangles: two solids sharing an edge or touching at a
//! corner become two solids), refuse edges still shared by more than two triangles, orient
//! each connected component consistently (refusing non-orientable ones), close small
//! holes by a fan from the hole's centroid, refuse larger ones, refuse components with no
//! volume (sheets), and turn every component whose signed volume is negative inside out.
//! Components are treated as separate solids: objects made of several overlapping closed
//! parts (a mug's body and handle) are fine.

use nalgebra::{Point3, Vector3};
use std::collections::{HashMap, HashSet, VecDeque};

/// Largest hole (number of boundary edges) closed automatically.
pub const MAX_HOLE_EDGES: usize = 32;

/// A closed, consistently wound triangle mesh (metres, z up).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<Point3<f64>>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// A topology problem that cannot be repaired: what, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct TopologyError {
    /// Where (a polygon origin, or a position).
    pub at: String,
    /// What is wrong.
    pub message: String,
}

fn point_at(p: &Point3<f64>) -> String {
    format!("near ({:.4}, {:.4}, {:.4})", p.x, p.y, p.z)
}

/// Merges vertices closer than `tolerance`; returns the new positions and the map from
/// old to new index.
pub fn weld(positions: &[Point3<f64>], tolerance: f64) -> (Vec<Point3<f64>>, Vec<u32>) {
    let key = |p: &Point3<f64>| {
        [
            (p.x / tolerance).floor() as i64,
            (p.y / tolerance).floor() as i64,
            (p.z / tolerance).floor() as i64,
        ]
    };
    let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut out: Vec<Point3<f64>> = Vec::new();
    let mut map = Vec::with_capacity(positions.len());
    for p in positions {
        let k = key(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz])
                        && let Some(&i) = list
                            .iter()
                            .find(|&&i| (out[i as usize] - p).norm() <= tolerance)
                    {
                        found = Some(i);
                        break 'search;
                    }
                }
            }
        }
        let i = found.unwrap_or_else(|| {
            out.push(*p);
            let i = (out.len() - 1) as u32;
            cells.entry(k).or_default().push(i);
            i
        });
        map.push(i);
    }
    (out, map)
}

/// Undirected edge key.
fn edge(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Signed volume of a set of triangles (positive for a closed outward-wound surface).
pub fn signed_volume(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize].coords);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum()
}

/// The triangles around each undirected edge.
fn triangles_by_edge(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), Vec<usize>> {
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            by_edge
                .entry(edge(tri[k], tri[(k + 1) % 3]))
                .or_default()
                .push(t);
        }
    }
    by_edge
}

/// Connected components (triangle indices) over shared edges.
pub fn components(triangles: &[[u32; 3]]) -> Vec<Vec<usize>> {
    let by_edge = triangles_by_edge(triangles);
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
                for &n in &by_edge[&edge(tri[k], tri[(k + 1) % 3])] {
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

/// Repairs a welded triangle list into a closed, outward-oriented mesh, or says why it
/// cannot. `origins[t]` names where triangle `t` came from. Returns the mesh and the list
/// of repairs made.
pub fn close_and_orient(
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
    origins: Vec<String>,
) -> Result<(Mesh, Vec<String>), TopologyError> {
    let mut repairs = Vec::new();
    let mut vertices = vertices;
    // Degenerate triangles: repeated corners or zero area.
    let mut tris = Vec::with_capacity(triangles.len());
    let mut origin_of = Vec::with_capacity(triangles.len());
    let mut dropped = 0;
    for (t, o) in triangles.into_iter().zip(origins) {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || (b - a).cross(&(c - a)).norm() == 0.0 {
            dropped += 1;
        } else {
            tris.push(t);
            origin_of.push(o);
        }
    }
    if dropped > 0 {
        repairs.push(format!("dropped {dropped} degenerate triangle(s)"));
    }
    if tris.is_empty() {
        return Err(TopologyError {
            at: "mesh".into(),
            message: "empty mesh: every triangle is degenerate".into(),
        });
    }
    // Duplicate triangles.
    let mut corners_seen = HashSet::new();
    let before = tris.len();
    let (kept, kept_origins): (Vec<_>, Vec<_>) = tris
        .into_iter()
        .zip(origin_of)
        .filter(|(t, _)| {
            let mut key = *t;
            key.sort_unstable();
            corners_seen.insert(key)
        })
        .unzip();
    let (mut tris, origin_of) = (kept, kept_origins);
    if tris.len() < before {
        repairs.push(format!(
            "dropped {} duplicate triangle(s)",
            before - tris.len()
        ));
    }
    // Sheets meeting at an edge or a vertex: one vertex copy per sheet.
    let split = split_sheets(&mut vertices, &mut tris);
    if split > 0 {
        repairs.push(format!(
            "split {split} vertex(es) where separate sheets meet"
        ));
    }
    // Non-manifold edges.
    let by_edge = triangles_by_edge(&tris);
    let mut keys: Vec<_> = by_edge.keys().copied().collect();
    keys.sort_unstable();
    for k in &keys {
        let list = &by_edge[k];
        if list.len() > 2 {
            return Err(TopologyError {
                at: origin_of[list[2]].clone(),
                message: format!(
                    "non-manifold edge shared by {} triangles {}: expected each edge in \
                     exactly two triangles",
                    list.len(),
                    point_at(&vertices[k.0 as usize])
                ),
            });
        }
    }
    // Consistent winding per component (breadth-first flips).
    let mut flip: Vec<Option<bool>> = vec![None; tris.len()];
    let mut flipped = 0;
    for start in 0..tris.len() {
        if flip[start].is_some() {
            continue;
        }
        flip[start] = Some(false);
        let mut queue = VecDeque::from([start]);
        while let Some(t) = queue.pop_front() {
            let ft = flip[t] == Some(true);
            let tri = tris[t];
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                for &n in &by_edge[&edge(a, b)] {
                    if n == t {
                        continue;
                    }
                    let nt = tris[n];
                    let same_direction = (0..3).any(|j| nt[j] == a && nt[(j + 1) % 3] == b);
                    let want = ft ^ same_direction;
                    match flip[n] {
                        None => {
                            flip[n] = Some(want);
                            queue.push_back(n);
                        }
                        Some(f) if f != want => {
                            return Err(TopologyError {
                                at: origin_of[n].clone(),
                                message: format!(
                                    "the surface is not orientable (Möbius-like) {}",
                                    point_at(&vertices[a as usize])
                                ),
                            });
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    for (t, f) in tris.iter_mut().zip(&flip) {
        if *f == Some(true) {
            t.swap(1, 2);
            flipped += 1;
        }
    }
    // Boundary: directed edges without their opposite, chained into loops.
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut boundary = 0;
    for tri in &tris {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if by_edge[&edge(a, b)].len() == 1 {
                next.entry(a).or_default().push(b);
                boundary += 1;
            }
        }
    }
    if boundary > 0 {
        let mut starts: Vec<u32> = next.keys().copied().collect();
        starts.sort_unstable();
        let mut holes = 0;
        for s in starts {
            while let Some(first) = next.get_mut(&s).and_then(Vec::pop) {
                let mut ring = vec![s];
                let mut at = first;
                while at != s {
                    ring.push(at);
                    let step = next.get_mut(&at).and_then(Vec::pop);
                    match step {
                        Some(n) if ring.len() <= MAX_HOLE_EDGES => at = n,
                        _ => {
                            return Err(TopologyError {
                                at: "mesh".into(),
                                message: format!(
                                    "open mesh: a hole with more than {MAX_HOLE_EDGES} \
                                     boundary edges {} (the physics needs closed meshes; \
                                     holes up to {MAX_HOLE_EDGES} edges are closed \
                                     automatically)",
                                    point_at(&vertices[s as usize])
                                ),
                            });
                        }
                    }
                }
                let centre = Point3::from(
                    ring.iter()
                        .map(|&i| vertices[i as usize].coords)
                        .sum::<Vector3<f64>>()
                        / ring.len() as f64,
                );
                vertices.push(centre);
                let c = (vertices.len() - 1) as u32;
                for k in 0..ring.len() {
                    let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                    tris.push([b, a, c]);
                }
                holes += 1;
            }
        }
        repairs.push(format!(
            "closed {holes} hole(s) ({boundary} boundary edges)"
        ));
    }
    // Outward orientation: each component's signed volume must be positive; a component
    // with none is a sheet, not a solid.
    let (lo, hi) = super::mesh::bounds(&vertices);
    let tiny = 1e-9 * (hi - lo).norm().powi(3);
    let mut inverted = 0;
    for comp in components(&tris) {
        let sub: Vec<[u32; 3]> = comp.iter().map(|&t| tris[t]).collect();
        let volume = signed_volume(&vertices, &sub);
        if volume.abs() <= tiny {
            return Err(TopologyError {
                at: "mesh".into(),
                message: format!(
                    "a part of {} triangle(s) {} encloses no volume (a sheet or a fin, \
                     once closed): expected closed solids",
                    comp.len(),
                    point_at(&vertices[sub[0][0] as usize])
                ),
            });
        }
        if volume < 0.0 {
            inverted += 1;
            for &t in &comp {
                tris[t].swap(1, 2);
            }
        }
    }
    if flipped > 0 {
        repairs.push(format!(
            "re-wound {flipped} triangle(s) inconsistent with their neighbours"
        ));
    }
    if inverted > 0 {
        repairs.push(format!("turned {inverted} inside-out component(s) outward"));
    }
    Ok((
        Mesh {
            vertices,
            triangles: tris,
        },
        repairs,
    ))
}

/// Splits every vertex whose incident triangles form more than one fan — triangles joined
/// through edges at the vertex that lie in at most two triangles — into one copy per fan
/// (the first fan keeps the vertex). Returns the number of copies made.
fn split_sheets(vertices: &mut Vec<Point3<f64>>, triangles: &mut [[u32; 3]]) -> usize {
    let by_edge = triangles_by_edge(triangles);
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
                    let shared = &by_edge[&edge(v as u32, w)];
                    if shared.len() > 2 {
                        continue;
                    }
                    for &n in shared {
                        if let Some(j) = around.iter().position(|&t| t == n)
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
