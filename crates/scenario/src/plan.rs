//! Turning a scenario into a concrete arm motion: the robot model, the chain from the
//! base link to the tip link, and a joint trajectory through the waypoints (tip poses
//! solved by IK from the previous waypoint's configuration, §2.2.1).

use crate::error::{Error, Result};
use crate::experiment::Experiment;
use crate::file::ScenarioFile;
use crate::scenario::Target;
use std::fmt::Write as _;
use std::path::Path;
use whisker_sim::kinematics::ik::{self, IkOptions};
use whisker_sim::kinematics::{Chain, JointTrajectory, PackagePaths, RobotModel};
use whisker_slam::pose;

/// A scenario's arm motion, ready to simulate.
#[derive(Clone)]
pub struct Plan {
    /// The robot model.
    pub model: RobotModel,
    /// The chain from `arm.base_link` to `arm.tip_link`.
    pub chain: Chain,
    /// Chain configuration at each waypoint, the initial one first (rad, m).
    pub waypoints: Vec<Vec<f64>>,
    /// Per-joint speed limits used (rad/s, m/s).
    pub speed: Vec<f64>,
    /// The joint trajectory.
    pub trajectory: JointTrajectory,
}

/// Converts joint values as written in a scenario (deg, m) to chain units (rad, m).
fn chain_units(chain: &Chain, values: &[f64]) -> Vec<f64> {
    values
        .iter()
        .zip(&chain.angular)
        .map(|(v, &angular)| if angular { v.to_radians() } else { *v })
        .collect()
}

/// Checks a configuration against the chain: count and limits.
fn check_joints(file: &Path, field: &str, chain: &Chain, q: &[f64]) -> Result {
    if q.len() != chain.dof() {
        return Err(Error::field(
            file,
            field,
            format!(
                "expected {} values (one per joint of the chain {} -> {}: {}), got {}",
                chain.dof(),
                chain.base,
                chain.tip,
                chain.joint_names.join(", "),
                q.len()
            ),
        ));
    }
    for (i, v) in q.iter().enumerate() {
        let (lo, hi) = (chain.lower[i], chain.upper[i]);
        if *v < lo - 1e-12 || *v > hi + 1e-12 {
            let unit = |x: f64| {
                if chain.angular[i] {
                    format!("{:.3}°", x.to_degrees())
                } else {
                    format!("{x:.4} m")
                }
            };
            return Err(Error::field(
                file,
                &format!("{field}[{i}]"),
                format!(
                    "joint {} at {} is outside its limits [{}, {}]",
                    chain.joint_names[i],
                    unit(*v),
                    unit(lo),
                    unit(hi)
                ),
            ));
        }
    }
    Ok(())
}

impl Plan {
    /// Loads the URDF of the scenario in `file` and plans its trajectory.
    pub fn new(file: &ScenarioFile) -> Result<Self> {
        let packages = PackagePaths::new(file.package_paths());
        let urdf = file.urdf_path();
        let (scenario, file) = (&file.scenario, file.path.as_path());
        if !urdf.is_file() {
            return Err(Error::field(
                file,
                "arm.urdf",
                format!("no such file: {}", urdf.display()),
            ));
        }
        let model = RobotModel::load(&urdf, &packages)?;
        let arm = &scenario.arm;
        let chain = Chain::new(&model, &arm.base_link, &arm.tip_link)
            .map_err(|e| Error::field(file, "arm.base_link / arm.tip_link", e))?;
        if chain.dof() == 0 {
            return Err(Error::field(
                file,
                "arm.tip_link",
                format!("no movable joint between {} and {}", chain.base, chain.tip),
            ));
        }
        let start = chain_units(&chain, &arm.initial_joints_deg);
        check_joints(file, "arm.initial_joints_deg", &chain, &start)?;

        let options = IkOptions {
            seed: scenario.seed,
            ..IkOptions::default()
        };
        let mut waypoints = vec![start];
        let mut holds = vec![0.0];
        for (k, w) in scenario.trajectory.waypoints.iter().enumerate() {
            let field = format!("trajectory.waypoints[{k}]");
            let previous = waypoints.last().expect("start");
            let q = match w.target(file, &field)? {
                Target::Joints(values) => {
                    let q = chain_units(&chain, &values);
                    check_joints(file, &format!("{field}.joints_deg"), &chain, &q)?;
                    q
                }
                Target::Pose { position, rpy } => {
                    let target = pose::from_xyz_rpy(position, rpy);
                    ik::solve(&chain, &target, previous, &options)
                        .map_err(|e| Error::field(file, &field, e))?
                }
            };
            waypoints.push(q);
            holds.push(w.hold_s);
        }
        let speed: Vec<f64> = chain
            .velocity
            .iter()
            .map(|v| v.min(arm.joint_speed_limit_rad_s))
            .collect();
        let trajectory = JointTrajectory::through(&waypoints, &holds, &speed);
        Ok(Self {
            model,
            chain,
            waypoints,
            speed,
            trajectory,
        })
    }

    /// Model joint positions (one per URDF joint) for chain configuration `q`; joints
    /// off the chain stay at 0.
    pub fn model_joints(&self, q: &[f64]) -> Vec<f64> {
        let mut all = vec![0.0; self.model.joints.len()];
        for (&j, v) in self.chain.joint_indices.iter().zip(q) {
            all[j] = *v;
        }
        all
    }

    /// The links from the model's root along the chain to its tip (for drawing the arm).
    pub fn skeleton(&self) -> Vec<usize> {
        let tip = self.model.link(&self.chain.tip).expect("chain tip exists");
        std::iter::once(self.model.root)
            .chain(
                self.model
                    .path_from_root(tip)
                    .iter()
                    .map(|&j| self.model.joints[j].child),
            )
            .collect()
    }

    /// The poses of the `skeleton` links in the chain's base frame at configuration `q`.
    pub fn link_frames(&self, q: &[f64], skeleton: &[usize]) -> Vec<nalgebra::Isometry3<f64>> {
        let base = self
            .model
            .link(&self.chain.base)
            .expect("chain base exists");
        let poses = self.model.link_poses(&self.model_joints(q));
        let base_inv = poses[base].inverse();
        skeleton.iter().map(|&l| base_inv * poses[l]).collect()
    }

    /// What `whisker check` and `whisker run` say of the plan of the scenario in `file`:
    /// the arm, the trajectory and every waypoint.
    pub fn describe(&self, file: &ScenarioFile) -> String {
        let urdf = file.urdf_path();
        let (scenario, file) = (&file.scenario, file.path.as_path());
        let plan = self;
        let c = &plan.chain;
        let mut s = String::new();
        let _ = writeln!(s, "scenario   {} (seed {})", file.display(), scenario.seed);
        let _ = writeln!(
            s,
            "arm        {} from {}: {} -> {}, {} joints ({})",
            plan.model.name,
            urdf.display(),
            c.base,
            c.tip,
            c.dof(),
            c.joint_names.join(", ")
        );
        let speed = plan.speed.iter().cloned().fold(f64::INFINITY, f64::min);
        if let Experiment::Navigate(_) = scenario.experiment {
            let _ = writeln!(
                s,
                "trajectory none scripted: the base drives navigate.route_m; joint speeds ≤ {speed} rad/s"
            );
        } else if let (Experiment::ClosedLoop(_), 1) = (&scenario.experiment, plan.waypoints.len())
        {
            let _ = writeln!(
                s,
                "trajectory none scripted: the closed loop chooses each whisk's goal (Ch 6); joint speeds ≤ {speed} rad/s"
            );
        } else {
            let _ = writeln!(
                s,
                "trajectory {} waypoints, {:.2} s at joint speeds ≤ {speed} rad/s",
                plan.waypoints.len() - 1,
                plan.trajectory.duration()
            );
        }
        for (k, q) in plan.waypoints.iter().enumerate() {
            let tip = c.fk(q);
            let p = tip.translation.vector;
            let r = pose::rpy(&tip.rotation).map(f64::to_degrees);
            let deg: Vec<String> = q.iter().map(|v| format!("{:.2}", v.to_degrees())).collect();
            let label = if k == 0 {
                "start".to_string()
            } else {
                format!("#{}", k - 1)
            };
            let _ = writeln!(
                s,
                "  {label:>5}  tip ({:.4}, {:.4}, {:.4}) m  rpy ({:.1}, {:.1}, {:.1})°  joints [{}]°",
                p.x,
                p.y,
                p.z,
                r[0],
                r[1],
                r[2],
                deg.join(", ")
            );
        }
        s
    }
}
