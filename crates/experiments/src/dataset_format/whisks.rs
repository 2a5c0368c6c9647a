//! Physics whisks as whisk files (docs/dataset.md, level `streams`) for the datasets of
//! held-still whisks — object walks and closed loops: the files written as the simulation
//! produces the whisks (in parallel), the radial-distance model beside them, and the same
//! front end rebuilt from a dataset to replay them.

use super::manifest::{Manifest, Role};
use super::{Staging, records};
use crate::sensing::detection::Detection;
use crate::sensing::held::{PhysicsSensing, WhiskLog};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use whisker_scenario::{Error, Result};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::sensor::Sample as Reading;

/// A [`WhiskLog`] that writes each whisk's samples to a whisk file, keeping the first
/// failure for [`WhiskFiles::finish`] (a log cannot return one).
pub struct WhiskFiles {
    /// The log to hand to the sensing.
    pub log: WhiskLog,
    failure: Arc<Mutex<Option<String>>>,
}

impl WhiskFiles {
    /// Writes whisk `k` of stream `stream` to `path(stream, k)` (parent created), whisker
    /// columns `labels`, angles in counts of `angle_resolution` (rad).
    pub fn new(
        path: impl Fn(&str, usize) -> PathBuf + Send + Sync + 'static,
        labels: Vec<String>,
        angle_resolution: f64,
    ) -> Self {
        let failure = Arc::new(Mutex::new(None::<String>));
        let kept = failure.clone();
        let log: WhiskLog = Arc::new(move |stream: &str, k: usize, streams: &[Vec<Reading>]| {
            let path = path(stream, k);
            let written = records::whisk_csv(&labels, streams, angle_resolution)
                .map_err(|e| e.to_string())
                .and_then(|csv| {
                    std::fs::create_dir_all(path.parent().expect("a file in a directory"))
                        .and_then(|_| std::fs::write(&path, csv))
                        .map_err(|e| format!("cannot write {}: {e}", path.display()))
                });
            if let Err(e) = written {
                kept.lock().expect("not poisoned").get_or_insert(e);
            }
        });
        Self { log, failure }
    }

    /// The first failure to write, if any.
    pub fn finish(&self) -> Result {
        match self.failure.lock().expect("not poisoned").take() {
            Some(e) => Err(Error::Output(e)),
            None => Ok(()),
        }
    }
}

/// The radial-distance model's file in a dataset.
const MODEL: &str = "log/radial_model.json";

/// Writes `model` to `log/radial_model.json` (the format of `whisker radial train`).
pub fn put_model(s: &mut Staging, model: &RadialEstimator) -> Result {
    let text = serde_json::to_string_pretty(model).expect("plain JSON") + "\n";
    s.put(MODEL, Role::Log, text.as_bytes())
}

/// The front end of held-still physics whisks as the dataset in `dir` (manifest `m`) was
/// sensed: its radial-distance model, its array's shafts, and each whisker's detection
/// `levels` as the manifest records them (`closed_loop.frontend`, `object_slam.frontend`),
/// else the written default levels (500 counts) older datasets were detected at.
pub fn replay_sensing(
    dir: &Path,
    m: &Manifest,
    levels: Option<(&str, &[whisker_slam::frontend::contact::FrontEndParams])>,
) -> Result<PhysicsSensing> {
    let model = whisker_scenario::radial_model::load_or_default(Some(&m.file(dir, MODEL)?))?;
    // A dataset without levels predates the noise rule: detected at the written defaults.
    let written = Detection::as_written(whisker_slam::frontend::contact::FrontEndParams::default());
    let sensing = PhysicsSensing::new(Vec::new(), model, &written)
        .with_rigid(super::rigid_whiskers(dir, &m.array)?);
    Ok(match levels {
        None => sensing,
        Some((_, l)) if l.len() == m.array.labels.len() => sensing.with_levels(l.to_vec()),
        Some((field, l)) => {
            return Err(Error::field(
                &dir.join(super::manifest::FILE),
                field,
                format!(
                    "{} whiskers' detection levels, expected one per whisker ({})",
                    l.len(),
                    m.array.labels.len()
                ),
            ));
        }
    })
}
