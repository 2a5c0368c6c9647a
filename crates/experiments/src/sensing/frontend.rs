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

use super::contact::{HEADER, estimate, write_row};
use crate::record::Recorder;
use crate::record::{Contact, ContactKind};
use nalgebra::Isometry3;
use std::path::Path;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::files;
use whisker_sim::sensing::kinematic::RigidWhisker;
use whisker_sim::sensing::physics::WhiskerConfig;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::contact::Contact as SlamContact;
use whisker_slam::frontend::contact::FrontEndParams;
use whisker_slam::radial::RadialEstimator;
use whisker_slam::rng::StreamRng;
use whisker_slam::sensor::Sample;

/// The front end along a physics run.
pub struct FrontEnd {
    /// Each whisker's detection levels ([`super::detection::Detection::levels`]).
    params: Vec<FrontEndParams>,
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
    /// The front end of `scenario` for whiskers `configs` (RCP thresholds calibrated).
    pub fn new(file: &ScenarioFile, configs: &[WhiskerConfig]) -> Result<Self> {
        let scenario = &file.scenario;
        let model = scenario.frontend.model(&file.path)?;
        Ok(Self {
            params: super::detection::Detection::of_scenario(scenario).levels(configs),
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
    ) -> Result {
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

    fn process(&mut self, recording: Option<&dyn Recorder>) -> Result {
        let index = self.cycle.unwrap_or(0);
        let rate = whisker_slam::sensor::SAMPLE_RATE_HZ;
        let mut world = Vec::new();
        for (w, stream) in self.samples.iter().enumerate() {
            let whisker = &self.whiskers[w];
            let Some(e) = estimate(
                whisker,
                stream,
                rate,
                &self.params[w],
                &self.model,
                &mut self.rng,
                &self.poses,
            ) else {
                continue;
            };
            let p = e.point;
            world.push(Contact {
                whisker: w,
                point: [p.x, p.y, p.z],
            });
            let contact = SlamContact {
                whisker: w,
                time_s: self.cycle_start + e.event.onset as f64 / rate,
                angle_rad: e.event.onset_angle,
                radial_distance: e.radial_distance,
                point: e.pose.inverse_transform_point(&p),
                slope: e.event.slope,
            };
            write_row(
                &mut self.csv,
                index,
                self.cycle_start,
                &contact,
                &whisker.module.pixel(),
                &p,
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
    pub fn finish(self, dir: &Path) -> Result {
        files::write_atomic(&dir.join("frontend.csv"), self.csv.as_bytes())
    }
}
