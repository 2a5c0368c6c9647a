//! `whisker dataset noise IN --seed M --out OUT`: a clean dataset (`whisker dataset
//! --clean`) with noise added from seed `M`, ground truth unchanged.
//!
//! - Streams: every deflection reading gets N(0, σ) counts and is re-quantised and
//!   clipped at the saturation; every angle reading gets N(0, σ_θ) and is re-quantised
//!   to the angle resolution (§2.2.2.1; the simulator's sensor model, here applied after
//!   the fact: noise drawn in the simulation also feeds back through RCP, this cannot).
//!   Sub-stream `dataset-noise/whisk/<c>/whisker/<w>` of M.
//! - Contacts: the §6.1.3.1.2 model — detection with probability p, the point displaced
//!   by N(0, f·L) per axis, the slope by N(0, s). Sub-stream
//!   `dataset-noise/contacts/whisker/<w>` of M.
//! - Odometry: the §3.1.2 error model (Lognormal(−4.3, 0.45) m, Normal(8.39e-4, 0.3)°)
//!   from sub-stream `maze-slam/odometry` of M — the same draws as a noisy dataset
//!   written with seed M; the pose log is dead-reckoned again from it.

use crate::dataset_format::manifest::{
    ContactNoiseInfo, Experiment, Level, Manifest, NoiseInfo, Odometry6Noise, Role, SensorNoise,
};
use crate::dataset_format::records;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::path::PathBuf;
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::noise::{ContactNoise, PointNoise};
use whisker_slam::ratslam::odometry::OdometryNoise;
use whisker_slam::ratslam::odometry::noisy_steps;
use whisker_slam::rng::{gauss, substream};

/// What `whisker dataset noise` adds.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The clean dataset.
    pub input: PathBuf,
    /// Seed of the noise.
    pub seed: u64,
    /// The noisy dataset's directory (must not exist).
    pub out: PathBuf,
    /// σ of the deflection noise (counts).
    pub deflection_counts: f64,
    /// σ of the angle noise (degrees).
    pub angle_deg: f64,
    /// Probability that a contact is registered (level contacts).
    pub detection: f64,
    /// σ of the contact point's noise as a fraction of the whisker's length.
    pub point_fraction: f64,
    /// Which way it displaces the point.
    pub point_model: PointNoise,
    /// σ of the contact slope.
    pub slope_sigma: f64,
}

/// `whisker dataset noise`.
pub fn run(o: &Settings) -> Result<crate::dataset_format::Written> {
    let m = Manifest::read(&o.input)?;
    let contact_noise = check(o, &m)?;
    crate::dataset_format::timed(&o.out, |s| {
        let mut out = m.clone();
        out.noise = NoiseInfo {
            added_with_seed: Some(o.seed),
            ..NoiseInfo::default()
        };
        for entry in &m.files {
            if let Some(bytes) = noisy_file(o, &m, entry, contact_noise, s, &mut out.noise)? {
                s.put(&entry.path, entry.role, &bytes)?;
            }
        }
        if m.level == Level::Streams {
            let sigma = SensorNoise {
                deflection_counts: o.deflection_counts,
                angle_rad: o.angle_deg.to_radians(),
            };
            out.noise.sensor = Some(sigma);
            noisy_streams(o, &m, sigma, s)?;
        }
        Ok(out)
    })
}

/// Refuses a dataset that holds noise already or a closed loop's, and noise parameters out
/// of range; returns the contact noise.
fn check(o: &Settings, m: &Manifest) -> Result<ContactNoise> {
    if !m.noise.is_clean() {
        return Err(Error::Input(format!(
            "{}: field `noise`: the dataset already holds noise; write it with \
             `whisker dataset --clean` to noise it later",
            o.input
                .join(crate::dataset_format::manifest::FILE)
                .display()
        )));
    }
    if m.experiment == Experiment::ClosedLoop {
        return Err(Error::Input(format!(
            "{}: a closed loop's path depends on its noise: its dataset is written with the \
             noise it ran with and cannot be noised later",
            o.input
                .join(crate::dataset_format::manifest::FILE)
                .display()
        )));
    }
    let contact_noise = ContactNoise {
        point_fraction: o.point_fraction,
        slope_sigma: o.slope_sigma,
        detection_probability: o.detection,
        point_model: o.point_model,
    };
    contact_noise
        .validate()
        .map_err(|e| Error::Input(format!("--{}: {}", e.field.replace('_', "-"), e.message)))?;
    // Along the whisker needs each whisker's shaft: the standard array's modules.
    let standard = whisker_sim::whisker::array::labels();
    if o.point_model == PointNoise::AlongWhisker
        && let Some(l) = m.array.labels.iter().find(|l| !standard.contains(l))
    {
        return Err(Error::Input(format!(
            "{}: field `array.labels`: {l:?} is not a whisker of the standard array (A1 … F3), \
             whose shaft --point-noise along-whisker needs",
            o.input
                .join(crate::dataset_format::manifest::FILE)
                .display()
        )));
    }
    // σ up to a whole 12-bit range of counts and a whole turn.
    for (name, v, max) in [
        ("deflection-counts", o.deflection_counts, 4096.0),
        ("angle-deg", o.angle_deg, 360.0),
    ] {
        if !(v >= 0.0 && v <= max) {
            return Err(Error::Input(format!(
                "--{name}: expected a number from 0 to {max}, got {}",
                whisker_slam::message::short(v)
            )));
        }
    }
    Ok(contact_noise)
}

/// The noisy dataset's bytes of one file of the clean one (None: not copied; the whisk
/// streams are noised apart and the pose logs written with their odometry); notes in
/// `noise` what was added.
fn noisy_file(
    o: &Settings,
    m: &Manifest,
    entry: &crate::dataset_format::manifest::FileEntry,
    contact_noise: ContactNoise,
    s: &mut crate::dataset_format::Staging,
    noise: &mut NoiseInfo,
) -> Result<Option<Vec<u8>>> {
    let path = o.input.join(&entry.path);
    let (parent, name) = entry.path.rsplit_once('/').unwrap_or(("", &entry.path));
    // An object walk's directory `log/<object>/<A|B>`, or the maze's `log`.
    let walk = parent
        .strip_prefix("log/")
        .filter(|_| m.experiment == Experiment::ObjectSlam);
    Ok(Some(match (entry.role, name) {
        (Role::Log, "odometry.csv") => match walk {
            // The §3.1.2 error, as a noisy dataset of seed M holds it; the pose
            // log dead-reckoned again from it.
            None => {
                let odometry = OdometryNoise::default();
                noise.odometry = Some(odometry);
                let clean = crate::maze_slam::dataset::read_odometry(&path, None)?;
                let steps = noisy_steps(&clean, &odometry, o.seed);
                let poses = crate::maze_slam::dataset::pose_log_of(&o.input, m, &steps)?;
                s.put("log/poses.csv", Role::Log, poses.as_bytes())?;
                crate::maze_slam::dataset::odometry_csv(&steps).into_bytes()
            }
            // The walk's Gaussian error from `object-slam/<object>/<A|B>/odometry`.
            Some(walk) => {
                noise.odometry_6d = Some(Odometry6Noise::WALK);
                let (clean, start) = crate::object_slam::dataset::read_log(&o.input, m, walk)?;
                let noisy = whisker_slam::whisker_ratslam::walk_odometry::noisy_odometry(
                    &clean,
                    o.seed,
                    &format!("object-slam/{walk}"),
                );
                let poses = crate::object_slam::dataset::pose_log(&start, &noisy, false, None);
                s.put(&format!("{parent}/poses.csv"), Role::Log, poses.as_bytes())?;
                crate::object_slam::dataset::odometry_csv(&noisy).into_bytes()
            }
        },
        (Role::Log, "poses.csv") => return Ok(None),
        (Role::Log, "contacts.csv") => {
            noise.contacts = Some(ContactNoiseInfo {
                point_fraction: o.point_fraction,
                slope_sigma: o.slope_sigma,
                detection_probability: o.detection,
                point_model: o.point_model,
            });
            let whisks = match (walk, &m.maze) {
                (Some(walk), _) => crate::object_slam::dataset::whisks(m, walk)?,
                (None, Some(maze)) => maze.updates,
                (None, None) => 0,
            };
            let cycles = records::read_contacts(&path, whisks, &m.array.labels)?;
            let tag = walk.map_or(String::new(), |w| format!("{w}/"));
            let noisy = noisy_contacts(
                &cycles,
                (&m.array.lengths_m, &m.array.labels),
                contact_noise,
                o.seed,
                &tag,
            );
            records::contacts_csv(&noisy, &m.array.labels).into_bytes()
        }
        _ if entry.path.starts_with("log/whisks/") => return Ok(None),
        (Role::Truth, _) if !path.exists() => return Ok(None),
        _ => std::fs::read(&path)
            .map_err(|e| Error::Input(format!("{}: cannot read: {e}", path.display())))?,
    }))
}

/// The whisk streams with sensor noise `sigma`, re-quantised and clipped as the sensor
/// would (one sub-stream per whisk and whisker), into the staging directory.
fn noisy_streams(
    o: &Settings,
    m: &Manifest,
    sigma: SensorNoise,
    s: &mut crate::dataset_format::Staging,
) -> Result {
    let sensor = m.sensor_section(&o.input)?;
    let files: Vec<Result<(String, String)>> = (0..sensor.whisks)
        .into_par_iter()
        .map(|c| {
            let name = format!("log/whisks/{}", records::whisk_name(c));
            let mut streams = records::read_whisk(
                &o.input.join(&name),
                &m.array.labels,
                sensor.samples_per_whisk,
                sensor.angle_resolution_rad,
            )?;
            for (w, stream) in streams.iter_mut().enumerate() {
                let mut rng = substream(o.seed, &format!("dataset-noise/whisk/{c}/whisker/{w}"));
                let q = sensor.angle_resolution_rad;
                let limit = sensor.saturation_counts;
                for r in stream.iter_mut() {
                    r.angle_rad =
                        ((r.angle_rad + gauss(sigma.angle_rad, &mut rng)) / q).round() * q;
                    r.x = (r.x + gauss(sigma.deflection_counts, &mut rng))
                        .round()
                        .clamp(-limit, limit)
                        + 0.0;
                    r.y = (r.y + gauss(sigma.deflection_counts, &mut rng))
                        .round()
                        .clamp(-limit, limit)
                        + 0.0;
                }
            }
            Ok((
                name,
                records::whisk_csv(&m.array.labels, &streams, sensor.angle_resolution_rad)?,
            ))
        })
        .collect();
    for f in files {
        let (name, csv) = f?;
        s.put(&name, Role::Log, csv.as_bytes())?;
    }
    Ok(())
}

/// The §6.1.3.1.2 noise on clean contacts (whisker lengths `lengths`), from sub-streams
/// `dataset-noise/<tag>contacts/whisker/<w>` of `seed` (`tag`: an object walk's
/// `<object>/<A|B>/`, or empty).
fn noisy_contacts(
    cycles: &[whisker_slam::contact::ContactCycle],
    (lengths, labels): (&[f64], &[String]),
    noise: ContactNoise,
    seed: u64,
    tag: &str,
) -> Vec<whisker_slam::contact::ContactCycle> {
    // Each whisker's module by its label (the manifest's labels are the standard array's
    // when the noise lies along the whisker: checked on reading).
    let modules: Vec<Option<whisker_sim::whisker::array::Module>> = {
        let all = whisker_sim::whisker::array::modules();
        labels
            .iter()
            .map(|l| all.iter().find(|m| m.pixel() == *l).cloned())
            .collect()
    };
    let mut rngs: Vec<_> = (0..lengths.len())
        .map(|w| substream(seed, &format!("dataset-noise/{tag}contacts/whisker/{w}")))
        .collect();
    cycles
        .iter()
        .map(|cycle| {
            let mut c = cycle.clone();
            c.contacts = cycle
                .contacts
                .iter()
                .filter_map(|x| {
                    // The shaft in the array frame (the contact point's) at its angle.
                    let shaft = modules[x.whisker].as_ref().map_or(Vector3::z(), |m| {
                        m.whisker_pose(x.angle_rad).rotation * Vector3::z()
                    });
                    let (offset, slope) =
                        noise.draw(lengths[x.whisker], &shaft, x.slope, &mut rngs[x.whisker])?;
                    let mut x = *x;
                    x.point += Vector3::from(offset);
                    x.slope = slope;
                    Some(x)
                })
                .collect();
            c
        })
        .collect()
}
