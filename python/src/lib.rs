//! The `whisker_slam._native` extension of the Python package (`python/`, issue #65): a
//! scenario's run, a dataset read into numpy arrays, one whisk at a pose, and the
//! Chapter 6 closed loop stepped from Python ([`episode`]). Errors are raised as the
//! package's exceptions with the command line's own messages: `InputError` (a
//! `ValueError`: bad scenario, dataset or argument — the CLI's exit code 2), `RunError` (a
//! `RuntimeError`), and `OSError` for an output that could not be written.

mod dataset;
mod episode;
mod pose;
mod whisk;

use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;
use whisker_experiments::record::{Context, Target};
use whisker_scenario::overrides::Override;
use whisker_scenario::{Error, ScenarioFile};

create_exception!(
    _native,
    InputError,
    PyValueError,
    "Bad input: a scenario, dataset, mesh or argument (the command line's exit code 2)."
);
create_exception!(
    _native,
    RunError,
    PyRuntimeError,
    "A run failed while doing valid work (the command line's exit code 1)."
);

/// The Python exception of a run's error, with the message the command line prints after
/// `error: `.
pub(crate) fn raise(e: Error) -> PyErr {
    let message = e.to_string();
    match e {
        Error::Input(_) => InputError::new_err(message),
        Error::Failure(_) => RunError::new_err(message),
        Error::Output(_) => PyOSError::new_err(message),
        Error::Interrupted { .. } => PyKeyboardInterrupt::new_err(message),
    }
}

/// The scenario in `path` with `overrides` (`PATH=VALUE`, as `whisker run --set`) and,
/// when given, its seed replaced.
pub(crate) fn scenario(
    path: &str,
    overrides: &[String],
    seed: Option<u64>,
) -> PyResult<ScenarioFile> {
    let overrides = parse_overrides(overrides)?;
    let mut file = ScenarioFile::load_with(&PathBuf::from(path), &overrides).map_err(raise)?;
    if let Some(seed) = seed {
        file.scenario.seed = seed;
    }
    Ok(file)
}

fn parse_overrides(overrides: &[String]) -> PyResult<Vec<Override>> {
    overrides
        .iter()
        .map(|o| Override::parse(o).map_err(|e| InputError::new_err(format!("overrides: {e}"))))
        .collect()
}

/// Runs the scenario in `scenario` as `whisker run` does (without a Rerun recording) into
/// `out` (default: the scenario's `output.dir`), with `overrides` and `seed`; returns the
/// output directory. The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (scenario, overrides = Vec::new(), out = None, seed = None))]
fn run(
    py: Python<'_>,
    scenario: String,
    overrides: Vec<String>,
    out: Option<String>,
    seed: Option<u64>,
) -> PyResult<String> {
    let file = self::scenario(&scenario, &overrides, seed)?;
    let dir = out
        .map(PathBuf::from)
        .unwrap_or_else(|| file.scenario.output.dir.clone());
    py.detach(|| whisker_experiments::run::execute(&file, &dir, &Target::off(), Context::QUIET))
        .map_err(raise)?;
    Ok(dir.to_string_lossy().into_owned())
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add("RunError", m.py().get_type::<RunError>())?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(dataset::load_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(whisk::sense, m)?)?;
    m.add_function(wrap_pyfunction!(whisk::array_pose, m)?)?;
    m.add_function(wrap_pyfunction!(episode::step_many, m)?)?;
    m.add_function(wrap_pyfunction!(episode::time_loop, m)?)?;
    m.add_class::<episode::Episode>()?;
    Ok(())
}
