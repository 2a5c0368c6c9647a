//! `[navigate.object]` of a scenario (documented in `scenarios/README.md`): object mode
//! on the mobile robot (issue #36, thesis Fig 5.1, Ch 6) — when the mode-switch cue says
//! "object" the base stops, the arm (or the base, `dock`) turns to face it, and the Ch 6
//! closed loop (`[navigate.object.explore]`, the `[explore]` fields) identifies it against
//! the known object maps within a whisk budget; what it cannot identify it maps.

use crate::error::{Error, Result};
use crate::explore::{ExploreConfig, Task};
use crate::sensing::Sensing;
use serde::Deserialize;
use std::path::Path;

/// `[navigate.object]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectModeConfig {
    /// What turns to face the object: `"arm"` (the shoulder's pan joint; the base stays
    /// where it stopped) or `"base"` (the base turns in place and drives up to
    /// `dock_distance_m`, its odometry reading both legs with its errors) ["arm"].
    #[serde(default)]
    pub dock: DockBy,
    /// How far ahead of the base's centre (the arm's base) the base docks the outline's
    /// centre, the contacts' centroid on the object's near side (m) [0.45]: the Ch 6
    /// scenarios' 0.55 m to the object's centre less a small object's half width.
    #[serde(default = "dock")]
    pub dock_distance_m: f64,
    /// A new stop only where the outline's centre lies farther than this from the last
    /// stop's (m) [1.0]: one object, one stop per pass.
    #[serde(default = "revisit")]
    pub revisit_m: f64,
    /// Energy a re-observed landmark injects in place of Eq 5.8's e [1.0]: one
    /// recognition, a whole packet's worth (the images' 0.1 does not close a drifted
    /// loop in one observation: `crates/slam/tests/landmarks.rs`).
    #[serde(default = "one")]
    pub landmark_energy: f64,
    /// An identity re-observed within this of one of its landmarks in the map (from the
    /// map's current estimate, m) is that landmark; farther, it is another object of the
    /// same kind, a new landmark [1.5]: data association, so that a Box-Stack taken for
    /// the Box 3.5 m away does not close the loop there.
    #[serde(default = "gate")]
    pub landmark_gate_m: f64,
    /// Whether a stop that recognises nothing builds the object's map there (Ch 6 map
    /// building, `[navigate.object.explore]` with `task = "map"`) and adds it to the
    /// known maps as `object-<n>` [true].
    #[serde(default = "yes")]
    pub map_unmapped: bool,
    /// The most whisks of such a map building [2000: the Box's two loops take ~1700].
    #[serde(default = "map_whisks")]
    pub map_whisks: usize,
    /// `[navigate.object.explore]`: the closed loop at a stop, in the arm's base frame
    /// (its table is the floor, `mount_height_m` below); `task` must be "recognise" and
    /// `object` is left out (the stop sets it).
    pub explore: ExploreConfig,
}

/// `[navigate.object]` `dock`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DockBy {
    /// The arm's shoulder pan turns the arm to face the object.
    #[default]
    Arm,
    /// The base turns and drives.
    Base,
}

fn dock() -> f64 {
    0.45
}
fn revisit() -> f64 {
    1.0
}
fn one() -> f64 {
    1.0
}
fn gate() -> f64 {
    1.5
}
fn yes() -> bool {
    true
}
fn map_whisks() -> usize {
    2000
}

impl ObjectModeConfig {
    /// Checks the fields (`objects` the scenario's object names); errors name the field
    /// under `navigate.object`; the stops are sensed by `sensing`.
    pub fn validate(&self, file: &Path, objects: &[String], sensing: Sensing) -> Result {
        let bad = |field: &str, msg: String| {
            Err(Error::field(file, &format!("navigate.object.{field}"), msg))
        };
        for (name, v) in [
            ("dock_distance_m", self.dock_distance_m),
            ("revisit_m", self.revisit_m),
            ("landmark_energy", self.landmark_energy),
            ("landmark_gate_m", self.landmark_gate_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(name, format!("{v}: expected a number > 0"));
            }
        }
        if !(1..=crate::explore::MAX_ITERATIONS).contains(&self.map_whisks) {
            return bad(
                "map_whisks",
                format!(
                    "{}: expected 1 to {}",
                    self.map_whisks,
                    crate::explore::MAX_ITERATIONS
                ),
            );
        }
        if self.explore.task != Task::Recognise {
            return bad(
                "explore.task",
                "object mode recognises: expected \"recognise\"".into(),
            );
        }
        if self.explore.object.is_some() {
            return bad(
                "explore.object",
                "each stop explores the object it met: expected none".into(),
            );
        }
        let Some(first) = objects.first() else {
            return bad(
                "explore",
                "object mode needs objects: expected [[objects]] entries".into(),
            );
        };
        self.episode(first)
            .validate(file, objects, sensing)
            .map_err(|e| {
                Error::Input(
                    e.to_string()
                        .replace("field `explore.", "field `navigate.object.explore."),
                )
            })
    }

    /// The closed loop's `[explore]` for a stop at the object named `object`.
    pub fn episode(&self, object: &str) -> ExploreConfig {
        ExploreConfig {
            object: Some(object.to_string()),
            ..self.explore.clone()
        }
    }
}
