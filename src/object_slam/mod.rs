//! `whisker object-slam`: the WhiskerRatSLAM experiments of thesis §5.2 with kinematic
//! sensing (or, `--sensing physics`, physics whiskers through the signal front end:
//! [`physics`]) — localisation on each catalogue object (Table 5.1's twelve parameter sets,
//! Fig 5.15) and object identification by appended object maps (Figs 5.16–5.17).
//!
//! For each object, the array whisks once per pose along trajectory A (two laps: the
//! first builds the object map, the second re-localises in it) and along the novel
//! trajectory B (one lap, the map of A as prior knowledge); `--placement` puts the object
//! where the thesis did relative to the trajectories (the Kettle on their centre, the
//! others off it: [`Placement`]) or centres every object. Contacts come from the
//! kinematic sweep with the noise of §6.1.3.1.2 (sub-streams `object-slam/<object>/<A|B>`
//! of the seed); odometry is the true motion between poses with Gaussian errors —
//! 5 % of the step per translation axis, 0.5° per rotation axis
//! (`object-slam/<object>/<A|B>/odometry`). Features: the PFH of the contact points in
//! the array frame, and the SDA of the slopes (clipped to ±10: Eq 6.14 is unbounded when
//! the contacted normal lies in the sweep plane). Contact points by the tip assumption
//! (each whisker's tip at its contact angle) or "svr": kinematically, the noisy anticipated
//! point, whose 25 %-of-length noise is §6.1.3.1.2's model of the SVR estimate; in physics,
//! the radial-distance model's estimate (default svr10) at the detected onset angle.
//!
//! A localisation estimate is the map pose of the experience a whisk re-localises onto;
//! its error is the distance (m) and the minimum rotation angle to the true pose, both
//! relative to the first experience (A's first pose). Beside it, Ch 3's way of scoring a
//! re-localisation: the *perceived-pose error*, between the true pose where the
//! experience was made and the current true pose, which does not depend on the map's
//! relaxation; a re-localisation is a *true revisit* when that error is within the
//! thesis' step (11 cm and 12°; the Box 3 cm and 3°, §5.2.2.1), and *aliasing* otherwise.
//! `--slam` picks the WhiskerRatSLAM (`Params::corrected` by default, or Alg 2 as
//! printed). Identification uses the maps of the best set (both features, no merging,
//! svr) of every object but the Skull, appended; each object, Skull included, is explored
//! for one lap of A and of B while a leaky integrator per mapped object (decay 0.9 per
//! whisk) is fed by re-localisations.

pub mod dataset;
mod trajectory;
mod walk_recording;
pub use trajectory::{Placement, Trajectory, mean_step};

use crate::choice::Choice;
use crate::error::{Error, Result};
use crate::record::{Context, Reporter, Target};
use crate::scenario::SensingMode;
use crate::sensing::held::{self as physics, PhysicsSensing};
use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use whisker_sim::environment::assets::{Asset, CATALOGUE, generate};
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::whisker::array::{self, Module};
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::contact::ContactCycle;
use whisker_slam::features::similarity::{FeatureSet, Features};
use whisker_slam::features::whisk::whisk_features;
use whisker_slam::radial::RadialEstimator;
use whisker_slam::recognition::Identification;
use whisker_slam::sensor::Odometry;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;
use whisker_slam::whisker_ratslam::slam::{Params, WhiskerRatSlam};
use whisker_slam::whisker_ratslam::walk_odometry::{clean_odometry, noisy_odometry};

/// The object left out of the appended maps (§5.2.2.2).
const UNMAPPED: &str = "skull";
/// Identification decay per whisk.
const DECAY: f64 = 0.9;

/// What `whisker object-slam` runs.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Catalogue objects [default: all eight].
    pub objects: Vec<String>,
    /// Seed of every random draw.
    pub seed: u64,
    /// Directory for object maps and CSV results (created; files written atomically).
    pub out: Option<PathBuf>,
    /// How contacts are sensed: the kinematic sweep with the noise of §6.1.3.1.2, or
    /// physics whiskers through the signal front end and a radial-distance model.
    pub sensing: SensingMode,
    /// With physics sensing: the radial-distance model file [default: the built-in svr10].
    pub radial_model: Option<PathBuf>,
    /// Which WhiskerRatSLAM.
    pub slam: SlamVersion,
    /// Where each object sits relative to its trajectories (§5.2.2.1).
    pub placement: Placement,
    /// Where the recording goes.
    pub rrd: Target,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            objects: Vec::new(),
            seed: 0,
            out: None,
            sensing: SensingMode::Kinematic,
            radial_model: None,
            slam: SlamVersion::Corrected,
            placement: Placement::Thesis,
            rrd: Target::default(),
        }
    }
}

/// Which WhiskerRatSLAM: with the corrections of issue #19, or Alg 2 as printed (the
/// closed loop's default; robust relaxation on in both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlamVersion {
    /// Ω relative to the packet's peak, the test before the injection, phase-exact path
    /// integration, the odometry anchor (`Params::corrected`).
    Corrected,
    /// Alg 2 as printed (`Params::default`).
    Printed,
}

impl Choice for SlamVersion {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            SlamVersion::Corrected,
            "corrected",
            "Ω relative to the packet's peak, the test before the injection, phase-exact path integration, the odometry anchor",
        ),
        (SlamVersion::Printed, "printed", "Alg 2 as printed"),
    ];
}

/// How contact points are placed (Table 5.1 "contact algorithm").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ContactEstimate {
    Tip,
    Svr,
}

/// One of Table 5.1's parameter sets.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Combo {
    features: FeatureSet,
    merge: bool,
    contact: ContactEstimate,
}

impl Combo {
    fn name(&self) -> String {
        let f = match self.features {
            FeatureSet::Pfh => "pfh",
            FeatureSet::Sda => "sda",
            FeatureSet::Both => "both",
        };
        let c = match self.contact {
            ContactEstimate::Tip => "tip",
            ContactEstimate::Svr => "svr",
        };
        format!("{f}/{}/{c}", if self.merge { "merged" } else { "unmerged" })
    }

    fn all() -> Vec<Combo> {
        let mut out = Vec::new();
        for features in [FeatureSet::Pfh, FeatureSet::Sda, FeatureSet::Both] {
            for merge in [true, false] {
                for contact in [ContactEstimate::Tip, ContactEstimate::Svr] {
                    out.push(Combo {
                        features,
                        merge,
                        contact,
                    });
                }
            }
        }
        out
    }

    const BEST: Combo = Combo {
        features: FeatureSet::Both,
        merge: false,
        contact: ContactEstimate::Svr,
    };
}

/// A re-localisation.
#[derive(Debug, Clone)]
struct Event {
    /// The whisk.
    sample: usize,
    /// Map-pose error (m, degrees), when the true pose is known.
    error: Option<(f64, f64)>,
    /// Perceived-pose error (m, degrees), when the experience's true pose is known.
    perceived: Option<(f64, f64)>,
    /// The object the experience belongs to (appended maps).
    object: Option<String>,
}

/// The thesis' step for an object (m, degrees): the pass mark of §5.2.2.1.
fn thesis_step(object: &str) -> (f64, f64) {
    if object == "box" {
        (0.03, 3.0)
    } else {
        (0.11, 12.0)
    }
}
/// One localisation run: (object index, parameter set, events on A's second lap,
/// events on B, the object map A built).
type LocalisationRun = (usize, Combo, Vec<Event>, Vec<Event>, ObjectMap);
/// One identification run: (object index, trajectory, events, confidences per whisk).
type IdentificationRun = (
    usize,
    Trajectory,
    Vec<Event>,
    Vec<std::collections::BTreeMap<String, f64>>,
);
/// One object's walks: (asset, A (two laps), B, mean step of A (m, rad) when the true
/// poses are known).
pub type Sensed<'a> = (&'a Asset, Walk, Walk, Option<(f64, f64)>);

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
    fn part(&self, range: std::ops::Range<usize>) -> Walk {
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
/// draws from `seed`; `noise` false leaves out the contact noise and the odometry error (a
/// clean dataset).
pub struct WalkSensing<'a> {
    pub placement: Placement,
    pub seed: u64,
    pub physics: Option<&'a PhysicsSensing>,
    pub noise: bool,
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
                if noise {
                    ContactNoise::default()
                } else {
                    ContactNoise::NONE
                },
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
    let odometry = if noise {
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
fn features(cycle: &ContactCycle, contact: ContactEstimate, modules: &[Module]) -> Features {
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
fn explore(
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

fn params(combo: Combo, slam: SlamVersion) -> Params {
    let mut p = match slam {
        SlamVersion::Corrected => Params::corrected(),
        SlamVersion::Printed => Params::default(),
    };
    p.matching.features = combo.features;
    p.merge_features = combo.merge;
    p
}

/// `whisker object-slam`: senses the walks of `o`, then [`analyse`].
pub fn run(o: &Settings, ctx: Context) -> Result<Report> {
    let data = sense(o, true, None, ctx)?;
    analyse(o, &data, ctx)
}

/// `whisker object-slam --dataset DIR`: the walks of the dataset in `dir` (its objects and
/// seed), then [`analyse`] with the settings of `o` that do not sense.
pub fn replay(o: &Settings, dir: &Path, ctx: Context) -> Result<Report> {
    let manifest = crate::dataset::manifest::Manifest::read(dir)?;
    let data = crate::object_slam::dataset::read(dir, &manifest)?;
    let o = Settings {
        seed: manifest.seed,
        ..o.clone()
    };
    analyse(&o, &data, ctx)
}

/// The catalogue objects named by `--objects` (all eight when none).
pub fn objects(names: &[String]) -> Result<Vec<&'static Asset>> {
    if names.is_empty() {
        return Ok(CATALOGUE.iter().collect());
    }
    names
        .iter()
        .map(|n| {
            CATALOGUE.iter().find(|a| a.name == n).ok_or_else(|| {
                let names: Vec<&str> = CATALOGUE.iter().map(|a| a.name).collect();
                Error::Input(format!(
                    "--objects: unknown object {n:?}; expected some of {}",
                    names.join(", ")
                ))
            })
        })
        .collect()
}

/// Senses every object of `o` (walks A and B); `noise` false: a clean dataset's walks;
/// physics sensing hands every whisk's samples to `log` (a dataset writer).
pub fn sense(
    o: &Settings,
    noise: bool,
    log: Option<physics::WhiskLog>,
    ctx: Context,
) -> Result<Vec<Sensed<'static>>> {
    let assets = objects(&o.objects)?;
    let model: Option<RadialEstimator> = match (o.sensing, &o.radial_model) {
        (SensingMode::Kinematic, None) => None,
        (SensingMode::Kinematic, Some(_)) => {
            return Err(Error::Input(
                "--radial-model: only used with --sensing physics".into(),
            ));
        }
        (SensingMode::Physics, path) => {
            Some(crate::radial_model::load_or_default(path.as_deref())?)
        }
    };
    assets
        .par_iter()
        .map(|asset| {
            let mesh = generate(asset);
            let shape = mesh
                .shape()
                .map_err(|e| Error::Failure(format!("{}: {e}", asset.name)))?;
            let target = SweepTarget::new(mesh);
            let physics = model.clone().map(|m| {
                let mut p = PhysicsSensing::new(vec![(shape.clone(), Isometry3::identity())], m);
                p.log = log.clone();
                p
            });
            let object = Object {
                asset,
                target: &target,
                shape: &shape,
            };
            let how = WalkSensing {
                placement: o.placement,
                seed: o.seed,
                physics: physics.as_ref(),
                noise,
                reporter: ctx.reporter,
            };
            let laps = |which, n| walk(&object, which, n, &how);
            let (a, b) = (laps(Trajectory::A, 2), laps(Trajectory::B, 1));
            let truth = a.truth.as_deref().unwrap_or_default();
            let step = trajectory::mean_step(&truth[..truth.len() / 2]);
            ctx.note(&format!(
                "{}: {} poses per lap sensed",
                asset.name,
                a.cycles.len() / 2
            ));
            Ok((*asset, a, b, Some(step)))
        })
        .collect()
}

/// Localisation and identification on sensed walks (§5.2.2): reports and `--out` files.
pub fn analyse(o: &Settings, data: &[Sensed], ctx: Context) -> Result<Report> {
    if let Some(dir) = &o.out {
        crate::output::create_dir(dir)?;
    }
    let modules = array::modules();
    // Localisation: every object × every parameter set.
    let jobs: Vec<(usize, Combo)> = (0..data.len())
        .flat_map(|i| Combo::all().into_iter().map(move |c| (i, c)))
        .collect();
    let results: Vec<LocalisationRun> = jobs
        .par_iter()
        .map(|&(i, combo)| {
            let (_, a, b, _) = &data[i];
            let lap = a.cycles.len() / 2;
            let origin = a.truth.as_ref().map(|t| t[0]);
            let origin = origin.as_ref();
            let mut slam = WhiskerRatSlam::new(params(combo, o.slam), ObjectMap::default());
            let mut made = Vec::new();
            let on_a = explore(&mut slam, a, combo, &modules, origin, lap, &mut made);
            let map = slam.map.clone();
            let mut slam_b = WhiskerRatSlam::new(params(combo, o.slam), map.clone());
            let on_b = explore(&mut slam_b, b, combo, &modules, origin, 0, &mut made);
            (i, combo, on_a, on_b, map)
        })
        .collect();
    ctx.note(&format!("localisation: {} runs done", results.len()));
    let localisation = results::localisation(o, data, &results)?;
    // Identification with the best set's maps, the unmapped object left out.
    let mut appended = ObjectMap::default();
    let mut mapped = Vec::new();
    for (i, combo, _, _, map) in &results {
        let name = data[*i].0.name;
        if *combo == Combo::BEST && name != UNMAPPED {
            appended.append(map, name);
            mapped.push(name.to_string());
        }
    }
    let id_runs: Vec<_> = (0..data.len())
        .flat_map(|i| [(i, Trajectory::A), (i, Trajectory::B)])
        .collect();
    let id_results: Vec<IdentificationRun> = id_runs
        .par_iter()
        .map(|&(i, which)| {
            let (_, a, b, _) = &data[i];
            let walk = match which {
                Trajectory::A => a.part(0..a.cycles.len() / 2),
                Trajectory::B => b.clone(),
            };
            let mut slam = WhiskerRatSlam::new(params(Combo::BEST, o.slam), appended.clone());
            let mut id = Identification::new(mapped.clone(), DECAY);
            let mut series = Vec::new();
            let mut made = Vec::new();
            let origin = a.truth.as_ref().map(|t| t[0]);
            let events = explore(
                &mut slam,
                &walk,
                Combo::BEST,
                &modules,
                origin.as_ref(),
                0,
                &mut made,
            );
            let mut e = events.iter().peekable();
            for k in 0..walk.cycles.len() {
                let onto = e.next_if(|x| x.sample == k).and_then(|x| x.object.clone());
                id.update(onto.as_deref());
                series.push(id.confidence.clone());
            }
            (i, which, events, series)
        })
        .collect();
    let identification = results::identification(o, data, &mapped, &id_results)?;
    walk_recording::write(o, data, &id_results, ctx)?;
    Ok(Report {
        seed: o.seed,
        localisation,
        identification,
        mapped,
    })
}

mod results;
pub use results::{IdentificationRow, LocalisationRow, Report, Summary, WalkStats};
