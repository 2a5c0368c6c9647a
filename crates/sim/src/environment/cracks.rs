//! Cracks in a welded triangle mesh (issue #20): T-junctions and holes.
//!
//! - A **T-junction** is a vertex of one triangle lying on the edge of another that does
//!   not have it as a corner (a face subdivided on one side of an edge but not on the
//!   other, common in CAD exports). Such an edge is in one triangle only, as are the two
//!   halves beside it, so the surface looks open along a crack of zero width. The
//!   triangle with the long edge is split at the vertex (a fan from its opposite corner),
//!   which closes the crack without moving any point of the surface.
//! - A **hole** is a loop of boundary edges. Holes of at most [`MAX_HOLE_EDGES`] edges
//!   are closed by a fan from the centroid of the rim; larger ones only when the rim is
//!   planar and encloses a simple polygon (the open end of a scanned or extruded part),
//!   by ear clipping in its plane. Other holes are refused: closing them would invent a
//!   surface.

use super::edges::{EdgeMap, FastMap, TopologyError, point_at};
use nalgebra::{Point3, Vector3};

/// Largest hole (number of boundary edges) closed automatically whatever its shape.
pub const MAX_HOLE_EDGES: usize = 32;

/// A large hole's rim counts as planar when no rim vertex is farther than this fraction
/// of the rim's diameter from the rim's mean plane.
pub const PLANAR_FRACTION: f64 = 0.01;

/// Directed boundary edges (a → b as wound in their one triangle) with that triangle, in
/// a fixed order.
fn boundary_edges(triangles: &[[u32; 3]]) -> Vec<(u32, u32, usize)> {
    let by_edge = EdgeMap::new(triangles);
    let mut out = Vec::new();
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if by_edge.get(a, b).len() == 1 {
                out.push((a, b, i));
            }
        }
    }
    out
}

/// Splits triangles at T-junctions: boundary vertices within `tolerance` of the inside of
/// a boundary edge (farther than `tolerance` from both its ends). Returns the number of
/// vertices inserted into edges; `origins` follows the triangles.
pub fn split_t_junctions(
    vertices: &[Point3<f64>],
    triangles: &mut Vec<[u32; 3]>,
    origins: &mut Vec<String>,
    tolerance: f64,
) -> usize {
    let mut inserted = 0;
    // Each pass splits at most one edge per triangle; a triangle with T-junctions on
    // several edges is finished in later passes.
    for _ in 0..16 {
        let boundary = boundary_edges(triangles);
        if boundary.is_empty() {
            break;
        }
        let cell = (boundary
            .iter()
            .map(|&(a, b, _)| (vertices[b as usize] - vertices[a as usize]).norm())
            .sum::<f64>()
            / boundary.len() as f64)
            .max(10.0 * tolerance);
        let key = |p: &Point3<f64>| p.coords.map(|x| (x / cell).floor() as i64);
        let mut grid: FastMap<[i64; 3], Vec<u32>> = FastMap::default();
        let mut on_boundary: Vec<u32> = boundary.iter().flat_map(|&(a, b, _)| [a, b]).collect();
        on_boundary.sort_unstable();
        on_boundary.dedup();
        for &v in &on_boundary {
            let k = key(&vertices[v as usize]);
            grid.entry([k.x, k.y, k.z]).or_default().push(v);
        }
        let mut done = vec![false; triangles.len()];
        let mut pass = 0;
        for &(a, b, t) in &boundary {
            if done[t] {
                continue;
            }
            let (pa, pb) = (vertices[a as usize], vertices[b as usize]);
            let along = pb - pa;
            let length = along.norm();
            let lo = key(&(pa.inf(&pb) - Vector3::repeat(tolerance)));
            let hi = key(&(pa.sup(&pb) + Vector3::repeat(tolerance)));
            let mut on_edge: Vec<(f64, u32)> = Vec::new();
            for x in lo.x..=hi.x {
                for y in lo.y..=hi.y {
                    for z in lo.z..=hi.z {
                        for &m in grid.get(&[x, y, z]).into_iter().flatten() {
                            let s = (vertices[m as usize] - pa).dot(&along) / length;
                            let off = (vertices[m as usize] - pa - along * (s / length)).norm();
                            if m != a
                                && m != b
                                && s > tolerance
                                && s < length - tolerance
                                && off <= tolerance
                            {
                                on_edge.push((s, m));
                            }
                        }
                    }
                }
            }
            if on_edge.is_empty() {
                continue;
            }
            on_edge.sort_by(|x, y| x.0.total_cmp(&y.0));
            let tri = triangles[t];
            let k = (0..3).find(|&k| tri[k] == a).expect("edge of its triangle");
            let c = tri[(k + 2) % 3];
            let mut chain = vec![a];
            chain.extend(on_edge.iter().map(|&(_, m)| m));
            chain.push(b);
            triangles[t] = [chain[0], chain[1], c];
            for w in chain[1..].windows(2) {
                triangles.push([w[0], w[1], c]);
                origins.push(origins[t].clone());
            }
            done[t] = true;
            pass += on_edge.len();
        }
        inserted += pass;
        if pass == 0 {
            break;
        }
    }
    inserted
}

/// A cap for a large hole: the rim's triangulation by ear clipping in its mean plane
/// (through `centre`, the rim's centroid), as triangles of rim positions in rim order — or
/// None when the rim is not planar (within [`PLANAR_FRACTION`] of its diameter) or its
/// projection is not a simple polygon.
fn planar_cap(rim: &[Point3<f64>], centre: &Point3<f64>) -> Option<Vec<[usize; 3]>> {
    let n = rim.len();
    // Newell's normal: the rim runs counter-clockwise about it.
    let normal: Vector3<f64> = (0..n)
        .map(|k| (rim[k] - centre).cross(&(rim[(k + 1) % n] - centre)))
        .sum();
    let normal = normal.try_normalize(0.0)?;
    let diameter = 2.0 * rim.iter().map(|p| (p - centre).norm()).fold(0.0, f64::max);
    if rim
        .iter()
        .any(|p| normal.dot(&(p - centre)).abs() > PLANAR_FRACTION * diameter)
    {
        return None;
    }
    let u = normal
        .cross(&Vector3::x())
        .try_normalize(1e-6)
        .unwrap_or_else(|| normal.cross(&Vector3::y()).normalize());
    let w = normal.cross(&u);
    let flat: Vec<(f64, f64)> = rim
        .iter()
        .map(|p| ((p - centre).dot(&u), (p - centre).dot(&w)))
        .collect();
    let cross = |a: usize, b: usize, c: usize| {
        let (pa, pb, pc) = (flat[a], flat[b], flat[c]);
        (pb.0 - pa.0) * (pc.1 - pa.1) - (pb.1 - pa.1) * (pc.0 - pa.0)
    };
    let mut left: Vec<usize> = (0..n).collect();
    let mut cap = Vec::with_capacity(n - 2);
    let (mut i, mut misses) = (0, 0);
    while left.len() > 3 {
        if misses > left.len() {
            return None; // a full pass without an ear: not a simple polygon
        }
        let m = left.len();
        let (a, b, c) = (left[(i + m - 1) % m], left[i % m], left[(i + 1) % m]);
        let ear = cross(a, b, c) > 0.0
            && left.iter().all(|&p| {
                p == a
                    || p == b
                    || p == c
                    || flat[p] == flat[a]
                    || flat[p] == flat[b]
                    || flat[p] == flat[c]
                    || cross(a, b, p) < 0.0
                    || cross(b, c, p) < 0.0
                    || cross(c, a, p) < 0.0
            });
        if ear {
            cap.push([a, b, c]);
            left.remove(i % m);
            misses = 0;
        } else {
            i += 1;
            misses += 1;
        }
    }
    cap.push([left[0], left[1], left[2]]);
    Some(cap)
}

/// Closes the holes of a consistently wound mesh (see the module documentation) and says
/// what it did, or refuses the first hole it cannot close.
pub fn close_holes(
    vertices: &mut Vec<Point3<f64>>,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<Option<String>, TopologyError> {
    let boundary = boundary_edges(triangles);
    if boundary.is_empty() {
        return Ok(None);
    }
    let mut next: FastMap<u32, Vec<u32>> = FastMap::default();
    for &(a, b, _) in &boundary {
        next.entry(a).or_default().push(b);
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let (mut holes, mut large) = (0, 0);
    for s in starts {
        while let Some(first) = next.get_mut(&s).and_then(Vec::pop) {
            let mut ring = vec![s];
            let mut at = first;
            while at != s {
                ring.push(at);
                match next.get_mut(&at).and_then(Vec::pop) {
                    Some(n) if ring.len() <= boundary.len() => at = n,
                    _ => {
                        return Err(TopologyError {
                            at: "mesh".into(),
                            message: format!(
                                "open mesh: a boundary that does not close into a loop {}",
                                point_at(&vertices[s as usize])
                            ),
                        });
                    }
                }
            }
            let rim: Vec<Point3<f64>> = ring.iter().map(|&i| vertices[i as usize]).collect();
            let centre =
                Point3::from(rim.iter().map(|p| p.coords).sum::<Vector3<f64>>() / rim.len() as f64);
            if ring.len() > MAX_HOLE_EDGES {
                let Some(cap) = planar_cap(&rim, &centre) else {
                    return Err(TopologyError {
                        at: "mesh".into(),
                        message: format!(
                            "open mesh: a hole of {} boundary edges {} that is neither small \
                             (at most {MAX_HOLE_EDGES} edges) nor a planar rim enclosing a \
                             simple polygon, so closing it would invent a surface",
                            ring.len(),
                            point_at(&vertices[s as usize])
                        ),
                    });
                };
                // The cap runs against the rim (as the fan below does).
                for [a, b, c] in cap {
                    triangles.push([ring[c], ring[b], ring[a]]);
                }
                large += 1;
            } else {
                vertices.push(centre);
                let c = (vertices.len() - 1) as u32;
                for k in 0..ring.len() {
                    let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                    triangles.push([b, a, c]);
                }
            }
            holes += 1;
        }
    }
    let mut report = format!("closed {holes} hole(s) ({} boundary edges", boundary.len());
    if large > 0 {
        report += &format!("; {large} of them planar with more than {MAX_HOLE_EDGES} edges");
    }
    Ok(Some(report + ")"))
}
