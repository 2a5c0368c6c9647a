//! `[[objects]]`, `[maze]` and `[kinematic]` of a scenario (documented in
//! `scenarios/README.md`): the fixed environment and the kinematic sensing options.
//!
//! Poses are in the arm's base link frame (the world of a run). Mesh paths are relative
//! to the scenario file. Every problem names the scenario field and, for mesh files, the
//! mesh file and the line or record in it.

use crate::error::{Error, Result};
use crate::paths::relative_to;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use whisker_sim::environment::maze::{Deformities, MazeLayout, Post, Wall};
use whisker_sim::environment::mesh::{
    self, Decimation, MeshOptions, Origin, Repair, Units, UpAxis,
};

/// Default largest quadric error of a decimation collapse (m).
pub const DECIMATE_TOLERANCE_M: f64 = 0.0005;
use whisker_sim::environment::{Environment, Piece};
use whisker_sim::sensing::noise::{ContactNoise, PointNoise};
use whisker_slam::pose;

/// One `[[objects]]` entry: a mesh placed in the world.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectConfig {
    /// Mesh file (.obj, .stl, .ply), relative to the scenario file.
    pub mesh: PathBuf,
    /// A name for messages and the recording [default: the file stem].
    pub name: Option<String>,
    /// Position of the mesh origin (m).
    #[serde(default)]
    pub position_m: [f64; 3],
    /// Orientation as roll, pitch, yaw (deg).
    #[serde(default)]
    pub rpy_deg: [f64; 3],
    /// Placement jitter: x and y each moved by a uniform draw in ±this (m, 0–1) from the
    /// seed's sub-stream `objects/jitter/NN` [0].
    pub jitter_m: Option<f64>,
    /// Placement jitter: yaw (about the world's vertical through the origin) changed by a
    /// uniform draw in ±this (deg, 0–180), same sub-stream [0].
    pub jitter_yaw_deg: Option<f64>,
    /// The file's length unit: "m", "cm", "mm" or "in".
    #[serde(default = "metres")]
    pub units: String,
    /// Extra uniform scale factor.
    #[serde(default = "unit_scale")]
    pub scale: f64,
    /// The file's up axis: "z" or "y".
    #[serde(default = "z_up")]
    pub up: String,
    /// What to do when the file is not a clean closed solid: "strict", "auto", "hull",
    /// "voxel" or "soup".
    #[serde(default = "auto_repair")]
    pub repair: String,
    /// Voxel size of `repair = "voxel"` (m, after units and scale) [the longest side of
    /// the bounding box / 64].
    pub voxel_size_m: Option<f64>,
    /// Openings up to this width (m) sealed before the voxel fill [none].
    pub voxel_closing_m: Option<f64>,
    /// Decimate the solid to at most this many triangles [no decimation].
    pub decimate: Option<usize>,
    /// Largest quadric error of a decimation collapse (m) [0.0005].
    pub decimate_tolerance_m: Option<f64>,
    /// Where the mesh's origin is: "file" (its own) or "base" (the bottom centre of its
    /// bounding box, after units, scale and up axis).
    #[serde(default = "file_origin")]
    pub origin: String,
}

impl ObjectConfig {
    /// The object's name: `name`, else the mesh file's stem, else "object `i`".
    pub fn display_name(&self, i: usize) -> String {
        self.name.clone().unwrap_or_else(|| {
            self.mesh
                .file_stem()
                .map_or_else(|| format!("object {i}"), |s| s.to_string_lossy().into())
        })
    }
}

/// `[maze]`: the maze board placed in the world.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MazeConfig {
    /// Position of the board's corner (x = y = 0, top surface) (m).
    #[serde(default)]
    pub position_m: [f64; 3],
    /// Orientation of the board as roll, pitch, yaw (deg).
    #[serde(default)]
    pub rpy_deg: [f64; 3],
    /// Board size x, y (m) [1.35 × 1].
    #[serde(default = "board")]
    pub board_m: [f64; 2],
    /// `[[maze.walls]]`.
    #[serde(default)]
    pub walls: Vec<Wall>,
    /// `[[maze.posts]]`.
    #[serde(default)]
    pub posts: Vec<Post>,
    /// `[maze.deformities]`.
    pub deformities: Option<Deformities>,
}

/// `[kinematic]`: options of `sensing = "kinematic"` (contact noise, §6.1.3.1.2).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KinematicConfig {
    /// Whether contact features get noise.
    #[serde(default = "yes")]
    pub noise: bool,
    /// σ of the contact point's noise as a fraction of the whisker length [0.25].
    #[serde(default = "point_fraction")]
    pub point_noise_fraction: f64,
    /// Which way it displaces the point: `"along_whisker"` (the radial distance, as the
    /// thesis models it; default) or `"per_coordinate"` (x, y and z each).
    #[serde(default)]
    pub point_noise: PointNoise,
    /// σ of the slope [0.33].
    #[serde(default = "slope_sigma")]
    pub slope_noise: f64,
    /// Probability that a contact is registered [0.98].
    #[serde(default = "detection")]
    pub detection_probability: f64,
}

impl Default for KinematicConfig {
    fn default() -> Self {
        Self {
            noise: true,
            point_noise_fraction: point_fraction(),
            point_noise: PointNoise::default(),
            slope_noise: slope_sigma(),
            detection_probability: detection(),
        }
    }
}

fn metres() -> String {
    "m".into()
}
fn unit_scale() -> f64 {
    1.0
}
fn z_up() -> String {
    "z".into()
}
fn auto_repair() -> String {
    "auto".into()
}
fn file_origin() -> String {
    "file".into()
}
fn board() -> [f64; 2] {
    [1.35, 1.0]
}
fn yes() -> bool {
    true
}
fn point_fraction() -> f64 {
    ContactNoise::default().point_fraction
}
fn slope_sigma() -> f64 {
    ContactNoise::default().slope_sigma
}
fn detection() -> f64 {
    ContactNoise::default().detection_probability
}

fn pose_of(
    file: &Path,
    field: &str,
    p: [f64; 3],
    rpy: [f64; 3],
) -> Result<nalgebra::Isometry3<f64>> {
    if let Some(i) = p.iter().chain(&rpy).position(|v| !v.is_finite()) {
        let (name, k) = if i < 3 {
            ("position_m", i)
        } else {
            ("rpy_deg", i - 3)
        };
        return Err(Error::field(
            file,
            &format!("{field}.{name}[{k}]"),
            "expected a finite number",
        ));
    }
    Ok(pose::from_xyz_rpy(p, rpy.map(f64::to_radians)))
}

impl KinematicConfig {
    /// The noise model (none if `noise = false`), validated.
    pub fn noise(&self, file: &Path) -> Result<ContactNoise> {
        let model = ContactNoise {
            point_fraction: self.point_noise_fraction,
            slope_sigma: self.slope_noise,
            detection_probability: self.detection_probability,
            point_model: self.point_noise,
        };
        model.validate().map_err(|e| {
            let name = match e.field.as_str() {
                "point_fraction" => "point_noise_fraction",
                "slope_sigma" => "slope_noise",
                other => other,
            };
            Error::field(file, &format!("kinematic.{name}"), &e.message)
        })?;
        Ok(if self.noise {
            model
        } else {
            ContactNoise::NONE
        })
    }
}

/// A loaded environment and what `whisker check` should say about it.
pub struct LoadedEnvironment {
    /// The pieces.
    pub environment: Environment,
    /// One line per object or maze: what it is and any repairs made to its mesh.
    pub report: Vec<String>,
}

/// Loads `[[objects]]`, `[maze]` (its deformities from `seed`) and `[office]`, in that
/// order (the objects' pieces first, one each).
pub fn load(
    file: &Path,
    objects: &[ObjectConfig],
    maze: Option<&MazeConfig>,
    office: Option<&crate::office::OfficeConfig>,
    seed: u64,
) -> Result<LoadedEnvironment> {
    let mut environment = Environment::default();
    let mut report = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        let (piece, line) = load_object(file, i, o, seed)?;
        environment.pieces.push(piece);
        report.push(line);
    }
    if let Some(m) = maze {
        let (pieces, line) = load_maze(file, m, seed)?;
        environment.pieces.extend(pieces);
        report.push(line);
    }
    if let Some(o) = office {
        let (pieces, line) = crate::office::load(file, o)?;
        environment.pieces.extend(pieces);
        report.push(line);
    }
    Ok(LoadedEnvironment {
        environment,
        report,
    })
}

/// The object's position and orientation (deg) with its placement jitter drawn from the
/// sub-stream `objects/jitter/NN` of `seed` (none drawn without jitter).
fn jittered(
    file: &Path,
    field: &str,
    i: usize,
    o: &ObjectConfig,
    seed: u64,
) -> Result<([f64; 3], [f64; 3])> {
    let (mut p, mut rpy) = (o.position_m, o.rpy_deg);
    let check = |name: &str, v: Option<f64>, max: f64| match v {
        Some(x) if !(0.0..=max).contains(&x) => Err(Error::field(
            file,
            &format!("{field}.{name}"),
            format!(
                "expected 0 to {max}, got {}",
                whisker_slam::message::short(x)
            ),
        )),
        _ => Ok(v.unwrap_or(0.0)),
    };
    let (d, yaw) = (
        check("jitter_m", o.jitter_m, 1.0)?,
        check("jitter_yaw_deg", o.jitter_yaw_deg, 180.0)?,
    );
    if d > 0.0 || yaw > 0.0 {
        use rand::RngExt;
        let mut rng = whisker_slam::rng::substream(seed, &format!("objects/jitter/{i:02}"));
        p[0] += rng.random_range(-1.0..=1.0) * d;
        p[1] += rng.random_range(-1.0..=1.0) * d;
        rpy[2] += rng.random_range(-1.0..=1.0) * yaw;
    }
    Ok((p, rpy))
}

/// One `[[objects]]` entry: its mesh loaded, repaired and placed, and its line of the report.
fn load_object(file: &Path, i: usize, o: &ObjectConfig, seed: u64) -> Result<(Piece, String)> {
    let field = format!("objects[{i}]");
    let options = mesh_options(file, &field, o)?;
    let (position, rpy) = jittered(file, &field, i, o, seed)?;
    let pose = pose_of(file, &field, position, rpy)?;
    let path = relative_to(file, &o.mesh);
    let loaded =
        mesh::load(&path, &options).map_err(|e| Error::field(file, &format!("{field}.mesh"), e))?;
    let shape = if loaded.solid {
        whisker_sim::environment::solids::shape(&loaded.mesh)
    } else {
        whisker_sim::environment::solids::soup_shape(&loaded.mesh)
    }
    .map_err(|e| Error::field(file, &format!("{field}.mesh"), e))?;
    let name = o.display_name(i);
    let line = object_report(&name, &path, &loaded, position);
    let piece = Piece {
        name: format!("object {name}"),
        shape,
        mesh: loaded.mesh,
        pose,
        soup: !loaded.solid,
    };
    Ok((piece, line))
}

/// How an object's mesh file is read and repaired: units, scale, up axis, repair, origin,
/// voxel sizes and decimation, each checked and named by its field.
fn mesh_options(file: &Path, field: &str, o: &ObjectConfig) -> Result<MeshOptions> {
    // A keyword field: parsed, or an error naming the field and the choices.
    let keyword = |name: &str, value: &str, choices: &str| {
        Error::field(
            file,
            &format!("{field}.{name}"),
            format!("{value:?}: expected {choices}"),
        )
    };
    let units = Units::parse(&o.units)
        .ok_or_else(|| keyword("units", &o.units, "\"m\", \"cm\", \"mm\" or \"in\""))?;
    let up = match o.up.as_str() {
        "z" => UpAxis::Z,
        "y" => UpAxis::Y,
        other => return Err(keyword("up", other, "\"z\" or \"y\"")),
    };
    if !(o.scale.is_finite() && o.scale > 0.0) {
        return Err(Error::field(
            file,
            &format!("{field}.scale"),
            format!("expected a positive number, got {}", o.scale),
        ));
    }
    let repair =
        Repair::parse(&o.repair).ok_or_else(|| keyword("repair", &o.repair, Repair::CHOICES))?;
    for (name, value) in [
        ("voxel_size_m", o.voxel_size_m),
        ("voxel_closing_m", o.voxel_closing_m),
    ] {
        let Some(v) = value else { continue };
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::field(
                file,
                &format!("{field}.{name}"),
                format!("expected a positive length, got {v}"),
            ));
        }
        if repair != Repair::Voxel {
            return Err(Error::field(
                file,
                &format!("{field}.{name}"),
                format!("applies to repair = \"voxel\" only, not {:?}", o.repair),
            ));
        }
    }
    let decimate = decimation(file, field, o, repair)?;
    let origin = Origin::parse(&o.origin)
        .ok_or_else(|| keyword("origin", &o.origin, "\"file\" or \"base\""))?;
    Ok(MeshOptions {
        units,
        scale: o.scale,
        up,
        repair,
        origin,
        voxel_size: o.voxel_size_m,
        voxel_closing: o.voxel_closing_m,
        decimate,
    })
}

/// `decimate` and `decimate_tolerance_m` of an object: none, or a checked target.
fn decimation(
    file: &Path,
    field: &str,
    o: &ObjectConfig,
    repair: Repair,
) -> Result<Option<Decimation>> {
    let (n, tolerance) = match (o.decimate, o.decimate_tolerance_m) {
        (None, None) => return Ok(None),
        (None, Some(_)) => {
            return Err(Error::field(
                file,
                &format!("{field}.decimate_tolerance_m"),
                "applies with decimate only: expected decimate = <triangles> too",
            ));
        }
        (Some(n), tolerance) => (n, tolerance.unwrap_or(DECIMATE_TOLERANCE_M)),
    };
    if n < 4 {
        return Err(Error::field(
            file,
            &format!("{field}.decimate"),
            format!("expected a target of at least 4 triangles, got {n}"),
        ));
    }
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(Error::field(
            file,
            &format!("{field}.decimate_tolerance_m"),
            format!("expected a positive length, got {tolerance}"),
        ));
    }
    if repair == Repair::Soup {
        return Err(Error::field(
            file,
            &format!("{field}.decimate"),
            "a triangle soup (repair = \"soup\") is kept as it is: expected a solid \
             repair (\"auto\", \"hull\" or \"voxel\") to decimate",
        ));
    }
    Ok(Some(Decimation {
        triangles: n,
        tolerance,
    }))
}

/// `whisker check`'s line about a loaded object: file, triangles, parts, size, extent about
/// its origin, position, and the repairs made.
fn object_report(
    name: &str,
    path: &Path,
    loaded: &mesh::LoadedMesh,
    position_m: [f64; 3],
) -> String {
    let (lo, hi) = mesh::bounds(&loaded.mesh.vertices);
    let size = hi - lo;
    format!(
        "object     {name}: {} ({} triangles, {} {}, {:.3} x {:.3} x {:.3} m, from ({:.3}, {:.3}, {:.3}) to ({:.3}, {:.3}, {:.3}) m about its origin) at ({:.3}, {:.3}, {:.3}) m{}",
        path.display(),
        loaded.mesh.triangles.len(),
        loaded.mesh.component_volumes().len(),
        if loaded.solid {
            "solid part(s)"
        } else {
            "connected part(s) of a triangle soup"
        },
        size.x,
        size.y,
        size.z,
        lo.x,
        lo.y,
        lo.z,
        hi.x,
        hi.y,
        hi.z,
        position_m[0],
        position_m[1],
        position_m[2],
        if loaded.repairs.is_empty() {
            String::new()
        } else {
            format!(
                "\nwarning    {name}: mesh repaired: {}",
                loaded.repairs.join("; ")
            )
        }
    )
}

/// The `[maze]` board built at its pose (deformities drawn from `seed`), and its report line.
fn load_maze(file: &Path, m: &MazeConfig, seed: u64) -> Result<(Vec<Piece>, String)> {
    let layout = MazeLayout {
        board: m.board_m,
        walls: m.walls.clone(),
        posts: m.posts.clone(),
        deformities: m.deformities.clone(),
    };
    layout
        .validate()
        .map_err(|(f, msg)| Error::field(file, &format!("maze.{f}"), msg))?;
    let pose = pose_of(file, "maze", m.position_m, m.rpy_deg)?;
    let built = layout.build(&pose, seed);
    let line = format!(
        "maze       {} x {} m board, {} walls, {} posts, {} deformities at ({:.3}, {:.3}, {:.3}) m",
        m.board_m[0],
        m.board_m[1],
        m.walls.len(),
        m.posts.len(),
        m.deformities.as_ref().map_or(0, |d| d.count),
        m.position_m[0],
        m.position_m[1],
        m.position_m[2]
    );
    Ok((built.pieces, line))
}
