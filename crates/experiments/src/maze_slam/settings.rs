//! The settings of `whisker maze-slam`.

use crate::record::Target;
use std::path::{Path, PathBuf};
use whisker_scenario::SensingMode;
use whisker_scenario::overrides::Override;
use whisker_sim::whisker::beam::Bending;

/// What `whisker maze-slam` runs; every setting but the scenario overrides the scenario.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Scenario with a `[maze]`, pose waypoints (the loop's corners) and optionally
    /// `[maze_slam]`.
    pub scenario: PathBuf,
    /// Seeds: one run per seed [default: the scenario's `seed`].
    pub seeds: Option<Vec<u64>>,
    /// Also run the kidnapped variant of every seed (§3.3.1) [scenario:
    /// `maze_slam.kidnap`].
    pub kidnap: bool,
    /// Local-view matching thresholds (Eq 3.1): RatSLAM runs once per value [scenario:
    /// `maze_slam.ratslam.local_view.match_threshold`].
    pub match_threshold: Option<Vec<f64>>,
    /// Pose-cell injection energies (Eq 5.8) [scenario:
    /// `maze_slam.ratslam.local_view.inject_energy`].
    pub inject_energy: Option<Vec<f64>>,
    /// Directory for `trajectory-<images>-<variant>-<seed>.csv` and `images-….csv`.
    pub out: Option<PathBuf>,
    /// Read each seed's tactile images from the `images-….csv` an earlier `out` wrote to
    /// this directory, instead of sensing.
    pub images: Option<PathBuf>,
    /// How tactile images are made [scenario: `sensing`].
    pub sensing: Option<SensingMode>,
    /// Physics: whisk with RCP at 20 × the free-whisking σ (§3.2.2) [scenario:
    /// `array.rcp`].
    pub rcp: bool,
    /// Physics: shaft joint model [scenario: `array.bending`].
    pub bending: Option<Bending>,
    /// Physics: segments per whisker [scenario: `array.segments`].
    pub segments: Option<usize>,
    /// Physics: Rapier substeps per 0.5 ms step [scenario: `array.substeps`].
    pub substeps: Option<usize>,
    /// Changes to scenario fields, as `whisker run --set`.
    pub set: Vec<Override>,
    /// Where the recording goes.
    pub rrd: Target,
}

impl Settings {
    /// The settings of `whisker maze-slam FILE` with nothing else given.
    pub fn of(file: &Path) -> Self {
        Self {
            scenario: file.to_path_buf(),
            seeds: None,
            kidnap: false,
            match_threshold: None,
            inject_energy: None,
            out: None,
            images: None,
            sensing: None,
            rcp: false,
            bending: None,
            segments: None,
            substeps: None,
            set: Vec::new(),
            rrd: Target::default(),
        }
    }
}
