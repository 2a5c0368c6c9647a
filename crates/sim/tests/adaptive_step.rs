//! Speed-adaptive steps (`whisker_sim::sensing::adaptive_step`): a whisker tip flying at
//! ~10 m/s into a 1 mm plate goes through it with one world step per sample and is
//! stopped with adaptive steps; far from every surface the adaptive stepping is the
//! fixed stepping bit for bit.

use nalgebra::{Isometry3, Point3, Translation3};
use rapier3d_f64::prelude::SharedShape;
use whisker_sim::sensing::physics::{EnvironmentPiece, WhiskerConfig, WhiskerUnit};
use whisker_sim::whisker::array::{self, Module};
use whisker_slam::sensor::Sample;

const DT: f64 = 5e-4;
/// The plate's whisk angle and half thickness (m).
const PLATE_ANGLE_DEG: f64 = 100.0;
const PLATE_HALF: f64 = 0.0005;

fn config(module: Module, frequency: f64, adaptive_steps: bool) -> WhiskerConfig {
    let mut c = WhiskerConfig::with_defaults(module);
    c.pattern.frequency = frequency;
    c.adaptive_steps = adaptive_steps;
    c
}

/// A 1 mm plate in the whisker's path: the plane through the shaft at the plate's whisk
/// angle, from `inner` × the whisker's length out to twice it, 10 cm wide across the
/// sweep plane, `offset` (m) further along the sweep.
fn plate(module: &Module, inner: f64, offset: f64) -> EnvironmentPiece {
    let length = module.beam.length;
    let f = module.whisker_pose(PLATE_ANGLE_DEG.to_radians());
    let half_radial = (2.0 - inner) * length / 2.0;
    let centre = f * Point3::new(0.0, offset, inner * length + half_radial);
    let pose = Isometry3::from_parts(Translation3::from(centre.coords), f.rotation);
    (SharedShape::cuboid(0.05, PLATE_HALF, half_radial), pose)
}

/// Samples of 0.5 s of whisking at `frequency`, and how many of them had a shaft point
/// beyond the plate (past its far face, within its radial span).
fn whisk(
    module: &Module,
    environment: &[EnvironmentPiece],
    frequency: f64,
    adaptive: bool,
) -> (Vec<Sample>, usize) {
    let mut unit = WhiskerUnit::new(
        config(module.clone(), frequency, adaptive),
        environment,
        &Isometry3::identity(),
        3,
        DT,
    );
    let inverse = module.pose.inverse();
    let length = module.beam.length;
    let far_face = |p: Point3<f64>| {
        let local = inverse * p;
        let r = local.coords.norm();
        // Angle from the plate's radial line towards protraction (the shaft at whisk
        // angle θ lies at atan2(y, z) = θ − 90° in the module frame).
        let angle = local.y.atan2(local.z) - (PLATE_ANGLE_DEG - 90.0).to_radians();
        r > 0.4 * length && r * angle.sin() > PLATE_HALF + 1e-3
    };
    let mut samples = Vec::new();
    let mut past = 0;
    for _ in 0..(0.5 / DT) as usize {
        samples.push(unit.step(&Isometry3::identity()));
        let beam = unit.whisker.beam;
        let through = (0..=50)
            .map(|i| {
                unit.whisker
                    .point_at(&unit.world, beam.length * i as f64 / 50.0)
            })
            .any(far_face);
        past += usize::from(through);
    }
    (samples, past)
}

#[test]
fn a_fast_tip_goes_through_a_thin_plate_with_fixed_steps_and_not_with_adaptive_ones() {
    // The 100 mm whisker at 20 Hz: its tip sweeps at ~11 m/s, 5 mm a sample.
    let module = array::modules()[6].clone();
    let wall = [plate(&module, 0.3, 0.0)];
    let (_, fixed) = whisk(&module, &wall, 20.0, false);
    assert!(
        fixed > 0,
        "with one world step per sample the tip should pass the plate (the set-up no \
         longer provokes tunnelling)"
    );
    let (samples, adaptive) = whisk(&module, &wall, 20.0, true);
    assert_eq!(
        adaptive, 0,
        "{adaptive} samples with the shaft through the plate"
    );
    assert!(samples.iter().all(|s| s.x.is_finite() && s.y.is_finite()));
    assert!(
        samples.iter().any(|s| s.y.abs() > 100.0),
        "the whisker should press on the plate"
    );
}

#[test]
fn far_from_every_surface_adaptive_steps_are_the_fixed_steps_bit_for_bit() {
    let module = array::modules()[6].clone();
    // Nothing at all, and a plate 10 cm beyond the whisker's reach, at 10 Hz.
    let away = [plate(&module, 0.3, 0.3)];
    for environment in [&[][..], &away[..]] {
        let (a, _) = whisk(&module, environment, 10.0, true);
        let (b, _) = whisk(&module, environment, 10.0, false);
        assert_eq!(a, b);
    }
}
