//! The surface placement controller (thesis §6.1.1, Alg 7) closed through kinematic
//! sensing with the §6.1.3.1.2 contact noise: from 100 random start poses near a plane
//! and 100 near a box's vertical edge it meets its three conditions within K adjustments
//! in at least 95 % of the runs, and never moves the array's housing into the surface.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::shape::Cylinder;
use rand::RngExt;
use whisker_sim::environment::shapes::cuboid;
use whisker_sim::environment::solids::Solids;
use whisker_sim::environment::{Environment, Piece};
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::whisker::array::modules;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::exploration::placement::{self, Placement, PlacementParams, UP};
use whisker_slam::rng::substream;

/// The array's housing (the URDF's collision cylinder: radius 55 mm, 60 mm long behind
/// the front face) at array pose `pose`.
fn housing(pose: &Isometry3<f64>) -> (Cylinder, Isometry3<f64>) {
    let y_to_z = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
    (
        Cylinder::new(0.03, 0.055),
        pose * Isometry3::from_parts(Translation3::new(0.0, 0.0, -0.03), y_to_z),
    )
}

fn environment(lo: Point3<f64>, hi: Point3<f64>) -> Environment {
    let mesh = cuboid(lo, hi);
    let half = (hi - lo) / 2.0;
    let centre = Translation3::from((lo.coords + hi.coords) / 2.0);
    let shifted = whisker_sim::environment::shapes::transformed(
        &mesh,
        &Isometry3::from_parts(centre.inverse(), UnitQuaternion::identity()),
    );
    Environment {
        pieces: vec![Piece {
            name: "block".into(),
            shape: parry3d_f64::shape::SharedShape::cuboid(half.x, half.y, half.z),
            mesh: shifted,
            pose: Isometry3::from_parts(centre, UnitQuaternion::identity()),
            soup: false,
        }],
    }
}

/// Runs the controller from `start`; returns whether it finished within K adjustments,
/// and asserts the housing never enters the solid.
fn settle(
    start: Isometry3<f64>,
    sensing: &mut KinematicArray,
    target: &SweepTarget,
    solids: &Solids,
    params: &PlacementParams,
    cycle: &mut u64,
) -> bool {
    let mut pose = start;
    for _ in 0..=params.max_adjustments {
        let c = sensing.sense(target, *cycle, *cycle as f64, &pose);
        *cycle += 1;
        let points: Vec<Point3<f64>> = c.contacts.iter().map(|k| pose * k.point).collect();
        let decision = placement::correct(params, &pose, &points);
        if std::env::var("SPC_DEBUG").is_ok() {
            let z = pose.rotation * Vector3::z();
            eprintln!(
                "at {:?} z {:?} n {} -> {:?}",
                pose.translation.vector.as_slice(),
                z.as_slice(),
                points.len(),
                decision
                    .pose()
                    .map(|p| (p.translation.vector, p.rotation * Vector3::z()))
            );
        }
        match decision {
            Placement::Done(_) => return true,
            Placement::Approach(next)
            | Placement::Turn(next)
            | Placement::Move(next)
            | Placement::BackOff(next) => {
                let (h, at) = housing(&next);
                assert!(
                    !solids.overlaps(&h, &at),
                    "the controller moved the housing into the solid: {next}"
                );
                pose = next;
            }
        }
    }
    false
}

fn sensing(seed: u64) -> KinematicArray {
    let whiskers: Vec<RigidWhisker> = modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, 3.0e-3))
        .collect();
    let patterns = vec![WhiskingPattern::default(); whiskers.len()];
    KinematicArray::new(whiskers, patterns, ContactNoise::default(), seed)
}

/// A unit vector within `max` radians of `axis`, uniformly in angle about it.
fn tilted(axis: &Vector3<f64>, max: f64, rng: &mut impl rand::Rng) -> Vector3<f64> {
    let perp = axis.cross(&Vector3::new(0.3, 0.5, 0.7)).normalize();
    let spin = UnitQuaternion::from_axis_angle(
        &nalgebra::Unit::new_normalize(*axis),
        rng.random_range(0.0..std::f64::consts::TAU),
    );
    let tilt = UnitQuaternion::from_axis_angle(
        &nalgebra::Unit::new_normalize(spin * perp),
        rng.random_range(0.0..max),
    );
    tilt * axis
}

/// Runs the controller from 100 start poses drawn by `draw` that leave the housing clear of
/// the block from `lo` to `hi`; returns how many settled within K adjustments.
fn settled_of_100(
    lo: Point3<f64>,
    hi: Point3<f64>,
    seed: u64,
    mut draw: impl FnMut(&mut whisker_slam::rng::StreamRng) -> Isometry3<f64>,
) -> usize {
    let env = environment(lo, hi);
    let target = SweepTarget::new(env.world_mesh());
    let solids = Solids::new(&env).unwrap();
    let params = PlacementParams::default();
    let mut rng = substream(seed, "test/spc-starts");
    let mut array = sensing(seed);
    let (mut runs, mut ok, mut cycle) = (0, 0, 0);
    while runs < 100 {
        let start = draw(&mut rng);
        let (h, at) = housing(&start);
        if solids.overlaps(&h, &at) {
            continue;
        }
        runs += 1;
        ok += usize::from(settle(
            start, &mut array, &target, &solids, &params, &mut cycle,
        ));
    }
    eprintln!("settled in {ok} of 100 runs");
    ok
}

#[test]
fn near_a_plane_the_controller_settles_within_k_adjustments() {
    // A wall whose face is the plane x = 0.3, facing −x; starts 3.5–8 cm out, tilted up to 30°.
    let ok = settled_of_100(
        Point3::new(0.3, -0.5, 0.0),
        Point3::new(0.5, 0.5, 1.0),
        1,
        |rng| {
            let on = Point3::new(0.3, rng.random_range(-0.1..0.1), rng.random_range(0.4..0.6));
            let distance = rng.random_range(0.035..0.08);
            let pointing = tilted(&Vector3::x(), 30f64.to_radians(), rng);
            placement::maintain_yaw(on.coords - pointing * distance, &pointing, &UP)
        },
    );
    assert!(ok >= 95, "settled in {ok} of 100 runs");
}

#[test]
fn near_a_box_edge_the_controller_settles_within_k_adjustments() {
    // A 20 × 20 × 35 cm box; facing its front face x = 0.4, the axis meeting it up to 5 cm
    // inside its vertical edge y = 0.1 or up to 1 cm past it: part of the whisker field
    // misses the box.
    let ok = settled_of_100(
        Point3::new(0.4, -0.1, 0.0),
        Point3::new(0.6, 0.1, 0.35),
        2,
        |rng| {
            let aim = Point3::new(
                0.4,
                rng.random_range(0.05..0.11),
                rng.random_range(0.1..0.25),
            );
            let distance = rng.random_range(0.03..0.07);
            let pointing = tilted(&Vector3::x(), 20f64.to_radians(), rng);
            placement::maintain_yaw(aim.coords - pointing * distance, &pointing, &UP)
        },
    );
    assert!(ok >= 95, "settled in {ok} of 100 runs");
}

#[test]
fn the_clearance_check_sees_a_housing_inside_and_beside_the_block() {
    let env = environment(Point3::new(0.3, -0.5, 0.0), Point3::new(0.5, 0.5, 1.0));
    let solids = Solids::new(&env).unwrap();
    let facing = |x: f64| placement::maintain_yaw(Vector3::new(x, 0.0, 0.5), &Vector3::x(), &UP);
    // Front face 1 cm short of the wall: clear; 1 cm into it: overlapping; deep inside: too.
    let (h, at) = housing(&facing(0.29));
    assert!(!solids.overlaps(&h, &at));
    let (h, at) = housing(&facing(0.31));
    assert!(solids.overlaps(&h, &at));
    let (h, at) = housing(&facing(0.45));
    assert!(solids.overlaps(&h, &at));
}
