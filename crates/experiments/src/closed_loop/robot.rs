//! The arm in the closed loop (thesis §2.2.1, §6.1): a goal pose of the array → IK from
//! the current joints within the joint limits → a straight joint-space move at the
//! joint-speed limit, checked for collisions of every arm link and the array's housing
//! with the environment along the way (MoveIt's job on the real robot).
//!
//! A goal the IK cannot reach, or whose move would touch the object, is refused: the arm
//! stays where it is and the caller counts the fallback.

use nalgebra::Isometry3;
use whisker_scenario::plan::Plan;
use whisker_scenario::{Error, Result};
use whisker_sim::arm::LinkShapes;
use whisker_sim::environment::Environment;
use whisker_sim::environment::solids::Solids;
use whisker_sim::kinematics::Chain;
use whisker_sim::kinematics::ik::{self, IkOptions};

/// Largest joint step (rad) between two configurations whose clearance is checked.
const CHECK_STEP_RAD: f64 = 0.02;

/// How a move ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Motion {
    /// The array is at the goal; the move took `duration` seconds.
    Reached { duration: f64 },
    /// No IK solution within the joint limits.
    Unreachable,
    /// The move would bring these links into the environment.
    Collision(Vec<String>),
}

impl Motion {
    /// The `ik_status` column of `explore.csv`.
    pub fn status(&self) -> &'static str {
        match self {
            Motion::Reached { .. } => "reached",
            Motion::Unreachable => "unreachable",
            Motion::Collision(_) => "collision",
        }
    }
}

/// The arm, where it is, and what it must not touch.
pub struct Robot {
    /// The scenario's robot model and joint-speed limits.
    pub plan: Plan,
    /// The chain from the base link to the array.
    pub chain: Chain,
    /// Current joint positions (rad).
    pub q: Vec<f64>,
    shapes: LinkShapes,
    solids: Solids,
    ik: IkOptions,
}

impl Robot {
    /// The arm of `plan` at its initial joints, clear of `environment`.
    pub fn new(plan: Plan, chain: Chain, environment: &Environment, seed: u64) -> Result<Self> {
        let solids = Solids::new(environment).map_err(|e| Error::Failure(e.to_string()))?;
        let shapes = LinkShapes::new(&plan.model);
        let q = plan.waypoints[0].clone();
        Ok(Self {
            shapes,
            solids,
            ik: IkOptions {
                seed,
                ..IkOptions::default()
            },
            q,
            chain,
            plan,
        })
    }

    /// The array's pose now (base frame = world).
    pub fn array_pose(&self) -> Isometry3<f64> {
        self.chain.fk(&self.q)
    }

    /// Links touching the environment at chain configuration `q`.
    pub fn colliding(&self, q: &[f64]) -> Vec<String> {
        self.shapes
            .colliding(&self.plan.model, &self.plan.model_joints(q), &self.solids)
    }

    /// Moves the array to `goal` if it can (see the module documentation).
    pub fn move_to(&mut self, goal: &Isometry3<f64>) -> Motion {
        let Ok(q) = ik::solve(&self.chain, goal, &self.q, &self.ik) else {
            return Motion::Unreachable;
        };
        let largest = q
            .iter()
            .zip(&self.q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let steps = (largest / CHECK_STEP_RAD).ceil().max(1.0) as usize;
        for k in 1..=steps {
            let s = k as f64 / steps as f64;
            let at: Vec<f64> = self
                .q
                .iter()
                .zip(&q)
                .map(|(a, b)| a + s * (b - a))
                .collect();
            let hits = self.colliding(&at);
            if !hits.is_empty() {
                return Motion::Collision(hits);
            }
        }
        let duration = q
            .iter()
            .zip(&self.q)
            .zip(&self.plan.speed)
            .map(|((a, b), v)| (a - b).abs() / v)
            .fold(0.0, f64::max);
        self.q = q;
        Motion::Reached { duration }
    }
}
