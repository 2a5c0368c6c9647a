//! The closed loop as a library call: `whisker run` with an `[explore]` section, the
//! tests, datasets and batch trials all call [`run`] or [`run_logged`]; the mobile robot's
//! stops call [`run_knowing`] with the maps it built.

use super::episode::{Episode, Refused};
use super::setup::{self, Outlets};
use super::state::Outcome;
use crate::record::{Recorder, Reporter, Silent};
use crate::sensing::held::WhiskLog;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::explore::ExploreConfig;
use whisker_scenario::plan::Plan;
use whisker_sim::environment::Environment;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;

/// Runs the closed loop `config` of the scenario in `file` in `environment`.
pub fn run(
    file: &ScenarioFile,
    config: &ExploreConfig,
    plan: Plan,
    environment: &Environment,
) -> Result<Outcome> {
    run_knowing(file, config, plan, environment, &[])
}

/// [`run`] knowing `learned` object maps (name, map) besides `[explore].maps`.
pub fn run_knowing(
    file: &ScenarioFile,
    config: &ExploreConfig,
    plan: Plan,
    environment: &Environment,
    learned: &[(String, ObjectMap)],
) -> Result<Outcome> {
    run_recorded(file, config, plan, environment, learned, None)
}

/// [`run_knowing`], each whisk logged to `recording` (the arm's motion is recorded after
/// the loop: [`super::outputs::record_arm`]).
pub fn run_recorded(
    file: &ScenarioFile,
    config: &ExploreConfig,
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
        setup::build(file, config, plan, environment, outlets)?,
        file.scenario.seed,
    )
}

/// Runs a built loop from the array's pose, its random draws from `seed`: its
/// [`Episode`] stepped to the end with the loop's own goals.
fn start(state: super::state::Loop<'_>, seed: u64) -> Result<Outcome> {
    let mut episode = Episode::new(state, seed);
    while episode.step(None, Refused::Strategy)? {}
    episode.finish()
}

/// The closed loop `config` of the scenario in `file` in `environment`, ready to be
/// stepped ([`Episode::step`]) by a caller that chooses the goals (nothing recorded or
/// said); its random draws from the scenario's seed.
pub fn episode(
    file: &ScenarioFile,
    config: &ExploreConfig,
    plan: Plan,
    environment: &Environment,
) -> Result<Episode<'static>> {
    let outlets = Outlets {
        log: None,
        recording: None,
        reporter: &Silent,
        learned: &[],
    };
    let state = setup::build(file, config, plan, environment, outlets)?;
    Ok(Episode::new(state, file.scenario.seed))
}

/// [`run`], physics whisks' samples handed to `log` (stream `explore/physics/<k>`), each
/// whisk logged to `recording`, progress said to `reporter`.
pub fn run_logged(
    file: &ScenarioFile,
    config: &ExploreConfig,
    plan: Plan,
    environment: &Environment,
    (log, recording): (Option<WhiskLog>, Option<&dyn Recorder>),
    reporter: &dyn Reporter,
) -> Result<Outcome> {
    let outlets = Outlets {
        log,
        recording,
        reporter,
        learned: &[],
    };
    start(
        setup::build(file, config, plan, environment, outlets)?,
        file.scenario.seed,
    )
}
