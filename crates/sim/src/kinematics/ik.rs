//! Inverse kinematics of a [`Chain`] to a target pose of its tip link: damped least
//! squares (Levenberg–Marquardt) with joint limits and seeded restarts.
//!
//! This replaces MoveIt's IK in the thesis (§2.2.1). Each attempt minimises the 6-D
//! pose error e = (p* − p, log(R*·Rᵀ)) in the base frame with steps
//! Δq = (JᵀJ + λ·I)⁻¹·Jᵀe, clamped into the joint limits, accepting a step only if it
//! lowers |e| and adapting λ. The first attempt starts at the current configuration,
//! so the answer is the solution that the arm reaches from where it is (the nearest one
//! in the usual case); revolute coordinates are then moved by whole turns towards the
//! current configuration where the limits allow. Further attempts start from
//! configurations drawn from the sub-stream `"ik"` of [`IkOptions::seed`], so a result
//! is reproducible. A target no attempt reaches within tolerance is an error: the IK
//! never returns a configuration that misses its target.

use super::chain::Chain;
use nalgebra::{DMatrix, DVector, Isometry3};
use rand::RngExt;
use std::f64::consts::{PI, TAU};
use whisker_slam::{pose, rng};

/// Settings of the IK solver.
#[derive(Debug, Clone)]
pub struct IkOptions {
    /// Accepted position error (m).
    pub position_tolerance: f64,
    /// Accepted orientation error (rad).
    pub orientation_tolerance: f64,
    /// Iterations per attempt.
    pub max_iterations: usize,
    /// Attempts from random starts after the one from the current configuration.
    pub restarts: usize,
    /// Seed of the restarts' sub-stream.
    pub seed: u64,
}

impl Default for IkOptions {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-9,
            orientation_tolerance: 1e-9,
            max_iterations: 200,
            restarts: 24,
            seed: 0,
        }
    }
}

/// Why IK failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IkError {
    /// No attempt reached the target within tolerance (out of reach, or only reachable
    /// outside the joint limits).
    #[error(
        "target pose of \"{tip}\" is unreachable within the joint limits: the best of {attempts} attempts ends {position_error:.6} m and {orientation_error:.6} rad away"
    )]
    Unreachable {
        tip: String,
        attempts: usize,
        position_error: f64,
        orientation_error: f64,
    },
    /// The start configuration has the wrong length or non-finite values.
    #[error("IK start configuration must have {expected} finite values, got {got:?}")]
    BadStart { expected: usize, got: Vec<f64> },
}

/// Residual of configuration `q`: see [`residual`].
fn pose_error(chain: &Chain, q: &[f64], target: &Isometry3<f64>) -> (DVector<f64>, f64, f64) {
    residual(&chain.fk(q), target)
}

/// The 6-D error (Δp, rotation vector) from `tip` to `target`, and its two norms.
fn residual(tip: &Isometry3<f64>, target: &Isometry3<f64>) -> (DVector<f64>, f64, f64) {
    let dp = target.translation.vector - tip.translation.vector;
    let dr = pose::rotation_error(&tip.rotation, &target.rotation);
    let e = DVector::from_iterator(6, dp.iter().chain(dr.iter()).copied());
    (e, dp.norm(), dr.norm())
}

/// One Levenberg–Marquardt descent from `q`; returns the final configuration and errors.
fn descend(
    chain: &Chain,
    mut q: Vec<f64>,
    target: &Isometry3<f64>,
    opts: &IkOptions,
) -> (Vec<f64>, f64, f64) {
    let n = chain.dof();
    let mut lambda = 1e-2;
    let (tip, mut jac) = chain.fk_jacobian(&q);
    let (mut e, mut ep, mut er) = residual(&tip, target);
    for _ in 0..opts.max_iterations {
        if ep <= opts.position_tolerance && er <= opts.orientation_tolerance {
            break;
        }
        let jt = jac.transpose();
        let a = &jt * &jac + DMatrix::identity(n, n) * lambda;
        let Some(dq) = a.cholesky().map(|c| c.solve(&(&jt * &e))) else {
            lambda *= 10.0;
            continue;
        };
        let mut trial: Vec<f64> = q.iter().zip(dq.iter()).map(|(a, b)| a + b).collect();
        chain.clamp(&mut trial);
        let (te, tp, tr) = pose_error(chain, &trial, target);
        if te.norm() < e.norm() {
            q = trial;
            (e, ep, er) = (te, tp, tr);
            jac = chain.fk_jacobian(&q).1;
            lambda = (lambda / 3.0).max(1e-12);
        } else {
            lambda *= 4.0;
            if lambda > 1e8 {
                break;
            }
        }
    }
    (q, ep, er)
}

/// Moves revolute coordinates of `q` by whole turns towards `near`, within limits.
fn unwrap_towards(chain: &Chain, q: &mut [f64], near: &[f64]) {
    for i in 0..q.len() {
        if !chain.angular[i] {
            continue;
        }
        let turns = ((near[i] - q[i]) / TAU).round();
        let moved = q[i] + turns * TAU;
        if moved >= chain.lower[i] && moved <= chain.upper[i] {
            q[i] = moved;
        }
    }
}

/// A configuration of `chain` that puts its tip at `target` (in the base frame),
/// searched from `start`.
pub fn solve(
    chain: &Chain,
    target: &Isometry3<f64>,
    start: &[f64],
    opts: &IkOptions,
) -> Result<Vec<f64>, IkError> {
    if start.len() != chain.dof() || start.iter().any(|v| !v.is_finite()) {
        return Err(IkError::BadStart {
            expected: chain.dof(),
            got: start.to_vec(),
        });
    }
    let mut rng = rng::substream(opts.seed, "ik");
    let mut best = (f64::INFINITY, f64::INFINITY);
    let mut q0 = start.to_vec();
    chain.clamp(&mut q0);
    for attempt in 0..=opts.restarts {
        if attempt > 0 {
            for (i, v) in q0.iter_mut().enumerate() {
                let (lo, hi) = (chain.lower[i].max(-PI), chain.upper[i].min(PI));
                *v = if lo < hi {
                    rng.random_range(lo..hi)
                } else {
                    lo
                };
            }
        }
        let (mut q, ep, er) = descend(chain, q0.clone(), target, opts);
        if ep <= opts.position_tolerance && er <= opts.orientation_tolerance {
            unwrap_towards(chain, &mut q, start);
            return Ok(q);
        }
        if ep + er < best.0 + best.1 {
            best = (ep, er);
        }
    }
    Err(IkError::Unreachable {
        tip: chain.tip.clone(),
        attempts: opts.restarts + 1,
        position_error: best.0,
        orientation_error: best.1,
    })
}
