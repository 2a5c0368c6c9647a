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

impl GoalMesh {
    /// The axis-aligned ellipsoid with `centre` and `semi_axes`, `n` bands × `n` sectors.
    pub fn ellipsoid(centre: Point3<f64>, semi_axes: Vector3<f64>, n: usize) -> Self {
        let n = n.max(3);
        let vertex = |i: usize, j: usize| {
            let lat = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * i as f64 / n as f64;
            let lon = -std::f64::consts::PI + std::f64::consts::TAU * j as f64 / n as f64;
            centre
                + Vector3::new(
                    semi_axes.x * lat.cos() * lon.cos(),
                    semi_axes.y * lat.cos() * lon.sin(),
                    semi_axes.z * lat.sin(),
                )
        };
        let mut faces = Vec::with_capacity(n * n);
        for band in 0..n {
            for sector in 0..n {
                let [a, b, c, d] = [
                    vertex(band, sector),
                    vertex(band + 1, sector),
                    vertex(band + 1, sector + 1),
                    vertex(band, sector + 1),
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

#[cfg(test)]
mod tests {
    use super::*;

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
