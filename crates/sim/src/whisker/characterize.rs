//! Characterising one whisker design: a static point load, then a free ring-down.
//!
//! The whisker is held still (its driver fixed, no gravity). A force perpendicular to
//! the shaft, in the sweep plane (+Y of the whisker frame), is applied at arc length `at`
//! with the joint damping raised so that the load settles quickly; once settled, the
//! load-point and tip deflections (in the shaft's base frame, so that they are the
//! shaft's own bending, comparable with a cantilever clamped at its base), the bending
//! moment at the base and the follicle sensor reading are taken. Then the load is
//! released, the damping restored to the design's, and the tip's Y deflection is recorded:
//! the first natural frequency comes from the mean period between upward zero crossings,
//! the damping ratio from the logarithmic decrement of successive peaks.
//!
//! Steps are chosen from the design's first-mode estimate: a twentieth of its period for
//! the static phase (implicit joint springs make statics independent of the step), and
//! 1/200 of it for the ring-down, where an implicit integrator's frequency error is about
//! (ω·dt)²/3 (0.03 %).

use super::beam::BeamDesign;
use super::body::{RootDrive, Whisker};
use super::follicle::FollicleDesign;
use super::solver::SolverPath;
use nalgebra::{Isometry3, Vector3};
use rapier3d_f64::prelude::*;
use std::f64::consts::TAU;
use whisker_slam::invalid::Invalid;

/// What a characterisation measured (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct Characterization {
    /// Deflection of the load point perpendicular to the shaft, base frame (m).
    pub load_deflection_m: f64,
    /// Deflection of the tip perpendicular to the shaft, base frame (m).
    pub tip_deflection_m: f64,
    /// Bending moment at the shaft's base (N·m).
    pub base_moment_nm: f64,
    /// Follicle sensor reading: magnet displacement along y (m).
    pub follicle_deflection_m: f64,
    /// First natural frequency from the ring-down (Hz).
    pub first_frequency_hz: f64,
    /// Damping ratio from the ring-down's logarithmic decrement.
    pub damping_ratio: f64,
    /// Integration step of the ring-down (s).
    pub dt_s: f64,
    /// Simulated steps taken to settle the static load.
    pub settle_steps: usize,
}

/// What the static phase measured (SI units); see [`Characterization`].
#[derive(Debug, Clone, PartialEq)]
pub struct StaticLoad {
    /// Deflection of the load point perpendicular to the shaft, base frame (m).
    pub load_deflection_m: f64,
    /// Deflection of the tip perpendicular to the shaft, base frame (m).
    pub tip_deflection_m: f64,
    /// Bending moment at the shaft's base (N·m).
    pub base_moment_nm: f64,
    /// Follicle sensor reading: magnet displacement along y (m).
    pub follicle_deflection_m: f64,
    /// Steps taken to settle.
    pub settle_steps: usize,
}

/// A held, gravity-free world with one whisker at the origin, stepping at `dt`.
fn test_rig(
    beam: BeamDesign,
    follicle: Option<FollicleDesign>,
    dt: f64,
) -> (PhysicsWorld, Whisker) {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    world.integration_parameters.dt = dt;
    // The multibody path physics sensing uses (patches of vendor/PATCHES.md).
    SolverPath::default().apply(&mut world.integration_parameters);
    let groups = InteractionGroups::new(Group::GROUP_3, Group::NONE, InteractionTestMode::And);
    // Welded: the rig's driver never moves, and the statics want the root held.
    let whisker = Whisker::build(
        &mut world,
        Isometry3::identity(),
        beam,
        follicle,
        groups,
        RootDrive::Welded,
    );
    (world, whisker)
}

/// Deflection (m) along the whisker frame's y of the shaft point at arc length `s`,
/// in the shaft's base frame.
fn deflection(w: &Whisker, world: &PhysicsWorld, s: f64) -> f64 {
    (w.base_pose(world).inverse() * w.point_at(world, s)).y
}

fn check(
    beam: &BeamDesign,
    follicle: &Option<FollicleDesign>,
    force: f64,
    at: f64,
) -> Result<(), Invalid> {
    beam.validate()?;
    if let Some(f) = follicle {
        f.validate()?;
    }
    if !(at.is_finite() && at > 0.0 && at <= beam.length) {
        return Err(format!(
            "the load's arc length must be in (0, {}] m, got {at}",
            beam.length
        )
        .into());
    }
    if !force.is_finite() {
        return Err(format!("the force must be a finite number, got {force}").into());
    }
    Ok(())
}

/// Holds force `force` (N, along +y) at arc length `at` on a whisker in `world`, with
/// about critical damping, until the load point moves less than 1e-7 of its deflection
/// over one first-mode period.
fn settle(
    world: &mut PhysicsWorld,
    whisker: &mut Whisker,
    force: f64,
    at: f64,
) -> Result<usize, Invalid> {
    let beam = whisker.beam;
    let dt = world.integration_parameters.dt;
    whisker.set_damping_scale(world, 1.0 / beam.damping_ratio.max(1e-3));
    let load = Vector3::new(0.0, force, 0.0);
    let window = ((TAU / beam.first_mode_estimate() / dt) as usize).max(10);
    let (mut last, mut steps) = (f64::NAN, 0);
    loop {
        for _ in 0..window {
            whisker.apply_force(world, at, load);
            world.step();
        }
        steps += window;
        let now = deflection(whisker, world, at);
        if !now.is_finite() {
            return Err("the simulation diverged (non-finite deflection)".into());
        }
        if (now - last).abs() <= 1e-7 * now.abs().max(1e-12) {
            return Ok(steps);
        }
        if steps > 1000 * window {
            return Err(format!("the static load did not settle within {steps} steps").into());
        }
        last = now;
    }
}

/// A rig holding the settled static load, and what the static phase measured. The
/// step is a twentieth of the first-mode period (≤ 0.5 ms): statics do not depend on it.
fn loaded_rig(
    beam: BeamDesign,
    follicle: Option<FollicleDesign>,
    force: f64,
    at: f64,
) -> Result<(PhysicsWorld, Whisker, StaticLoad), Invalid> {
    check(&beam, &follicle, force, at)?;
    let dt = (TAU / beam.first_mode_estimate() / 20.0).min(5e-4);
    let (mut world, mut whisker) = test_rig(beam, follicle, dt);
    let settle_steps = settle(&mut world, &mut whisker, force, at)?;
    let statics = StaticLoad {
        load_deflection_m: deflection(&whisker, &world, at),
        tip_deflection_m: deflection(&whisker, &world, beam.length),
        base_moment_nm: -whisker.base_moment(&world).x,
        follicle_deflection_m: whisker.magnet_displacement(&world).1,
        settle_steps,
    };
    Ok((world, whisker, statics))
}

/// The static phase alone: settle the load, read deflections, moment and sensor.
pub fn static_load(
    beam: BeamDesign,
    follicle: Option<FollicleDesign>,
    force: f64,
    at: f64,
) -> Result<StaticLoad, Invalid> {
    loaded_rig(beam, follicle, force, at).map(|(_, _, statics)| statics)
}

/// Steps per first-mode period in the ring-down.
const RING_DOWN_STEPS_PER_PERIOD: f64 = 200.0;
/// First-mode periods recorded in the ring-down.
const RING_DOWN_PERIODS: f64 = 12.0;
/// The lowest first mode characterised (Hz): 12 periods of a lower one at the 0.5 ms
/// step take more than 48,000 steps (a 1 m long default whisker is at 0.64 Hz; rat
/// whiskers and the thesis' artificial ones ring at tens to hundreds of Hz).
pub const MIN_FIRST_MODE_HZ: f64 = 0.5;

/// Refuses a design whose first mode (Euler–Bernoulli estimate) is below
/// [`MIN_FIRST_MODE_HZ`]: its ring-down would run for hours.
pub fn check_first_mode(beam: &BeamDesign) -> Result<(), Invalid> {
    let estimate = beam.first_mode_estimate() / TAU;
    if estimate >= MIN_FIRST_MODE_HZ {
        return Ok(());
    }
    Err(format!(
        "the design's first mode is about {estimate:.3} Hz (Euler–Bernoulli estimate): \
         expected at least {MIN_FIRST_MODE_HZ} Hz, a whisker-like design (its ring-down \
         would take {:.0} s of simulated time; shorten or stiffen it)",
        RING_DOWN_PERIODS / estimate
    )
    .into())
}

/// Runs the whole characterisation of `beam` in `follicle` (None: rigidly clamped)
/// under a static force `force` (N) at arc length `at` (m): [`static_load`], then, in
/// the same world, the ring-down from that load at 200 steps per first-mode period
/// (≤ 0.5 ms) over 12 periods.
pub fn characterize(
    beam: BeamDesign,
    follicle: Option<FollicleDesign>,
    force: f64,
    at: f64,
) -> Result<Characterization, Invalid> {
    check_first_mode(&beam)?;
    let (mut world, mut whisker, statics) = loaded_rig(beam, follicle, force, at)?;
    // Released from the settled load, now at the ring-down's finer step.
    let period = TAU / beam.first_mode_estimate();
    let dt = (period / RING_DOWN_STEPS_PER_PERIOD).min(5e-4);
    world.integration_parameters.dt = dt;
    whisker.clear_forces(&mut world);
    whisker.set_damping_scale(&mut world, 1.0);
    let n = (RING_DOWN_PERIODS * period / dt) as usize;
    let mut trace = Vec::with_capacity(n);
    for _ in 0..n {
        world.step();
        trace.push(deflection(&whisker, &world, beam.length));
    }
    let (first_frequency_hz, damping_ratio) =
        ring_down(&trace, dt).ok_or("the ring-down has too few oscillations to measure")?;
    Ok(Characterization {
        load_deflection_m: statics.load_deflection_m,
        tip_deflection_m: statics.tip_deflection_m,
        base_moment_nm: statics.base_moment_nm,
        follicle_deflection_m: statics.follicle_deflection_m,
        first_frequency_hz,
        damping_ratio,
        dt_s: dt,
        settle_steps: statics.settle_steps,
    })
}

/// Frequency (Hz) and damping ratio of a decaying oscillation sampled every `dt`:
/// mean period between upward zero crossings (linearly interpolated) and logarithmic
/// decrement between successive maxima, δ = ln(xₖ/xₖ₊₁), ζ = δ/√(4π² + δ²).
pub fn ring_down(x: &[f64], dt: f64) -> Option<(f64, f64)> {
    let crossings: Vec<f64> = x
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(i, w)| (i as f64 + w[0] / (w[0] - w[1])) * dt)
        .collect();
    if crossings.len() < 3 {
        return None;
    }
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    // Maxima between consecutive upward crossings.
    let peaks: Vec<f64> = crossings
        .windows(2)
        .map(|w| {
            let (a, b) = ((w[0] / dt) as usize, (w[1] / dt) as usize);
            x[a..=b.min(x.len() - 1)]
                .iter()
                .cloned()
                .fold(f64::MIN, f64::max)
        })
        .collect();
    let decrements: Vec<f64> = peaks
        .windows(2)
        .filter(|p| p[0] > 0.0 && p[1] > 0.0)
        .map(|p| (p[0] / p[1]).ln())
        .collect();
    if decrements.is_empty() {
        return None;
    }
    let delta = decrements.iter().sum::<f64>() / decrements.len() as f64;
    Some((1.0 / period, delta / (TAU * TAU + delta * delta).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_down_recovers_a_known_damped_oscillation() {
        let (f, zeta, dt) = (80.0, 0.03, 1e-5);
        let wn = TAU * f;
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        let x: Vec<f64> = (0..40_000)
            .map(|i| {
                let t = i as f64 * dt;
                (-zeta * wn * t).exp() * (wd * t).cos()
            })
            .collect();
        let (fm, zm) = ring_down(&x, dt).unwrap();
        assert!((fm / (wd / TAU) - 1.0).abs() < 1e-4, "{fm}");
        assert!((zm / zeta - 1.0).abs() < 1e-2, "{zm}");
    }
}
