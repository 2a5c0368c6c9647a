//! Where the array goes next (thesis §6.1.2–§6.1.3): the goal meshes' faces (map building
//! and the default trajectory), and steps between experiences for FEH and LSR, cut into
//! short segments in the array's tangent plane (§6.1.2.1–§6.1.2.2).

use super::goal_mesh::GoalMesh;
use super::placement::{UP, maintain_yaw};
use crate::whisker_ratslam::object_map::ObjectMap;
use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use serde::Deserialize;
use std::collections::VecDeque;

/// Which relative pose a step between experiences uses (§6.1.2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum StepPose {
    /// The experiences' map poses (corrected by re-localisations).
    #[default]
    Map,
    /// The odometry recorded on the link between them.
    Odometry,
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::whisker_ratslam::object_map::Link;
    use nalgebra::UnitQuaternion;

    fn level(at: [f64; 3], pointing: Vector3<f64>) -> Isometry3<f64> {
        maintain_yaw(Vector3::from(at), &pointing, &UP)
    }

    /// A step is cut into equal segments of at most `segment`, in the array's tangent
    /// plane: the pointing component of the offset is dropped, the orientation kept.
    #[test]
    fn segments_stay_in_the_tangent_plane_and_are_short() {
        let now = level([0.3, 0.0, 0.2], Vector3::x());
        // 10 cm sideways (world y = array −x), 4 cm up, 5 cm further along the axis.
        let goal = level([0.35, 0.1, 0.24], Vector3::y());
        let s = segments(&now, &goal, 0.03);
        let planar = (0.1f64.powi(2) + 0.04f64.powi(2)).sqrt();
        assert_eq!(s.len(), (planar / 0.03).ceil() as usize);
        let mut previous = now;
        for p in &s {
            let step = p.translation.vector - previous.translation.vector;
            assert!(step.norm() <= 0.03 + 1e-12);
            assert!(
                step.x.abs() < 1e-12,
                "moved along the pointing axis: {step}"
            );
            assert!((p.rotation.angle_to(&now.rotation)) < 1e-12);
            previous = *p;
        }
        let last = s.back().unwrap().translation.vector;
        assert!((last - Vector3::new(0.3, 0.1, 0.24)).norm() < 1e-12);
        assert!(segments(&now, &now, 0.03).is_empty());
    }

    /// A step's goal is the anchor's true pose composed with the relative pose between the
    /// two experiences, from their map poses or from the link's odometry.
    #[test]
    fn step_goals_compose_the_anchor_with_the_relative_pose() {
        let mut map = ObjectMap::default();
        let a = Isometry3::new(Vector3::new(0.1, 0.2, 0.0), Vector3::z() * 0.3);
        let b = Isometry3::new(Vector3::new(0.15, 0.1, 0.05), Vector3::y() * -0.2);
        map.add(Default::default(), [0.0; 6], &a, None);
        map.add(Default::default(), [0.0; 6], &b, None);
        let odometry = Isometry3::new(Vector3::new(0.01, 0.0, 0.0), Vector3::zeros());
        map.links.push(Link::new(0, 1, &odometry));
        let truth = Isometry3::from_parts(
            Translation3::new(0.5, 0.0, 0.2),
            UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
        );
        let by_map = step_goal(&map, (0, truth), 1, StepPose::Map).unwrap();
        let expected = truth * a.inverse() * b;
        assert!((by_map.to_homogeneous() - expected.to_homogeneous()).norm() < 1e-12);
        let by_odometry = step_goal(&map, (0, truth), 1, StepPose::Odometry).unwrap();
        assert!(
            (by_odometry.to_homogeneous() - (truth * odometry).to_homogeneous()).norm() < 1e-12
        );
        // Backwards along the link: its inverse; no link: no odometry step.
        let back = step_goal(&map, (1, truth), 0, StepPose::Odometry).unwrap();
        assert!(
            (back.to_homogeneous() - (truth * odometry.inverse()).to_homogeneous()).norm() < 1e-12
        );
        map.links.clear();
        assert!(step_goal(&map, (0, truth), 1, StepPose::Odometry).is_none());
    }

    /// A tour visits every usable face once per loop, skipping faces below the floor.
    #[test]
    fn a_tour_visits_each_usable_face_once_per_loop() {
        let mesh = GoalMesh::sphere(Point3::new(0.5, 0.0, 0.1), 0.2, 8);
        let mut tour = FaceTour::new(mesh, 0.0);
        let usable = tour.usable();
        assert!(usable < 64 && usable > 0);
        let mut seen = vec![0usize; 64];
        for _ in 0..usable {
            let f = tour.next(40).unwrap();
            assert!(tour.mesh.faces[f].centroid.z >= 0.0);
            seen[f] += 1;
        }
        assert_eq!(tour.loops, 0);
        assert!(seen.iter().all(|&n| n <= 1));
        assert_eq!(seen.iter().sum::<usize>(), usable);
        tour.next(40).unwrap();
        assert_eq!(tour.loops, 1);
    }
}
