//! Goal meshes around an object (thesis §6.1.3, §6.1.3.2): the ellipsoid whose faces are
//! visited to build an object map, and the sphere of the default recognition trajectory.
//!
//! Both are latitude–longitude meshes like MATLAB's `ellipsoid(…, n)` / `sphere(n)`
//! (n = 20: 20 bands from pole to pole, 20 around; the thesis gives no resolution, and
//! Fig 6.2 speaks of "a line of latitude"). A face's goal is its centroid with the array
//! pointing along the face's inward normal; faces are visited nearest unvisited first.

use nalgebra::{Point3, Vector3};

/// One face of a goal mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalFace {
    /// Latitude band (0 at the south pole) and longitude index.
    pub band: usize,
    /// Longitude index.
    pub sector: usize,
    /// Centroid of the face's four corners (world, m).
    pub centroid: Point3<f64>,
    /// Unit normal of the face pointing into the mesh (the array's pointing direction).
    pub inward: Vector3<f64>,
}

/// A latitude–longitude goal mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalMesh {
    /// Faces, band by band from the south pole, sector by sector from longitude −180°.
    pub faces: Vec<GoalFace>,
}

/// The outside of an object that goals are placed at reach of.
pub trait Surface {
    /// The point the goals' rays start from (inside the object).
    fn centre(&self) -> Point3<f64>;
    /// The outermost point of the object along the ray from the centre in the unit
    /// `direction`.
    fn outermost(&self, direction: &Vector3<f64>) -> Point3<f64>;
    /// The point of the object nearest `p` (outside it).
    fn nearest(&self, p: &Point3<f64>) -> Point3<f64>;
}

/// The point along the ray from `surface`'s centre in the unit `direction` that lies
/// `clearance` (> 0) from the object, beyond its outermost point along the ray (found by
/// bisection: at the outermost point the distance is 0, and 10 × `clearance` further it
/// is at least `clearance` unless the ray grazes the surface within 6°).
pub fn at_clearance(
    surface: &dyn Surface,
    direction: &Vector3<f64>,
    clearance: f64,
) -> Point3<f64> {
    let from = surface.outermost(direction);
    let distance = |t: f64| {
        let p = from + direction * t;
        (p - surface.nearest(&p)).norm()
    };
    let (mut lo, mut hi) = (0.0, 10.0 * clearance);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if distance(mid) < clearance {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    from + direction * hi
}

impl GoalMesh {
    /// The axis-aligned ellipsoid with `centre` and `semi_axes`, `n` bands × `n` sectors.
    pub fn ellipsoid(centre: Point3<f64>, semi_axes: Vector3<f64>, n: usize) -> Self {
        Self::lat_long(centre, n, |lat, lon| {
            centre + ellipsoid_point(&semi_axes, lat, lon)
        })
    }

    /// Goals at whisker reach (issue #35): the lat-long mesh whose vertices lie
    /// `clearance` from the object's `surface` along the rays from its centre in the
    /// directions of the ellipsoid with `semi` axes (the thesis' ellipsoid's shape, so
    /// that the faces spread over the object as over it), each face's goal moved along its
    /// ray to that clearance too; the array points from it at the nearest point of the
    /// object — straight at a side, obliquely at an edge. `clearance` is the distance the
    /// §5.2 trajectories keep from the surface.
    pub fn around(surface: &dyn Surface, semi: Vector3<f64>, clearance: f64, n: usize) -> Self {
        let centre = surface.centre();
        let mut mesh = Self::lat_long(centre, n, |lat, lon| {
            at_clearance(
                surface,
                &ellipsoid_point(&semi, lat, lon).normalize(),
                clearance,
            )
        });
        for f in &mut mesh.faces {
            let u = (f.centroid - centre).normalize();
            f.centroid = at_clearance(surface, &u, clearance);
            f.inward = (surface.nearest(&f.centroid) - f.centroid)
                .try_normalize(1e-12)
                .unwrap_or(-u);
        }
        mesh
    }

    /// Every face whose centroid lies nearer than `clearance` to the object's `surface`
    /// moved out along its ray from the object's centre to that clearance; directions
    /// kept.
    pub fn outside(mut self, surface: &dyn Surface, clearance: f64) -> Self {
        let centre = surface.centre();
        for f in &mut self.faces {
            if (f.centroid - surface.nearest(&f.centroid)).norm() < clearance {
                let u = (f.centroid - centre).normalize();
                f.centroid = at_clearance(surface, &u, clearance);
            }
        }
        self
    }

    /// The lat-long mesh of `n` bands × `n` sectors about `centre` through
    /// `vertex(latitude, longitude)` (radians, each vertex evaluated once), each face's
    /// inward direction its normal turned towards `centre`.
    fn lat_long(centre: Point3<f64>, n: usize, vertex: impl Fn(f64, f64) -> Point3<f64>) -> Self {
        let n = n.max(3);
        // (n + 1) × (n + 1): the last sector's far edge is evaluated at +180°, as before.
        let grid: Vec<Point3<f64>> = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| (i, j)))
            .map(|(i, j)| {
                let lat = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * i as f64 / n as f64;
                let lon = -std::f64::consts::PI + std::f64::consts::TAU * j as f64 / n as f64;
                vertex(lat, lon)
            })
            .collect();
        let at = |i: usize, j: usize| grid[i * (n + 1) + j];
        let mut faces = Vec::with_capacity(n * n);
        for band in 0..n {
            for sector in 0..n {
                let [a, b, c, d] = [
                    at(band, sector),
                    at(band + 1, sector),
                    at(band + 1, sector + 1),
                    at(band, sector + 1),
                ];
                let centroid = Point3::from((a.coords + b.coords + c.coords + d.coords) / 4.0);
                let mut normal = (c - a).cross(&(d - b));
                if normal.dot(&(centroid - centre)) > 0.0 {
                    normal = -normal;
                }
                let inward = normal
                    .try_normalize(1e-15)
                    .unwrap_or_else(|| (centre - centroid).normalize());
                faces.push(GoalFace {
                    band,
                    sector,
                    centroid,
                    inward,
                });
            }
        }
        Self { faces }
    }

    /// The sphere of `radius` about `centre`.
    pub fn sphere(centre: Point3<f64>, radius: f64, n: usize) -> Self {
        Self::ellipsoid(centre, Vector3::repeat(radius), n)
    }

    /// Of the faces not yet `visited`, the one whose centroid is nearest `from` (the
    /// first by index on ties); None when every face is visited.
    pub fn nearest_unvisited(&self, from: &Point3<f64>, visited: &[bool]) -> Option<usize> {
        self.faces
            .iter()
            .enumerate()
            .filter(|(i, _)| !visited[*i])
            .map(|(i, f)| (i, (f.centroid - from).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .map(|(i, _)| i)
    }
}

/// The point of the ellipsoid with `semi` axes about the origin at latitude `lat` and
/// longitude `lon` (radians).
fn ellipsoid_point(semi: &Vector3<f64>, lat: f64, lon: f64) -> Vector3<f64> {
    Vector3::new(
        semi.x * lat.cos() * lon.cos(),
        semi.y * lat.cos() * lon.sin(),
        semi.z * lat.sin(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An object's axis-aligned bounding box: its centre and half extents (m).
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct BoundingBox {
        pub centre: Point3<f64>,
        pub half: Vector3<f64>,
    }

    impl BoundingBox {
        /// The distance from `p` to the box (0 inside).
        pub fn distance(&self, p: &Point3<f64>) -> f64 {
            (p - self.nearest(p)).norm()
        }
    }

    impl Surface for BoundingBox {
        fn centre(&self) -> Point3<f64> {
            self.centre
        }

        fn outermost(&self, direction: &Vector3<f64>) -> Point3<f64> {
            // The exit through the first face the ray reaches.
            let t = (0..3)
                .filter(|&i| direction[i] != 0.0)
                .map(|i| self.half[i] / direction[i].abs())
                .fold(f64::INFINITY, f64::min);
            self.centre + direction * t
        }

        fn nearest(&self, p: &Point3<f64>) -> Point3<f64> {
            let d = p - self.centre;
            self.centre + Vector3::from_fn(|i, _| d[i].clamp(-self.half[i], self.half[i]))
        }
    }

    #[test]
    fn sphere_faces_point_at_the_centre_and_tile_the_surface() {
        let c = Point3::new(0.5, 0.0, 0.2);
        let m = GoalMesh::sphere(c, 0.3, 20);
        assert_eq!(m.faces.len(), 400);
        for f in &m.faces {
            // A face of a sphere's lat-long mesh is symmetric about its meridian and its
            // normal lies in that meridian's plane, pointing at the centre.
            let to_centre = (c - f.centroid).normalize();
            assert!(f.inward.dot(&to_centre) > 0.99, "{f:?}");
            assert!((f.inward.norm() - 1.0).abs() < 1e-12);
            assert!((f.centroid - c).norm() < 0.3);
        }
        // Bands are symmetric about the equator.
        let z: Vec<f64> = (0..20).map(|b| m.faces[b * 20].centroid.z - c.z).collect();
        for b in 0..10 {
            assert!((z[b] + z[19 - b]).abs() < 1e-12);
        }
    }

    /// Goals at reach of a 20 × 20 × 35 cm box: each vertex of the mesh lies 4 cm beyond
    /// the box's surface along its ray from the centre, every face's array points at the
    /// box's nearest point from its centroid, which lies outside the box; at a side's
    /// middle the array faces that side square on.
    #[test]
    fn goals_around_a_box_lie_at_reach_and_point_at_it() {
        let b = BoundingBox {
            centre: Point3::new(0.55, 0.0, 0.175),
            half: Vector3::new(0.1, 0.1, 0.175),
        };
        let m = GoalMesh::around(&b, b.half * 3f64.sqrt(), 0.04, 20);
        assert_eq!(m.faces.len(), 400);
        for f in &m.faces {
            let d = b.distance(&f.centroid);
            assert!((d - 0.04).abs() < 1e-9, "{f:?}: {d} m from the box");
            let to = (b.nearest(&f.centroid) - f.centroid).normalize();
            assert!((f.inward - to).norm() < 1e-12, "{f:?}");
        }
        // Along a ray, the surface point is on the box and the goal 4 cm beyond it.
        let u = Vector3::new(-1.0, -0.2, 0.1).normalize();
        let s = b.outermost(&u);
        assert!((s.x - 0.45).abs() < 1e-12, "{s}");
        // The face whose centroid is nearest the −x side's middle faces it square on.
        let middle = Point3::new(0.45 - 0.04, 0.0, 0.175);
        let f = m
            .faces
            .iter()
            .min_by(|a, c| {
                (a.centroid - middle)
                    .norm()
                    .total_cmp(&(c.centroid - middle).norm())
            })
            .unwrap();
        assert!((f.inward - Vector3::x()).norm() < 1e-9, "{f:?}");
        // A sphere too small for the box: its goals inside the band are moved out to it.
        let sphere = GoalMesh::sphere(b.centre, 0.165, 20).outside(&b, 0.04);
        for f in &sphere.faces {
            assert!(b.distance(&f.centroid) >= 0.04 - 1e-9, "{f:?}");
        }
    }

    #[test]
    fn nearest_unvisited_walks_neighbour_to_neighbour() {
        let m = GoalMesh::ellipsoid(Point3::origin(), Vector3::new(0.3, 0.2, 0.4), 10);
        let mut visited = vec![false; m.faces.len()];
        let mut at = 55;
        visited[at] = true;
        let next = m
            .nearest_unvisited(&m.faces[at].centroid, &visited)
            .unwrap();
        // The nearest of a face's neighbours is one of the 8 around it.
        let (b, s) = (m.faces[next].band as i64, m.faces[next].sector as i64);
        assert!((b - 5).abs() <= 1 && ((s - 5).abs() <= 1));
        for _ in 1..m.faces.len() {
            at = m
                .nearest_unvisited(&m.faces[at].centroid, &visited)
                .unwrap();
            visited[at] = true;
        }
        assert!(visited.iter().all(|&v| v));
        assert_eq!(m.nearest_unvisited(&Point3::origin(), &visited), None);
    }
}
