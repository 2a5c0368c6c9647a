//! `whisker radial generate`: the physics data sets of thesis §4.1.2.
//!
//! - Training (§4.1.2.1, Fig 4.1a): one whisker module whisks into a rod (6 mm across,
//!   its axis along the whisk axis) placed so that the rigid shaft first touches it at
//!   radial distance r; r takes 20 equally spaced values from 25 mm from the shaft's base
//!   to the tip, for whisker lengths 65, 78, 87, 88, 94, 107, 113 and 137 mm; at each, the
//!   whisker whisks once at each of `--frequencies` frequencies drawn log-uniformly from
//!   0.2–2.5 Hz, with the rod at a contact angle drawn uniformly from 60°–110°.
//! - Validation (§4.1.2.2, Fig 4.1b): the full array, its whiskers cut to 50, 64, 80, 95,
//!   101, 127, 128, 150 and 154 mm (two of each, shortest on the rostral ring), held
//!   still at `--waypoints` poses around the Box (of 512 poses 2–8 cm off its surface,
//!   those where the most whiskers touch at ≤ 0.7 L), whisking `--whisks` times at 1 Hz.
//!
//! Whisking uses RCP at the sensor's saturation (§4.1.1). Ground truth is the kinematic
//! sweep (the anticipated intersect, §4.1.2.3); every contact the front end detects on a
//! whisker the sweep says touches becomes a row of the data set
//! (`whisker_slam::radial::dataset`). Each (whisker, rod or waypoint) is a simulation
//! of its own with sensor noise from the sub-stream `radial/<case>` of the seed, so the
//! file does not depend on the number of threads.

use crate::record::Context;
use crate::sensing::contact::detect_on;
use nalgebra::{Isometry3, Point3, Vector3};
use rand::RngExt;
use rayon::prelude::*;
use serde::Serialize;
use std::fmt;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use whisker_scenario::files::write_atomic;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::assets::{CATALOGUE, placed};
use whisker_sim::environment::{Environment, Piece};
use whisker_sim::sensing::kinematic::{Intersect, RigidWhisker, SweepTarget};
use whisker_sim::sensing::physics::{DT, PhysicsArray, WhiskerConfig};
use whisker_sim::sensing::viewpoints;
use whisker_sim::whisker::array::{self, Module};
use whisker_sim::whisker::beam::BeamDesign;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::frontend::contact::FrontEndParams;
use whisker_slam::radial::dataset::{RadialSample, to_csv};
use whisker_slam::rng::{substream, substream_key};
use whisker_slam::sensor::Sample;

/// Whisker lengths of the training set (mm, §4.1.2.1).
pub const TRAINING_LENGTHS_MM: [f64; 8] = [65.0, 78.0, 87.0, 88.0, 94.0, 107.0, 113.0, 137.0];
/// Whisker lengths of the validation set (mm, §4.1.2.2).
pub const VALIDATION_LENGTHS_MM: [f64; 9] =
    [50.0, 64.0, 80.0, 95.0, 101.0, 127.0, 128.0, 150.0, 154.0];
/// Rod radius (m).
const ROD_RADIUS: f64 = 3.0e-3;
/// Radial distances per whisker length, and the first one (m).
const DISTANCES: usize = 20;
const FIRST_DISTANCE: f64 = 0.025;

/// Which data set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Set {
    /// Single whiskers against a rod (§4.1.2.1).
    Training,
    /// The array around the Box (§4.1.2.2).
    Validation,
}

impl whisker_scenario::choice::Choice for Set {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            Set::Training,
            "training",
            "Single whiskers against a rod (§4.1.2.1)",
        ),
        (
            Set::Validation,
            "validation",
            "The array around the Box (§4.1.2.2)",
        ),
    ];
}

/// What `whisker radial generate` simulates.
#[derive(Debug, Clone)]
pub struct GenerateSettings {
    /// Which set.
    pub set: Set,
    /// Output CSV file.
    pub out: PathBuf,
    /// Seed of every random draw (frequencies, rod angles, waypoints, sensor noise).
    pub seed: u64,
    /// Training: whisks (each at its own frequency) per whisker length and distance.
    pub frequencies: usize,
    /// Training: only these whisker lengths (mm) [default: all eight].
    pub lengths: Vec<f64>,
    /// Validation: array poses held still around the Box.
    pub waypoints: usize,
    /// Validation: whisks (1 Hz) per pose.
    pub whisks: usize,
    /// Rapier substeps per 0.5 ms step.
    pub substeps: usize,
    /// Where the recording goes [default: beside the data set, `<out>.rrd`].
    pub rrd: crate::record::Target,
}

/// What a data set holds.
#[derive(Debug, Clone, Serialize)]
pub struct Generated {
    pub out: PathBuf,
    pub contacts: usize,
    /// Contacts whose ground truth lies at ≤ 0.7 L.
    pub near: usize,
    pub whisks: usize,
    /// Whisks the sweep says touch with no contact detected.
    pub missed: usize,
    pub seconds: f64,
}

impl fmt::Display for Generated {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}: {} contacts ({} at ≤ 0.7 L) from {} whisks that the sweep says touch; \
             {} whisks with no contact detected ({:.1} %); {:.0} s",
            self.out.display(),
            self.contacts,
            self.near,
            self.whisks,
            self.missed,
            100.0 * self.missed as f64 / self.whisks.max(1) as f64,
            self.seconds
        )
    }
}

/// A candidate pose: whiskers touching at ≤ 0.7 L, the pose, (whisker, intersect) of all touching.
type Scored = (usize, Isometry3<f64>, Vec<(usize, Intersect)>);

/// One simulation: a whisker, what it touches, where the array is, the ground truth.
struct Job {
    case: String,
    object: String,
    config: WhiskerConfig,
    environment: Vec<Piece>,
    array_pose: Isometry3<f64>,
    truth: Intersect,
    whisks: usize,
}

/// What a job's whisks gave: detected contacts, and whisks with none; for the recording,
/// the whisks' samples.
struct Outcome {
    samples: Vec<RadialSample>,
    missed: usize,
    streams: Vec<Sample>,
}

fn whisker_config(module: Module, frequency: f64, substeps: usize) -> WhiskerConfig {
    let mut c = WhiskerConfig::with_defaults(module);
    c.pattern = WhiskingPattern {
        frequency,
        ..WhiskingPattern::default()
    };
    c.contact_threshold = Some(c.sensor.saturation_counts);
    c.control.rcp = true;
    c.substeps = substeps;
    c
}

/// A rod along the whisk axis that the rigid shaft of `whisker` (array at the origin)
/// first touches at `theta`, `r` from the shaft's base: its axis lies one rod radius
/// ahead of the shaft (in the sweep direction) at that point.
fn rod(whisker: &RigidWhisker, r: f64, theta: f64) -> Piece {
    let frame = whisker.module.whisker_pose(theta);
    let centre = frame * Point3::new(0.0, ROD_RADIUS, whisker.base_offset + r);
    let pose = Isometry3::face_towards(
        &centre,
        &(centre + frame.rotation * Vector3::x()),
        &(frame.rotation * Vector3::y()),
    );
    Piece::cylinder("rod".into(), ROD_RADIUS, 0.06, pose)
}

fn training_jobs(o: &GenerateSettings) -> Result<Vec<Job>> {
    let lengths: Vec<f64> = if o.lengths.is_empty() {
        TRAINING_LENGTHS_MM.to_vec()
    } else {
        o.lengths.clone()
    };
    if let Some(bad) = lengths.iter().find(|&&l| !(l > 30.0 && l <= 400.0)) {
        return Err(Error::Input(format!(
            "--lengths: expected whisker lengths in mm, 30 < L ≤ 400, got {}",
            whisker_slam::message::short(*bad)
        )));
    }
    let module = array::modules().remove(0);
    let mut jobs = Vec::new();
    for &mm in &lengths {
        let length = mm / 1000.0;
        let module = Module {
            beam: BeamDesign::with_length(length),
            ..module.clone()
        };
        for k in 0..DISTANCES {
            let r = FIRST_DISTANCE + k as f64 * (length - FIRST_DISTANCE) / (DISTANCES - 1) as f64;
            for j in 0..o.frequencies {
                let case = format!("L{mm:03}/r{k:02}/f{j}");
                let mut rng = substream(o.seed, &format!("radial/{case}/setup"));
                let frequency = (0.2f64.ln() + rng.random::<f64>() * (2.5f64 / 0.2).ln()).exp();
                let theta = rng.random_range(60.0..110.0f64).to_radians();
                let config = whisker_config(module.clone(), frequency, o.substeps);
                let rigid = config.rigid();
                let piece = rod(&rigid, r, theta);
                let target = SweepTarget::new(piece_mesh(&piece));
                // The 64-gon rod may be first met a step later or, at the tip, missed.
                let Some(truth) = target.sweep(&rigid, &Isometry3::identity()) else {
                    continue;
                };
                jobs.push(Job {
                    case,
                    object: "rod".into(),
                    config,
                    environment: vec![piece],
                    array_pose: Isometry3::identity(),
                    truth,
                    whisks: 1,
                });
            }
        }
    }
    Ok(jobs)
}

fn piece_mesh(piece: &Piece) -> whisker_sim::environment::Mesh {
    Environment {
        pieces: vec![piece.clone()],
    }
    .world_mesh()
}

fn validation_jobs(o: &GenerateSettings) -> Result<Vec<Job>> {
    let asset = CATALOGUE
        .iter()
        .find(|a| a.name == "box")
        .expect("the catalogue has a box");
    let (environment, shape) = placed(asset).map_err(|e| Error::Failure(format!("box: {e}")))?;
    let piece = environment.pieces[0].clone();
    let configs: Vec<WhiskerConfig> = array::modules()
        .into_iter()
        .map(|m| {
            // Two whiskers of each length, shortest on the rostral ring.
            let mm = VALIDATION_LENGTHS_MM[(m.ring * array::PER_RING + m.column) / 2];
            let m = Module {
                beam: BeamDesign::with_length(mm / 1000.0),
                ..m
            };
            whisker_config(m, 1.0, o.substeps)
        })
        .collect();
    let rigid: Vec<RigidWhisker> = configs.iter().map(WhiskerConfig::rigid).collect();
    let target = SweepTarget::of(&environment);
    let stream = format!("radial/validation/{}/waypoints", o.seed);
    let candidates = viewpoints::facing(&shape, asset.size, 512, &stream);
    // Score each pose by its whiskers touching at ≤ 0.7 L; skip poses where a whisker
    // would start inside the Box (touching within 3° of retraction).
    let mut scored: Vec<Scored> = candidates
        .into_iter()
        .filter_map(|pose| {
            let hits: Vec<(usize, Intersect)> = rigid
                .iter()
                .enumerate()
                .filter_map(|(i, w)| target.sweep(w, &pose).map(|h| (i, h)))
                .collect();
            hits.iter().all(|(_, h)| h.step >= 3).then(|| {
                let near = hits
                    .iter()
                    .filter(|(i, h)| h.radial_distance <= 0.7 * rigid[*i].module.beam.length)
                    .count();
                (near, pose, hits)
            })
        })
        .collect();
    // Stable sort: equal scores keep the draw order.
    scored.sort_by_key(|s| std::cmp::Reverse(s.0));
    let mut jobs = Vec::new();
    for (w, (_, pose, hits)) in scored.into_iter().take(o.waypoints).enumerate() {
        for (i, truth) in hits {
            jobs.push(Job {
                case: format!("wp{w:02}/{}", rigid[i].module.pixel()),
                object: "box".into(),
                config: configs[i].clone(),
                environment: vec![piece.clone()],
                array_pose: pose,
                truth,
                whisks: o.whisks,
            });
        }
    }
    Ok(jobs)
}

fn run_job(job: &Job, seed: u64, params: &FrontEndParams, keep: bool) -> Outcome {
    let pieces = Environment {
        pieces: job.environment.clone(),
    }
    .physics_pieces();
    let noise_seed = substream_key(seed, &format!("radial/{}", job.case));
    let mut array = PhysicsArray::new(
        vec![job.config.clone()],
        &pieces,
        &job.array_pose,
        noise_seed,
        DT,
    );
    let rigid = job.config.rigid();
    let mut outcome = Outcome {
        samples: Vec::new(),
        missed: 0,
        streams: Vec::new(),
    };
    for w in 0..job.whisks {
        let cycle = array.whisk(w as u64, |_| job.array_pose);
        if keep {
            outcome.streams.extend(&cycle.samples[0]);
        }
        let Some(event) = detect_on(&rigid, &cycle.samples[0], cycle.rate_hz, params) else {
            outcome.missed += 1;
            continue;
        };
        let base = rigid.shaft_point(&job.array_pose, event.onset_angle, 0.0);
        let direction =
            (rigid.shaft_point(&job.array_pose, event.onset_angle, 1.0) - base).normalize();
        outcome.samples.push(RadialSample {
            case: if job.whisks > 1 {
                format!("{}/w{w}", job.case)
            } else {
                job.case.clone()
            },
            object: job.object.clone(),
            whisker: job.config.module.pixel(),
            frequency_hz: job.config.pattern.frequency,
            truth_radial_m: job.truth.radial_distance,
            truth_angle_rad: job.truth.angle,
            onset_angle_rad: event.onset_angle,
            features: event.features,
            base,
            direction,
        });
    }
    outcome
}

/// Runs `whisker radial generate`.
pub fn run(o: &GenerateSettings, ctx: Context) -> Result<Generated> {
    // Counts that multiply the physics to run: ranges wide enough for any study, bounded
    // so that a typo does not start weeks of simulation.
    let counts = [
        ("--substeps", o.substeps, 1, 64),
        ("--frequencies", o.frequencies, 1, 100),
        ("--waypoints", o.waypoints, 1, 1000),
        ("--whisks", o.whisks, 1, 100),
    ];
    for (option, n, min, max) in counts {
        if !(min..=max).contains(&n) {
            return Err(Error::Input(format!(
                "{option} {n}: expected {min} to {max}"
            )));
        }
    }
    let jobs = match o.set {
        Set::Training => training_jobs(o)?,
        Set::Validation => validation_jobs(o)?,
    };
    let simulated: f64 = jobs
        .iter()
        .map(|j| j.whisks as f64 / j.config.pattern.frequency)
        .sum();
    ctx.note(&format!(
        "{:?} set: {} simulations, {simulated:.0} whisker-seconds of physics",
        o.set,
        jobs.len()
    ));
    let params = FrontEndParams::default();
    // The recording: `--rrd`, else beside the data set (`<out>.rrd`).
    let recording = (!o.rrd.no_rrd).then(|| {
        o.rrd
            .rrd
            .clone()
            .unwrap_or_else(|| o.out.with_extension("rrd"))
    });
    let done = AtomicUsize::new(0);
    let start = Instant::now();
    let outcomes: Vec<Outcome> = jobs
        .par_iter()
        .map(|j| {
            let out = run_job(j, o.seed, &params, recording.is_some());
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            ctx.progress("simulations", n as u64, jobs.len() as u64);
            out
        })
        .collect();
    if let Some(path) = &recording {
        record(path, o, &jobs, &outcomes, ctx)?;
    }
    let missed: usize = outcomes.iter().map(|o| o.missed).sum();
    let samples: Vec<RadialSample> = outcomes.into_iter().flat_map(|o| o.samples).collect();
    let whisks: usize = jobs.iter().map(|j| j.whisks).sum();
    let near = samples
        .iter()
        .filter(|s| s.truth_radial_m <= 0.7 * s.features.wl)
        .count();
    write_atomic(&o.out, to_csv(&samples).as_bytes())?;
    Ok(Generated {
        out: o.out.clone(),
        contacts: samples.len(),
        near,
        whisks,
        missed,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Jobs per row of the recording's grid of frames.
const JOBS_PER_ROW: usize = 20;

/// Spacing of the jobs' frames in the recording's grid (m): twice the span of all their
/// environments and contacts along x or y, whichever is larger, so that no two cases
/// overlap and the camera's case stands apart from its neighbours.
fn job_spacing(jobs: &[Job]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for j in jobs {
        let p = j.truth.point;
        let environment = Environment {
            pieces: j.environment.clone(),
        };
        if let Some((l, h)) = crate::record::bounds(&environment, &[[p.x, p.y, p.z]]) {
            for i in 0..2 {
                lo[i] = lo[i].min(l[i]);
                hi[i] = hi[i].max(h[i]);
            }
        }
    }
    2.0 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(0.05)
}

/// Writes the recording of a data set (docs/recording.md): per simulation
/// (`world/cases/<case>`, on a grid) its environment and the ground-truth contact, and its
/// whisker's 2 kHz streams (`sensors/<case>/<label>`), the jobs one after the other in
/// their order (the recording does not depend on the thread count).
fn record(
    path: &std::path::Path,
    o: &GenerateSettings,
    jobs: &[Job],
    outcomes: &[Outcome],
    ctx: Context,
) -> Result {
    use crate::record::{Contact, ContactKind, Eye, Layout, SensorColumns, entity_name, id};
    let rec = ctx.recordings.create(
        path,
        &id(&format!("radial-{:?}", o.set).to_lowercase(), o.seed),
        Layout::Cases {
            cases: jobs.iter().map(|j| entity_name(&j.case)).collect(),
            // The first job's frame is the world's.
            eye: jobs.first().and_then(|j| {
                Eye::of(
                    &Environment {
                        pieces: j.environment.clone(),
                    },
                    &Eye::reach(&j.array_pose),
                )
            }),
        },
    )?;
    let spacing = job_spacing(jobs);
    for (k, (job, out)) in jobs.iter().zip(outcomes).enumerate() {
        let case = entity_name(&job.case);
        let frame = format!("world/cases/{case}");
        let (x, y) = (
            (k % JOBS_PER_ROW) as f64 * spacing,
            (k / JOBS_PER_ROW) as f64 * spacing,
        );
        rec.frame(&frame, [x, y, 0.0])?;
        rec.environment_in(
            &format!("{frame}/environment"),
            &Environment {
                pieces: job.environment.clone(),
            },
        )?;
        let p = job.truth.point;
        rec.at(0.0);
        rec.contacts_in(
            &format!("{frame}/contacts"),
            ContactKind::True,
            k as u64,
            &[Contact {
                whisker: job.config.module.index,
                point: [p.x, p.y, p.z],
            }],
        )?;
        let label = job.config.module.pixel();
        let mut columns = SensorColumns::new(
            rec.as_ref(),
            &format!("sensors/{case}"),
            std::slice::from_ref(&label),
        )?;
        // RCP state is not kept by a whisk cycle.
        columns.push_streams(
            rec.as_ref(),
            0.0,
            0,
            std::slice::from_ref(&out.streams),
            None,
        )?;
        columns.send(rec.as_ref())?;
        rec.checkpoint()?;
    }
    rec.finish()
}
