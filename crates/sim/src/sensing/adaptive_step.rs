//! Speed-adaptive steps: a whisker's 0.5 ms sample step is split into shorter world steps
//! while a shaft segment approaches a surface faster than Rapier's contacts can catch.
//!
//! Rapier finds contacts once per world step, for pairs closer than the speculative
//! horizon (`normalized_prediction_distance` × `length_unit`: 0.5 mm here); its substeps
//! reuse them. A segment that starts a step farther away than the horizon and moves more
//! than that distance in the step meets no constraint and ends up inside the surface.
//! That is how a whisker tunnelled: a shaft bent over the Mug's handle snaps off its edge
//! and its tip flies at up to ~17 m/s — 8 mm in one 0.5 ms step — into the handle, where
//! it stays (`whisker soak --objects mug --whiskers D1 --duration 10 --nudges 19`: 50 of
//! 140 runs with the array nudged by nanometres went deeper than 1 mm or non-finite).
//! More substeps cannot help (they reuse the step's contacts), nor can a longer horizon
//! (it makes constraints of faces the tip has not reached: see
//! [`super::physics::contact_parameters`]).
//!
//! Before each world step, each segment whose end points could move more than half the
//! horizon in what is left of the sample is checked against every fixed collider: if one
//! lies within that reach, the next world step is cut so that the segment's faster end
//! point moves at most half the horizon; steps are never shorter than 1/[`MAX_SPLITS`] of
//! the sample. Far from every surface (free whisking, even at 10 Hz) nothing is split, so
//! the sample's single world step — bit for bit the fixed-step simulation — is kept
//! whenever nothing fast is near a surface. The array's driver moves along the straight
//! line (and rotation) between its poses at the sample's start and end.
//!
//! Measured on that soak (the composite path; `--fixed-steps` for the old stepping):
//! 0 of 20 nudged runs deeper than 1 mm (the deepest 0.0 mm), at 1.27 world steps per
//! sample for that whisker. Bounding only the approach along the closest-point normal
//! (1.03 steps per sample) was not enough: the nominal run tunnelled at 1.44 s, the snap
//! hitting another part of the handle than the closest one.

use crate::whisker::body::Whisker;
use nalgebra::Point3;
use rapier3d_f64::parry::bounding_volume::{Aabb, BoundingVolume};
use rapier3d_f64::parry::query;
use rapier3d_f64::prelude::*;

/// The shortest world step is the sample's step over this.
pub const MAX_SPLITS: f64 = 64.0;

/// The next world step (s) for a whisker with `left` seconds of its sample step `dt` to
/// go: `left` itself unless a segment within reach of a fixed collider moves too fast.
pub fn next_step(world: &PhysicsWorld, whisker: &Whisker, left: f64, dt: f64) -> f64 {
    let p = &world.integration_parameters;
    let limit = 0.5 * p.normalized_prediction_distance * p.length_unit;
    let l = whisker.beam.segment_length();
    let mut fastest: f64 = 0.0;
    let mut fixed_boxes: Option<Vec<(&Collider, Aabb)>> = None;
    for &h in &whisker.segments {
        let body = &world.bodies[h];
        let pose = Whisker::pose(world, h);
        let ends = [0.0, l].map(|z| {
            let q = pose * Point3::new(0.0, 0.0, z);
            body.velocity_at_point(Vector::new(q.x, q.y, q.z))
        });
        let speed = ends.iter().map(|v| v.length()).fold(0.0, f64::max);
        if speed * left <= limit {
            continue;
        }
        let reach = speed * left + 2.0 * limit;
        // Only colliders whose bounding box comes within `reach` of the segment's can be
        // within `reach` of it (box separation ≤ shape separation on every axis): the
        // exact distance is asked of those alone — the same answer, without the distance
        // queries to the far walls of an office (bit-identical streams).
        let fixed = fixed_boxes.get_or_insert_with(|| fixed(world).collect());
        let near = body.colliders().iter().any(|&c| {
            let segment = &world.colliders[c];
            let bounds = segment.compute_aabb().loosened(reach);
            fixed.iter().any(|(x, b)| {
                bounds.intersects(b)
                    && query::distance(segment.position(), segment.shape(), x.position(), x.shape())
                        .is_ok_and(|d| d.distance <= reach)
            })
        });
        if near {
            fastest = fastest.max(speed);
        }
    }
    if fastest * left <= limit {
        left
    } else {
        (limit / fastest).max(dt / MAX_SPLITS).min(left)
    }
}

/// The world's fixed colliders (the environment: no parent body) and their bounding boxes.
fn fixed(world: &PhysicsWorld) -> impl Iterator<Item = (&Collider, Aabb)> {
    world
        .colliders
        .iter()
        .filter(|(_, c)| c.parent().is_none())
        .map(|(_, c)| (c, c.compute_aabb()))
}
