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
mod results;
mod settings;
mod trajectory;
mod walk;
mod walk_recording;
pub use results::{
    IdentificationRow, IdentificationRun, LocalisationRow, LocalisationRun, Report, Summary,
    WalkStats,
};
pub use settings::{Settings, SlamVersion};
pub use trajectory::{Placement, Trajectory, mean_step};
pub use walk::{Object, Sensed, Walk, WalkSensing, anticipated, stream, walk};

use crate::record::Context;
use crate::sensing::detection::Detection;
use crate::sensing::held::{self as physics, PhysicsSensing};
use nalgebra::Isometry3;
use rayon::prelude::*;
use settings::{Combo, DECAY, UNMAPPED, params};
use std::path::Path;
use walk::explore;
use whisker_scenario::SensingMode;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::assets::{Asset, CATALOGUE, generate};
use whisker_sim::sensing::kinematic::SweepTarget;
use whisker_sim::whisker::array::{self};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::recognition::Identification;
use whisker_slam::whisker_ratslam::object_map::ObjectMap;
use whisker_slam::whisker_ratslam::slam::WhiskerRatSlam;

/// `whisker object-slam`: senses the walks of `o`, then [`analyse`].
pub fn run(o: &Settings, ctx: Context) -> Result<Report> {
    let data = sense(o, true, None, ctx)?;
    analyse(o, &data, ctx)
}

/// `whisker object-slam --dataset DIR`: the walks of the dataset in `dir` (its objects and
/// seed), then [`analyse`] with the settings of `o` that do not sense.
pub fn replay(o: &Settings, dir: &Path, ctx: Context) -> Result<Report> {
    let manifest = crate::dataset_format::manifest::Manifest::read(dir)?;
    let data = dataset::read(dir, &manifest)?;
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

/// The detection levels of `--sensing physics`: the defaults ([`Detection::default_at`])
/// on the training condition's array ([`physics::training_configs`]), σ on `seed`.
pub fn physics_levels(seed: u64) -> Vec<whisker_slam::frontend::contact::FrontEndParams> {
    Detection::default_at(seed).levels(&physics::training_configs())
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
        (SensingMode::Physics, path) => Some(whisker_scenario::radial_model::load_or_default(
            path.as_deref(),
        )?),
    };
    // The levels once for every object (a free-whisking calibration of each whisker).
    let levels = model.as_ref().map(|_| physics_levels(o.seed));
    assets
        .par_iter()
        .map(|asset| {
            let mesh = generate(asset);
            let shape = whisker_sim::environment::solids::shape(&mesh)
                .map_err(|e| Error::Failure(format!("{}: {e}", asset.name)))?;
            let target = SweepTarget::new(mesh);
            let physics = model.clone().zip(levels.clone()).map(|(m, levels)| {
                let mut p = PhysicsSensing::with_params(
                    vec![(shape.clone(), Isometry3::identity())],
                    m,
                    physics::training_configs(),
                    levels,
                );
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
                noise: noise.then_some(o.point_noise),
                reporter: ctx.reporter,
            };
            let laps = |which, n| walk(&object, which, n, &how);
            let (a, b) = (laps(Trajectory::A, 2), laps(Trajectory::B, 1));
            let truth = a.truth.as_deref().unwrap_or_default();
            let step = mean_step(&truth[..truth.len() / 2]);
            ctx.note(&format!(
                "{}: {} poses per lap sensed",
                asset.name,
                a.cycles.len() / 2
            ));
            Ok(Sensed {
                asset,
                a,
                b,
                step: Some(step),
            })
        })
        .collect()
}

/// Localisation and identification on sensed walks (§5.2.2): reports and `--out` files.
pub fn analyse(o: &Settings, data: &[Sensed], ctx: Context) -> Result<Report> {
    if let Some(dir) = &o.out {
        whisker_scenario::files::create_dir(dir)?;
    }
    let modules = array::modules();
    // Localisation: every object × every parameter set.
    let jobs: Vec<(usize, Combo)> = (0..data.len())
        .flat_map(|i| Combo::all().into_iter().map(move |c| (i, c)))
        .collect();
    let results: Vec<LocalisationRun> = jobs
        .par_iter()
        .map(|&(i, combo)| {
            let Sensed { a, b, .. } = &data[i];
            let lap = a.cycles.len() / 2;
            let origin = a.truth.as_ref().map(|t| t[0]);
            let origin = origin.as_ref();
            let mut slam = WhiskerRatSlam::new(params(combo, o.slam), ObjectMap::default());
            let mut made = Vec::new();
            let on_a = explore(&mut slam, a, combo, &modules, origin, lap, &mut made);
            let map = slam.map.clone();
            let mut slam_b = WhiskerRatSlam::new(params(combo, o.slam), map.clone());
            let on_b = explore(&mut slam_b, b, combo, &modules, origin, 0, &mut made);
            LocalisationRun {
                object: i,
                combo,
                on_a,
                on_b,
                map,
            }
        })
        .collect();
    ctx.note(&format!("localisation: {} runs done", results.len()));
    let localisation = results::localisation(o, data, &results)?;
    // Identification with the best set's maps, the unmapped object left out.
    let mut appended = ObjectMap::default();
    let mut mapped = Vec::new();
    for run in &results {
        let name = data[run.object].asset.name;
        if run.combo == Combo::BEST && name != UNMAPPED {
            appended.append(&run.map, name);
            mapped.push(name.to_string());
        }
    }
    let id_runs: Vec<_> = (0..data.len())
        .flat_map(|i| [(i, Trajectory::A), (i, Trajectory::B)])
        .collect();
    let id_results: Vec<IdentificationRun> = id_runs
        .par_iter()
        .map(|&(i, which)| {
            let Sensed { a, b, .. } = &data[i];
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
            IdentificationRun {
                object: i,
                which,
                events,
                series,
            }
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
