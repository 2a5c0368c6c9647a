//! The signal front end during `whisker run` with `sensing = "physics"` (thesis Ch 4,
//! §5.1.1.1): every whisk cycle of every whisker's 2 kHz stream goes through contact
//! detection ([`whisker_slam::frontend::contact::detect`]); a detected contact's radial
//! distance comes from the scenario's radial-distance model (`[frontend] radial_model`,
//! by default the built-in svr10 of `assets/models/svr10.json`), and it is localised at the
//! onset's whisk angle with the array where it was at the onset (Eq 5.1–5.2). The
//! contacts are written to `frontend.csv` in the columns of `contacts.csv`
//! (`scenarios/README.md`), beside the ground truth of `anticipated.csv`.
//!
//! Whisk cycles follow whisker A1's pattern (cycles start fully retracted); a cycle cut
//! off by the end of the run is not processed.

use crate::contacts::HEADER;
use crate::error::{CliError, CliResult};
use crate::output;
use crate::record::Recorder;
use crate::record::{Contact, ContactKind};
use crate::scenario::Scenario;
use nalgebra::Isometry3;
use std::fmt::Write as _;
use std::path::Path;
use whisker_sim::sensing::kinematic::RigidWhisker;
use whisker_sim::sensing::physics::WhiskerConfig;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::frontend::contact::{FrontEndParams, detect};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::rng::StreamRng;
use whisker_slam::sensor::Sample;

/// The built-in default radial-distance model: svr10 (CP-CA-DV-DA-AV), the thesis'
/// choice (§4.2.1), trained by `whisker radial train` on the physics training set.
pub const DEFAULT_MODEL: &str = include_str!("../assets/models/svr10.json");

/// The radial-distance model file at `path` (a `whisker radial train` output), or the
/// built-in svr10.
pub fn radial_model(path: Option<&Path>) -> CliResult<RadialEstimator> {
    match path {
        Some(p) => crate::radial::load_model(p),
        None => serde_json::from_str(DEFAULT_MODEL)
            .map_err(|e| CliError::Failure(format!("the built-in svr10 model: {e}"))),
    }
}

/// The front end along a physics run.
pub struct FrontEnd {
    params: FrontEndParams,
    model: RadialEstimator,
    whiskers: Vec<RigidWhisker>,
    pattern: WhiskingPattern,
    rng: StreamRng,
    cycle: Option<i64>,
    cycle_start: f64,
    samples: Vec<Vec<Sample>>,
    poses: Vec<Isometry3<f64>>,
    csv: String,
    contacts: u64,
}

impl FrontEnd {
    /// The front end of `scenario` for whiskers `configs`.
    pub fn new(scenario: &Scenario, file: &Path, configs: &[WhiskerConfig]) -> CliResult<Self> {
        let model = scenario.frontend.model(file)?;
        Ok(Self {
            params: scenario.frontend.detection,
            model,
            whiskers: configs.iter().map(WhiskerConfig::rigid).collect(),
            pattern: configs[0].pattern,
            rng: whisker_slam::rng::substream(scenario.seed, "frontend/radial"),
            cycle: None,
            cycle_start: 0.0,
            samples: vec![Vec::new(); configs.len()],
            poses: Vec::new(),
            csv: HEADER.to_string(),
            contacts: 0,
        })
    }

    /// Takes the samples of time `t` (s) with the array at `pose`; processes the cycle
    /// that `t` closes.
    pub fn push(
        &mut self,
        t: f64,
        pose: &Isometry3<f64>,
        samples: &[Sample],
        recording: Option<&dyn Recorder>,
    ) -> CliResult {
        let k = self.pattern.cycle(t);
        if self.cycle != Some(k) {
            if self.cycle.is_some() {
                self.process(recording)?;
            }
            self.cycle = Some(k);
            self.cycle_start = t;
            self.poses.clear();
            self.samples.iter_mut().for_each(Vec::clear);
        }
        self.poses.push(*pose);
        for (buffer, s) in self.samples.iter_mut().zip(samples) {
            buffer.push(*s);
        }
        Ok(())
    }

    fn process(&mut self, recording: Option<&dyn Recorder>) -> CliResult {
        let index = self.cycle.unwrap_or(0);
        let rate = whisker_slam::sensor::SAMPLE_RATE_HZ;
        let mut world = Vec::new();
        for (w, stream) in self.samples.iter().enumerate() {
            let whisker = &self.whiskers[w];
            let Some(event) = detect(stream, rate, whisker.module.beam.length, &self.params) else {
                continue;
            };
            let r = self.model.estimate(&event.features, &mut self.rng);
            let pose = self.poses[event.onset.min(self.poses.len() - 1)];
            let p = whisker.shaft_point(&pose, event.onset_angle, r);
            let local = pose.inverse_transform_point(&p);
            world.push(Contact {
                whisker: w,
                point: [p.x, p.y, p.z],
            });
            let _ = writeln!(
                self.csv,
                "{index},{},{w},{},{},{},{r},{},{},{},{},{},{},{}",
                self.cycle_start,
                whisker.module.pixel(),
                self.cycle_start + event.onset as f64 / rate,
                event.onset_angle.to_degrees(),
                local.x,
                local.y,
                local.z,
                p.x,
                p.y,
                p.z,
                event.slope
            );
            self.contacts += 1;
        }
        if let Some(rec) = recording {
            rec.contacts(
                ContactKind::Estimated,
                index as u64,
                self.cycle_start,
                &world,
            )?;
        }
        Ok(())
    }

    /// Contacts detected so far.
    pub fn contacts(&self) -> u64 {
        self.contacts
    }

    /// Writes `frontend.csv` into `dir`.
    pub fn finish(self, dir: &Path) -> CliResult {
        output::write_atomic(&dir.join("frontend.csv"), self.csv.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use whisker_slam::frontend::features::Feature;

    #[test]
    fn the_built_in_model_is_svr10() {
        let model = radial_model(None).unwrap();
        let RadialEstimator::Svr { features, model } = model else {
            panic!("the default model is not an SVR");
        };
        use Feature::*;
        assert_eq!(features, [Cp, Ca, Dv, Da, Av]);
        assert!(!model.support.is_empty());
        assert!(model.support.iter().all(|s| s.len() == 5));
    }
}
