//! Seeded datasets in the thesis lab's own log layout (§3.1.2–§3.1.3), with ground truth
//! beside it, and SLAM that runs from them as it would from a real robot's logs. The
//! format is specified in `docs/dataset.md`; in short:
//!
//! ```text
//! DIR/dataset.json          manifest: format version, experiment, level, seed, array,
//!                           sensors, noise, the experiment's parameters, every file's SHA-256
//! DIR/log/whisks/whisk_NNNNNN.csv   (level "streams") one file per whisk cycle: one row
//!                           per 2 kHz sample, 4 columns per whisker (angle, x and y
//!                           deflection, spare) in the order A1…F1, A2…F2, A3…F3
//! DIR/log/contacts.csv      (level "contacts") the contacts of every whisk
//! DIR/log/poses.csv         the end effector's pose at 1 Hz and the latest whisk file
//! DIR/log/odometry.csv      the odometry SLAM consumes, one row per update
//! DIR/truth/…               ground truth: true poses, noise-free odometry, anticipated
//!                           contacts, the scenario as run
//! ```
//!
//! `whisker dataset SCENARIO --seed N --out DIR` writes one ([`write`]); `whisker dataset
//! noise IN --seed M --out OUT` adds noise to a clean one ([`noise`]); `whisker
//! maze-slam --dataset DIR` and `whisker slam DIR` run SLAM from one. A dataset is
//! written into a temporary sibling directory and renamed into place when complete; an
//! existing `--out` is never overwritten.

pub mod manifest;
pub mod records;
pub mod sections;
pub mod table;
pub mod whisks;

use manifest::{FileEntry, Manifest, Role};
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};

/// What was written: a dataset's directory, its manifest and the time it took.
#[derive(Debug, Clone)]
pub struct Written {
    pub out: PathBuf,
    pub manifest: Manifest,
    pub seconds: f64,
}

impl std::fmt::Display for Written {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let bytes: u64 = self.manifest.files.iter().map(|f| f.bytes).sum();
        writeln!(
            f,
            "{}: {} files, {:.1} MB ({} level, seed {}), written in {:.1} s ({:.1} MB/s)",
            self.out.display(),
            self.manifest.files.len() + 1,
            bytes as f64 / 1e6,
            self.manifest.level.name(),
            self.manifest.seed,
            self.seconds,
            bytes as f64 / 1e6 / self.seconds.max(1e-9),
        )
    }
}

/// [`write`], timed.
pub fn timed(out: &Path, fill: impl FnOnce(&mut Staging) -> Result<Manifest>) -> Result<Written> {
    let started = std::time::Instant::now();
    let manifest = write(out, fill)?;
    Ok(Written {
        out: out.to_path_buf(),
        manifest,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The files of a dataset being written into a staging directory.
pub struct Staging {
    dir: PathBuf,
    files: Vec<FileEntry>,
}

impl Staging {
    /// Writes `bytes` to `path` (relative, `/`-separated) and lists it with its checksum.
    pub fn put(&mut self, path: &str, role: Role, bytes: &[u8]) -> Result {
        let full = self.dir.join(path);
        if let Some(parent) = full.parent() {
            whisker_scenario::files::create_dir(parent)?;
        }
        std::fs::write(&full, bytes).map_err(|e| Error::output(&full, e))?;
        self.files.push(FileEntry::of(path, role, bytes));
        Ok(())
    }

    /// The staging directory's path of `path` (relative).
    pub fn path(&self, path: &str) -> PathBuf {
        self.dir.join(path)
    }

    /// Lists a file already written at `path` (relative) with its checksum.
    pub fn register(&mut self, path: &str, role: Role) -> Result {
        let bytes = std::fs::read(self.dir.join(path))
            .map_err(|e| Error::Failure(format!("cannot read back {path}: {e}")))?;
        self.files.push(FileEntry::of(path, role, &bytes));
        Ok(())
    }
}

/// Writes a dataset to `out` (which must not exist): `fill` writes the files into a
/// staging directory and returns the manifest (its file list is filled in here); the
/// staging directory is renamed to `out` once `dataset.json` is written, and removed on
/// any error.
pub fn write(out: &Path, fill: impl FnOnce(&mut Staging) -> Result<Manifest>) -> Result<Manifest> {
    if out.exists() {
        return Err(Error::Input(format!(
            "{}: already exists; a dataset is never written over another (choose a new --out)",
            out.display()
        )));
    }
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "dataset".into());
    let staging = out.with_file_name(format!(".{name}.partial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&staging);
    whisker_scenario::files::create_dir(&staging)?;
    let mut s = Staging {
        dir: staging.clone(),
        files: Vec::new(),
    };
    let result = fill(&mut s).and_then(|mut manifest| {
        manifest.files = std::mem::take(&mut s.files);
        let text = serde_json::to_string_pretty(&manifest).expect("plain JSON") + "\n";
        whisker_scenario::files::write_atomic(&staging.join(manifest::FILE), text.as_bytes())?;
        std::fs::rename(&staging, out).map_err(|e| {
            Error::Failure(format!("cannot move the dataset to {}: {e}", out.display()))
        })?;
        whisker_scenario::files::wrote(out);
        Ok(manifest)
    });
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    result
}

/// The whiskers' description for the manifest: labels, lengths and base offsets.
pub fn array_info(
    whiskers: &[whisker_sim::sensing::kinematic::RigidWhisker],
) -> manifest::ArrayInfo {
    manifest::ArrayInfo {
        labels: whiskers.iter().map(|w| w.module.pixel()).collect(),
        lengths_m: whiskers.iter().map(|w| w.module.beam.length).collect(),
        base_offsets_m: whiskers.iter().map(|w| w.base_offset).collect(),
    }
}

/// The standard array's rigid whiskers with the dataset's base offsets; an error if the
/// dataset's array is not the standard one (this build's geometry knows only it).
pub fn rigid_whiskers(
    dir: &Path,
    array: &manifest::ArrayInfo,
) -> Result<Vec<whisker_sim::sensing::kinematic::RigidWhisker>> {
    let modules = whisker_sim::whisker::array::modules();
    let same = modules.len() == array.labels.len()
        && modules.iter().enumerate().all(|(i, m)| {
            m.pixel() == array.labels[i] && (m.beam.length - array.lengths_m[i]).abs() < 1e-9
        });
    if !same {
        return Err(Error::field(
            &dir.join(manifest::FILE),
            "array",
            "expected the standard 18-whisker array (labels A1…F3 and their lengths in order)",
        ));
    }
    Ok(modules
        .into_iter()
        .zip(&array.base_offsets_m)
        .map(|(m, &b)| whisker_sim::sensing::kinematic::RigidWhisker::new(m, b))
        .collect())
}

/// Whisk file `k` of folder `folder` (e.g. `log/whisks`) of the streams dataset in `dir`:
/// every whisker's samples, checked against the manifest's sensor section.
pub fn whisk_streams(
    dir: &Path,
    m: &Manifest,
    folder: &str,
    k: usize,
) -> Result<Vec<Vec<whisker_slam::sensor::Sample>>> {
    let sensor = m.sensor.ok_or_else(|| {
        Error::field(
            &dir.join(manifest::FILE),
            "sensor",
            "level streams needs it",
        )
    })?;
    let path = m.file(dir, &format!("{folder}/{}", records::whisk_name(k)))?;
    records::read_whisk(
        &path,
        &m.array.labels,
        sensor.samples_per_whisk,
        sensor.angle_resolution_rad,
    )
}
