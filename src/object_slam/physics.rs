//! Physics sensing for `whisker object-slam --sensing physics`: at each pose of a walk
//! the array is held still and whisks once (1 Hz, RCP at saturation — the conditions the
//! radial-distance models are trained under, §4.1.1) in Rapier; the signal front end
//! detects each whisker's contact, the radial-distance model (default svr10) places it
//! along the shaft at the onset's whisk angle (Eq 5.1–5.2), and the slope is the
//! gradient of y against x deflection (§5.1.1.1.3).
//!
//! Only the whiskers whose rigid sweep meets the object are simulated (a bending shaft
//! reaches no further than the straight one; the others would whisk freely and, with the
//! front end's confirmation, register nothing). Each pose is a simulation of its own with
//! sensor noise from the sub-stream `<stream>/physics/<k>` of the seed, so results do not
//! depend on the number of threads. An undefined slope (no x or y variation) reads as
//! flat (0), as a missing SDA entry does.

use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use whisker_sim::sensing::kinematic::{RigidWhisker, SweepTarget};
use whisker_sim::sensing::physics::{DT, EnvironmentPiece, PhysicsArray, WhiskerConfig};
use whisker_sim::whisker::array;
use whisker_slam::contact::{Contact, ContactCycle};
use whisker_slam::frontend::contact::{FrontEndParams, detect};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::rng::{substream, substream_key};

/// The array's whiskers in physics, and how their contacts are estimated.
pub struct PhysicsSensing {
    /// The object in the physics worlds.
    pub environment: Vec<EnvironmentPiece>,
    /// Radial-distance model.
    pub model: RadialEstimator,
    configs: Vec<WhiskerConfig>,
    rigid: Vec<RigidWhisker>,
    params: FrontEndParams,
}

impl PhysicsSensing {
    /// The default array (1 Hz, RCP at the sensor's saturation) against `environment`.
    pub fn new(environment: Vec<EnvironmentPiece>, model: RadialEstimator) -> Self {
        let configs = array::modules()
            .into_iter()
            .map(WhiskerConfig::with_defaults)
            .collect();
        Self::with_configs(environment, model, configs)
    }

    /// The array of `configs` against `environment`; a whisker without RCP gets RCP at
    /// its sensor's saturation (the radial-distance models' training condition, §4.1.1).
    pub fn with_configs(
        environment: Vec<EnvironmentPiece>,
        model: RadialEstimator,
        mut configs: Vec<WhiskerConfig>,
    ) -> Self {
        for c in &mut configs {
            c.rcp_threshold.get_or_insert(c.sensor.saturation_counts);
        }
        let rigid = configs.iter().map(WhiskerConfig::rigid).collect();
        Self {
            environment,
            model,
            configs,
            rigid,
            params: FrontEndParams::default(),
        }
    }

    /// One whisk at each of `poses` (whisk k starts at time k s): the contact cycles.
    pub fn sense(
        &self,
        target: &SweepTarget,
        poses: &[Isometry3<f64>],
        seed: u64,
        stream: &str,
    ) -> Vec<ContactCycle> {
        let done = AtomicUsize::new(0);
        poses
            .par_iter()
            .enumerate()
            .map(|(k, pose)| {
                let cycle = self.whisk(target, k, pose, seed, &format!("{stream}/physics/{k}"));
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if n.is_multiple_of(10) || n == poses.len() {
                    eprintln!("  {stream}: {n}/{} whisks simulated", poses.len());
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
        let mut rng = substream(seed, &format!("{stream}/radial"));
        let cycle = array.whisk(k as u64, |_| *pose);
        let mut contacts = Vec::new();
        for (j, &i) in touching.iter().enumerate() {
            let whisker = &self.rigid[i];
            let length = whisker.module.beam.length;
            let Some(event) = detect(&cycle.samples[j], cycle.rate_hz, length, &self.params) else {
                continue;
            };
            let r = self.model.estimate(&event.features, &mut rng);
            let point: Point3<f64> =
                whisker.shaft_point(&Isometry3::identity(), event.onset_angle, r);
            contacts.push(Contact {
                whisker: i,
                time_s: k as f64 + event.onset as f64 / cycle.rate_hz,
                angle_rad: event.onset_angle,
                radial_distance: r,
                point,
                slope: if event.slope.is_nan() {
                    0.0
                } else {
                    event.slope
                },
            });
        }
        ContactCycle {
            index: k as u64,
            start_s: k as f64,
            array_pose: *pose,
            contacts,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Translation3;
    use whisker_sim::environment::assets::{CATALOGUE, placed};
    use whisker_sim::environment::viewpoints;

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
        let target = environment.sweep_target();
        let model = crate::frontend::radial_model(None).unwrap();
        let sensing = PhysicsSensing::new(vec![(shape, Isometry3::identity())], model);
        let cycles = sensing.sense(&target, &[far, near], 0, "test");
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
}
