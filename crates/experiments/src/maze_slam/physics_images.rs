//! Physics sensing for `whisker maze-slam --sensing physics` (thesis §3.1.1, §3.2.2): the
//! array moves continuously along the path (linearly interpolated between the 1.5 Hz
//! updates, whose poses are reached at t = k/1.5 s) while its Rapier whiskers whisk at
//! 1 Hz, open loop or with RCP (threshold 20 × the free-whisking σ, §3.2.2; the front
//! end's levels in counts then scale down to confirm at half the threshold). After each
//! whisk cycle the signal front end finds each whisker's contact and its angle by both of
//! §3.1.1's estimators — `max_angle` and `contact_angle` — and each gives a tactile image:
//! the height above the board of the straight shaft's tip at that angle, with the array
//! where it was at the contact's onset. An update uses the images of the latest whisk
//! cycle completed before it (the thesis published the latest image at 1.5 Hz).

use super::geometry::{Geometry, UPDATE_HZ};
use super::path::Sample;
use crate::record::Reporter;
use crate::sensing::contact::detect_on;
use crate::sensing::detection::Detection;
use nalgebra::Isometry3;
use whisker_sim::sensing::calibration::calibrate_array_rcp;
use whisker_sim::sensing::kinematic::RigidWhisker;
use whisker_sim::sensing::physics::{DT, EnvironmentPiece, PhysicsArray, WhiskerConfig};
use whisker_sim::whisker::control::RcpThreshold;
use whisker_slam::frontend::contact::FrontEndParams;
use whisker_slam::pose::wrap;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::sensor::Sample as Reading;

/// The physics whiskers of a maze run: their configurations and RCP mode.
#[derive(Debug, Clone)]
pub struct PhysicsWhiskers {
    /// Each whisker's configuration, RCP thresholds not yet calibrated.
    pub configs: Vec<WhiskerConfig>,
    /// How the contact thresholds of RCP and the whisking strategies are calibrated
    /// (None: open loop).
    pub contact: Option<RcpThreshold>,
}

/// The images of every update: (by max_angle, by contact_angle).
pub type Images = (Vec<TactileImage>, Vec<TactileImage>);

/// The pose at time `t` (s): the path interpolated between updates at 1.5 Hz.
pub fn pose_at(path: &[Sample], t: f64, g: &Geometry) -> Isometry3<f64> {
    let u = (t * UPDATE_HZ).min((path.len() - 1) as f64);
    let k = (u.floor() as usize).min(path.len().saturating_sub(2));
    let f = u - k as f64;
    let (a, b) = (path[k], path[(k + 1).min(path.len() - 1)]);
    let s = Sample {
        x: a.x + f * (b.x - a.x),
        y: a.y + f * (b.y - a.y),
        th: a.th + f * wrap(b.th - a.th),
    };
    g.pose(&s)
}

/// The front end that turns one whisk cycle's 2 kHz streams into the cycle's two tactile
/// images, the same from the simulator and from a log.
#[derive(Debug, Clone)]
pub struct ImageFrontEnd {
    /// Each whisker's detection parameters.
    pub params: Vec<FrontEndParams>,
    /// Each whisker's straight shaft (for the tip heights).
    pub rigid: Vec<RigidWhisker>,
    /// Whisk frequency (Hz).
    pub frequency: f64,
}

impl ImageFrontEnd {
    /// The front end of whiskers `configs` (RCP thresholds already calibrated) with the
    /// scenario's `detection` levels, fitted to each whisker's RCP threshold
    /// ([`Detection::levels`]).
    pub fn new(configs: &[WhiskerConfig], detection: &Detection) -> Self {
        let params = detection.levels(configs);
        Self {
            params,
            rigid: configs.iter().map(WhiskerConfig::rigid).collect(),
            frequency: configs[0].pattern.frequency,
        }
    }

    /// One whisk cycle's images (by max_angle, by contact_angle) from each whisker's
    /// samples.
    pub fn cycle(&self, streams: &[Vec<Reading>], g: &Geometry) -> (TactileImage, TactileImage) {
        let mut heights = [vec![None; self.rigid.len()], vec![None; self.rigid.len()]];
        for (w, stream) in streams.iter().enumerate() {
            let whisker = &self.rigid[w];
            let Some(e) = detect_on(whisker, stream, 1.0 / DT, &self.params[w]) else {
                continue;
            };
            for (k, angle) in [Some(e.max_angle), e.contact_angle].into_iter().enumerate() {
                heights[k][w] = angle.map(|a| g.tip_height(whisker, a));
            }
        }
        (g.image(&heights[0]), g.image(&heights[1]))
    }

    /// The images of each of `updates` updates from the images of each whisk cycle: an
    /// update uses the latest cycle completed before it (blank before the first).
    pub fn per_update(&self, by_cycle: &[(TactileImage, TactileImage)], updates: usize) -> Images {
        let mut max = Vec::with_capacity(updates);
        let mut contact = Vec::with_capacity(updates);
        for k in 0..updates {
            // Cycle c is complete at t = (c + 1)/f.
            let t = k as f64 / UPDATE_HZ;
            let done = (t * self.frequency + 1e-9).floor() as usize;
            let (a, b) = match done.checked_sub(1).and_then(|c| by_cycle.get(c)) {
                Some(&(a, b)) => (a, b),
                None => (TactileImage::default(), TactileImage::default()),
            };
            max.push(a);
            contact.push(b);
        }
        (max, contact)
    }
}

/// Samples per whisk cycle at whisk `frequency` (Hz).
pub fn per_cycle(frequency: f64) -> usize {
    (1.0 / (frequency * DT)).round() as usize
}

/// Whole whisk cycles at `frequency` (Hz) completed over a path of `updates` updates.
pub fn cycles(updates: usize, frequency: f64) -> usize {
    let duration = (updates - 1) as f64 / UPDATE_HZ;
    (duration * frequency).floor() as usize
}

/// `configs` with their contact thresholds calibrated (mode `contact`, noise from
/// `seed`), and their front end detecting as `detection` says, its free-whisking σ
/// measured on the same `seed`.
pub fn calibrated(
    mut configs: Vec<WhiskerConfig>,
    contact: Option<RcpThreshold>,
    detection: &Detection,
    seed: u64,
) -> (Vec<WhiskerConfig>, ImageFrontEnd) {
    if let Some(mode) = contact {
        calibrate_array_rcp(&mut configs, mode, seed, DT);
    }
    let front = ImageFrontEnd::new(&configs, &detection.at(seed));
    (configs, front)
}

/// Simulates the whole path with whiskers `configs` (calibrated) and hands each whisk
/// cycle's streams, in order, to `each`.
pub fn simulate<E>(
    path: &[Sample],
    environment: &[EnvironmentPiece],
    configs: Vec<WhiskerConfig>,
    seed: u64,
    g: &Geometry,
    reporter: &dyn Reporter,
    mut each: impl FnMut(usize, Vec<Vec<Reading>>) -> Result<(), E>,
) -> Result<(), E> {
    let frequency = configs[0].pattern.frequency;
    let (per_cycle, cycles) = (per_cycle(frequency), cycles(path.len(), frequency));
    let mut array = PhysicsArray::new(configs, environment, &pose_at(path, 0.0, g), seed, DT);
    let started = std::time::Instant::now();
    for c in 0..cycles {
        let poses: Vec<_> = (0..per_cycle)
            .map(|i| pose_at(path, (c * per_cycle + i + 1) as f64 * DT, g))
            .collect();
        each(c, array.run(&poses))?;
        if (c + 1) % 60 == 0 {
            // A line, not a bar: these runs take hours and are often logged to a file.
            let elapsed = started.elapsed();
            let left = elapsed.mul_f64((cycles - c - 1) as f64 / (c + 1) as f64);
            reporter.note(&format!(
                "  {} of {cycles} whisk cycles simulated ({} elapsed, about {} left)",
                c + 1,
                indicatif::HumanDuration(elapsed),
                indicatif::HumanDuration(left)
            ));
        }
    }
    Ok(())
}

/// Simulates the whole path and returns both images for every update.
pub fn images(
    path: &[Sample],
    environment: &[EnvironmentPiece],
    whiskers: &PhysicsWhiskers,
    detection: &Detection,
    seed: u64,
    g: &Geometry,
    reporter: &dyn Reporter,
) -> whisker_scenario::Result<Images> {
    let (configs, front) = calibrated(whiskers.configs.clone(), whiskers.contact, detection, seed);
    let mut by_cycle = Vec::new();
    simulate(
        path,
        environment,
        configs,
        seed,
        g,
        reporter,
        |_, streams| {
            whisker_scenario::stop::check()?;
            by_cycle.push(front.cycle(&streams, g));
            Ok::<(), whisker_scenario::Error>(())
        },
    )?;
    Ok(front.per_update(&by_cycle, path.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    use whisker_sim::sensing::noise::ContactNoise;

    /// Held still 6 cm beside the maze's tallest post, the physics whiskers light the
    /// pixels the kinematic sweep lights (the same whiskers touch; there the contacts are
    /// along the shafts — grazes by the very tip are missed by the front end, as in the
    /// radial training set), and no pixel lights before the first whisk cycle completes.
    #[test]
    fn physics_images_light_the_touching_whiskers() {
        let file = &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/maze.toml");
        let read = whisker_scenario::ScenarioFile::load(file).unwrap();
        let scenario = &read.scenario;
        let environment = read.environment().unwrap().environment;
        let g = Geometry {
            plane_z: 0.0,
            board_z: scenario.maze.as_ref().unwrap().position_m[2],
            yaw0: -std::f64::consts::FRAC_PI_2,
        };
        let at = Sample {
            x: 0.41,
            y: -0.05,
            th: 0.0,
        };
        let path = vec![at; 4];
        let configs = whisker_sim::sensing::physics::standard_array(
            18,
            whisker_sim::whisker::beam::Bending::SweepPlane,
            Some(8),
            2,
        );
        let detection = Detection::default_at(0);
        let (max, contact) = images(
            &path,
            &environment.physics_pieces(),
            &PhysicsWhiskers {
                configs,
                contact: None,
            },
            &detection,
            0,
            &g,
            &crate::record::Silent,
        )
        .unwrap();
        let target = whisker_sim::sensing::kinematic::SweepTarget::of(&environment);
        let whiskers = super::super::kinematic_whiskers();
        let kinematic: Vec<TactileImage> = super::super::kinematic_contacts(
            &path,
            &target,
            ContactNoise::NONE,
            0,
            &g,
            Default::default(),
        )
        .iter()
        .map(|c| g.contact_image(c, &whiskers))
        .collect();
        let lit =
            |img: &TactileImage| -> Vec<usize> { (0..18).filter(|&i| img.pixels[i] > 0).collect() };
        assert!(lit(&max[0]).is_empty() && lit(&contact[0]).is_empty());
        assert!(lit(&kinematic[3]).len() >= 2, "{:?}", kinematic[3]);
        assert_eq!(lit(&max[3]), lit(&kinematic[3]));
        assert!(
            lit(&contact[3])
                .iter()
                .all(|i| lit(&kinematic[3]).contains(i))
        );
    }
}
