//! Physics sensing with the array held still: at each pose (of an object walk, of the
//! closed loop, of an office tour) the array whisks once in Rapier; the signal front end
//! detects each whisker's contact at the detection levels of [`super::detection`], the
//! radial-distance model (default svr10) places it along the shaft at the onset's whisk
//! angle (Eq 5.1–5.2), and the slope is the gradient of y against x deflection
//! (§5.1.1.1.3). A scenario's run senses as its `[array]` (RCP mode and threshold, the
//! whisking strategies) and `[frontend]` (detection, model) say
//! ([`PhysicsSensing::of_scenario`]); `whisker object-slam --sensing physics`, which has
//! no scenario, senses in the conditions the radial-distance models are trained under
//! (1 Hz, RCP at the sensor's saturation, §4.1.1; [`PhysicsSensing::new`]).
//!
//! Only the whiskers whose rigid sweep meets the object are simulated (a bending shaft
//! reaches no further than the straight one; the others would whisk freely and, with the
//! front end's confirmation, register nothing). Each pose is a simulation of its own with
//! sensor noise from the sub-stream `<stream>/physics/<k>` of the seed, so results do not
//! depend on the number of threads. An undefined slope (no x or y variation) reads as
//! flat (0), as a missing SDA entry does.

use super::contact::estimate;
use super::detection::Detection;
use crate::record::Reporter;
use nalgebra::Isometry3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use whisker_scenario::{Result, ScenarioFile};
use whisker_sim::sensing::calibration::calibrate_array_rcp;
use whisker_sim::sensing::kinematic::{RigidWhisker, SweepTarget};
use whisker_sim::sensing::physics::{DT, EnvironmentPiece, PhysicsArray, WhiskerConfig};
use whisker_sim::whisker::array;
use whisker_slam::contact::{Contact, ContactCycle};
use whisker_slam::frontend::contact::FrontEndParams;
use whisker_slam::radial::RadialEstimator;
use whisker_slam::rng::{substream, substream_key};
use whisker_slam::sensor::Sample as Reading;

/// The array's whiskers in physics, and how their contacts are estimated.
pub struct PhysicsSensing {
    /// The object in the physics worlds.
    pub environment: Vec<EnvironmentPiece>,
    /// Radial-distance model.
    pub model: RadialEstimator,
    /// Called with each whisk's stream name (`<stream>/physics/<k>` in [`Self::sense`]),
    /// number and samples by [`Self::whisk`] (a dataset writer's log).
    pub log: Option<WhiskLog>,
    configs: Vec<WhiskerConfig>,
    rigid: Vec<RigidWhisker>,
    /// Each whisker's detection levels.
    params: Vec<FrontEndParams>,
}

/// The default array in the radial-distance models' training condition: 1 Hz, RCP at the
/// sensor's saturation (§4.1.1) — what `whisker object-slam --sensing physics` whisks.
pub fn training_configs() -> Vec<WhiskerConfig> {
    array::modules()
        .into_iter()
        .map(|m| {
            let mut c = WhiskerConfig::with_defaults(m);
            c.control.rcp = true;
            c.contact_threshold = Some(c.sensor.saturation_counts);
            c
        })
        .collect()
}

/// A receiver of whisks' samples: (stream, whisk number, every whisker's samples).
pub type WhiskLog = std::sync::Arc<dyn Fn(&str, usize, &[Vec<Reading>]) + Send + Sync>;

impl PhysicsSensing {
    /// The default array in the radial-distance models' training condition (1 Hz, RCP at
    /// the sensor's saturation, §4.1.1) detecting as `detection` says, against
    /// `environment`.
    pub fn new(
        environment: Vec<EnvironmentPiece>,
        model: RadialEstimator,
        detection: &Detection,
    ) -> Self {
        Self::with_configs(environment, model, training_configs(), detection)
    }

    /// The array and front end of the scenario in `file` against `environment`: its
    /// whiskers, RCP and the whisking strategies' thresholds calibrated as `[array] rcp`
    /// says (§3.2.2: k σ of free whisking, sub-streams `calibration/whisker/NN` of the
    /// seed; §4.1.1: the sensor's saturation), `[frontend.detection]` and the model of
    /// `[frontend]`.
    pub fn of_scenario(file: &ScenarioFile, environment: Vec<EnvironmentPiece>) -> Result<Self> {
        let scenario = &file.scenario;
        let mut configs = file.whisker_configs()?;
        if let Some(mode) = scenario.array.contact_mode() {
            calibrate_array_rcp(&mut configs, mode, scenario.seed, DT);
        }
        let model = scenario.frontend.model(&file.path)?;
        Ok(Self::with_configs(
            environment,
            model,
            configs,
            &Detection::of_scenario(scenario),
        ))
    }

    /// The array of `configs` (their RCP thresholds calibrated) against `environment`,
    /// detecting at the levels `detection` sets ([`Detection::levels`]).
    pub fn with_configs(
        environment: Vec<EnvironmentPiece>,
        model: RadialEstimator,
        configs: Vec<WhiskerConfig>,
        detection: &Detection,
    ) -> Self {
        let params = detection.levels(&configs);
        Self::with_params(environment, model, configs, params)
    }

    /// The array of `configs` against `environment`, detecting at each whisker's `params`
    /// (levels already set: computed once for many environments).
    pub fn with_params(
        environment: Vec<EnvironmentPiece>,
        model: RadialEstimator,
        configs: Vec<WhiskerConfig>,
        params: Vec<FrontEndParams>,
    ) -> Self {
        let rigid = configs.iter().map(WhiskerConfig::rigid).collect();
        Self {
            environment,
            model,
            log: None,
            configs,
            rigid,
            params,
        }
    }

    /// The same sensing detecting at each whisker's `levels` (a dataset's, as written).
    pub fn with_levels(mut self, levels: Vec<FrontEndParams>) -> Self {
        self.params = levels;
        self
    }

    /// Each whisker's detection levels.
    pub fn levels(&self) -> &[FrontEndParams] {
        &self.params
    }

    /// Whisker `i`'s whisking pattern.
    pub fn pattern(&self, i: usize) -> whisker_sim::whisker::control::WhiskingPattern {
        self.configs[i].pattern
    }

    /// The same sensing with the straight shafts of `rigid` (a log's array: contact points
    /// from its base offsets).
    pub fn with_rigid(mut self, rigid: Vec<RigidWhisker>) -> Self {
        self.rigid = rigid;
        self
    }

    /// One whisk at each of `poses` (whisk k starts at time k s): the contact cycles.
    pub fn sense(
        &self,
        target: &SweepTarget,
        poses: &[Isometry3<f64>],
        seed: u64,
        stream: &str,
        reporter: &dyn Reporter,
    ) -> Vec<ContactCycle> {
        let done = AtomicUsize::new(0);
        poses
            .par_iter()
            .enumerate()
            .map(|(k, pose)| {
                let cycle = self.whisk(target, k, pose, seed, &format!("{stream}/physics/{k}"));
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if n.is_multiple_of(10) || n == poses.len() {
                    reporter.note(&format!("  {stream}: {n}/{} whisks simulated", poses.len()));
                }
                cycle
            })
            .collect()
    }

    /// One whisk (number `k`, starting at k s) at `pose`, with noise from sub-stream
    /// `stream` of `seed`.
    pub fn whisk(
        &self,
        target: &SweepTarget,
        k: usize,
        pose: &Isometry3<f64>,
        seed: u64,
        stream: &str,
    ) -> ContactCycle {
        self.whisk_streams(target, k, pose, seed, stream).0
    }

    /// [`Self::whisk`], and the whisk's samples of every whisker.
    pub fn whisk_streams(
        &self,
        target: &SweepTarget,
        k: usize,
        pose: &Isometry3<f64>,
        seed: u64,
        stream: &str,
    ) -> (ContactCycle, Vec<Vec<Reading>>) {
        let streams = self.streams(target, pose, seed, stream);
        if let Some(log) = &self.log {
            log(stream, k, &streams);
        }
        let mut cycle = self.contacts(k, &streams, seed, stream);
        cycle.array_pose = *pose;
        (cycle, streams)
    }

    /// The straight (rigid) whiskers, for the anticipated intersect.
    pub fn rigid(&self) -> &[RigidWhisker] {
        &self.rigid
    }

    /// One whisk's 2 kHz samples of every whisker at `pose` (noise from sub-stream
    /// `stream` of `seed`). Only the whiskers whose rigid sweep meets the object are
    /// simulated; the others whisk freely and read their commanded angle (quantised as
    /// the sensor does) and no deflection.
    pub fn streams(
        &self,
        target: &SweepTarget,
        pose: &Isometry3<f64>,
        seed: u64,
        stream: &str,
    ) -> Vec<Vec<Reading>> {
        let touching: Vec<usize> = self
            .rigid
            .iter()
            .enumerate()
            .filter(|(_, w)| target.sweep(w, pose).is_some())
            .map(|(i, _)| i)
            .collect();
        let configs = touching.iter().map(|&i| self.configs[i].clone()).collect();
        let mut array = PhysicsArray::new(
            configs,
            &self.environment,
            pose,
            substream_key(seed, stream),
            DT,
        );
        let mut simulated = array.whisk(0, |_| *pose).samples.into_iter();
        let samples = (1.0 / (self.configs[0].pattern.frequency * DT)).round() as usize;
        self.configs
            .iter()
            .enumerate()
            .map(|(i, c)| match touching.contains(&i) {
                true => simulated.next().expect("one stream per simulated whisker"),
                false => {
                    let q = c.sensor.angle_resolution_rad;
                    (0..samples)
                        .map(|n| Reading {
                            angle_rad: (c.pattern.angle((n + 1) as f64 * DT) / q).round() * q,
                            x: 0.0,
                            y: 0.0,
                        })
                        .collect()
                }
            })
            .collect()
    }

    /// The contacts of whisk `k` from every whisker's samples: the front end, the
    /// radial-distance model (draws from sub-stream `<stream>/radial` of `seed`), the
    /// slope; contact points in the array frame. The same from the simulator and a log.
    pub fn contacts(
        &self,
        k: usize,
        streams: &[Vec<Reading>],
        seed: u64,
        stream: &str,
    ) -> ContactCycle {
        let mut rng = substream(seed, &format!("{stream}/radial"));
        let rate = 1.0 / DT;
        let mut contacts = Vec::new();
        for (i, samples) in streams.iter().enumerate() {
            let whisker = &self.rigid[i];
            let held = [Isometry3::identity()];
            let Some(e) = estimate(
                whisker,
                samples,
                rate,
                &self.params[i],
                &self.model,
                &mut rng,
                &held,
            ) else {
                continue;
            };
            contacts.push(Contact {
                whisker: i,
                time_s: k as f64 + e.event.onset as f64 / rate,
                angle_rad: e.event.onset_angle,
                radial_distance: e.radial_distance,
                point: e.point,
                slope: if e.event.slope.is_nan() {
                    0.0
                } else {
                    e.event.slope
                },
            });
        }
        ContactCycle {
            index: k as u64,
            start_s: k as f64,
            array_pose: Isometry3::identity(),
            contacts,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Translation3;
    use whisker_sim::environment::assets::{CATALOGUE, placed};
    use whisker_sim::sensing::viewpoints;

    /// Far from the object nothing is simulated and nothing is sensed; at the pose near the
    /// Box where the most whiskers touch (as in `crates/sim/tests/front_end.rs`), the front
    /// end detects the whiskers the rigid sweep says touch and no others, at onset angles
    /// within a few degrees of the anticipated ones, and svr10 places the contacts within
    /// half a whisker length of the anticipated points.
    #[test]
    fn physics_contacts_follow_the_anticipated_ones() {
        let asset = CATALOGUE.iter().find(|a| a.name == "box").unwrap();
        let (environment, shape) = placed(asset).unwrap();
        let (near, _) = viewpoints::busiest(&environment, &shape, asset.size).unwrap();
        let far = Isometry3::from_parts(Translation3::new(2.0, 0.0, 0.2), near.rotation);
        let target = SweepTarget::of(&environment);
        let model = whisker_scenario::radial_model::load_or_default(None).unwrap();
        let sensing = PhysicsSensing::new(
            vec![(shape, Isometry3::identity())],
            model,
            &Detection::default_at(0),
        );
        let cycles = sensing.sense(&target, &[far, near], 0, "test", &crate::record::Silent);
        assert!(cycles[0].contacts.is_empty());
        let contacts = &cycles[1].contacts;
        let touching: Vec<usize> = (0..sensing.rigid.len())
            .filter(|&i| target.sweep(&sensing.rigid[i], &near).is_some())
            .collect();
        assert!(touching.len() >= 4, "{touching:?}");
        let detected: Vec<usize> = contacts.iter().map(|c| c.whisker).collect();
        assert!(detected.iter().all(|w| touching.contains(w)));
        assert!(
            10 * detected.len() >= 9 * touching.len(),
            "{detected:?} of {touching:?}"
        );
        for c in contacts {
            let w = &sensing.rigid[c.whisker];
            let hit = target.sweep(w, &near).unwrap();
            assert!((c.angle_rad - hit.angle).to_degrees().abs() < 3.0);
            let d = (near * c.point - hit.point).norm();
            assert!(d < 0.5 * w.module.beam.length, "{}: {d}", w.module.pixel());
        }
    }

    /// A whisk's samples written as a whisk file (docs/dataset.md) and read back are the
    /// same numbers and give the very same contacts as the live whisk; the whiskers not
    /// simulated read no deflection and give no contact.
    #[test]
    fn contacts_from_a_whisk_file_equal_the_live_ones() {
        use crate::dataset_format::records;
        let asset = CATALOGUE.iter().find(|a| a.name == "box").unwrap();
        let (environment, shape) = placed(asset).unwrap();
        let (near, _) = viewpoints::busiest(&environment, &shape, asset.size).unwrap();
        let target = SweepTarget::of(&environment);
        let model = whisker_scenario::radial_model::load_or_default(None).unwrap();
        let sensing = PhysicsSensing::new(
            vec![(shape, Isometry3::identity())],
            model,
            &Detection::default_at(0),
        );
        let live = sensing.whisk(&target, 3, &near, 7, "t/physics/3");
        let streams = sensing.streams(&target, &near, 7, "t/physics/3");
        let labels: Vec<String> = sensing.rigid.iter().map(|w| w.module.pixel()).collect();
        let q = sensing.configs[0].sensor.angle_resolution_rad;
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("whisk_000003.csv");
        std::fs::write(&path, records::whisk_csv(&labels, &streams, q).unwrap()).unwrap();
        let back = records::read_whisk(&path, &labels, streams[0].len(), q).unwrap();
        assert_eq!(back, streams);
        let replay = sensing.contacts(3, &back, 7, "t/physics/3");
        assert!(live.contacts.len() >= 4, "{:?}", live.contacts);
        assert_eq!(replay.contacts, live.contacts);
        for (i, w) in sensing.rigid.iter().enumerate() {
            if target.sweep(w, &near).is_none() {
                assert!(streams[i].iter().all(|r| r.x == 0.0 && r.y == 0.0));
                assert!(live.contacts.iter().all(|c| c.whisker != i));
            }
        }
    }
}
