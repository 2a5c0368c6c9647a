//! The Chapter 6 closed loop stepped from Python (`whisker_slam.RecognitionEnv` is built
//! on it): [`Episode`] wraps the library's `closed_loop::Episode`, whose `run` is the same
//! loop stepped with its own goals — so a caller that passes back the loop's proposal
//! makes the run `whisker run` makes, byte for byte.

use crate::{InputError, RunError, pose, raise};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use whisker_experiments::closed_loop::{self, Refused};
use whisker_scenario::Experiment;
use whisker_scenario::plan::Plan;

type Inner = closed_loop::Episode<'static>;

/// A closed-loop run of a scenario with an `[explore]` section, one whisk per `step`.
#[pyclass(module = "whisker_slam._native")]
pub struct Episode {
    inner: Option<Inner>,
}

fn ended_error() -> PyErr {
    RunError::new_err("the episode was finished: make a new one")
}

impl Episode {
    fn get(&self) -> PyResult<&Inner> {
        self.inner.as_ref().ok_or_else(ended_error)
    }

    fn get_mut(&mut self) -> PyResult<&mut Inner> {
        self.inner.as_mut().ok_or_else(ended_error)
    }
}

/// A caller's goal: None, or 7 numbers.
fn goal(g: Option<PyReadonlyArray1<'_, f64>>) -> PyResult<Option<nalgebra::Isometry3<f64>>> {
    g.map(|g| pose::from_slice(g.as_slice()?, "goal"))
        .transpose()
}

/// One step, then the next proposal, so that both are made without the GIL (and in
/// parallel in [`step_many`]); the proposal is what the next step would take anyway.
fn step_and_propose(
    e: &mut Inner,
    goal: Option<nalgebra::Isometry3<f64>>,
    how: Refused,
) -> whisker_scenario::Result<bool> {
    let stepped = e.step(goal, how)?;
    e.proposal();
    Ok(stepped)
}

fn refused(stay: bool) -> Refused {
    if stay {
        Refused::Stay
    } else {
        Refused::Strategy
    }
}

#[pymethods]
impl Episode {
    /// The closed loop of `scenario` (with `overrides`, `PATH=VALUE`, and `seed` when
    /// given), set up and ready for its first step.
    #[new]
    #[pyo3(signature = (scenario, overrides = Vec::new(), seed = None))]
    fn new(
        py: Python<'_>,
        scenario: String,
        overrides: Vec<String>,
        seed: Option<u64>,
    ) -> PyResult<Self> {
        let file = crate::scenario(&scenario, &overrides, seed)?;
        let Experiment::ClosedLoop(config) = &file.scenario.experiment else {
            return Err(InputError::new_err(format!(
                "{}: the scenario has no [explore] section (the closed loop of Chapter 6)",
                file.path.display()
            )));
        };
        let inner = py
            .detach(|| {
                let plan = Plan::new(&file)?;
                let environment = file.environment()?.environment;
                closed_loop::episode(&file, config, plan, &environment)
            })
            .map_err(raise)?;
        Ok(Self { inner: Some(inner) })
    }

    /// The goal the loop would try next — `(pose [x, y, z, qx, qy, qz, qw], kind)`, kind as
    /// `explore.csv`'s `goal_kind` (`face:12`, `spc`, `step:40`) — or None (ended, or the
    /// strategy has none: the array whisks where it is).
    fn proposal<'py>(
        &mut self,
        py: Python<'py>,
    ) -> PyResult<Option<(Bound<'py, numpy::PyArray1<f64>>, String)>> {
        Ok(self
            .get_mut()?
            .proposal()
            .map(|(p, kind)| (pose::to_array(&p).to_vec().into_pyarray(py), kind)))
    }

    /// One whisk: to `goal` (7 numbers; None: the proposal), then WhiskerRatSLAM,
    /// recognition and the SPC. A refused goal (unreachable, or the arm would enter the
    /// object) is followed by the strategy's next goals, as in `whisker run`, or, with
    /// `stay_if_refused`, by a whisk where the array is. Returns False (doing nothing) once
    /// the episode has ended. The GIL is released while it whisks.
    #[pyo3(signature = (goal = None, stay_if_refused = false))]
    fn step(
        &mut self,
        py: Python<'_>,
        goal: Option<PyReadonlyArray1<'_, f64>>,
        stay_if_refused: bool,
    ) -> PyResult<bool> {
        let goal = self::goal(goal)?;
        let inner = self.get_mut()?;
        py.detach(|| step_and_propose(inner, goal, refused(stay_if_refused)))
            .map_err(raise)
    }

    /// Whether the episode has ended (recognised, every IC at `stop_ic`, the map's loops
    /// done, or the budget spent).
    fn ended(&mut self) -> PyResult<bool> {
        Ok(self.get_mut()?.ended())
    }

    /// What the robot knows after the last whisk, as numpy arrays: `touched` (18,) int8,
    /// `contacts` (18, 5) per whisker — x, y, z in the array frame (m), whisk angle (rad),
    /// radial distance (m), zeros where it did not touch —, `array_pose` (7,), `confidence`
    /// (objects, 2): raw RC and integrated IC per loaded object (`objects()` order),
    /// `pose_cell` (6,): the most active 6-D pose cell, `experiences` (1,).
    fn observation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let e = self.get()?;
        let d = PyDict::new(py);
        let mut touched = vec![0i8; 18];
        let mut contacts = Array2::<f64>::zeros((18, 5));
        if let Some(last) = e.last() {
            for &(w, p, angle, radial) in &last.contacts {
                if w < 18 {
                    touched[w] = 1;
                    let row = [p.x, p.y, p.z, angle, radial];
                    for (j, v) in row.into_iter().enumerate() {
                        contacts[(w, j)] = v;
                    }
                }
            }
        }
        d.set_item("touched", touched.into_pyarray(py))?;
        d.set_item("contacts", contacts.into_pyarray(py))?;
        let at = e.last().map_or_else(|| e.array_pose(), |l| l.pose);
        d.set_item("array_pose", pose::to_array(&at).to_vec().into_pyarray(py))?;
        let confidence: Vec<f64> = e.confidence().iter().flat_map(|&(r, i)| [r, i]).collect();
        let n = confidence.len() / 2;
        let confidence = Array2::from_shape_vec((n, 2), confidence).expect("two numbers an object");
        d.set_item("confidence", confidence.into_pyarray(py))?;
        let (cell, experiences) = e.pose_cells();
        d.set_item("pose_cell", cell.to_vec().into_pyarray(py))?;
        d.set_item("experiences", vec![experiences as f64].into_pyarray(py))?;
        Ok(d)
    }

    /// The last whisk's move status, goal kind and the loaded object it re-localised into
    /// (None before the first whisk).
    fn last_step(&self) -> PyResult<Option<(String, String, Option<String>)>> {
        Ok(self
            .get()?
            .last()
            .map(|l| (l.status.to_string(), l.goal_kind.clone(), l.onto.clone())))
    }

    /// The loaded objects, in the order of `observation()["confidence"]`.
    fn objects(&self) -> PyResult<Vec<String>> {
        Ok(self.get()?.objects().to_vec())
    }

    /// The explored object (ground truth: for rewards, not for policies).
    fn truth(&self) -> PyResult<String> {
        Ok(self.get()?.truth().to_string())
    }

    /// The IC threshold of recognition (§6.2); None while building a map.
    fn threshold(&self) -> PyResult<Option<f64>> {
        Ok(self.get()?.threshold())
    }

    /// The object recognised and at which whisk, if any.
    fn identified(&self) -> PyResult<Option<(String, u64)>> {
        Ok(self.get()?.identified())
    }

    /// The seed of the episode's random draws (the scenario's unless given).
    fn seed(&self) -> PyResult<u64> {
        Ok(self.get()?.seed())
    }

    /// Whisks made so far.
    fn whisks(&self) -> PyResult<usize> {
        Ok(self.get()?.whisks())
    }

    /// The whisk budget (`explore.max_iterations`).
    fn budget(&self) -> PyResult<usize> {
        Ok(self.get()?.budget())
    }

    /// Ends the episode: a dict with `explore_csv` and `contacts_csv` (the texts `whisker
    /// run` writes) and `summary_json` (summary.json's text).
    fn finish<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let inner = self.inner.take().ok_or_else(ended_error)?;
        let out = inner.finish().map_err(raise)?;
        let d = PyDict::new(py);
        d.set_item("explore_csv", out.csv)?;
        d.set_item("contacts_csv", out.contacts_csv)?;
        let summary = serde_json::to_string_pretty(&out.summary)
            .map_err(|e| RunError::new_err(e.to_string()))?;
        d.set_item("summary_json", summary + "\n")?;
        Ok(d)
    }
}

/// One step of each episode, `goals[i]` for episode `i` (None: its proposal), in parallel
/// threads with the GIL released. Returns each step's result (False: had ended).
#[pyfunction]
#[pyo3(signature = (episodes, goals, stay_if_refused = false))]
pub fn step_many(
    py: Python<'_>,
    episodes: Vec<PyRefMut<'_, Episode>>,
    goals: Vec<Option<PyReadonlyArray1<'_, f64>>>,
    stay_if_refused: bool,
) -> PyResult<Vec<bool>> {
    if goals.len() != episodes.len() {
        return Err(InputError::new_err(format!(
            "goals: expected one per episode ({}), got {}",
            episodes.len(),
            goals.len()
        )));
    }
    let goals = goals.into_iter().map(goal).collect::<PyResult<Vec<_>>>()?;
    let mut episodes = episodes;
    let mut inners = Vec::with_capacity(episodes.len());
    for e in episodes.iter_mut() {
        inners.push(e.get_mut()?);
    }
    let how = refused(stay_if_refused);
    py.detach(|| {
        inners
            .par_iter_mut()
            .zip(goals)
            .map(|(e, g)| step_and_propose(e, g, how))
            .collect::<Result<Vec<bool>, _>>()
    })
    .map_err(raise)
}

/// The baseline of `python/examples/bench.py`: the closed loop of `scenario` stepped to its
/// end in Rust with its own goals, as `whisker run` steps it. Returns (whisks, seconds of
/// stepping; set-up and outputs excluded). The GIL is released.
#[pyfunction]
#[pyo3(signature = (scenario, overrides = Vec::new(), seed = None))]
pub fn time_loop(
    py: Python<'_>,
    scenario: String,
    overrides: Vec<String>,
    seed: Option<u64>,
) -> PyResult<(usize, f64)> {
    let mut e = Episode::new(py, scenario, overrides, seed)?;
    let inner = e.get_mut()?;
    py.detach(|| {
        let t = std::time::Instant::now();
        while inner.step(None, Refused::Strategy)? {}
        Ok((inner.whisks(), t.elapsed().as_secs_f64()))
    })
    .map_err(raise)
}
