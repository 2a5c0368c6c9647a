//! Array poses near an object, for benchmarks, soak runs and tests: where to put the
//! array so that its whiskers reach the object.

use super::kinematic::{RigidWhisker, SweepTarget};
use crate::environment::Environment;
use crate::whisker::array;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::query::Ray;
use parry3d_f64::shape::SharedShape;
use rand::RngExt;

/// `count` array poses facing an object (`shape`, bounding box `size`, standing on z = 0
/// and centred on the z axis), the array face 2–8 cm out from the surface along a random
/// line of sight to the object's centre, randomly rolled; drawn from the sub-stream
/// `stream` of seed 0.
pub fn facing(
    shape: &SharedShape,
    size: [f64; 3],
    count: usize,
    stream: &str,
) -> Vec<Isometry3<f64>> {
    let mut rng = whisker_slam::rng::substream(0, stream);
    let centre = Vector3::new(0.0, 0.0, 0.5 * size[2]);
    (0..count)
        .map(|_| {
            let dir = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-0.5..1.0),
            )
            .normalize();
            let outside = centre + dir * 2.0;
            let ray = Ray::new(
                PVector::new(outside.x, outside.y, outside.z),
                PVector::new(-dir.x, -dir.y, -dir.z),
            );
            let surface = shape.cast_local_ray(&ray, 2.0, true).unwrap_or(2.0);
            let at = outside - dir * surface + dir * rng.random_range(0.02..0.08);
            let facing = UnitQuaternion::rotation_between(&Vector3::z(), &-dir)
                .unwrap_or_else(UnitQuaternion::identity);
            let roll = UnitQuaternion::from_axis_angle(
                &Vector3::z_axis(),
                rng.random_range(0.0..std::f64::consts::TAU),
            );
            Isometry3::from_parts(Translation3::from(at), facing * roll)
        })
        .collect()
}

/// Of `candidates`, the array pose where the most whiskers (rigid, 3 mm base offset)
/// touch `environment` by the kinematic sweep, and the indices of those whiskers. Poses where a whisker
/// would touch within 3° of full retraction are skipped: physics starts retracted, and
/// a whisker built inside a solid is not a test of anything.
pub fn most_touching(
    environment: &Environment,
    candidates: &[Isometry3<f64>],
) -> Option<(Isometry3<f64>, Vec<usize>)> {
    let target = SweepTarget::of(environment);
    let whiskers: Vec<RigidWhisker> = array::modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, 3.0e-3))
        .collect();
    candidates
        .iter()
        .filter_map(|p| {
            let hits: Vec<(usize, usize)> = whiskers
                .iter()
                .filter_map(|w| target.sweep(w, p).map(|h| (w.module.index, h.step)))
                .collect();
            hits.iter()
                .all(|&(_, k)| k >= 3)
                .then(|| (*p, hits.iter().map(|&(i, _)| i).collect::<Vec<usize>>()))
        })
        .max_by_key(|(_, touching)| touching.len())
}

/// The array pose near a catalogued object (`placed`) where the most whiskers touch, of
/// the 64 [`facing`] poses of the `bench/sensing` stream — the pose of `whisker soak`,
/// `whisker bench sensing`'s first case and the physics tests — and the touching whiskers.
pub fn busiest(
    environment: &Environment,
    shape: &SharedShape,
    size: [f64; 3],
) -> Option<(Isometry3<f64>, Vec<usize>)> {
    most_touching(environment, &facing(shape, size, 64, "bench/sensing"))
}
