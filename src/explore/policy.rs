//! Where the array goes next (thesis §6.1.2–§6.1.3): the goal meshes' faces (map building
//! and the default trajectory), and steps between experiences for FEH and LSR, cut into
//! short segments in the array's tangent plane (§6.1.2.1–§6.1.2.2).

use crate::scenario::explore::StepPose;
use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use std::collections::VecDeque;
use whisker_slam::exploration::goal_mesh::GoalMesh;
use whisker_slam::exploration::placement::{UP, maintain_yaw};
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// Faces of a goal mesh visited nearest-unvisited first, loop after loop.
pub struct FaceTour {
    /// The mesh.
    pub mesh: GoalMesh,
    usable: Vec<bool>,
    visited: Vec<bool>,
    /// Loops completed.
    pub loops: usize,
    /// The face visited last.
    pub current: Option<usize>,
}

impl FaceTour {
    /// A tour of `mesh`, skipping faces whose centroid is below `min_height` (m).
    pub fn new(mesh: GoalMesh, min_height: f64) -> Self {
        let usable: Vec<bool> = mesh
            .faces
            .iter()
            .map(|f| f.centroid.z >= min_height)
            .collect();
        let visited = usable.iter().map(|u| !u).collect();
        Self {
            mesh,
            usable,
            visited,
            loops: 0,
            current: None,
        }
    }

    /// Faces a loop visits.
    pub fn usable(&self) -> usize {
        self.usable.iter().filter(|&&u| u).count()
    }

    /// The indices of the faces a loop visits.
    pub fn usable_faces(&self) -> Vec<usize> {
        (0..self.usable.len()).filter(|&i| self.usable[i]).collect()
    }

    /// The usable face whose centroid is nearest `to`.
    pub fn nearest_usable(&self, to: &Point3<f64>) -> usize {
        let unusable: Vec<bool> = self.usable.iter().map(|u| !u).collect();
        self.mesh.nearest_unvisited(to, &unusable).unwrap_or(0)
    }

    /// The next face: face `start` first, then the nearest unvisited one; a new loop
    /// starts (from the current face's neighbourhood) when every face is visited.
    pub fn next(&mut self, start: usize) -> Option<usize> {
        if self.usable() == 0 {
            return None;
        }
        let next = match self.current {
            None if self.usable[start % self.usable.len()] => start % self.usable.len(),
            None => self.nearest_usable(&self.mesh.faces[start % self.usable.len()].centroid),
            Some(c) => match self
                .mesh
                .nearest_unvisited(&self.mesh.faces[c].centroid, &self.visited)
            {
                Some(n) => n,
                None => {
                    self.loops += 1;
                    self.visited = self.usable.iter().map(|u| !u).collect();
                    self.mesh
                        .nearest_unvisited(&self.mesh.faces[c].centroid, &self.visited)?
                }
            },
        };
        self.visited[next] = true;
        self.current = Some(next);
        Some(next)
    }

    /// The array's goal at face `i`: the centroid, pointing along the inward normal, yaw
    /// level (Alg 8).
    pub fn goal(&self, i: usize, level: &Vector3<f64>) -> Isometry3<f64> {
        let f = &self.mesh.faces[i];
        maintain_yaw(f.centroid.coords, &f.inward, level)
    }
}

/// The centre and half extents of a mesh's bounding box.
pub fn bounding_box(points: &[Point3<f64>]) -> (Point3<f64>, Vector3<f64>) {
    let (lo, hi) = whisker_sim::environment::mesh::bounds(points);
    (nalgebra::center(&lo, &hi), (hi - lo) / 2.0)
}

/// A step towards an experience (§6.1.2.1): where the array should go, relative to the
/// last experience it re-localised into (the anchor) and where it truly was then.
pub fn step_goal(
    map: &ObjectMap,
    anchor: (usize, Isometry3<f64>),
    target: usize,
    how: StepPose,
) -> Option<Isometry3<f64>> {
    let relative = match how {
        StepPose::Map => map.pose(anchor.0).inverse() * map.pose(target),
        StepPose::Odometry => map.links.iter().find_map(|l| {
            if (l.from, l.to) == (anchor.0, target) {
                Some(l.relative())
            } else if (l.from, l.to) == (target, anchor.0) {
                Some(l.relative().inverse())
            } else {
                None
            }
        })?,
    };
    Some(anchor.1 * relative)
}

/// The segments of a step from `now` towards `goal` (§6.1.2.2): the offset in the
/// array's frame with its pointing component dropped (the SPC owns distance and
/// orientation), cut into equal pieces no longer than `segment` (m); each segment is a
/// pose to go to, yaw level.
pub fn segments(
    now: &Isometry3<f64>,
    goal: &Isometry3<f64>,
    segment: f64,
) -> VecDeque<Isometry3<f64>> {
    let mut d = now.inverse_transform_vector(&(goal.translation.vector - now.translation.vector));
    d.z = 0.0;
    let n = (d.norm() / segment).ceil() as usize;
    let level = now.rotation * Vector3::y();
    let z = now.rotation * Vector3::z();
    (1..=n)
        .map(|k| {
            let offset = now.rotation * (d * (k as f64 / n as f64));
            let at = Translation3::from(now.translation.vector + offset);
            maintain_yaw(
                at.vector,
                &z,
                &if level.dot(&UP) > 0.0 { level } else { UP },
            )
        })
        .collect()
}
