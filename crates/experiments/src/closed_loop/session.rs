//! The closed loop as a library call: `whisker run` with an `[explore]` section, the
//! tests, datasets and batch trials all call [`run`] or [`run_logged`]; the mobile robot's
//! stops call [`run_knowing`] with the maps it built.

use super::setup::{self, Outlets};
use super::state::Outcome;
use crate::record::{Recorder, Reporter, Silent};
use crate::sensing::held::WhiskLog;
use std::path::Path;
use whisker_scenario::Scenario;
use whisker_scenario::error::Result;
use whisker_scenario::plan::Plan;
use whisker_sim::environment::Environment;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// Runs the closed loop of `scenario` (read from `file`) in `environment`.
pub fn run(
    scenario: &Scenario,
    file: &Path,
    plan: Plan,
    environment: &Environment,
) -> Result<Outcome> {
    run_knowing(scenario, file, plan, environment, &[])
}

/// [`run`] knowing `learned` object maps (name, map) besides `[explore].maps`.
pub fn run_knowing(
    scenario: &Scenario,
    file: &Path,
    plan: Plan,
    environment: &Environment,
    learned: &[(String, ObjectMap)],
) -> Result<Outcome> {
    run_recorded(scenario, file, plan, environment, learned, None)
}

/// [`run_knowing`], each whisk logged to `recording` (the arm's motion is recorded after
/// the loop: [`super::outputs::record_arm`]).
pub fn run_recorded(
    scenario: &Scenario,
    file: &Path,
    plan: Plan,
    environment: &Environment,
    learned: &[(String, ObjectMap)],
    recording: Option<&dyn Recorder>,
) -> Result<Outcome> {
    let outlets = Outlets {
        log: None,
        recording,
        reporter: &Silent,
        learned,
    };
    start(
        setup::build(scenario, file, plan, environment, outlets)?,
        scenario,
    )
}

/// Runs a built loop from the array's pose.
fn start(mut state: super::state::Loop<'_>, scenario: &Scenario) -> Result<Outcome> {
    let at = state.robot.array_pose();
    state.run(scenario.seed, at)
}

/// [`run`], physics whisks' samples handed to `log` (stream `explore/physics/<k>`), each
/// whisk logged to `recording`, progress said to `reporter`.
pub fn run_logged(
    scenario: &Scenario,
    file: &Path,
    plan: Plan,
    environment: &Environment,
    log: Option<WhiskLog>,
    recording: Option<&dyn Recorder>,
    reporter: &dyn Reporter,
) -> Result<Outcome> {
    let outlets = Outlets {
        log,
        recording,
        reporter,
        learned: &[],
    };
    start(
        setup::build(scenario, file, plan, environment, outlets)?,
        scenario,
    )
}
