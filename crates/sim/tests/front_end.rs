//! The signal front end on physics whiskers (thesis §4.1.2.3, Fig 4.3): the array whisks
//! against the Box; for every whisker the anticipated-intersect sweep says will touch, the
//! front end must detect a contact in the 2 kHz stream, and its onset angle is compared
//! with the sweep's contact angle (rigid straight whiskers). The thesis measured a median
//! difference of −16.7° (σ 17.6°) on its hardware; here, for the 16 whiskers that reach
//! the Box from the `whisker soak` pose, all are detected and the onset angles lie within
//! ±1.3° of the anticipated ones (median 0.2°): the simulated whiskers bend little before
//! the follicle reads.

use whisker_sim::environment::assets::{CATALOGUE, placed};
use whisker_sim::sensing::kinematic::SweepTarget;
use whisker_sim::sensing::physics::{DT, PhysicsArray, WhiskerConfig};
use whisker_sim::sensing::viewpoints;
use whisker_sim::whisker::array;
use whisker_slam::frontend::contact::{FrontEndParams, detect};

#[test]
fn physics_contacts_are_detected_at_the_anticipated_angle() {
    let asset = CATALOGUE.iter().find(|a| a.name == "box").unwrap();
    let (environment, shape) = placed(asset).unwrap();
    let (pose, touching) = viewpoints::busiest(&environment, &shape, asset.size).unwrap();
    let target = SweepTarget::new(environment.world_mesh());
    let configs: Vec<WhiskerConfig> = array::modules()
        .into_iter()
        .filter(|m| touching.contains(&m.index))
        .map(WhiskerConfig::with_defaults)
        .collect();
    let anticipated: Vec<f64> = configs
        .iter()
        .map(|c| {
            let w = c.rigid();
            target.sweep(&w, &pose).unwrap().angle
        })
        .collect();
    let mut physics =
        PhysicsArray::new(configs.clone(), &environment.physics_pieces(), &pose, 0, DT);
    let cycle = physics.whisk(0, |_| pose);
    let params = FrontEndParams::default();
    let mut errors = Vec::new();
    for (k, c) in configs.iter().enumerate() {
        let event = detect(
            &cycle.samples[k],
            cycle.rate_hz,
            c.module.beam.length,
            &params,
        );
        let event = event.unwrap_or_else(|| panic!("whisker {} not detected", c.module.pixel()));
        errors.push((event.onset_angle - anticipated[k]).to_degrees());
    }
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2];
    println!(
        "{} whiskers, onset − anticipated angle (°): {errors:?}",
        errors.len()
    );
    assert!(errors.len() >= 4);
    assert!(median.abs() < 1.5, "median {median}°");
    assert!(errors.iter().all(|e| e.abs() < 3.0), "{errors:?}");
}

/// The closed loop simulates each held whisk on a fresh array (issue #61, item 3: carry the
/// array's state between whisks, or show that a fresh one gives the same streams). Held at
/// the same pose without sensor noise, the second whisk of an array that has just whisked
/// is compared with a fresh array's first whisk, for every whisker touching the Box, RCP
/// on and off. The streams are not identical: a fresh array starts at rest, the carried
/// one in its periodic state (up to ~30 counts of free-whisking deflection at retraction),
/// and along the steep rise of a contact (~20 counts per sample) the two differ by up to
/// 186 counts open loop and 233 with RCP (2026-12-07) — a shift of a few samples. What the front end takes from them
/// is the same: the same whiskers detected, onset angles within 0.5°, peaks within 5 % of
/// the larger. Far from the object the fresh array's start from rest differs from the
/// periodic state by 31 counts at most, under a tenth of the detection's confirmation.
#[test]
fn a_whisk_after_a_whisk_gives_a_fresh_arrays_contacts() {
    let asset = CATALOGUE.iter().find(|a| a.name == "box").unwrap();
    let (environment, shape) = placed(asset).unwrap();
    let (pose, touching) = viewpoints::busiest(&environment, &shape, asset.size).unwrap();
    let far =
        nalgebra::Isometry3::from_parts(nalgebra::Translation3::new(2.0, 0.0, 0.3), pose.rotation);
    let params = FrontEndParams::default();
    for rcp in [false, true] {
        let configs: Vec<WhiskerConfig> = array::modules()
            .into_iter()
            .filter(|m| touching.contains(&m.index))
            .map(|m| {
                let mut c = WhiskerConfig::with_defaults(m);
                c.sensor.noise_counts = 0.0;
                c.sensor.angle_noise_rad = 0.0;
                c.control.rcp = rcp;
                c.contact_threshold = rcp.then_some(c.sensor.saturation_counts);
                c
            })
            .collect();
        let pieces = environment.physics_pieces();
        for (at, touches) in [(pose, true), (far, false)] {
            let fresh = PhysicsArray::new(configs.clone(), &pieces, &at, 0, DT).whisk(0, |_| at);
            let mut carried = PhysicsArray::new(configs.clone(), &pieces, &at, 0, DT);
            carried.whisk(0, |_| at);
            let second = carried.whisk(1, |_| at);
            let mut worst: f64 = 0.0;
            for (k, c) in configs.iter().enumerate() {
                let (a, b) = (&fresh.samples[k], &second.samples[k]);
                for (x, y) in a.iter().zip(b) {
                    worst = worst.max((x.y - y.y).abs()).max((x.x - y.x).abs());
                }
                let length = c.module.beam.length;
                let ea = detect(a, fresh.rate_hz, length, &params);
                let eb = detect(b, second.rate_hz, length, &params);
                assert_eq!(ea.is_some(), eb.is_some(), "{} rcp {rcp}", c.module.pixel());
                if let (Some(ea), Some(eb)) = (ea, eb) {
                    let d = (ea.onset_angle - eb.onset_angle).to_degrees();
                    assert!(d.abs() < 0.5, "{} rcp {rcp}: onset {d}°", c.module.pixel());
                    let peak = |s: &[whisker_slam::sensor::Sample]| {
                        s.iter().map(|r| r.y.abs()).fold(0.0, f64::max)
                    };
                    let (pa, pb) = (peak(a), peak(b));
                    assert!((pa - pb).abs() <= 0.05 * pa.max(pb), "{pa} vs {pb}");
                }
            }
            println!("rcp {rcp}, touching {touches}: streams differ by ≤ {worst} counts");
            if !touches {
                assert!(
                    worst < 0.1 * params.confirm_counts,
                    "free whisking: {worst} counts"
                );
            }
        }
    }
}
