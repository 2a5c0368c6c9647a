//! Forward kinematics against the published UR5 poses, Jacobians against finite
//! differences, chain algebra, and the IK round trip.

mod common;

use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use rand::RngExt;
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;
use whisker_sim::kinematics::ik::{self, IkError, IkOptions};
use whisker_sim::kinematics::{Chain, PackagePaths, RobotModel};
use whisker_slam::{pose, rng};

/// Published tool0 poses of the UR5 in base_link (ROS UR5 model).
const UR5_CASES: [([f64; 6], [f64; 3]); 3] = [
    ([0.0; 6], [0.817250, 0.191450, -0.005491]),
    (
        [0.0, -FRAC_PI_2, 0.0, -FRAC_PI_2, 0.0, 0.0],
        [0.0, 0.191450, 1.001059],
    ),
    (
        [0.1, -0.5, 0.8, -1.2, 1.5, 0.3],
        [0.857037, 0.201539, 0.182468],
    ),
];

#[test]
fn tool0_poses_match_the_published_ur5_values_in_both_descriptions() {
    for model in [common::ur5_array(), common::ur5_ros_style()] {
        let chain = Chain::new(&model, "base_link", "tool0").unwrap();
        assert_eq!(chain.dof(), 6);
        for (q, p) in UR5_CASES {
            let t = chain.fk(&q).translation.vector;
            assert!(
                (t - Vector3::from(p)).norm() < 1e-6,
                "{}: q {q:?} gives {t:?}, expected {p:?}",
                model.name
            );
        }
        let r = chain.fk(&[0.0; 6]).rotation.to_rotation_matrix();
        let expected = Matrix3::new(-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0);
        assert!(
            (r.matrix() - expected).norm() < 1e-6,
            "{}: rotation {r:?}",
            model.name
        );
    }
}

/// The REP-103 `base` frame is base_link turned by π about z: x and y flip sign.
#[test]
fn chains_may_start_at_a_sibling_frame() {
    let model = common::ur5_ros_style();
    let chain = Chain::new(&model, "base", "tool0").unwrap();
    let t = chain.fk(&[0.0; 6]).translation.vector;
    assert!(
        (t - Vector3::new(-0.817250, -0.191450, -0.005491)).norm() < 1e-6,
        "{t:?}"
    );
}

#[test]
fn the_reversed_chain_gives_the_inverse_pose() {
    let model = common::ur5_array();
    let fwd = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let back = Chain::new(&model, "whisker_array", "base_link").unwrap();
    let mut r = rng::substream(11, "test/reverse");
    for _ in 0..50 {
        let q: Vec<f64> = (0..6).map(|_| r.random_range(-PI..PI)).collect();
        // The reversed chain lists the joints tip first.
        let q_back: Vec<f64> = q.iter().rev().copied().collect();
        assert_eq!(back.joint_names.first(), fwd.joint_names.last());
        let product = fwd.fk(&q) * back.fk(&q_back);
        let (dt, dr) = pose::distance(&product, &Isometry3::identity());
        assert!(dt < 1e-12 && dr < 1e-12, "{dt} {dr}");
    }
}

#[test]
fn model_link_poses_agree_with_chain_fk_and_the_array_mount_offset() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "tool0").unwrap();
    let q = [0.3, -1.1, 1.4, -0.7, 0.9, -2.0];
    let mut all = vec![0.0; model.joints.len()];
    for (&j, v) in chain.joint_indices.iter().zip(q) {
        all[j] = v;
    }
    let poses = model.link_poses(&all);
    let tool0 = poses[model.link("tool0").unwrap()];
    let (dt, dr) = pose::distance(&tool0, &chain.fk(&q));
    assert!(dt < 1e-12 && dr < 1e-12);
    // The documented mount: whisker_array is 60 mm along tool0's z axis, same axes.
    let array = poses[model.link("whisker_array").unwrap()];
    let offset = tool0.inverse() * array;
    assert!((offset.translation.vector - Vector3::new(0.0, 0.0, 0.060)).norm() < 1e-12);
    assert!(offset.rotation.angle() < 1e-12);
}

/// Joint origins: the shoulder stands d1 = 89.159 mm above the base whatever the joints
/// (UR5 DH), joint k's origin moves with the joints before it only (each turns about an
/// axis through its own origin), and the reach from the last origin to tool0 is d6's.
#[test]
fn joint_origins_depend_only_on_the_joints_before_them() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "tool0").unwrap();
    let q = [0.3, -1.1, 1.4, -0.7, 0.9, -2.0];
    let origins = chain.joint_origins(&q);
    assert_eq!(origins.len(), 6);
    assert!((Vector3::from(origins[0]) - Vector3::new(0.0, 0.0, 0.089159)).norm() < 1e-9);
    for k in 0..6 {
        let mut moved = q;
        for v in &mut moved[k..] {
            *v += 0.7;
        }
        let (a, b) = (origins[k], chain.joint_origins(&moved)[k]);
        assert!(
            (Vector3::from(a) - Vector3::from(b)).norm() < 1e-12,
            "joint {k}"
        );
    }
    let tip = chain.fk(&q).translation.vector;
    assert!(((tip - Vector3::from(origins[5])).norm() - 0.0823).abs() < 1e-9);
}

/// Geometric Jacobian columns equal central finite differences of the pose.
#[test]
fn jacobian_matches_finite_differences() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let back = Chain::new(&model, "whisker_array", "shoulder_link").unwrap();
    let mut r = rng::substream(5, "test/jacobian");
    for c in [&chain, &back] {
        for _ in 0..20 {
            let q: Vec<f64> = (0..c.dof()).map(|_| r.random_range(-PI..PI)).collect();
            let (_, jac) = c.fk_jacobian(&q);
            let h = 1e-6;
            for i in 0..c.dof() {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[i] += h;
                qm[i] -= h;
                let (tp, tm) = (c.fk(&qp), c.fk(&qm));
                let lin = (tp.translation.vector - tm.translation.vector) / (2.0 * h);
                let ang = pose::rotation_error(&tm.rotation, &tp.rotation) / (2.0 * h);
                let col = jac.column(i);
                assert!(
                    (col.fixed_rows::<3>(0) - lin).norm() < 1e-7,
                    "linear column {i}"
                );
                assert!(
                    (col.fixed_rows::<3>(3) - ang).norm() < 1e-7,
                    "angular column {i}"
                );
            }
        }
    }
}

const SLIDER: &str = r#"<robot name="slider">
  <link name="rail"/>
  <link name="carriage"/>
  <link name="arm"/>
  <link name="tip"/>
  <joint name="slide" type="prismatic">
    <parent link="rail"/><child link="carriage"/>
    <axis xyz="2 0 0"/><limit lower="-1" upper="1" effort="1" velocity="0.5"/>
  </joint>
  <joint name="turn" type="continuous">
    <parent link="carriage"/><child link="arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="end" type="fixed">
    <parent link="arm"/><child link="tip"/><origin xyz="0.5 0 0"/>
  </joint>
</robot>"#;

/// A prismatic then a continuous joint: the tip is at (s + 0.5 cos θ, 0.5 sin θ, 0.1),
/// and the (unnormalised) URDF axis is taken as a direction.
#[test]
fn prismatic_and_continuous_joints_follow_the_analytic_formula() {
    let model = RobotModel::parse(
        SLIDER,
        Path::new("slider.urdf"),
        Path::new("."),
        &PackagePaths::default(),
    )
    .unwrap();
    let chain = Chain::new(&model, "rail", "tip").unwrap();
    assert_eq!(chain.angular, vec![false, true]);
    assert_eq!(
        (chain.lower[1], chain.upper[1]),
        (f64::NEG_INFINITY, f64::INFINITY)
    );
    for (s, th) in [(0.0, 0.0), (0.3, 1.0), (-0.7, -2.5), (1.0, 7.0)] {
        let t = chain.fk(&[s, th]).translation.vector;
        let expected = Vector3::new(s + 0.5 * th.cos(), 0.5 * th.sin(), 0.1);
        assert!((t - expected).norm() < 1e-12, "{t:?} vs {expected:?}");
    }
}

/// 1000 random configurations within limits -> FK -> IK from another random
/// configuration -> FK: the pose is recovered to 1e-6 m and 1e-6 rad in ≥ 99 % of cases,
/// and the solution respects the joint limits.
#[test]
fn ik_round_trip_recovers_poses() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let mut r = rng::substream(2026, "test/ik-round-trip");
    let draw = |r: &mut rng::StreamRng| -> Vec<f64> {
        (0..6)
            .map(|i| r.random_range(chain.lower[i]..chain.upper[i]))
            .collect()
    };
    let options = IkOptions::default();
    let (mut ok, n) = (0, 1000);
    for _ in 0..n {
        let (q, start) = (draw(&mut r), draw(&mut r));
        let target = chain.fk(&q);
        match ik::solve(&chain, &target, &start, &options) {
            Ok(sol) => {
                assert!(
                    chain.within_limits(&sol, 1e-12),
                    "solution outside limits: {sol:?}"
                );
                let (dt, dr) = pose::distance(&chain.fk(&sol), &target);
                assert!(
                    dt < 1e-6 && dr < 1e-6,
                    "IK claimed success with error {dt} m, {dr} rad"
                );
                ok += 1;
            }
            Err(e) => assert!(matches!(e, IkError::Unreachable { .. })),
        }
    }
    eprintln!("IK round trip: {ok}/{n} recovered");
    assert!(ok as f64 >= 0.99 * n as f64, "only {ok}/{n} recovered");
}

#[test]
fn ik_starting_at_the_answer_stays_there() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let q = vec![0.2, -1.3, 1.6, -1.9, -1.5, 0.4];
    let sol = ik::solve(&chain, &chain.fk(&q), &q, &IkOptions::default()).unwrap();
    for (a, b) in sol.iter().zip(&q) {
        assert!((a - b).abs() < 1e-9, "{sol:?}");
    }
}

#[test]
fn unreachable_targets_are_errors() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let start = [0.0, -1.5, 1.5, -1.5, -1.5, 0.0];
    let far = pose::from_xyz_rpy([2.0, 0.0, 0.3], [PI, 0.0, 0.0]);
    match ik::solve(&chain, &far, &start, &IkOptions::default()) {
        Err(IkError::Unreachable { position_error, .. }) => {
            // The UR5 reaches about 0.85 m (+ wrist and mount): the best miss is over 1 m.
            assert!(position_error > 0.9, "{position_error}");
        }
        other => panic!("expected Unreachable, got {other:?}"),
    }
    let rotated = Isometry3::from_parts(far.translation, UnitQuaternion::identity());
    assert!(ik::solve(&chain, &rotated, &start, &IkOptions::default()).is_err());
    assert!(matches!(
        ik::solve(&chain, &far, &[0.0; 5], &IkOptions::default()),
        Err(IkError::BadStart { .. })
    ));
    assert!(matches!(
        ik::solve(&chain, &far, &[f64::NAN; 6], &IkOptions::default()),
        Err(IkError::BadStart { .. })
    ));
}
