//! One whisk's contacts, from any sensing: the contact pipeline of physics sensing
//! (detect → radial distance → the point on the shaft, [`estimate`]), the rows of
//! `contacts.csv` (one writer for `contacts.csv`, `anticipated.csv` and `frontend.csv`,
//! columns in `scenarios/README.md`), and the anticipated intersect and straight shafts
//! of the kinematic sweep for the recordings' ground truth.

use crate::record::Contact;
use nalgebra::{Isometry3, Point3};
use std::fmt::Write as _;
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_slam::contact::{Contact as SlamContact, ContactCycle};
use whisker_slam::frontend::contact::{ContactEvent, FrontEndParams, detect};
use whisker_slam::radial::RadialEstimator;
use whisker_slam::rng::StreamRng;
use whisker_slam::sensor::Sample;

/// Header of `contacts.csv` / `anticipated.csv`.
pub const HEADER: &str = "cycle,t_cycle_s,whisker,pixel,t_contact_s,angle_deg,radial_distance_m,\
                          x_m,y_m,z_m,world_x_m,world_y_m,world_z_m,slope\n";

/// Appends the rows of one whisk cycle's contacts, made with the array at `pose`, to a
/// `contacts.csv` text (`pixels`: each whisker's tactile-image label); returns the contacts
/// in the world.
pub fn append_cycle(
    csv: &mut String,
    cycle: &ContactCycle,
    pose: &Isometry3<f64>,
    pixels: &[String],
) -> Vec<Contact> {
    let mut world = Vec::with_capacity(cycle.contacts.len());
    for c in &cycle.contacts {
        let w = pose * c.point;
        world.push(Contact {
            whisker: c.whisker,
            point: [w.x, w.y, w.z],
        });
        write_row(csv, cycle.index, cycle.start_s, c, &pixels[c.whisker], &w);
    }
    world
}

/// Appends one contact's row: of whisk cycle `index` starting at `start` (s), the whisker
/// labelled `pixel`, the contact in the array frame (`c.point`) and in the world (`world`).
pub fn write_row(
    csv: &mut String,
    index: impl std::fmt::Display,
    start: f64,
    c: &SlamContact,
    pixel: &str,
    world: &Point3<f64>,
) {
    let _ = writeln!(
        csv,
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
        index,
        start,
        c.whisker,
        pixel,
        c.time_s,
        c.angle_rad.to_degrees(),
        c.radial_distance,
        c.point.x,
        c.point.y,
        c.point.z,
        world.x,
        world.y,
        world.z,
        c.slope
    );
}

/// A contact the front end detected in one whisker's stream of a whisk and the
/// radial-distance model placed on the shaft (Eq 5.1–5.2).
pub struct Estimate {
    /// The front end's event (onset, angles, features, slope).
    pub event: ContactEvent,
    /// The model's radial distance (m).
    pub radial_distance: f64,
    /// The array's pose at the onset.
    pub pose: Isometry3<f64>,
    /// The contact point on the straight shaft at the onset's whisk angle, in the frame of
    /// `pose`'s parent.
    pub point: Point3<f64>,
}

/// The front end's contact event in `whisker`'s samples of one whisk cycle (sampled at
/// `rate` Hz), if any (§4.1.1, `whisker_slam::frontend::contact::detect`).
pub fn detect_on(
    whisker: &RigidWhisker,
    samples: &[Sample],
    rate: f64,
    params: &FrontEndParams,
) -> Option<ContactEvent> {
    detect(samples, rate, whisker.module.beam.length, params)
}

/// The contact pipeline of physics sensing, the same from the simulator and from a log:
/// the front end's event ([`detect_on`]), its radial distance from `model` (draws from
/// `rng`), and the point on the straight shaft at the onset's whisk angle with the array
/// where it was at the onset (`poses[k]`: its pose at sample k; the last one for later
/// samples).
pub fn estimate(
    whisker: &RigidWhisker,
    samples: &[Sample],
    rate: f64,
    params: &FrontEndParams,
    model: &RadialEstimator,
    rng: &mut StreamRng,
    poses: &[Isometry3<f64>],
) -> Option<Estimate> {
    let event = detect_on(whisker, samples, rate, params)?;
    let radial_distance = model.estimate(&event.features, rng);
    let pose = poses[event.onset.min(poses.len() - 1)];
    let point = whisker.shaft_point(&pose, event.onset_angle, radial_distance);
    Some(Estimate {
        event,
        radial_distance,
        pose,
        point,
    })
}

/// The anticipated intersects of `whiskers` with the array at `pose`: the noise-free
/// contacts (world), for the recording's ground truth.
pub fn anticipated(
    target: &SweepTarget,
    whiskers: &[RigidWhisker],
    pose: &Isometry3<f64>,
) -> Vec<Contact> {
    whiskers
        .iter()
        .filter_map(|w| {
            let hit = target.sweep(w, pose)?;
            Some(Contact {
                whisker: w.module.index,
                point: [hit.point.x, hit.point.y, hit.point.z],
            })
        })
        .collect()
}

/// The anticipated intersects of a kinematic `array`'s last whisk, before noise (world).
pub fn intersects(array: &KinematicArray) -> Vec<Contact> {
    array
        .intersects
        .iter()
        .map(|(w, p)| Contact {
            whisker: *w,
            point: [p.x, p.y, p.z],
        })
        .collect()
}

/// The straight shafts of a kinematic `array` at time `t` with the array at `pose` (world;
/// base and tip of each), at each whisker's pattern angle.
pub fn rigid_shafts(array: &KinematicArray, pose: &Isometry3<f64>, t: f64) -> Vec<Vec<[f64; 3]>> {
    array
        .whiskers
        .iter()
        .zip(&array.patterns)
        .map(|(w, p)| {
            let theta = p.angle(t);
            [0.0, w.module.beam.length]
                .map(|r| {
                    let q = w.shaft_point(pose, theta, r);
                    [q.x, q.y, q.z]
                })
                .to_vec()
        })
        .collect()
}
