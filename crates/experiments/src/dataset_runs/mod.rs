//! Datasets of the experiments (docs/dataset.md): `whisker dataset SCENARIO` writes the
//! run the scenario describes with the writer of its experiment, `whisker dataset
//! object-slam` the object walks, [`noise`] adds noise to a clean dataset of any of them,
//! and `whisker slam DIR` runs the replay its manifest names. The format is
//! [`crate::dataset_format`]; each experiment's writer and reader sit beside the experiment
//! (`maze_slam::dataset`, `object_slam::dataset`, `closed_loop::dataset`).

pub mod noise;

use crate::dataset_format::manifest::{Experiment, Manifest};
use crate::dataset_format::{self, Written};
use std::path::{Path, PathBuf};
use whisker_scenario::Experiment as Runs;
use whisker_scenario::ScenarioFile;
use whisker_scenario::{Error, Result};

/// What `whisker dataset SCENARIO --seed N --out DIR` writes.
#[derive(Debug, Clone)]
pub struct ScenarioDataset {
    /// A maze scenario (`[maze]`, run as `whisker maze-slam` runs it), a closed loop
    /// (`[explore]`, run as `whisker run` runs it: the path it took) or an office run
    /// (`[navigate]`, as `whisker run` runs it).
    pub scenario: PathBuf,
    /// Seed [default: the scenario's `seed`].
    pub seed: Option<u64>,
    /// The dataset's directory (must not exist).
    pub out: PathBuf,
    /// Without noise (no sensor noise, odometry error or contact noise), to be noised
    /// later by [`noise::run`].
    pub clean: bool,
    /// Changes to scenario fields, as `whisker run --set`.
    pub set: Vec<whisker_scenario::overrides::Override>,
}

/// `whisker dataset SCENARIO`: a maze run, a closed loop or an office run written as a
/// dataset.
pub fn write_scenario(w: &ScenarioDataset, ctx: crate::record::Context) -> Result<Written> {
    let mut file = ScenarioFile::load_with(&w.scenario, &w.set)?;
    // The scenario as run, for truth/scenario.toml: its base merged, --set applied (the
    // seed is the manifest's: the truth does not change with it).
    let text = toml::to_string(&file.table).map_err(|e| Error::Failure(e.to_string()))?;
    file.scenario.seed = w.seed.unwrap_or(file.scenario.seed);
    let file = &file;
    let path = file.path.display();
    dataset_format::timed(&w.out, |staging| match &file.scenario.experiment {
        Runs::ClosedLoop(_) if w.clean => Err(Error::Input(format!(
            "{path}: --clean: a closed loop's path depends on its noise; write it with the \
             noise it runs with"
        ))),
        Runs::ClosedLoop(config) => {
            crate::closed_loop::dataset::write(file, config, &text, staging, ctx.reporter)
        }
        Runs::Navigate(_) if w.clean => Err(Error::Input(format!(
            "{path}: --clean: the robot's stops depend on its noise; write the office run with \
             the noise it runs with"
        ))),
        Runs::Navigate(config) => {
            crate::navigation::dataset::write(file, config, &text, staging, ctx.reporter)
        }
        Runs::Scripted if file.scenario.maze.is_some() => {
            crate::maze_slam::dataset::write(file, &text, w.clean, staging, ctx.reporter)
        }
        Runs::Scripted => Err(file.error(
            "maze",
            "whisker dataset writes maze scenarios ([maze]), closed loops ([explore]) \
             and office runs ([navigate]); object walks: `whisker dataset object-slam`",
        )),
    })
}

/// `whisker dataset object-slam`: the walks of `whisker object-slam` as a dataset.
pub fn write_objects(
    o: &crate::object_slam::dataset::ObjectDataset,
    ctx: crate::record::Context,
) -> Result<Written> {
    dataset_format::timed(&o.out, |staging| {
        crate::object_slam::dataset::write(o, staging, ctx)
    })
}

/// What `whisker slam DIR` found: the report of the experiment the manifest names.
#[derive(Debug, Clone, serde::Serialize)]
#[serde(untagged)]
pub enum SlamReport {
    Maze(crate::maze_slam::Report),
    Object(crate::object_slam::Report),
    ClosedLoop(crate::closed_loop::dataset::ReplaySummary),
    Navigate(crate::navigation::replay::Report),
}

impl std::fmt::Display for SlamReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SlamReport::Maze(r) => r.fmt(f),
            SlamReport::Object(r) => r.fmt(f),
            SlamReport::ClosedLoop(r) => r.fmt(f),
            SlamReport::Navigate(r) => r.fmt(f),
        }
    }
}

/// `whisker slam DIR`: the front end and the SLAM the manifest of the dataset in `dir`
/// names, results into `out` as the experiment's own command writes them.
pub fn slam(dir: &Path, out: Option<&Path>, ctx: crate::record::Context) -> Result<SlamReport> {
    let manifest = Manifest::read(dir)?;
    match manifest.experiment {
        Experiment::MazeSlam => {
            let mut settings = crate::maze_slam::Settings::of(Path::new(""));
            settings.out = out.map(Path::to_path_buf);
            crate::maze_slam::replay(&settings, dir, &manifest, ctx).map(SlamReport::Maze)
        }
        Experiment::ObjectSlam => {
            let data = crate::object_slam::dataset::read(dir, &manifest)?;
            let settings = crate::object_slam::Settings {
                seed: manifest.seed,
                out: out.map(Path::to_path_buf),
                ..Default::default()
            };
            crate::object_slam::analyse(&settings, &data, ctx).map(SlamReport::Object)
        }
        Experiment::ClosedLoop => {
            crate::closed_loop::dataset::replay(dir, &manifest, out).map(SlamReport::ClosedLoop)
        }
        Experiment::Navigate => {
            crate::navigation::replay::replay(dir, &manifest, out).map(SlamReport::Navigate)
        }
    }
}
