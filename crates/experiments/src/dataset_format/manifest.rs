//! `dataset.json`, a dataset's manifest (docs/dataset.md): the format and its version,
//! what was recorded and how (array, sensors, noise, the experiment's parameters) and
//! every file with its size and SHA-256. Read strictly: unknown fields, a newer version,
//! a missing log file or a checksum mismatch exit with code 2 naming the file.

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};
use whisker_slam::invalid::Invalid;

pub use super::sections::{
    ClosedLoopInfo, MazeInfo, NavigateInfo, NavigateObjectInfo, ObjectSlamInfo, PostureInfo,
    WalkInfo,
};
use whisker_slam::ratslam::odometry::OdometryNoise;

/// The manifest's file name.
pub const FILE: &str = "dataset.json";
/// The `format` field.
pub const FORMAT: &str = "whisker-slam dataset";
/// The format version this build writes and reads (and the newest it reads).
pub const VERSION: u32 = 1;

/// `dataset.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Always [`FORMAT`].
    pub format: String,
    /// The format version ([`VERSION`]).
    pub version: u32,
    /// The program that wrote it (`whisker <version>`).
    pub written_by: String,
    /// The experiment whose SLAM the dataset feeds.
    pub experiment: Experiment,
    /// What the log holds: raw 2 kHz streams or detected contacts.
    pub level: Level,
    /// The seed of the run that wrote it.
    pub seed: u64,
    /// The whiskers, in column order.
    pub array: ArrayInfo,
    /// The sensors (level `streams`).
    pub sensor: Option<SensorInfo>,
    /// The noise in the log.
    pub noise: NoiseInfo,
    /// The maze experiment's parameters (experiment `maze-slam`).
    pub maze: Option<MazeInfo>,
    /// The object experiment's walks (experiment `object-slam`).
    pub object_slam: Option<ObjectSlamInfo>,
    /// The closed loop's parameters (experiment `closed-loop`).
    pub closed_loop: Option<ClosedLoopInfo>,
    /// The mobile robot's run in the office (experiment `navigate`; absent from other
    /// experiments' manifests).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub navigate: Option<NavigateInfo>,
    /// Every file, relative to the dataset's directory, with its role and checksum.
    pub files: Vec<FileEntry>,
}

/// `experiment`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Experiment {
    /// Planar RatSLAM with tactile images (Ch 3).
    MazeSlam,
    /// WhiskerRatSLAM localisation and identification on catalogue objects (§5.2).
    ObjectSlam,
    /// The path of a closed-loop run (Ch 6), replayed open loop.
    ClosedLoop,
    /// The mobile robot in the office (issue #36, Fig 5.1): terrain whisks, the base's
    /// odometry and each stop's closed loop, replayed by the robot's own decisions.
    Navigate,
}

/// `level`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Level {
    /// `log/whisks/*.csv`: every whisker's 2 kHz samples (the lab layout, §3.1.3).
    Streams,
    /// `log/contacts.csv`: the contacts of every whisk (kinematic sensing has no signal).
    Contacts,
}

impl Level {
    /// The name in the manifest.
    pub fn name(self) -> &'static str {
        match self {
            Level::Streams => "streams",
            Level::Contacts => "contacts",
        }
    }
}

/// `array`: the whiskers in column order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArrayInfo {
    /// Tactile-image labels, `A1` … `F3`.
    pub labels: Vec<String>,
    /// Shaft lengths (m).
    pub lengths_m: Vec<f64>,
    /// Distance from the whisk axis to the shaft's base along the shaft (m).
    pub base_offsets_m: Vec<f64>,
}

/// `sensor`: how the whisk files' integers are read.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorInfo {
    /// Samples per second per whisker.
    pub sample_rate_hz: f64,
    /// Whisk frequency (Hz): one whisk file per cycle.
    pub whisk_hz: f64,
    /// Rows per whisk file.
    pub samples_per_whisk: usize,
    /// Number of whisk files.
    pub whisks: usize,
    /// Radians per angle count.
    pub angle_resolution_rad: f64,
    /// Deflection saturation (counts).
    pub saturation_counts: f64,
}

/// `noise`: what noise the log holds and where it came from.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseInfo {
    /// Seed of noise added by `whisker dataset noise` (None: noise from the simulation,
    /// drawn from the run's seed).
    pub added_with_seed: Option<u64>,
    /// Sensor noise (None: none).
    pub sensor: Option<SensorNoise>,
    /// Planar odometry error model of §3.1.2 (maze; None: none).
    pub odometry: Option<OdometryNoise>,
    /// 6-D odometry error (object walks; None: none).
    pub odometry_6d: Option<Odometry6Noise>,
    /// Contact noise of level `contacts` (None: none).
    pub contacts: Option<ContactNoiseInfo>,
}

impl NoiseInfo {
    /// Whether the log holds no noise at all.
    pub fn is_clean(&self) -> bool {
        self.sensor.is_none()
            && self.odometry.is_none()
            && self.odometry_6d.is_none()
            && self.contacts.is_none()
    }
}

/// The 6-D odometry error of the §5.2 walks: Gaussian, per axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Odometry6Noise {
    /// σ of each translation component as a fraction of the step's length.
    pub translation_fraction: f64,
    /// σ of each rotation-vector component (degrees).
    pub rotation_deg: f64,
}

impl Odometry6Noise {
    /// The walks' model (`whisker object-slam`): 5 % of the step, 0.5°.
    pub const WALK: Odometry6Noise = Odometry6Noise {
        translation_fraction: 0.05,
        rotation_deg: 0.5,
    };
}

/// Sensor noise: Gaussian, before quantisation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorNoise {
    /// σ of each deflection reading (counts).
    pub deflection_counts: f64,
    /// σ of each angle reading (rad).
    pub angle_rad: f64,
}

impl SensorNoise {
    /// The readings' noise of the sensors `model`.
    pub fn of(model: &whisker_sim::whisker::sensor::SensorModel) -> Self {
        Self {
            deflection_counts: model.noise_counts,
            angle_rad: model.angle_noise_rad,
        }
    }
}

/// Contact noise (§6.1.3.1.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactNoiseInfo {
    /// σ of each contact-point coordinate / the whisker's length.
    pub point_fraction: f64,
    /// σ of the slope.
    pub slope_sigma: f64,
    /// Probability that a contact is registered.
    pub detection_probability: f64,
    /// Which way the point's noise displaced it (`per_coordinate` when absent: the only
    /// model before issue #35).
    #[serde(default = "per_coordinate")]
    pub point_model: whisker_sim::sensing::noise::PointNoise,
}

/// What a manifest written before issue #35 used.
fn per_coordinate() -> whisker_sim::sensing::noise::PointNoise {
    whisker_sim::sensing::noise::PointNoise::PerCoordinate
}

impl ContactNoiseInfo {
    /// The record of `noise` (None for no noise).
    pub fn of(noise: whisker_sim::sensing::noise::ContactNoise) -> Option<Self> {
        (noise != whisker_sim::sensing::noise::ContactNoise::NONE).then_some(Self {
            point_fraction: noise.point_fraction,
            slope_sigma: noise.slope_sigma,
            detection_probability: noise.detection_probability,
            point_model: noise.point_model,
        })
    }
}

/// One file of the dataset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileEntry {
    /// Path relative to the dataset's directory, `/`-separated.
    pub path: String,
    /// `log` (what a real robot records) or `truth` (ground truth: may be deleted).
    pub role: Role,
    /// Size in bytes.
    pub bytes: u64,
    /// SHA-256 of the contents, lower-case hex.
    pub sha256: String,
}

/// A file's role.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Role {
    /// Part of the log a real robot would record.
    Log,
    /// Ground truth, absent from real logs.
    Truth,
}

/// Lower-case hex SHA-256 of `bytes`.
pub fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

impl FileEntry {
    /// The entry of `bytes` written at `path` (relative).
    pub fn of(path: &str, role: Role, bytes: &[u8]) -> Self {
        Self {
            path: path.into(),
            role,
            bytes: bytes.len() as u64,
            sha256: sha256(bytes),
        }
    }
}

impl Manifest {
    /// A manifest of `experiment` at `level` written by this build for `seed` and `array`:
    /// no sensor section, no noise, no experiment section, no files yet.
    pub fn new(experiment: Experiment, level: Level, seed: u64, array: ArrayInfo) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            written_by: format!("whisker {}", env!("CARGO_PKG_VERSION")),
            experiment,
            level,
            seed,
            array,
            sensor: None,
            noise: NoiseInfo::default(),
            maze: None,
            object_slam: None,
            closed_loop: None,
            navigate: None,
            files: Vec::new(),
        }
    }

    /// Reads and checks `dir/dataset.json`: the format, the version, the fields; then
    /// every listed file: log files must exist, and every file present must have its
    /// size and checksum (truth files may be missing: ground truth is then unavailable).
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(FILE);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            Error::Input(format!(
                "{}: cannot read the dataset's manifest: {e}",
                path.display()
            ))
        })?;
        let bad = |m: String| Error::Input(format!("{}: {m}", path.display()));
        let value: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| bad(format!("not JSON: {e}")))?;
        if value.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
            return Err(bad(format!("field `format`: expected {FORMAT:?}")));
        }
        match value.get("version").and_then(|v| v.as_u64()) {
            Some(v) if v > u64::from(VERSION) => {
                return Err(bad(format!(
                    "field `version`: format version {v} is newer than this whisker reads \
                     ({VERSION}); update whisker"
                )));
            }
            Some(v) if v >= 1 => {}
            _ => return Err(bad(format!("field `version`: expected 1 to {VERSION}"))),
        }
        let manifest: Manifest = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
        manifest.check(&path)?;
        for entry in &manifest.files {
            entry.verify(dir)?;
        }
        Ok(manifest)
    }

    /// Internal consistency: one label, length and offset per whisker; the experiment's
    /// section present.
    fn check(&self, path: &Path) -> Result {
        let bad = |field: &str, m: &str| Error::field(path, field, m);
        let n = self.array.labels.len();
        if n == 0 || self.array.lengths_m.len() != n || self.array.base_offsets_m.len() != n {
            return Err(bad(
                "array",
                "expected as many lengths_m and base_offsets_m as labels (at least one)",
            ));
        }
        if self.level == Level::Streams && self.sensor.is_none() {
            return Err(bad("sensor", "level \"streams\" needs a sensor section"));
        }
        // The parameters a replay runs with, checked as a scenario's are.
        if let Some(m) = &self.maze {
            m.ratslam
                .validate()
                .map_err(|e| Error::field(path, "maze.ratslam", e))?;
            for (key, t) in &m.tuned {
                t.over(m.ratslam)
                    .validate()
                    .map_err(|e| Error::field(path, &format!("maze.tuned.{key:?}"), e))?;
            }
        }
        if let Some(c) = &self.closed_loop {
            let sub = |name: &str, r: std::result::Result<(), Invalid>| {
                r.map_err(|e| {
                    let field = format!("closed_loop.{name}.{}", e.field);
                    Error::field(path, &field, e.message)
                })
            };
            sub("odometry_noise", c.odometry_noise.validate())?;
            sub("recognition", c.recognition.validate())?;
            c.slam
                .pose_cells
                .validate()
                .map_err(|e| Error::field(path, "closed_loop.slam.pose_cells", e))?;
        }
        if let Some(n) = &self.navigate {
            n.check()
                .map_err(|e| Error::field(path, &format!("navigate.{}", e.field), e.message))?;
            n.ratslam
                .validate()
                .map_err(|e| Error::field(path, "navigate.ratslam", e))?;
            n.switch
                .validate()
                .map_err(|e| Error::field(path, "navigate.switch", e))?;
            if let Some(o) = &n.object {
                o.recognition.validate().map_err(|e| {
                    let field = format!("navigate.object.recognition.{}", e.field);
                    Error::field(path, &field, e.message)
                })?;
                o.slam
                    .pose_cells
                    .validate()
                    .map_err(|e| Error::field(path, "navigate.object.slam.pose_cells", e))?;
                if !matches!(o.dock.as_str(), "arm" | "base") {
                    return Err(bad("navigate.object.dock", "expected \"arm\" or \"base\""));
                }
            }
        }
        match self.experiment {
            Experiment::MazeSlam if self.maze.is_none() => {
                Err(bad("maze", "experiment \"maze-slam\" needs a maze section"))
            }
            Experiment::ObjectSlam if self.object_slam.is_none() => Err(bad(
                "object_slam",
                "experiment \"object-slam\" needs an object_slam section",
            )),
            Experiment::ClosedLoop if self.closed_loop.is_none() => Err(bad(
                "closed_loop",
                "experiment \"closed-loop\" needs a closed_loop section",
            )),
            Experiment::Navigate if self.navigate.is_none() => Err(bad(
                "navigate",
                "experiment \"navigate\" needs a navigate section",
            )),
            _ => Ok(()),
        }
    }

    /// The `maze` section of the manifest read from `dir` (present whenever `experiment`
    /// is maze-slam: [`Manifest::read`] refuses one without it).
    pub fn maze_section(&self, dir: &Path) -> Result<&MazeInfo> {
        self.maze.as_ref().ok_or_else(|| {
            Error::field(
                &dir.join(FILE),
                "maze",
                "a maze dataset needs a maze section",
            )
        })
    }

    /// The `sensor` section of the manifest read from `dir` (present whenever `level` is
    /// streams: [`Manifest::read`] refuses one without it).
    pub fn sensor_section(&self, dir: &Path) -> Result<SensorInfo> {
        self.sensor.ok_or_else(|| {
            Error::field(
                &dir.join(FILE),
                "sensor",
                "level \"streams\" needs a sensor section",
            )
        })
    }

    /// The entry of `path` (relative), if listed.
    pub fn entry(&self, path: &str) -> Option<&FileEntry> {
        self.files.iter().find(|f| f.path == path)
    }

    /// Whether every truth file listed is present (ground truth available).
    pub fn has_truth(&self, dir: &Path) -> bool {
        self.files
            .iter()
            .filter(|f| f.role == Role::Truth)
            .all(|f| dir.join(&f.path).exists())
    }

    /// `dir/path` for a listed file; an error naming the manifest if it is not listed.
    pub fn file(&self, dir: &Path, path: &str) -> Result<PathBuf> {
        match self.entry(path) {
            Some(_) => Ok(dir.join(path)),
            None => Err(Error::Input(format!(
                "{}: field `files`: {path} is not listed",
                dir.join(FILE).display()
            ))),
        }
    }
}

impl FileEntry {
    /// Checks the file under `dir`: present (unless ground truth), its size and checksum.
    fn verify(&self, dir: &Path) -> Result {
        if self.path.split('/').any(|p| p == ".." || p.is_empty()) || self.path.starts_with('/') {
            return Err(Error::Input(format!(
                "{}: field `files`: {:?} is not a relative path inside the dataset",
                dir.join(FILE).display(),
                self.path
            )));
        }
        let path = dir.join(&self.path);
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(_) if self.role == Role::Truth && !path.exists() => return Ok(()),
            Err(e) => {
                return Err(Error::Input(format!(
                    "{}: cannot read (listed in {FILE} as a log file): {e}",
                    path.display()
                )));
            }
        };
        if bytes.len() as u64 != self.bytes || sha256(&bytes) != self.sha256 {
            return Err(Error::Input(format!(
                "{}: checksum mismatch: {} bytes, SHA-256 {}; {FILE} lists {} bytes, {} \
                 (the file was changed after the dataset was written)",
                path.display(),
                bytes.len(),
                sha256(&bytes),
                self.bytes,
                self.sha256
            )));
        }
        Ok(())
    }
}
