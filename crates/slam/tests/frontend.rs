//! The signal front end on synthetic whisks with known contact onset (thesis §5.1.1.1.1,
//! Fig 4.5): clean, noisy, slip-off and moving-array contacts, and whisks without
//! contact; surface slope from synthetic x/y deflections (§5.1.1.1.3).
//!
//! A synthetic contact is a whisker meeting a surface at contact angle θc while it
//! protracts (θ(t) = 90° − 50°·cos 2πt, 1 Hz): the follicle reads k·(θ − θc) for as long
//! as θ > θc, saturated at ±2047 counts, split between y and x by the surface normal,
//! with Gaussian noise of 2 counts (the sensor's) or 10 ("noisy"). Rates measured
//! (`cargo test --release -p whisker-slam --test frontend -- --nocapture`): onsets within
//! 0.5 ms (clean, slip-off, moving array) and 1.5 ms (noisy); 0, 0, 9 and 10 of 200
//! contacts missed; no false contact in 200 free whisks of each kind.

use rand::RngExt;
use rand_distr::{Distribution, Normal};
use whisker_slam::frontend::contact::{FrontEndParams, detect};
use whisker_slam::rng::{StreamRng, substream};
use whisker_slam::sensor::Sample;

const RATE: f64 = 2000.0;

fn angle(t: f64) -> f64 {
    (90.0 - 50.0 * (std::f64::consts::TAU * t).cos()).to_radians()
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Clean,
    Noisy,
    SlipOff,
    Moving,
}

/// One whisk of 2000 samples and the true onset time (s); `contact` false: free whisking.
fn whisk(kind: Kind, contact: bool, rng: &mut StreamRng) -> (Vec<Sample>, f64) {
    let sigma = if kind == Kind::Noisy { 10.0 } else { 2.0 };
    let noise = Normal::new(0.0, sigma).unwrap();
    let theta_c = rng.random_range(55f64..110.0).to_radians();
    let k = rng.random_range(1500.0..4000.0); // counts per rad past contact
    let drift = if kind == Kind::Moving {
        rng.random_range(20f64..60.0).to_radians()
    } else {
        0.0
    };
    let slip = rng.random_range(0.06..0.15);
    let onset = (0..2000)
        .map(|i| i as f64 / RATE)
        .find(|&t| angle(t) >= theta_c + drift * t.max(0.0))
        .unwrap_or(1.0);
    let samples = (0..2000)
        .map(|i| {
            let t = i as f64 / RATE;
            let mut s = if contact {
                (k * (angle(t) - theta_c - drift * t)).max(0.0)
            } else {
                0.0
            };
            if kind == Kind::SlipOff && contact && t > onset + slip {
                // The tip slips off: the deflection collapses and rings at 25 Hz.
                let u = t - onset - slip;
                s *= (-u / 0.002).exp();
                s += 60.0 * (-u / 0.03).exp() * (std::f64::consts::TAU * 25.0 * u).sin();
            }
            let y = (s + noise.sample(rng)).round().clamp(-2047.0, 2047.0);
            Sample {
                angle_rad: angle(t),
                x: noise.sample(rng).round(),
                y,
            }
        })
        .collect();
    (samples, onset)
}

/// Runs `n` contact whisks and `n` free whisks of a kind; returns (largest onset error
/// in s over the detected contacts, missed, false detections).
fn trial(kind: Kind, name: &str, n: usize) -> (f64, usize, usize) {
    let mut rng = substream(11, &format!("test/frontend/{name}"));
    let params = FrontEndParams::default();
    let (mut worst, mut missed, mut false_hits) = (0.0f64, 0, 0);
    for _ in 0..n {
        let (samples, onset) = whisk(kind, true, &mut rng);
        match detect(&samples, RATE, 0.1, &params) {
            Some(c) => worst = worst.max((c.onset as f64 / RATE - onset).abs()),
            None => missed += 1,
        }
        let (free, _) = whisk(kind, false, &mut rng);
        false_hits += usize::from(detect(&free, RATE, 0.1, &params).is_some());
    }
    println!(
        "{name}: {n} contacts, {missed} missed, {false_hits} false in {n} free whisks, worst onset error {:.2} ms",
        worst * 1e3
    );
    (worst, missed, false_hits)
}

#[test]
fn onsets_are_found_within_2_ms() {
    for (kind, name) in [
        (Kind::Clean, "clean"),
        (Kind::Noisy, "noisy"),
        (Kind::SlipOff, "slip-off"),
        (Kind::Moving, "moving array"),
    ] {
        let (worst, missed, false_hits) = trial(kind, name, 200);
        assert!(worst <= 0.002, "{name}: onset off by {} ms", worst * 1e3);
        assert_eq!(false_hits, 0, "{name}");
        // Misses are slips and retreats too short or too small for findpeaks' minimum
        // width (100 samples) and prominence (500 counts).
        assert!(missed <= 15, "{name}: {missed} of 200 missed");
    }
}

#[test]
fn slope_is_the_surface_normals_n_y_over_n_x() {
    // The surface pushes the shaft along its normal's (n_x, n_y) in the whisker frame, so
    // x and y grow in that ratio: the gradient of y against x is n_y / n_x (Eq 6.14).
    for (nx, ny) in [(0.5, 0.8), (-0.3, 0.9), (0.8, 0.6)] {
        for sigma in [0.0f64, 2.0] {
            let mut rng = substream(12, "test/frontend/slope");
            let noise = Normal::new(0.0, sigma.max(1e-300)).unwrap();
            let samples: Vec<Sample> = (0..2000)
                .map(|i| {
                    let t = i as f64 / RATE;
                    let s = (3000.0 * (angle(t) - 70f64.to_radians())).clamp(0.0, 2000.0);
                    let n = |rng: &mut StreamRng| if sigma > 0.0 { noise.sample(rng) } else { 0.0 };
                    Sample {
                        angle_rad: angle(t),
                        x: nx * s + n(&mut rng),
                        y: ny * s + n(&mut rng),
                    }
                })
                .collect();
            let c = detect(&samples, RATE, 0.1, &FrontEndParams::default()).unwrap();
            let want = ny / nx;
            let tolerance = if sigma == 0.0 {
                1e-9
            } else {
                0.02 * want.abs()
            };
            assert!((c.slope - want).abs() <= tolerance, "{} vs {want}", c.slope);
        }
    }
}

#[test]
fn contact_angle_lies_within_the_contact_despite_an_earlier_swing() {
    // A clean contact at θc = 100° (2500 counts/rad) after a fast swing of free whisking
    // early in the cycle (a 400-count half sine over 0.12 s, |dy/dt| up to ~10,000
    // counts/s, smaller than the contact's peak): `contact_angle` is where |dy/dt| first
    // exceeds 5000 counts/s within the contact — after the onset angle, before the peak —
    // not in the swing.
    let theta_c = 100f64.to_radians();
    let samples: Vec<Sample> = (0..2000)
        .map(|i| {
            let t = i as f64 / RATE;
            let swing = if (0.05..0.17).contains(&t) {
                400.0 * (std::f64::consts::PI * (t - 0.05) / 0.12).sin()
            } else {
                0.0
            };
            let contact = (2500.0 * (angle(t) - theta_c)).max(0.0);
            Sample {
                angle_rad: angle(t),
                x: 0.0,
                y: (swing + contact).min(2047.0),
            }
        })
        .collect();
    let c = detect(&samples, RATE, 0.1, &FrontEndParams::default()).expect("the contact");
    let got = c
        .contact_angle
        .expect("|dy/dt| crosses 5000 counts/s")
        .to_degrees();
    assert!(
        got >= c.onset_angle.to_degrees() - 3.0 && got <= angle(c.peak as f64 / RATE).to_degrees(),
        "contact_angle {got}° outside the contact (onset {}°)",
        c.onset_angle.to_degrees()
    );
    assert!((got - 100.0).abs() < 5.0, "contact_angle {got}°");
}
