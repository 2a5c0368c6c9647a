//! Physics whiskers against catalogue meshes: the shaft's centre line never goes more
//! than 1 mm (about its base radius) inside a solid and nothing turns non-finite, at the
//! concave creases of the Barrel's hoops and around the Mug's handle. A short version of
//! `whisker soak`, which runs every object and the maze for 60 s (default substeps).

use nalgebra::{Isometry3, Vector3};
use whisker_sim::environment::assets::{CATALOGUE, placed};
use whisker_sim::environment::solids::Solids;
use whisker_sim::sensing::kinematic::{RigidWhisker, SweepTarget};
use whisker_sim::sensing::physics::{DT, PhysicsArray, WhiskerConfig};
use whisker_sim::sensing::viewpoints;
use whisker_sim::whisker::array;

/// Whisks (1 Hz) the whiskers that reach the object (by the kinematic sweep, not already
/// touching when retracted) for `seconds` with the array at `pose` (None: the pose of
/// `whisker soak`); returns the deepest centre-line depth, whether anything broke, and
/// how many whiskers were simulated.
fn whisk_against(name: &str, pose: Option<Isometry3<f64>>, seconds: f64) -> (f64, bool, usize) {
    let asset = CATALOGUE.iter().find(|a| a.name == name).unwrap();
    let (environment, shape) = placed(asset).unwrap();
    let solids = Solids::new(&environment).unwrap();
    let pose = pose.unwrap_or_else(|| {
        viewpoints::busiest(&environment, &shape, asset.size)
            .unwrap()
            .0
    });
    let target = SweepTarget::new(environment.world_mesh());
    let configs: Vec<WhiskerConfig> = array::modules()
        .into_iter()
        .filter(|m| {
            target
                .sweep(&RigidWhisker::new(m.clone(), 3.0e-3), &pose)
                .is_some_and(|h| h.step >= 3)
        })
        .map(WhiskerConfig::with_defaults)
        .collect();
    let n = configs.len();
    let mut array = PhysicsArray::new(configs, &[(shape, Isometry3::identity())], &pose, 0, DT);
    let mut deepest: f64 = 0.0;
    let mut broken = false;
    for k in 1..=(seconds / DT) as usize {
        array.step(&pose);
        if k % 10 == 0 {
            for u in &array.units {
                deepest = deepest.max(u.shaft_depth(&solids));
                broken |= u.is_broken();
            }
        }
    }
    (deepest, broken, n)
}

/// The array facing −x, its face at x, at height z.
fn facing_minus_x(x: f64, z: f64) -> Isometry3<f64> {
    Isometry3::new(
        Vector3::new(x, 0.0, z),
        Vector3::y() * -std::f64::consts::FRAC_PI_2,
    )
}

#[test]
fn whiskers_stay_outside_the_barrel_hoops_and_the_mug_handle() {
    // Barrel, at the pose `whisker soak` uses: with Rapier's default correction speed a
    // 60 mm whisker's tip (D1) wedges over 1 mm into the crease above a hoop within the
    // first whisk; with one substep per step C2's tip goes through after 1.6 s.
    let (depth, broken, n) = whisk_against("barrel", None, 2.0);
    assert!(n >= 4, "only {n} whiskers reach the barrel");
    assert!(!broken);
    assert!(depth <= 1.0e-3, "barrel: centre line {depth} m inside");
    // Mug: its handle spans x ≈ 0.045–0.13 m in the plane y = 0 (the body is centred at
    // x = −0.04 m); the array's face level with the handle's outermost point, rolled 30°
    // so that the sweep planes of two 60 mm whiskers (C1, F1) cut the handle.
    let rolled =
        facing_minus_x(0.13, 0.12) * Isometry3::rotation(Vector3::z() * 30f64.to_radians());
    let (depth, broken, n) = whisk_against("mug", Some(rolled), 2.0);
    assert!(n >= 1, "no whisker reaches the mug");
    assert!(!broken);
    assert!(depth <= 1.0e-3, "mug: centre line {depth} m inside");
}
