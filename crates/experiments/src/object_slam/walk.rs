//! The §5.2 walks: a whisk at each pose of a trajectory around a catalogue object, the
//! features of each whisk, and WhiskerRatSLAM run along a walk.

use super::settings::{Combo, ContactEstimate};
use super::trajectory::{self, Placement, Trajectory};
use crate::record::Reporter;
use crate::sensing::held::PhysicsSensing;
use nalgebra::{Isometry3, Point3};
use whisker_sim::environment::assets::Asset;
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::noise::{ContactNoise, PointNoise};
use whisker_sim::whisker::array::{self, Module};
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::contact::ContactCycle;
use whisker_slam::features::similarity::Features;
use whisker_slam::features::whisk::whisk_features;
use whisker_slam::sensor::Odometry;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;
use whisker_slam::whisker_ratslam::walk_odometry::{clean_odometry, noisy_odometry};

/// A re-localisation.
#[derive(Debug, Clone)]
pub struct Event {
    /// The whisk.
    pub sample: usize,
    /// Map-pose error (m, degrees), when the true pose is known.
    pub error: Option<(f64, f64)>,
    /// Perceived-pose error (m, degrees), when the experience's true pose is known.
    pub perceived: Option<(f64, f64)>,
    /// The object the experience belongs to (appended maps).
    pub object: Option<String>,
}

/// One sensed walk: a whisk at each pose.
#[derive(Debug, Clone)]
pub struct Walk {
    /// The true pose of each whisk (None: a log without ground truth).
    pub truth: Option<Vec<Isometry3<f64>>>,
    /// The contacts of each whisk.
    pub cycles: Vec<ContactCycle>,
    /// The odometry from the previous whisk (the first: none).
    pub odometry: Vec<Odometry>,
}

impl Walk {
    /// Whisks `range` of the walk.
    pub fn part(&self, range: std::ops::Range<usize>) -> Walk {
        Walk {
            truth: self.truth.as_ref().map(|t| t[range.clone()].to_vec()),
            cycles: self.cycles[range.clone()].to_vec(),
            odometry: self.odometry[range].to_vec(),
        }
    }
}

/// The stream names of an object's walk: contacts `object-slam/<object>/<A|B>`, odometry
/// the same + `/odometry`.
pub fn stream(object: &str, which: Trajectory) -> String {
    format!("object-slam/{object}/{}", which.name())
}

/// A catalogue object to walk around: the sweep's target and the solid's shape.
pub struct Object<'a> {
    pub asset: &'a Asset,
    pub target: &'a SweepTarget,
    pub shape: &'a parry3d_f64::shape::SharedShape,
}

/// How a walk is sensed: kinematically or (given `physics`) by physics whiskers, with
/// draws from `seed`; `noise` None leaves out the contact noise and the odometry error (a
/// clean dataset), otherwise it says which way the contact noise displaces a point.
pub struct WalkSensing<'a> {
    pub placement: Placement,
    pub seed: u64,
    pub physics: Option<&'a PhysicsSensing>,
    pub noise: Option<PointNoise>,
    pub reporter: &'a dyn Reporter,
}

/// Senses `laps` laps of trajectory `which` around `object`.
pub fn walk(object: &Object, which: Trajectory, laps: usize, how: &WalkSensing) -> Walk {
    let (asset, target, seed, noise) = (object.asset, object.target, how.seed, how.noise);
    let (placement, shape) = (how.placement, object.shape);
    let lap = trajectory::lap(which, placement, asset.name, shape, asset.size);
    let truth: Vec<Isometry3<f64>> = (0..laps).flat_map(|_| lap.iter().copied()).collect();
    let stream = stream(asset.name, which);
    let cycles = match how.physics {
        Some(p) => p.sense(target, &truth, seed, &stream, how.reporter),
        None => {
            let whiskers: Vec<RigidWhisker> = array::modules()
                .into_iter()
                .map(|m| RigidWhisker::new(m, 3.0e-3))
                .collect();
            let patterns = vec![WhiskingPattern::default(); whiskers.len()];
            let mut sensing = KinematicArray::new(
                whiskers,
                patterns,
                noise.map_or(ContactNoise::NONE, |point_model| ContactNoise {
                    point_model,
                    ..ContactNoise::default()
                }),
                whisker_slam::rng::substream_key(seed, &stream),
            );
            truth
                .iter()
                .enumerate()
                .map(|(k, p)| sensing.sense(target, k as u64, k as f64, p))
                .collect()
        }
    };
    let clean = clean_odometry(&truth);
    let odometry = if noise.is_some() {
        noisy_odometry(&clean, seed, &stream)
    } else {
        clean
    };
    Walk {
        truth: Some(truth),
        cycles,
        odometry,
    }
}

/// The noise-free anticipated contacts (the rigid sweep) of the kinematic array at each
/// of `poses`.
pub fn anticipated(target: &SweepTarget, poses: &[Isometry3<f64>]) -> Vec<ContactCycle> {
    let whiskers: Vec<RigidWhisker> = array::modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, 3.0e-3))
        .collect();
    let patterns = vec![WhiskingPattern::default(); whiskers.len()];
    let mut sweep = KinematicArray::new(whiskers, patterns, ContactNoise::NONE, 0);
    poses
        .iter()
        .enumerate()
        .map(|(k, p)| sweep.sense(target, k as u64, k as f64, p))
        .collect()
}

/// The features of one whisk for a contact estimate.
pub fn features(cycle: &ContactCycle, contact: ContactEstimate, modules: &[Module]) -> Features {
    let points: Vec<Point3<f64>> = cycle
        .contacts
        .iter()
        .map(|c| match contact {
            ContactEstimate::Svr => c.point,
            ContactEstimate::Tip => {
                let m = &modules[c.whisker];
                m.whisker_pose(c.angle_rad) * Point3::new(0.0, 0.0, m.beam.length)
            }
        })
        .collect();
    whisk_features(cycle, &points)
}

/// Runs `walk` through `slam`; returns its re-localisations from sample `from` on, with
/// their errors relative to `origin` (A's first true pose; None without ground truth).
/// `made` holds, per experience, the true pose where it was made (relative to `origin`);
/// new experiences are added.
pub fn explore(
    slam: &mut WhiskerRatSlam,
    walk: &Walk,
    combo: Combo,
    modules: &[Module],
    origin: Option<&Isometry3<f64>>,
    from: usize,
    made: &mut Vec<Option<Isometry3<f64>>>,
) -> Vec<Event> {
    let mut out = Vec::new();
    let degrees = |(t, r): (f64, f64)| (t, r.to_degrees());
    for (k, (cycle, odo)) in walk.cycles.iter().zip(&walk.odometry).enumerate() {
        let step = slam.step(&features(cycle, combo.contact, modules), odo);
        let truth = origin
            .zip(walk.truth.as_ref())
            .map(|(o, t)| o.inverse() * t[k]);
        made.resize(slam.map.experiences.len(), None);
        if step.created {
            made[step.experience] = truth;
        }
        if step.relocalised && k >= from {
            let map_origin = slam.map.pose(0).inverse();
            let estimate = map_origin * slam.map.pose(step.experience);
            out.push(Event {
                sample: k,
                error: truth.map(|t| degrees(whisker_slam::pose::distance(&estimate, &t))),
                perceived: made[step.experience]
                    .zip(truth)
                    .map(|(at, t)| degrees(whisker_slam::pose::distance(&at, &t))),
                object: slam.map.experiences[step.experience].object.clone(),
            });
        }
    }
    out
}

/// One object's walks: A (two laps) and B, and A's mean step (m, rad) when the true poses
/// are known.
pub struct Sensed<'a> {
    pub asset: &'a Asset,
    pub a: Walk,
    pub b: Walk,
    pub step: Option<(f64, f64)>,
}
