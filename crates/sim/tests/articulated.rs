//! The articulated-body factorisation (vendor/PATCHES.md, patch 6) against the dense
//! matrices it replaces, on one bent state: the same inverses up to rounding. Each check
//! was seen to fail with a deliberate mistake in the vendored code (listed per test).

mod common;

use nalgebra::{DMatrix, DVector, Isometry3, Vector3};
use rapier3d_f64::prelude::{Multibody, MultibodyMassMatrix};
use whisker_sim::sensing::physics::{
    DT, Lever, PhysicsArray, SolverPath, WhiskerConfig, WhiskerUnit,
};
use whisker_sim::whisker::array;

/// The short, a middle and the longest whisker whisking at `frequency` by `path`, their
/// roots welded to the drivers, bent around poles at half their length when `poles`.
fn array_of(frequency: f64, path: SolverPath, poles: bool) -> PhysicsArray {
    let modules = array::modules();
    let whiskers = [0, 6, 12];
    let configs: Vec<_> = whiskers
        .iter()
        .map(|&i| {
            let mut c = WhiskerConfig::with_defaults(modules[i].clone());
            c.pattern.frequency = frequency;
            c.solver = path;
            // The older paths' model, so that free whisking compares like with like: the
            // root welded to the driver.
            c.without = Some(Lever::DrivenRoot);
            c
        })
        .collect();
    let pieces: Vec<_> = whiskers
        .iter()
        .filter(|_| poles)
        .map(|&i| {
            let m = &modules[i];
            common::pole(m, 0.5 * m.beam.length, 100f64.to_radians(), 0.2)
        })
        .collect();
    PhysicsArray::new(configs, &pieces, &Isometry3::identity(), 3, DT)
}

fn multibody(u: &WhiskerUnit) -> Multibody {
    u.world
        .multibody_joints
        .get(u.whisker.joints[0])
        .expect("a multibody")
        .0
        .clone()
}

/// The matrix `P⁻¹·L·U` factorised in `lu`.
fn factored(lu: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>) -> DMatrix<f64> {
    let mut m = lu.l() * lu.u();
    lu.p().inv_permute_rows(&mut m);
    m
}

/// Deterministic pseudo-random vectors (xorshift), entries in [-1, 1].
fn vectors(n: usize, count: usize) -> Vec<DVector<f64>> {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    (0..count)
        .map(|_| {
            DVector::from_fn(n, |_, _| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
        })
        .collect()
}

/// A constraint row's unit wrenches on every link: per link and axis, a unit force along the
/// axis and a unit torque about the next one, as `(link, axis, force, torque)`.
fn unit_wrenches(links: usize) -> impl Iterator<Item = (usize, usize, Vector3<f64>, Vector3<f64>)> {
    (0..links).flat_map(|link| {
        (0..3).map(move |axis| {
            let mut f = Vector3::zeros();
            f[axis] = 1.0;
            let mut t = Vector3::zeros();
            t[(axis + 1) % 3] = 1.0;
            (link, axis, f, t)
        })
    })
}

/// `‖x − y‖_H / ‖y‖_H` in the energy norm of the (symmetric positive definite) plain
/// matrix `h`.
fn energy_error(h: &DMatrix<f64>, x: &DVector<f64>, y: &DVector<f64>) -> f64 {
    let d = x - y;
    (d.dot(&(h * &d)) / y.dot(&(h * y))).sqrt()
}

/// Three whiskers bent around poles (0.3 s of whisking into them), then, at that one
/// state, the dense matrices (composite assembly, patch 5) and the articulated
/// factorisation built from the same multibody:
/// - `H⁻¹b` for random `b`, for the plain matrix (contacts) and the semi-implicit one with
///   the gyroscopic and Coriolis terms (free motion): energy-norm error < 1e-12, and the
///   residual `‖Hx − b‖` against the dense `H` at rounding (< 1e-12 of `‖H‖‖x‖`);
/// - `H·a` by the two passes equals the dense product;
/// - the free accelerations (`update_acceleration`, gravity, springs, damping, Coriolis):
///   energy-norm error < 1e-12;
/// - constraint rows (`fill_jacobians`: a unit force and torque on every link): the
///   response `M⁻¹Jᵀf` within 1e-12 in energy norm.
///
/// Measured: energy errors ≤ 2e-15, residuals ≤ 4e-20 of `‖H‖‖x‖`, accelerations 9e-16,
/// constraint responses 5e-15. Mutations of the vendored code tried, each failing this test
/// and the next (first failure, energy error): the implicit springs dropped from `Δ` 10,
/// the lever arm `A` negated 1.2e-2, the Coriolis block `B` dropped 6.8e-5 (semi-implicit),
/// the link's own Coriolis rows in `Ψ` dropped 3.7e-6 (semi-implicit).
#[test]
fn articulated_factorisation_inverts_the_dense_matrices() {
    let mut a = array_of(2.0, SolverPath::OncePerStep, true);
    let bent = a.run(&vec![Isometry3::identity(); 600]);
    let dt = a.units[0].world.integration_parameters.dt;
    // The largest error of each kind, printed for the record.
    let mut worst = [0.0f64; 7];
    let mut note = |k: usize, e: f64| worst[k] = worst[k].max(e);
    for (w, unit) in a.units.iter().enumerate() {
        assert!(bent[w].last().unwrap().y.abs() > 200.0, "whisker {w} bent");
        let bodies = &unit.world.bodies;
        let mut dense = multibody(unit);
        let mut articulated = multibody(unit);
        let acc_dense = dense.refresh_dynamics(dt, bodies, MultibodyMassMatrix::Composite, true);
        let acc_art =
            articulated.refresh_dynamics(dt, bodies, MultibodyMassMatrix::Articulated, true);
        assert!(articulated.is_articulated() && !dense.is_articulated());
        let n = dense.ndofs();
        assert_eq!(n, 57, "free root, follicle and 16 spherical joints");
        let h = factored(dense.inv_augmented_mass());
        let h_acc = factored(dense.acc_inv_augmented_mass());
        assert!(h_acc.iter().all(|x| x.is_finite()));

        // Each matrix: its dense form, the two solves, the articulated product, and where
        // its energy error and residual are noted.
        type Solve = fn(&Multibody, &mut DVector<f64>);
        type Product = fn(&Multibody, &DVector<f64>) -> DVector<f64>;
        let matrices: [(&str, &DMatrix<f64>, Solve, Product, usize); 2] = [
            (
                "plain",
                &h,
                |m, x| m.solve_augmented_mass_mut(x),
                |m, a| m.augmented_mass_mul(a),
                0,
            ),
            (
                "semi-implicit",
                &h_acc,
                |m, x| m.solve_acc_augmented_mass_mut(x),
                |m, a| m.acc_augmented_mass_mul(a),
                2,
            ),
        ];
        for (k, b) in vectors(n, 8).iter().enumerate() {
            for &(name, matrix, solve, product, slot) in &matrices {
                let mut x = b.clone();
                solve(&articulated, &mut x);
                let mut y = b.clone();
                solve(&dense, &mut y);
                let e = energy_error(&h, &x, &y);
                note(slot, e);
                assert!(e < 1e-12, "whisker {w} b{k}, {name}: energy error {e:e}");
                let residual = (matrix * &x - b).norm() / (matrix.norm() * x.norm());
                note(slot + 1, residual);
                assert!(
                    residual < 1e-12,
                    "whisker {w} b{k}, {name}: residual {residual:e}"
                );
                let exact = matrix * b;
                let rel = (&product(&articulated, b) - &exact).norm() / exact.norm();
                note(6, rel);
                assert!(rel < 1e-12, "whisker {w} b{k}, {name}: H·a {rel:e}");
            }
        }

        let e = energy_error(&h, &acc_art, &acc_dense);
        note(4, e);
        assert!(e < 1e-12, "whisker {w}: accelerations, energy error {e:e}");
        assert!(acc_dense.norm() > 0.0);

        for (link, axis, f, t) in unit_wrenches(dense.num_links()) {
            let (ja, ra) = articulated.constraint_response(link, f.into(), t.into());
            let (jd, rd) = dense.constraint_response(link, f.into(), t.into());
            assert_eq!(ja, jd, "the row itself is the same code");
            let e = energy_error(&h, &ra, &rd);
            note(5, e);
            assert!(e < 1e-12, "whisker {w} link {link} axis {axis}: {e:e}");
        }
    }
    println!(
        "energy error plain {:e}, semi-implicit {:e}; residual plain {:e}, semi-implicit {:e}; \
         accelerations {:e}; constraint responses {:e}; products {:e}",
        worst[0], worst[2], worst[1], worst[3], worst[4], worst[5], worst[6]
    );
}

/// Whole steps of free whisking at 10 Hz (the largest inertial terms), 0.3 s,
/// articulated against the dense path with the same integrator: every body within
/// 1e-11 m — with semi-implicit Coriolis terms against `OncePerStep`, with explicit ones
/// (the default, [`Lever::ExplicitCoriolis`]) against `ExplicitCoriolis`. In contact,
/// rounding differences grow as any perturbation does (stick-slip), so whisks into poles
/// are compared per whisk against Rapier as released, with the other fast paths, in
/// `solver_paths.rs`.
#[test]
fn articulated_free_whisking_follows_the_dense_path() {
    let poses = vec![Isometry3::identity(); 600];
    let position = |a: &PhysicsArray| -> Vec<Vector3<f64>> {
        a.units
            .iter()
            .flat_map(|u| u.world.bodies.iter().map(|(_, b)| b.position().translation))
            .map(|t| Vector3::new(t.x, t.y, t.z))
            .collect()
    };
    for (dense_path, without) in [
        (SolverPath::OncePerStep, Some(Lever::ExplicitCoriolis)),
        (SolverPath::ExplicitCoriolis, None),
    ] {
        let mut dense = array_of(10.0, dense_path, false);
        let mut articulated = array_of(10.0, SolverPath::Articulated, false);
        for u in &mut articulated.units {
            let p = &mut u.world.integration_parameters;
            SolverPath::Articulated.apply_without(p, without);
            assert_eq!(
                p.multibody_semi_implicit_coriolis,
                dense.units[0]
                    .world
                    .integration_parameters
                    .multibody_semi_implicit_coriolis
            );
        }
        dense.run(&poses);
        articulated.run(&poses);
        let mut worst: f64 = 0.0;
        for (p, q) in position(&dense).iter().zip(position(&articulated)) {
            worst = worst.max((p - q).norm());
        }
        println!("free whisking against {dense_path:?}, largest body difference: {worst:e} m");
        assert!(
            worst < 1e-11,
            "free whisking against {dense_path:?}: {worst:e} m"
        );
    }
}

/// Forward kinematics without the dense body Jacobians (patch 9), on three whiskers bent
/// around poles, at one state, against the same multibody with them:
/// - the free accelerations (the generalised forces of every link's weight, inertial,
///   gyroscopic and applied forces, summed by one pass from the tips): energy-norm error
///   < 1e-12;
/// - constraint rows `Jᵀf` (a unit force and torque on every link, one pass up the branch):
///   within 1e-12 of the dense row's norm, and their responses `M⁻¹Jᵀf` within 1e-12 in
///   energy norm;
/// - the dense Jacobian rebuilt from the own columns equals the dense one within 1e-12.
///
/// Mutations of the vendored code tried, each failing this test: the moment arm's sign
/// flipped in `to_parent`, the wrench passed to the parent left out (only a link's own
/// forces).
#[test]
fn lazy_jacobians_give_the_dense_forces_and_rows() {
    let mut a = array_of(2.0, SolverPath::Articulated, true);
    let bent = a.run(&vec![Isometry3::identity(); 600]);
    let dt = a.units[0].world.integration_parameters.dt;
    assert!(
        a.units[0]
            .world
            .integration_parameters
            .multibody_lazy_jacobians
    );
    let mut worst = [0.0f64; 3];
    for (w, unit) in a.units.iter().enumerate() {
        assert!(bent[w].last().unwrap().y.abs() > 200.0, "whisker {w} bent");
        let bodies = &unit.world.bodies;
        let at = |lazy: bool| {
            let mut m = multibody(unit);
            m.set_lazy_jacobians(lazy);
            m.forward_kinematics(bodies, false);
            assert_eq!(m.has_dense_jacobians(), !lazy);
            let acc = m.refresh_dynamics(dt, bodies, MultibodyMassMatrix::Articulated, true);
            assert_eq!(m.has_dense_jacobians(), !lazy, "kept through the dynamics");
            (m, acc)
        };
        let (dense, acc_dense) = at(false);
        let (lazy, acc_lazy) = at(true);
        let mut reference = multibody(unit);
        reference.set_lazy_jacobians(false);
        reference.forward_kinematics(bodies, false);
        reference.refresh_dynamics(dt, bodies, MultibodyMassMatrix::Composite, true);
        let h = factored(reference.inv_augmented_mass());

        let e = energy_error(&h, &acc_lazy, &acc_dense);
        worst[0] = worst[0].max(e);
        assert!(e < 1e-12, "whisker {w}: accelerations, energy error {e:e}");
        assert!(acc_dense.norm() > 0.0);

        for (link, axis, f, t) in unit_wrenches(dense.num_links()) {
            let (jl, rl) = lazy.constraint_response(link, f.into(), t.into());
            let (jd, rd) = dense.constraint_response(link, f.into(), t.into());
            let e = (&jl - &jd).norm() / jd.norm();
            worst[1] = worst[1].max(e);
            assert!(e < 1e-12, "whisker {w} link {link} axis {axis}: row {e:e}");
            let e = energy_error(&h, &rl, &rd);
            worst[2] = worst[2].max(e);
            assert!(
                e < 1e-12,
                "whisker {w} link {link} axis {axis}: response {e:e}"
            );
        }
    }
    println!(
        "lazy Jacobians: accelerations {:e}, rows {:e}, responses {:e}",
        worst[0], worst[1], worst[2]
    );
}

/// Whole steps of free whisking at 10 Hz, 0.3 s, with and without the dense body
/// Jacobians (patch 9): every body within 1e-11 m.
#[test]
fn lazy_jacobians_follow_the_dense_path_in_free_whisking() {
    let poses = vec![Isometry3::identity(); 600];
    let mut lazy = array_of(10.0, SolverPath::Articulated, false);
    let mut dense = array_of(10.0, SolverPath::Articulated, false);
    for u in &mut dense.units {
        SolverPath::Articulated.apply_without(
            &mut u.world.integration_parameters,
            Some(Lever::LazyJacobians),
        );
        assert!(!u.world.integration_parameters.multibody_lazy_jacobians);
    }
    lazy.run(&poses);
    dense.run(&poses);
    let mut worst: f64 = 0.0;
    for (l, d) in lazy.units.iter().zip(&dense.units) {
        assert!(!multibody(l).has_dense_jacobians(), "the lazy path ran");
        assert!(multibody(d).has_dense_jacobians());
        for ((_, p), (_, q)) in l.world.bodies.iter().zip(d.world.bodies.iter()) {
            let diff = p.position().translation - q.position().translation;
            worst = worst.max(diff.length());
        }
    }
    println!("free whisking, lazy against dense Jacobians: {worst:e} m");
    assert!(worst < 1e-11, "free whisking: {worst:e} m");
}
