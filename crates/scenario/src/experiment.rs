//! What a scenario runs, chosen once when it is read: the scripted run of its waypoints,
//! the closed loop of Chapter 6 (`[explore]`) or the office robot of Fig 5.1
//! (`[navigate]`). One thing moves the arm, and every command dispatches on this.

use crate::error::{Error, Result};
use crate::explore::ExploreConfig;
use crate::navigate::NavigateConfig;
use crate::sensing::Sensing;
use std::path::Path;

/// What a scenario runs.
#[derive(Debug, Clone, Default)]
pub enum Experiment {
    /// The arm visits `[trajectory]`'s waypoints (`whisker run`: `path.csv`; a `[maze]`
    /// scenario's waypoints are also `whisker maze-slam`'s route).
    #[default]
    Scripted,
    /// `[explore]`: the closed loop of Chapter 6 chooses where the arm whisks.
    ClosedLoop(Box<ExploreConfig>),
    /// `[navigate]`: a mobile base drives a route round the `[office]`, the arm on it.
    Navigate(Box<NavigateConfig>),
}

impl Experiment {
    /// The closed loop's settings, if this is one.
    pub fn explore(&self) -> Option<&ExploreConfig> {
        match self {
            Experiment::ClosedLoop(e) => Some(e),
            _ => None,
        }
    }

    /// The closed loop's settings to change, if this is one.
    pub fn explore_mut(&mut self) -> Option<&mut ExploreConfig> {
        match self {
            Experiment::ClosedLoop(e) => Some(e),
            _ => None,
        }
    }

    /// The office run's settings, if this is one.
    pub fn navigate(&self) -> Option<&NavigateConfig> {
        match self {
            Experiment::Navigate(n) => Some(n),
            _ => None,
        }
    }
}

/// The kind of experiment the sections of a scenario (read from `file`) ask for: one thing
/// moves the arm — the base along its route (`[navigate]`), the closed loop (`[explore]`)
/// or the trajectory's waypoints; the first two sense (kinematic or physics).
pub(crate) fn check_driver(
    file: &Path,
    (explore, navigate): (bool, bool),
    waypoints: usize,
    sensing: Sensing,
) -> Result {
    let bad = |field: &str, msg: String| Err(Error::field(file, field, msg));
    let driver = match (navigate, explore) {
        (true, true) => {
            return bad(
                "explore",
                "with [navigate] the robot explores the objects it meets: expected no \
                 [explore] section"
                    .into(),
            );
        }
        (true, false) => Some(("[navigate]", "the base follows navigate.route_m")),
        (false, true) => Some(("[explore]", "the loop chooses where the arm goes")),
        (false, false) => None,
    };
    match driver {
        Some((section, why)) => {
            if waypoints != 0 {
                let msg = format!("with {section} {why}: expected no waypoints");
                return bad("trajectory.waypoints", msg);
            }
            if !matches!(sensing, Sensing::Kinematic | Sensing::Physics) {
                let msg = format!("{section} needs sensing = \"kinematic\" or \"physics\"");
                return bad("sensing", msg);
            }
        }
        None if waypoints == 0 => {
            return bad(
                "trajectory.waypoints",
                "expected at least one waypoint (or an [explore] or [navigate] section)".into(),
            );
        }
        None => {}
    }
    Ok(())
}
