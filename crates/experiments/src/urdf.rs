//! `whisker urdf info URDF` and `whisker urdf fk URDF --joints …`: a robot description
//! looked at from the command line.

use crate::record::Context;
use serde::Serialize;
use std::fmt;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};
use whisker_sim::kinematics::urdf::Geometry;
use whisker_sim::kinematics::{Chain, PackagePaths, RobotModel};
use whisker_slam::pose;

/// Loads a URDF given on the command line.
pub fn load(path: &Path, package_paths: &[PathBuf]) -> Result<RobotModel> {
    if !path.is_file() {
        return Err(Error::Input(format!(
            "{}: no such URDF file",
            path.display()
        )));
    }
    Ok(RobotModel::load(
        path,
        &PackagePaths::new(package_paths.iter().cloned()),
    )?)
}

fn leaves(model: &RobotModel) -> Vec<usize> {
    (0..model.links.len())
        .filter(|&l| !model.joints.iter().any(|j| j.parent == l))
        .collect()
}

/// The default base link: `base_link` if present, else the root.
pub fn default_base(model: &RobotModel) -> String {
    if model.link("base_link").is_some() {
        "base_link".into()
    } else {
        model.links[model.root].name.clone()
    }
}

/// The default tip link: `tool0` if present, else the only leaf link.
pub fn default_tip(model: &RobotModel) -> Result<String> {
    if model.link("tool0").is_some() {
        return Ok("tool0".into());
    }
    match leaves(model).as_slice() {
        [l] => Ok(model.links[*l].name.clone()),
        many => Err(Error::Input(format!(
            "{}: no tool0 link and {} leaf links ({}): choose one with --link",
            model.source.display(),
            many.len(),
            many.iter()
                .map(|&l| model.links[l].name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

fn fmt_limit(v: f64, angular: bool) -> String {
    if !v.is_finite() {
        return "∞".into();
    }
    if angular {
        format!("{:.1}°", v.to_degrees())
    } else {
        format!("{v:.4} m")
    }
}

/// `whisker urdf info`.
pub fn info(path: &Path, package_paths: &[PathBuf], ctx: Context) -> Result {
    let model = load(path, package_paths)?;
    ctx.say(&format!("robot  {} ({})", model.name, path.display()));
    ctx.say(&format!("root   {}", model.links[model.root].name));
    ctx.say(&format!("links  {}", model.links.len()));
    for l in &model.links {
        let shapes: Vec<String> = l
            .collisions
            .iter()
            .map(|c| match &c.geometry {
                Geometry::Box { size } => {
                    format!("box {:.3}×{:.3}×{:.3} m", size.x, size.y, size.z)
                }
                Geometry::Cylinder { radius, length } => {
                    format!("cylinder r {radius:.3} l {length:.3} m")
                }
                Geometry::Capsule { radius, length } => {
                    format!("capsule r {radius:.3} l {length:.3} m")
                }
                Geometry::Sphere { radius } => format!("sphere r {radius:.3} m"),
                Geometry::Mesh {
                    filename, resolved, ..
                } => match resolved {
                    Some(p) => format!("mesh {}", p.display()),
                    None => format!("mesh {filename} (not found)"),
                },
            })
            .collect();
        let shapes = if shapes.is_empty() {
            "no collision geometry".to_string()
        } else {
            shapes.join("; ")
        };
        ctx.say(&format!("  {:<24} {shapes}", l.name));
    }
    ctx.say(&format!("joints {}", model.joints.len()));
    for j in &model.joints {
        let angular = !matches!(j.kind, whisker_sim::kinematics::JointKind::Prismatic);
        let limits = if j.kind.is_single_dof() {
            format!(
                " limits [{}, {}] speed ≤ {}",
                fmt_limit(j.limits.lower, angular),
                fmt_limit(j.limits.upper, angular),
                if j.limits.velocity.is_finite() {
                    format!("{}", j.limits.velocity)
                } else {
                    "∞".into()
                }
            )
        } else {
            String::new()
        };
        let a = j.axis;
        let axis = if j.kind.is_single_dof() {
            format!(" axis ({}, {}, {})", a.x, a.y, a.z)
        } else {
            String::new()
        };
        ctx.say(&format!(
            "  {:<34} {:<10} {} -> {}{axis}{limits}",
            j.name,
            j.kind.name(),
            model.links[j.parent].name,
            model.links[j.child].name
        ));
    }
    let base = default_base(&model);
    if let Ok(tip) = default_tip(&model)
        && let Ok(chain) = Chain::new(&model, &base, &tip)
    {
        ctx.say(&format!(
            "chain  {base} -> {tip}: {} joints ({})",
            chain.dof(),
            chain.joint_names.join(", ")
        ));
    }
    Ok(())
}

/// Parses `q1,q2,…` (radians or metres).
pub fn parse_joints(text: &str) -> Result<Vec<f64>> {
    if text.trim().is_empty() {
        return Ok(Vec::new());
    }
    text.split(',')
        .enumerate()
        .map(|(i, s)| match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(Error::Input(format!(
                "--joints: value {} ({:?}) is not a finite number; expected comma-separated joint positions in rad (m for prismatic)",
                i + 1,
                s.trim()
            ))),
        })
        .collect()
}

/// A pose computed by forward kinematics (`whisker urdf fk`).
#[derive(Debug, Clone, Serialize)]
pub struct Fk {
    pub base: String,
    pub link: String,
    pub joint_names: Vec<String>,
    pub joints: Vec<f64>,
    pub position_m: [f64; 3],
    pub quaternion_xyzw: [f64; 4],
    pub rpy_rad: [f64; 3],
    /// The homogeneous transform, row by row.
    pub matrix: Vec<[f64; 4]>,
}

/// `whisker urdf fk`: the pose of `link` in `base` at joint positions `joints`
/// (comma-separated; rad, m for prismatic joints).
pub fn fk(
    path: &Path,
    package_paths: &[PathBuf],
    joints: &str,
    base: Option<&str>,
    link: Option<&str>,
) -> Result<Fk> {
    let model = load(path, package_paths)?;
    let base = base
        .map(str::to_string)
        .unwrap_or_else(|| default_base(&model));
    let tip = match link {
        Some(l) => l.to_string(),
        None => default_tip(&model)?,
    };
    let chain =
        Chain::new(&model, &base, &tip).map_err(|e| Error::Input(format!("--base/--link: {e}")))?;
    let q = parse_joints(joints)?;
    if q.len() != chain.dof() {
        return Err(Error::Input(format!(
            "--joints: expected {} values for the chain {base} -> {tip} ({}), got {}",
            chain.dof(),
            chain.joint_names.join(", "),
            q.len()
        )));
    }
    let p = chain.fk(&q);
    let t = p.translation.vector;
    let m = pose::matrix(&p);
    Ok(Fk {
        base,
        link: tip,
        joint_names: chain.joint_names.clone(),
        joints: q,
        position_m: [t.x, t.y, t.z],
        quaternion_xyzw: pose::quaternion_xyzw(&p.rotation),
        rpy_rad: pose::rpy(&p.rotation),
        matrix: (0..4)
            .map(|r| [m[(r, 0)], m[(r, 1)], m[(r, 2)], m[(r, 3)]])
            .collect(),
    })
}

impl fmt::Display for Fk {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.position_m;
        let q = self.quaternion_xyzw;
        writeln!(f, "pose of {} in {}", self.link, self.base)?;
        writeln!(f, "position_m       {x:.6} {y:.6} {z:.6}")?;
        writeln!(
            f,
            "quaternion_xyzw  {:.6} {:.6} {:.6} {:.6}",
            q[0], q[1], q[2], q[3]
        )?;
        writeln!(f, "matrix")?;
        for r in &self.matrix {
            writeln!(
                f,
                "  {:>10.6} {:>10.6} {:>10.6} {:>10.6}",
                r[0], r[1], r[2], r[3]
            )?;
        }
        Ok(())
    }
}
