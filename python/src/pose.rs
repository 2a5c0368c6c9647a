//! Poses between Rust and Python: 7 numbers `[x, y, z, qx, qy, qz, qw]` (metres; a unit
//! quaternion, scalar last, as ROS writes it).

use crate::InputError;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use pyo3::prelude::*;

/// A pose's 7 numbers.
pub fn to_array(pose: &Isometry3<f64>) -> [f64; 7] {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    [t.x, t.y, t.z, q.i, q.j, q.k, q.w]
}

/// The pose of 7 numbers named `what` in errors. A quaternion within 1e-12 of unit length
/// is taken as it is (so that a pose given back is the same pose, bit for bit); any other
/// non-zero one is normalised.
pub fn from_slice(v: &[f64], what: &str) -> PyResult<Isometry3<f64>> {
    if v.len() != 7 || v.iter().any(|x| !x.is_finite()) {
        return Err(InputError::new_err(format!(
            "{what}: expected 7 finite numbers [x, y, z, qx, qy, qz, qw], got {v:?}"
        )));
    }
    let q = Quaternion::new(v[6], v[3], v[4], v[5]);
    let n = q.norm();
    if n < 1e-9 {
        return Err(InputError::new_err(format!(
            "{what}: the quaternion [qx, qy, qz, qw] = {:?} has no direction",
            &v[3..]
        )));
    }
    let rotation = if (n - 1.0).abs() <= 1e-12 {
        UnitQuaternion::new_unchecked(q)
    } else {
        UnitQuaternion::new_normalize(q)
    };
    Ok(Isometry3::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        rotation,
    ))
}
