//! The arm, the array and one whisk from Python: the array's pose at joint values, and one
//! whisk cycle with the array held at a pose — kinematic (the anticipated intersect with
//! the scenario's noise) or physics (Rapier whiskers through the scenario's front end), as
//! the scenario's `sensing` says: the closed loop's whisk number `k` there. Physics draws
//! its noise from the whisk's own sub-stream (`explore/physics/<k>`), so it is that whisk
//! exactly; the kinematic contact noise comes from per-whisker streams drawn in sequence
//! over a run, so a fresh `sense` equals the loop's whisk k with that noise off.

use crate::{InputError, pose, raise};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use whisker_experiments::closed_loop;
use whisker_scenario::plan::Plan;
use whisker_sim::sensing::kinematic::SweepTarget;

/// The array's pose `[x, y, z, qx, qy, qz, qw]` (world) with the arm of `scenario` at
/// `joints` (the chain's units: rad, m; default: the scenario's initial joints).
#[pyfunction]
#[pyo3(signature = (scenario, joints = None, overrides = Vec::new()))]
pub fn array_pose<'py>(
    py: Python<'py>,
    scenario: String,
    joints: Option<Vec<f64>>,
    overrides: Vec<String>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let file = crate::scenario(&scenario, &overrides, None)?;
    let plan = Plan::new(&file).map_err(raise)?;
    let chain = closed_loop::array_chain(&file, &plan).map_err(raise)?;
    let q = joints.unwrap_or_else(|| plan.waypoints[0].clone());
    if q.len() != chain.dof() {
        return Err(InputError::new_err(format!(
            "joints: the chain has {} joints, got {} values",
            chain.dof(),
            q.len()
        )));
    }
    Ok(pose::to_array(&chain.fk(&q)).to_vec().into_pyarray(py))
}

/// One whisk with the array held at `pose` (`[x, y, z, qx, qy, qz, qw]`, world) in the
/// scenario's environment, sensed as the scenario says (`sensing`), its random draws those
/// of the closed loop's whisk number `k` with `seed` (default: the scenario's; module
/// documentation). Returns a
/// dict: `contacts` (a dict of arrays, one entry per contact: `whisker`, `time_s`,
/// `angle_rad`, `radial_distance_m`, `point_m` (n, 3) in the array frame, `slope`),
/// `streams` (physics: (18, samples, 3) — whisk angle in rad, x and y deflection in Hall
/// counts, at 2 kHz; kinematic: None) and `period_s`. The GIL is released while it whisks.
#[pyfunction]
#[pyo3(signature = (scenario, pose, k = 0, seed = None, overrides = Vec::new()))]
pub fn sense<'py>(
    py: Python<'py>,
    scenario: String,
    pose: PyReadonlyArray1<'py, f64>,
    k: u64,
    seed: Option<u64>,
    overrides: Vec<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let at = pose::from_slice(pose.as_slice()?, "pose")?;
    let file = crate::scenario(&scenario, &overrides, seed)?;
    let seed = file.scenario.seed;
    let environment = file.environment().map_err(raise)?.environment;
    let mut sensor = closed_loop::sensor(&file, &environment, None).map_err(raise)?;
    let target = SweepTarget::of(&environment);
    let (cycle, period, streams) = py.detach(|| sensor.whisk(&target, k, 0.0, &at, seed));
    let d = PyDict::new(py);
    let c = &cycle.contacts;
    let contacts = PyDict::new(py);
    let column = |f: &dyn Fn(&whisker_slam::contact::Contact) -> f64| -> Vec<f64> {
        c.iter().map(f).collect()
    };
    let whiskers: Vec<i64> = c.iter().map(|c| c.whisker as i64).collect();
    contacts.set_item("whisker", whiskers.into_pyarray(py))?;
    contacts.set_item("time_s", column(&|c| c.time_s).into_pyarray(py))?;
    contacts.set_item("angle_rad", column(&|c| c.angle_rad).into_pyarray(py))?;
    contacts.set_item(
        "radial_distance_m",
        column(&|c| c.radial_distance).into_pyarray(py),
    )?;
    let points: Vec<f64> = c
        .iter()
        .flat_map(|c| [c.point.x, c.point.y, c.point.z])
        .collect();
    let points = numpy::ndarray::Array2::from_shape_vec((c.len(), 3), points)
        .expect("three numbers a contact");
    contacts.set_item("point_m", points.into_pyarray(py))?;
    contacts.set_item("slope", column(&|c| c.slope).into_pyarray(py))?;
    d.set_item("contacts", contacts)?;
    match streams {
        Some(s) => {
            let samples = s.first().map_or(0, Vec::len);
            let flat: Vec<f64> = s
                .iter()
                .flat_map(|w| w.iter().flat_map(|r| [r.angle_rad, r.x, r.y]))
                .collect();
            let a = Array3::from_shape_vec((s.len(), samples, 3), flat)
                .expect("every whisker has the same samples");
            d.set_item("streams", a.into_pyarray(py))?;
        }
        None => d.set_item("streams", py.None())?,
    }
    d.set_item("period_s", period)?;
    Ok(d)
}
