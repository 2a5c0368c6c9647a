//! The arm as kinematic Rapier bodies: poses follow forward kinematics, velocities are
//! those of the motion between steps, and arm–environment contacts are detected.

mod common;

use nalgebra::{Isometry3, Vector3};
use rapier3d_f64::prelude::ColliderBuilder;
use std::f64::consts::FRAC_PI_2;
use whisker_sim::kinematics::Chain;
use whisker_sim::world::World;
use whisker_slam::pose;

fn model_q(chain: &Chain, n: usize, q: &[f64]) -> Vec<f64> {
    let mut all = vec![0.0; n];
    for (&j, v) in chain.joint_indices.iter().zip(q) {
        all[j] = *v;
    }
    all
}

#[test]
fn link_bodies_follow_forward_kinematics() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let n = model.joints.len();
    let q0 = [0.0, -1.57, 1.57, -1.57, -1.57, 0.0];
    let mut world = World::new(model.clone(), model_q(&chain, n, &q0), 0.01);
    let array = model.link("whisker_array").unwrap();
    let dt = 0.01;
    let handle = world
        .arm
        .bodies
        .iter()
        .find(|(l, _)| *l == array)
        .unwrap()
        .1;
    let mut prev = world.arm.link_pose(&world.physics, array).unwrap();
    let mut prev_com = world.physics.bodies[handle].center_of_mass();
    for k in 1..=50 {
        let q: Vec<f64> = q0
            .iter()
            .enumerate()
            .map(|(i, v)| v + 0.002 * k as f64 * (i as f64 - 2.5))
            .collect();
        world.step(&model_q(&chain, n, &q));
        let body = world.arm.link_pose(&world.physics, array).unwrap();
        let (dt_err, dr_err) = pose::distance(&body, &chain.fk(&q));
        assert!(
            dt_err < 1e-9 && dr_err < 1e-9,
            "step {k}: {dt_err} m {dr_err} rad"
        );
        // The body's velocities are those of the motion between the two poses.
        let b = &world.physics.bodies[handle];
        let (v, w, com) = (b.linvel(), b.angvel(), b.center_of_mass());
        let expected_v = (com - prev_com) / dt;
        let expected_w = pose::rotation_error(&prev.rotation, &body.rotation) / dt;
        assert!(
            (v - expected_v).length() < 1e-9,
            "step {k}: {v:?} vs {expected_v:?}"
        );
        let w = Vector3::new(w.x, w.y, w.z);
        assert!(
            (w - expected_w).norm() < 1e-9,
            "step {k}: {w:?} vs {expected_w:?}"
        );
        assert!(expected_w.norm() > 0.1, "the test moves the wrist");
        (prev, prev_com) = (body, com);
    }
}

#[test]
fn contacts_with_the_environment_are_detected_and_only_those() {
    let model = common::ur5_array();
    let chain = Chain::new(&model, "base_link", "whisker_array").unwrap();
    let n = model.joints.len();
    let q = [0.0, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0];
    let tip: Isometry3<f64> = chain.fk(&q);
    let mut world = World::new(model.clone(), model_q(&chain, n, &q), 0.01);
    // A 10 cm cube well clear of the arm: no contact, and adjacent links do not count.
    let away = tip.translation.vector + Vector3::new(0.0, 0.5, 0.0);
    world.add_fixed(ColliderBuilder::cuboid(0.05, 0.05, 0.05).translation(away.into()));
    world.step(&model_q(&chain, n, &q));
    assert!(
        world.arm_collisions().is_empty(),
        "{:?}",
        world.arm_collisions()
    );
    // A cube around the array's housing: the array link touches it.
    let at = tip * nalgebra::Point3::new(0.0, 0.0, -0.03);
    world.add_fixed(ColliderBuilder::cuboid(0.05, 0.05, 0.05).translation(at.coords.into()));
    world.step(&model_q(&chain, n, &q));
    let hits = world.arm_collisions();
    assert!(hits.contains(&"whisker_array".to_string()), "{hits:?}");
    assert!(!hits.contains(&"base_link".to_string()));
}

#[test]
fn collision_meshes_become_scaled_convex_hulls() {
    use whisker_sim::kinematics::{PackagePaths, RobotModel};
    let dir = tempfile::tempdir().unwrap();
    // A 100 mm cube in millimetres (ASCII OBJ), scaled to metres by the URDF.
    let mut obj = String::new();
    for i in 0..8 {
        obj += &format!(
            "v {} {} {}\n",
            100 * (i & 1),
            100 * ((i >> 1) & 1),
            100 * ((i >> 2) & 1)
        );
    }
    for q in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        obj += &format!("f {} {} {} {}\n", q[0], q[1], q[2], q[3]);
    }
    std::fs::write(dir.path().join("cube.obj"), obj).unwrap();
    std::fs::write(dir.path().join("other.dae"), "<COLLADA/>").unwrap();
    let urdf = r#"<robot name="r">
      <link name="base"/>
      <link name="block"><collision><geometry><mesh filename="cube.obj" scale="0.001 0.001 0.001"/></geometry></collision></link>
      <link name="fancy"><collision><geometry><mesh filename="other.dae"/></geometry></collision></link>
      <joint name="j" type="revolute"><parent link="base"/><child link="block"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="k" type="fixed"><parent link="base"/><child link="fancy"/></joint>
    </robot>"#;
    let path = dir.path().join("r.urdf");
    std::fs::write(&path, urdf).unwrap();
    let model = RobotModel::load(&path, &PackagePaths::new([])).unwrap();
    assert_eq!(
        whisker_sim::arm::links_without_colliders(&model),
        vec!["fancy".to_string()]
    );
    let mut world = World::new(model.clone(), vec![0.0; model.joints.len()], 0.01);
    // A ball just outside the cube's +x face (at 0.1 m): no contact; then inside: contact.
    world
        .add_fixed(ColliderBuilder::ball(0.01).translation(Vector3::new(0.115, 0.05, 0.05).into()));
    world.step(&vec![0.0; model.joints.len()]);
    assert!(
        world.arm_collisions().is_empty(),
        "{:?}",
        world.arm_collisions()
    );
    world
        .add_fixed(ColliderBuilder::ball(0.01).translation(Vector3::new(0.105, 0.05, 0.05).into()));
    world.step(&vec![0.0; model.joints.len()]);
    assert_eq!(world.arm_collisions(), vec!["block".to_string()]);
}
