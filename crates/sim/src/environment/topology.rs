//! Making a polygon soup into the closed, outward-oriented triangle mesh the physics needs
//! (docs/physics.md: open or zero-thickness walls are tunnelled through).
//!
//! Steps, each reported when it changed something: weld coincident vertices (STL stores
//! every triangle's corners separately), drop degenerate triangles, drop duplicate
//! triangles (the same three corners in either winding; the first is kept), split
//! triangles at T-junctions ([`super::cracks`]), split every
//! vertex where separate sheets meet into one copy per sheet (its fans of triangles joined
//! through edges in at most two triangles: two solids sharing an edge or touching at a
//! corner become two solids), refuse edges still shared by more than two triangles, orient
//! each connected component consistently (refusing non-orientable ones), close small
//! holes and planar ones by a fan from the hole's centroid ([`super::cracks`]), refuse
//! other holes, refuse components with no
//! volume (sheets), and turn every component whose signed volume is negative inside out.
//! Components are treated as separate solids: objects made of several overlapping closed
//! parts (a mug's body and handle) are fine.

use super::cracks::{close_holes, split_t_junctions};
pub use super::edges::TopologyError;
pub use super::edges::components;
use super::edges::point_at;
use super::edges::{EdgeMap, FastMap, split_sheets};
use super::triangles::{Mesh, signed_volume};
use nalgebra::Point3;
use std::collections::VecDeque;

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
    let mut cells: FastMap<[i64; 3], Vec<u32>> = FastMap::default();
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

/// Repairs a welded triangle list into a closed, outward-oriented mesh, or says why it
/// cannot. `origins[t]` names where triangle `t` came from. Returns the mesh and the list
/// of repairs made.
///
/// Coincident triangles wound oppositely are first taken as a zero-thickness double wall
/// and cancelled in pairs; if that leaves nothing or no solid, they are taken as a
/// double-sided surface (render models often carry every face twice) and one of each
/// pair is kept. When both fail, the second's error is returned.
pub fn close_and_orient(
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
    origins: Vec<String>,
) -> Result<(Mesh, Vec<String>), TopologyError> {
    let mut repairs = Vec::new();
    let before = triangles.len();
    // Degenerate triangles: repeated corners or zero area.
    let (tris, origin_of): (Vec<_>, Vec<_>) = triangles
        .into_iter()
        .zip(origins)
        .filter(|(t, _)| !degenerate(&vertices, t))
        .unzip();
    let dropped = before - tris.len();
    if dropped > 0 {
        repairs.push(format!("dropped {dropped} degenerate triangle(s)"));
    }
    if tris.is_empty() {
        return Err(TopologyError {
            at: "mesh".into(),
            message: "empty mesh: every triangle is degenerate".into(),
        });
    }
    // Coincident triangles: the same three corners. Pairs wound oppositely cancel (a
    // zero-thickness double wall: a saw cut, or the face two stacked parts share); of the
    // rest, one copy is kept (the first of the majority winding).
    let cancelling = Coincident::new(&tris, true);
    if cancelling.cancelled == 0 {
        let (tris, origin_of) = cancelling.select(tris, origin_of);
        repairs.extend(cancelling.report());
        return close_solid(vertices, tris, origin_of, repairs);
    }
    let (first_tris, first_origins) = cancelling.select(tris.clone(), origin_of.clone());
    let mut first_repairs = repairs.clone();
    first_repairs.extend(cancelling.report());
    let first = close_solid(vertices.clone(), first_tris, first_origins, first_repairs);
    if first.is_ok() {
        return first;
    }
    // Taken as a double-sided surface instead: one copy of each set of corners.
    let keeping = Coincident::new(&tris, false);
    let (tris, origin_of) = keeping.select(tris, origin_of);
    repairs.extend(keeping.report());
    close_solid(vertices, tris, origin_of, repairs)
}

/// The rest of [`close_and_orient`], once degenerate and coincident triangles are gone:
/// T-junctions, sheets, the manifold check, winding, holes and outward orientation.
fn close_solid(
    mut vertices: Vec<Point3<f64>>,
    mut tris: Vec<[u32; 3]>,
    mut origin_of: Vec<String>,
    mut repairs: Vec<String>,
) -> Result<(Mesh, Vec<String>), TopologyError> {
    if tris.is_empty() {
        return Err(TopologyError {
            at: "mesh".into(),
            message: "every triangle cancelled against a coincident one wound oppositely".into(),
        });
    }
    // T-junctions.
    let (lo, hi) = super::triangles::bounds(&vertices);
    let inserted = split_t_junctions(
        &vertices,
        &mut tris,
        &mut origin_of,
        1e-6 * (hi - lo).norm(),
    );
    if inserted > 0 {
        repairs.push(format!(
            "split triangles at {inserted} T-junction vertex(es) lying on another triangle's edge"
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
    let by_edge = EdgeMap::new(&tris);
    for (k, list) in by_edge.iter() {
        if list.len() > 2 {
            return Err(TopologyError {
                at: origin_of[list[2] as usize].clone(),
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
                for &n in by_edge.get(a, b) {
                    let n = n as usize;
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
    // Holes.
    if let Some(report) = close_holes(&mut vertices, &mut tris)? {
        repairs.push(report);
    }
    // Outward orientation: each component's signed volume must be positive; a component
    // with none is a sheet, not a solid.
    let (lo, hi) = super::triangles::bounds(&vertices);
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

/// Whether a triangle has a repeated corner or zero area.
fn degenerate(vertices: &[Point3<f64>], t: &[u32; 3]) -> bool {
    let [a, b, c] = t.map(|i| vertices[i as usize]);
    t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || (b - a).cross(&(c - a)).norm() == 0.0
}

/// A welded soup kept as it is for kinematic sensing (`repair = "soup"`): degenerate
/// triangles and repeated ones (the same corners, either winding: one copy of a
/// double-sided sheet still stops a whisker) dropped, nothing else changed. Returns the
/// mesh and what was done and found, in words.
pub fn clean_soup(vertices: Vec<Point3<f64>>, triangles: Vec<[u32; 3]>) -> (Mesh, Vec<String>) {
    let before = triangles.len();
    let tris: Vec<[u32; 3]> = triangles
        .into_iter()
        .filter(|t| !degenerate(&vertices, t))
        .collect();
    let units = vec![(); tris.len()];
    let (tris, _) = Coincident::new(&tris, false).select(tris, units);
    let by_edge = EdgeMap::new(&tris);
    let open = by_edge.iter().filter(|(_, l)| l.len() == 1).count();
    let non_manifold = by_edge.iter().filter(|(_, l)| l.len() > 2).count();
    let report = format!(
        "kept as a triangle soup (repair = \"soup\"; kinematic sensing only): {} degenerate \
         or repeated triangle(s) dropped, {open} open edge(s), {non_manifold} edge(s) in more \
         than two triangles",
        before - tris.len()
    );
    (
        Mesh {
            vertices,
            triangles: tris,
        },
        vec![report],
    )
}

/// Which of a list of triangles survive the coincident-triangle rule of
/// [`close_and_orient`], and how many were dropped.
struct Coincident {
    /// Per triangle: kept.
    keep: Vec<bool>,
    /// Same-winding copies dropped (with `cancel` off: every copy beyond the first).
    duplicates: usize,
    /// Oppositely wound triangles cancelled in pairs (none unless `cancel`).
    cancelled: usize,
    /// Whether pairs were cancelled.
    cancel: bool,
}

impl Coincident {
    /// With `cancel`, oppositely wound pairs cancel and one copy of the majority winding
    /// beyond them is kept; without, one copy of every set of corners is kept. The copy
    /// kept is always the first in the list.
    fn new(tris: &[[u32; 3]], cancel: bool) -> Self {
        // Per set of corners: the triangles wound as the sorted corners (even) and against.
        let mut groups: FastMap<[u32; 3], (Vec<usize>, Vec<usize>)> = FastMap::default();
        for (i, t) in tris.iter().enumerate() {
            let mut key = *t;
            key.sort_unstable();
            let even = (0..3).any(|k| [t[k], t[(k + 1) % 3], t[(k + 2) % 3]] == key);
            let g = groups.entry(key).or_default();
            if even { &mut g.0 } else { &mut g.1 }.push(i);
        }
        let mut keep = vec![false; tris.len()];
        let (mut duplicates, mut cancelled) = (0, 0);
        for (even, odd) in groups.values() {
            let pairs = if cancel { even.len().min(odd.len()) } else { 0 };
            cancelled += 2 * pairs;
            // The copies left: with `cancel`, those of the majority winding beyond the
            // pairs; without, all of them.
            let rest: Vec<usize> = if !cancel {
                even.iter().chain(odd).copied().collect()
            } else if even.len() > odd.len() {
                even.clone()
            } else {
                odd.clone()
            };
            let left = rest.len() - pairs;
            if left > 0 {
                keep[*rest.iter().min().expect("non-empty")] = true;
                duplicates += left - 1;
            }
        }
        Self {
            keep,
            duplicates,
            cancelled,
            cancel,
        }
    }

    /// The kept triangles and their origins, in their order.
    fn select<T>(&self, tris: Vec<[u32; 3]>, origins: Vec<T>) -> (Vec<[u32; 3]>, Vec<T>) {
        tris.into_iter()
            .zip(origins)
            .zip(&self.keep)
            .filter(|(_, k)| **k)
            .map(|(p, _)| p)
            .unzip()
    }

    /// What was dropped, in words.
    fn report(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.duplicates > 0 {
            out.push(format!(
                "dropped {} duplicate triangle(s){}",
                self.duplicates,
                if self.cancel {
                    ""
                } else {
                    " (each face of a double-sided surface once)"
                }
            ));
        }
        if self.cancelled > 0 {
            out.push(format!(
                "dropped {} coincident triangle(s) wound oppositely in pairs (zero-thickness \
                 double walls)",
                self.cancelled
            ));
        }
        out
    }
}
