//! Object datasets (experiment `object-slam`, thesis §5.2): the walks of `whisker
//! object-slam` around catalogue objects — trajectory A (two laps) and B (one lap), one
//! whisk per pose per second — written as logs, and read back into the same
//! localisation and identification.
//!
//! Kinematic sensing only (level `contacts`): per walk, `log/<object>/<A|B>/contacts.csv`
//! (the noisy contacts of every whisk, §6.1.3.1.2), `odometry.csv` (6-D, Eq 5.7: the
//! velocity and the rotation vector over each whisk's interval, with the walk's Gaussian
//! errors) and `poses.csv` (the pose log, dead-reckoned from that odometry); ground truth
//! `truth/<object>/<A|B>/poses.csv`, `odometry.csv` (noise-free) and `contacts.csv` (the
//! rigid sweep without noise).

use crate::dataset_format::manifest::{
    ContactNoiseInfo, Experiment, Level, Manifest, NoiseInfo, ObjectSlamInfo, Odometry6Noise, Role,
    SensorInfo, SensorNoise, WalkInfo,
};
use crate::dataset_format::records::{self, POSE_COLUMNS};
use crate::dataset_format::table::{Row, Table, columns};
use crate::dataset_format::whisks::{WhiskFiles, put_model, replay_sensing};
use crate::dataset_format::{Staging, array_info};
use crate::object_slam::{self, Sensed, Walk};
use crate::record::Context;
use crate::sensing::held::{PhysicsSensing, training_configs};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rayon::prelude::*;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use whisker_scenario::SensingMode;
use whisker_scenario::choice::Choice;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::assets::{CATALOGUE, generate};
use whisker_sim::sensing::kinematic::{RigidWhisker, SweepTarget};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::sensing::physics::WhiskerConfig;
use whisker_sim::whisker::array;
use whisker_slam::sensor::Odometry;
use whisker_slam::sensor::SAMPLE_RATE_HZ;

pub const ODOMETRY_COLUMNS: &str =
    "whisk,time_s,vx_m_s,vy_m_s,vz_m_s,wx_rad_s,wy_rad_s,wz_rad_s,dt_s";

/// What `whisker dataset object-slam` writes.
#[derive(Debug, Clone)]
pub struct ObjectDataset {
    /// Catalogue objects [default: all eight].
    pub objects: Vec<String>,
    /// Seed of every random draw.
    pub seed: u64,
    /// The dataset's directory (must not exist).
    pub out: PathBuf,
    /// Without noise (contact noise and odometry error left out; kinematic only).
    pub clean: bool,
    /// How contacts are sensed: the kinematic sweep (level contacts) or physics whiskers
    /// (level streams: one whisk file per pose, the front end at replay).
    pub sensing: SensingMode,
    /// With physics sensing: the radial-distance model [default: the built-in svr10];
    /// copied into the dataset.
    pub radial_model: Option<PathBuf>,
    /// Where each object sits relative to its trajectories; recorded in the manifest.
    pub placement: object_slam::Placement,
}

/// Writes the walks of `o` into `s` (as `whisker object-slam` senses them).
pub fn write(o: &ObjectDataset, s: &mut Staging, ctx: Context) -> Result<Manifest> {
    let physics = o.sensing == SensingMode::Physics;
    if physics && o.clean {
        return Err(Error::Input(
            "--clean: only with --sensing kinematic (physics whiskers' sensor noise is part \
             of the simulation)"
                .into(),
        ));
    }
    let settings = object_slam::Settings {
        objects: o.objects.clone(),
        seed: o.seed,
        sensing: o.sensing,
        radial_model: o.radial_model.clone(),
        placement: o.placement,
        ..Default::default()
    };
    let whiskers: Vec<RigidWhisker> = match physics {
        true => training_configs()
            .iter()
            .map(WhiskerConfig::rigid)
            .collect(),
        false => array::modules()
            .into_iter()
            .map(|m| RigidWhisker::new(m, 3.0e-3))
            .collect(),
    };
    let array = array_info(&whiskers);
    let sensor = training_configs()[0].sensor;
    // Physics: each whisk's samples straight to its file, as the walks are simulated.
    let files = physics.then(|| {
        let dir = s.path("log");
        let path = move |stream: &str, k: usize| {
            // `object-slam/<object>/<A|B>/physics/<k>`.
            let walk = stream.strip_prefix("object-slam/").unwrap_or(stream);
            let walk = walk.split("/physics/").next().unwrap_or(walk);
            dir.join(walk).join("whisks").join(records::whisk_name(k))
        };
        WhiskFiles::new(path, array.labels.clone(), sensor.angle_resolution_rad)
    });
    let data = object_slam::sense(
        &settings,
        !o.clean,
        files.as_ref().map(|f| f.log.clone()),
        ctx,
    )?;
    if let Some(files) = &files {
        files.finish()?;
        put_model(
            s,
            &whisker_scenario::radial_model::load_or_default(o.radial_model.as_deref())?,
        )?;
    }
    let mut walks = Vec::new();
    for Sensed { asset, a, b, .. } in &data {
        let target = SweepTarget::new(generate(asset));
        for (walk, which, laps) in [(a, "A", 2), (b, "B", 1)] {
            let dir = format!("{}/{which}", asset.name);
            write_walk(s, &dir, walk, &target, &array.labels, physics)?;
            walks.push(WalkInfo {
                object: asset.name.to_string(),
                trajectory: which.to_string(),
                laps,
                whisks: walk.cycles.len(),
            });
        }
    }
    Ok(manifest(o, walks, array))
}

/// One walk's files: its whisk files (registered: physics wrote them as it ran) or its
/// contacts, its odometry and pose log, and ground truth (poses, clean odometry, the rigid
/// sweep's contacts).
fn write_walk(
    s: &mut Staging,
    dir: &str,
    walk: &Walk,
    target: &SweepTarget,
    labels: &[String],
    physics: bool,
) -> Result {
    let truth = walk.truth.as_ref().expect("sensed walks have their truth");
    if physics {
        for k in 0..walk.cycles.len() {
            let name = records::whisk_name(k);
            s.register(&format!("log/{dir}/whisks/{name}"), Role::Log)?;
        }
    } else {
        let log_contacts = records::contacts_csv(&walk.cycles, labels);
        s.put(
            &format!("log/{dir}/contacts.csv"),
            Role::Log,
            log_contacts.as_bytes(),
        )?;
    }
    s.put(
        &format!("log/{dir}/odometry.csv"),
        Role::Log,
        odometry_csv(&walk.odometry).as_bytes(),
    )?;
    s.put(
        &format!("log/{dir}/poses.csv"),
        Role::Log,
        pose_log(&truth[0], &walk.odometry, false, None).as_bytes(),
    )?;
    let times: Vec<f64> = (0..truth.len()).map(|k| k as f64).collect();
    let poses = records::truth_poses_csv(truth, &times);
    s.put(
        &format!("truth/{dir}/poses.csv"),
        Role::Truth,
        poses.as_bytes(),
    )?;
    let clean = whisker_slam::whisker_ratslam::walk_odometry::clean_odometry(truth);
    s.put(
        &format!("truth/{dir}/odometry.csv"),
        Role::Truth,
        odometry_csv(&clean).as_bytes(),
    )?;
    let anticipated = object_slam::anticipated(target, truth);
    s.put(
        &format!("truth/{dir}/contacts.csv"),
        Role::Truth,
        records::contacts_csv(&anticipated, labels).as_bytes(),
    )?;
    Ok(())
}

/// The manifest of an object-slam dataset of `walks`.
fn manifest(
    o: &ObjectDataset,
    walks: Vec<WalkInfo>,
    array: crate::dataset_format::manifest::ArrayInfo,
) -> Manifest {
    let physics = o.sensing == SensingMode::Physics;
    let first = training_configs().swap_remove(0);
    let sensor = first.sensor;
    let noise = if o.clean || physics {
        ContactNoise::NONE
    } else {
        ContactNoise::default()
    };
    let whisks: usize = walks.iter().map(|w| w.whisks).sum();
    let level = if physics {
        Level::Streams
    } else {
        Level::Contacts
    };
    Manifest {
        sensor: physics.then_some(SensorInfo {
            sample_rate_hz: SAMPLE_RATE_HZ,
            whisk_hz: 1.0,
            samples_per_whisk: (SAMPLE_RATE_HZ / first.pattern.frequency).round() as usize,
            whisks,
            angle_resolution_rad: sensor.angle_resolution_rad,
            saturation_counts: sensor.saturation_counts,
        }),
        noise: NoiseInfo {
            sensor: physics.then_some(SensorNoise::of(&sensor)),
            odometry_6d: (!o.clean).then_some(Odometry6Noise::WALK),
            contacts: ContactNoiseInfo::of(noise),
            ..NoiseInfo::default()
        },
        object_slam: Some(ObjectSlamInfo {
            sensing: if physics { "physics" } else { "kinematic" }.into(),
            placement: o.placement.name().into(),
            walks,
            frontend: physics.then(|| object_slam::physics_levels(o.seed)),
        }),
        ..Manifest::new(Experiment::ObjectSlam, level, o.seed, array)
    }
}

/// A 6-D odometry file's text: per whisk, v (m/s) and ω (rad/s) in the body frame at the
/// interval's start, and the interval (s).
pub fn odometry_csv(odometry: &[Odometry]) -> String {
    let mut csv = String::from(ODOMETRY_COLUMNS) + "\n";
    for (k, o) in odometry.iter().enumerate() {
        let _ = writeln!(
            csv,
            "{k},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
            k as f64, o.v[0], o.v[1], o.v[2], o.omega[0], o.omega[1], o.omega[2], o.dt
        );
    }
    csv
}

/// The pose log: from `start`, each whisk's odometry applied (translation v·Δt, rotation
/// exp(ω·Δt), both in the body frame; the first whisk's only if `first`: an object walk's
/// first row is no motion), one row per whisk at whole seconds (`times`, if given, else
/// the whisk's number).
pub fn pose_log(
    start: &Isometry3<f64>,
    odometry: &[Odometry],
    first: bool,
    times: Option<&[f64]>,
) -> String {
    let mut at = *start;
    let mut csv = String::from(POSE_COLUMNS) + "\n";
    for (k, o) in odometry.iter().enumerate() {
        if k > 0 || first {
            let step = Isometry3::from_parts(
                Translation3::from(Vector3::from(o.v) * o.dt),
                UnitQuaternion::from_scaled_axis(Vector3::from(o.omega) * o.dt),
            );
            at *= step;
        }
        let t = times.map_or(k as f64, |t| t[k]);
        csv += &records::pose_row(t, &at, &format!("whisk_{k:06}"));
    }
    csv
}

/// Reads an object dataset into the walks `whisker object-slam` analyses.
pub fn read(dir: &Path, m: &Manifest) -> Result<Vec<Sensed<'static>>> {
    let file = dir.join(crate::dataset_format::manifest::FILE);
    let Some(info) = m
        .object_slam
        .as_ref()
        .filter(|_| m.experiment == Experiment::ObjectSlam)
    else {
        return Err(Error::Input(format!(
            "{}: not an object-slam dataset",
            file.display()
        )));
    };
    let physics = match (info.sensing.as_str(), m.level) {
        ("kinematic", Level::Contacts) => None,
        ("physics", Level::Streams) => {
            let levels = info.frontend.as_deref();
            Some(replay_sensing(
                dir,
                m,
                levels.map(|l| ("object_slam.frontend", l)),
            )?)
        }
        _ => {
            return Err(Error::field(
                &file,
                "object_slam.sensing",
                "expected \"kinematic\" (level contacts) or \"physics\" (level streams)",
            ));
        }
    };
    if object_slam::Placement::named(&info.placement).is_none() {
        return Err(Error::field(
            &file,
            "object_slam.placement",
            "expected \"thesis\" or \"centred\"",
        ));
    }
    crate::dataset_format::rigid_whiskers(dir, &m.array)?;
    let truth = m.has_truth(dir);
    let mut out = Vec::new();
    for pair in info.walks.chunks(2) {
        let [a, b] = pair else {
            return Err(Error::field(
                &file,
                "object_slam.walks",
                "expected A then B per object",
            ));
        };
        let asset = CATALOGUE
            .iter()
            .find(|x| x.name == a.object)
            .ok_or_else(|| {
                Error::field(
                    &file,
                    "object_slam.walks",
                    format!("unknown object {:?}", a.object),
                )
            })?;
        if (
            a.trajectory.as_str(),
            a.laps,
            b.trajectory.as_str(),
            b.laps,
            &b.object,
        ) != ("A", 2, "B", 1, &a.object)
        {
            return Err(Error::field(
                &file,
                "object_slam.walks",
                format!(
                    "{}: expected trajectory A (2 laps) then B (1 lap)",
                    a.object
                ),
            ));
        }
        let walk_a = read_walk(dir, m, a, truth, physics.as_ref())?;
        let walk_b = read_walk(dir, m, b, truth, physics.as_ref())?;
        let step = walk_a.truth.as_ref().map(|t| {
            let lap = walk_a.cycles.len() / 2;
            object_slam::mean_step(&t[..lap])
        });
        out.push(Sensed {
            asset,
            a: walk_a,
            b: walk_b,
            step,
        });
    }
    Ok(out)
}

/// The trajectory named `A` or `B`.
fn trajectory(name: &str) -> object_slam::Trajectory {
    match name {
        "A" => object_slam::Trajectory::A,
        _ => object_slam::Trajectory::B,
    }
}

/// The number of whisks of walk `walk` (`<object>/<A|B>`) in the manifest.
pub fn whisks(m: &Manifest, walk: &str) -> Result<usize> {
    m.object_slam
        .as_ref()
        .and_then(|i| {
            i.walks
                .iter()
                .find(|w| format!("{}/{}", w.object, w.trajectory) == walk)
        })
        .map(|w| w.whisks)
        .ok_or_else(|| {
            Error::Input(format!(
                "{}: field `object_slam.walks`: no walk {walk}",
                crate::dataset_format::manifest::FILE
            ))
        })
}

/// A walk's logged odometry and the first pose of its pose log (`walk`: `<object>/<A|B>`).
pub fn read_log(dir: &Path, m: &Manifest, walk: &str) -> Result<(Vec<Odometry>, Isometry3<f64>)> {
    let n = whisks(m, walk)?;
    let odometry = read_odometry(&m.file(dir, &format!("log/{walk}/odometry.csv"))?, n)?;
    let poses = records::read_poses(&m.file(dir, &format!("log/{walk}/poses.csv"))?)?;
    Ok((odometry, poses[0].1))
}

/// A 6-D odometry file of `n` whisks.
pub fn read_odometry(path: &Path, n: usize) -> Result<Vec<Odometry>> {
    read_rows(path, ODOMETRY_COLUMNS, n, |row| {
        let v: Vec<f64> = (2..9).map(|i| row.f64(i)).collect::<Result<_>>()?;
        Ok(Odometry {
            v: [v[0], v[1], v[2]],
            omega: [v[3], v[4], v[5]],
            dt: v[6],
        })
    })
}

/// One walk's contacts, odometry and (if `truth`) true poses.
fn read_walk(
    dir: &Path,
    m: &Manifest,
    w: &WalkInfo,
    truth: bool,
    physics: Option<&PhysicsSensing>,
) -> Result<Walk> {
    let base = format!("{}/{}", w.object, w.trajectory);
    let n = w.whisks;
    let cycles = match (physics, m.sensor) {
        // The front end and the radial-distance model on each whisk file, with the draws
        // the live run made (sub-streams of the run's seed, by the walk's stream name).
        (Some(p), Some(_)) => (0..n)
            .into_par_iter()
            .map(|k| {
                let streams =
                    crate::dataset_format::whisk_streams(dir, m, &format!("log/{base}/whisks"), k)?;
                let stream = object_slam::stream(&w.object, trajectory(&w.trajectory));
                Ok(p.contacts(k, &streams, m.seed, &format!("{stream}/physics/{k}")))
            })
            .collect::<Result<Vec<_>>>()?,
        _ => records::read_contacts(
            &m.file(dir, &format!("log/{base}/contacts.csv"))?,
            n,
            &m.array.labels,
        )?,
    };
    let odometry = read_odometry(&m.file(dir, &format!("log/{base}/odometry.csv"))?, n)?;
    // The pose log is not needed to replay (the odometry is), but a log the lab's tools
    // would read must be whole: read strictly, one row per whisk.
    let log = m.file(dir, &format!("log/{base}/poses.csv"))?;
    let poses = records::read_poses(&log)?;
    if poses.len() != n {
        return Err(Error::Input(format!(
            "{}: expected {n} poses (one per whisk, as the manifest's walk has), got {}",
            log.display(),
            poses.len()
        )));
    }
    let truth = if truth {
        Some(read_rows(
            &m.file(dir, &format!("truth/{base}/poses.csv"))?,
            records::TRUTH_POSE_COLUMNS,
            n,
            |row| {
                let v: Vec<f64> = (2..9).map(|i| row.f64(i)).collect::<Result<_>>()?;
                let q = Quaternion::new(v[6], v[3], v[4], v[5]);
                if (q.norm() - 1.0).abs() > 1e-9 {
                    return Err(
                        row.error("columns 6–9 (qx, qy, qz, qw): expected a unit quaternion")
                    );
                }
                // As written: not renormalised, so the replay sees the very same numbers.
                Ok(Isometry3::from_parts(
                    Translation3::new(v[0], v[1], v[2]),
                    UnitQuaternion::new_unchecked(q),
                ))
            },
        )?)
    } else {
        None
    };
    Ok(Walk {
        truth,
        cycles,
        odometry,
    })
}

/// The `n` rows of a per-whisk file (`whisk` = 0, 1, … in column 1, a time in column 2),
/// each read by `parse`.
pub(super) fn read_rows<T>(
    path: &Path,
    header: &str,
    n: usize,
    parse: impl Fn(&Row) -> Result<T>,
) -> Result<Vec<T>> {
    let table = Table::read(path, &columns(header))?;
    if table.len() != n {
        return Err(table.error(
            table.len() + 1,
            format!("expected {n} whisks, got {}", table.len()),
        ));
    }
    let mut out = Vec::with_capacity(n);
    for row in table.rows() {
        let row = row?;
        row.expect(0, out.len())?;
        row.f64(1)?;
        out.push(parse(&row)?);
    }
    Ok(out)
}
