//! `whisker export --mcap FILE DIR`: a dataset (or a run's output directory) as a ROS 2
//! bag in MCAP — every CSV table as a topic of row messages, the whisk files as Hall
//! samples, the standard views beside them, every other file as an MCAP attachment.

use super::bag::Bag;
use super::table::Table;
use super::{hall, schema, topic, views};
use crate::dataset_format::manifest::{self, Manifest};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result, files};

/// What an export wrote.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Exported {
    pub file: PathBuf,
    /// Size of the MCAP file (bytes).
    pub bytes: u64,
    /// Size of the files it carries (bytes).
    pub source_bytes: u64,
    pub topics: usize,
    pub messages: u64,
    pub attachments: usize,
    /// Files left out (Rerun recordings, hidden files).
    pub skipped: Vec<String>,
    pub seconds: f64,
}

impl std::fmt::Display for Exported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{}: {:.2} MB ({:.1}% of the {:.2} MB it carries), {} topics, {} messages, {} \
             attachments, written in {:.2} s ({:.1} MB/s)",
            self.file.display(),
            self.bytes as f64 / 1e6,
            100.0 * self.bytes as f64 / (self.source_bytes as f64).max(1.0),
            self.source_bytes as f64 / 1e6,
            self.topics,
            self.messages,
            self.attachments,
            self.seconds,
            self.source_bytes as f64 / 1e6 / self.seconds.max(1e-9)
        )?;
        if !self.skipped.is_empty() {
            writeln!(f, "not carried: {}", self.skipped.join(", "))?;
        }
        Ok(())
    }
}

/// What an export carries.
struct Sources {
    /// A dataset's manifest and its text.
    dataset: Option<(Manifest, Vec<u8>)>,
    /// The files to carry (relative paths).
    paths: Vec<String>,
    /// The files left out.
    skipped: Vec<String>,
}

/// The files to carry: a dataset's as its manifest lists them (checked), else every file
/// under `dir` but hidden files and Rerun recordings.
fn sources(dir: &Path) -> Result<Sources> {
    if dir.join(manifest::FILE).exists() {
        let m = Manifest::read(dir)?;
        let text = std::fs::read(dir.join(manifest::FILE))
            .map_err(|e| Error::Input(format!("{}: {e}", dir.display())))?;
        let paths = m
            .files
            .iter()
            .filter(|f| dir.join(&f.path).exists())
            .map(|f| f.path.clone())
            .collect();
        return Ok(Sources {
            dataset: Some((m, text)),
            paths,
            skipped: Vec::new(),
        });
    }
    if !dir.is_dir() {
        return Err(Error::Input(format!(
            "{}: expected a dataset or a run's output directory",
            dir.display()
        )));
    }
    let (mut paths, mut skipped) = (Vec::new(), Vec::new());
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let entries =
            std::fs::read_dir(&d).map_err(|e| Error::Input(format!("{}: {e}", d.display())))?;
        for entry in entries {
            let p = entry
                .map_err(|e| Error::Input(format!("{}: {e}", d.display())))?
                .path();
            let rel = p
                .strip_prefix(dir)
                .expect("under dir")
                .to_string_lossy()
                .replace('\\', "/");
            let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
            if name.is_some_and(|n| n.starts_with('.')) || rel.ends_with(".rrd") {
                skipped.push(rel);
            } else if p.is_dir() {
                stack.push(p);
            } else {
                paths.push(rel);
            }
        }
    }
    paths.sort();
    skipped.sort();
    Ok(Sources {
        dataset: None,
        paths,
        skipped,
    })
}

/// Writes `dir` (a dataset or a run's output) to `file` (which must not exist), through a
/// temporary sibling renamed into place when complete.
pub fn export(dir: &Path, file: &Path) -> Result<Exported> {
    let started = std::time::Instant::now();
    if file.exists() {
        return Err(Error::Input(format!(
            "{}: already exists; an export is never written over a file (choose a new --mcap)",
            file.display()
        )));
    }
    let Sources {
        dataset,
        paths,
        skipped,
    } = sources(dir)?;
    let tmp = files::temporary(file);
    let result = write_bag(dir, &tmp, dataset.as_ref(), &paths);
    let (topics, messages, attachments, source_bytes) = match result {
        Ok(v) => v,
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            return Err(e);
        }
    };
    files::commit(&tmp, file)?;
    let bytes = std::fs::metadata(file).map(|m| m.len()).unwrap_or(0);
    Ok(Exported {
        file: file.to_path_buf(),
        bytes,
        source_bytes,
        topics,
        messages,
        attachments,
        skipped,
        seconds: started.elapsed().as_secs_f64(),
    })
}

fn write_bag(
    dir: &Path,
    tmp: &Path,
    dataset: Option<&(Manifest, Vec<u8>)>,
    paths: &[String],
) -> Result<(usize, u64, usize, u64)> {
    let mut bag = Bag::create(tmp)?;
    let mut meta = BTreeMap::new();
    let mut source_bytes = 0u64;
    let experiment = dataset.map(|(m, _)| m.experiment);
    if let Some((m, text)) = dataset {
        meta.insert("kind".into(), "dataset".into());
        let name = |v: serde_json::Value| v.as_str().unwrap_or_default().to_string();
        meta.insert("experiment".into(), name(serde_json::json!(m.experiment)));
        meta.insert("level".into(), m.level.name().into());
        meta.insert("seed".into(), m.seed.to_string());
        bag.attach(manifest::FILE, text)?;
        source_bytes += text.len() as u64;
    } else {
        meta.insert("kind".into(), "run".into());
    }
    bag.metadata("whisker_slam", meta)?;
    let follicles = bag.channel("/tf_static", &schema::tf_message(), BTreeMap::new())?;
    bag.write(follicles, 0, 0, &views::follicles("array"))?;
    let sensor = dataset.and_then(|(m, _)| m.sensor.map(|s| (s, m.array.labels.clone())));
    let mut whisk_folders: BTreeMap<String, Vec<(usize, String)>> = BTreeMap::new();
    for path in paths {
        let full = dir.join(path);
        let unreadable = |e: std::io::Error| Error::Input(format!("{}: {e}", full.display()));
        if let (Some(_), Some((folder, k))) = (&sensor, super::whisk_file(path)) {
            source_bytes += std::fs::metadata(&full).map_err(unreadable)?.len();
            whisk_folders
                .entry(folder.to_string())
                .or_default()
                .push((k, path.clone()));
            continue;
        }
        let bytes = std::fs::read(&full).map_err(unreadable)?;
        source_bytes += bytes.len() as u64;
        let table = path
            .ends_with(".csv")
            .then(|| std::str::from_utf8(&bytes).ok().and_then(Table::parse))
            .flatten();
        match table {
            Some(mut t) => put_table(&mut bag, path, &bytes, &mut t, experiment)?,
            None => bag.attach(path, &bytes)?,
        }
    }
    if let Some((sensor, labels)) = &sensor {
        for (folder, files) in &whisk_folders {
            hall::put(&mut bag, dir, folder, files, sensor, labels)?;
        }
    }
    let counts = (bag.topics(), bag.messages, bag.attachments, source_bytes);
    bag.finish(tmp)?;
    Ok(counts)
}

/// A table's topic of row messages and its views.
fn put_table(
    bag: &mut Bag,
    path: &str,
    bytes: &[u8],
    t: &mut Table,
    experiment: Option<manifest::Experiment>,
) -> Result {
    let text = std::str::from_utf8(bytes).expect("parsed");
    let header = text.lines().next().expect("a header");
    let name = topic(path);
    // The type first: a known table's columns take their declared kinds.
    let ty = super::known::type_of(path, header, t);
    let meta = BTreeMap::from([
        ("csv_path".to_string(), path.to_string()),
        ("csv_header".to_string(), header.to_string()),
        ("csv_kinds".to_string(), t.kinds()),
    ]);
    let frame = frame_of(path, experiment);
    let rows = bag.channel(&name, &schema::row(&ty, &t.columns), meta)?;
    for i in 0..t.rows.len() {
        bag.write(rows, i, t.stamp(i), &t.encode(i, ""))?;
    }
    for (prefix, poses) in views::poses(t) {
        let pose = bag.channel(
            &format!("{name}/{prefix}pose"),
            &schema::pose_stamped(),
            BTreeMap::new(),
        )?;
        let tf = bag.channel("/tf", &schema::tf_message(), BTreeMap::new())?;
        let child = match prefix.trim_end_matches('_') {
            "" => frame.clone(),
            p => format!("{frame}_{p}"),
        };
        for (i, (stamp, p)) in poses.iter().enumerate() {
            bag.write(pose, i, *stamp, &views::pose_stamped(*stamp, "world", p))?;
            let transform = views::tf(*stamp, &[("world", child.clone(), *p)]);
            bag.write(tf, i, *stamp, &transform)?;
        }
    }
    if let Some(joints) = views::arm_joints(t) {
        let names: Vec<String> = views::ARM_JOINTS.iter().map(|s| s.to_string()).collect();
        let js = bag.channel(
            &format!("{name}/joint_states"),
            &schema::joint_state(),
            BTreeMap::new(),
        )?;
        for (i, (stamp, q)) in joints.iter().enumerate() {
            bag.write(js, i, *stamp, &views::joint_state(*stamp, &names, q))?;
        }
    }
    Ok(())
}

/// The `/tf` child frame of a pose table: the array (the mobile base in an office run) for
/// the pose log and a run's `explore.csv`, the base for an office run's `path.csv`, `…_true`
/// for ground truth, else the table's path; a prefixed group (`est_x_m` …) adds its prefix
/// (`base_est`).
fn frame_of(path: &str, experiment: Option<manifest::Experiment>) -> String {
    let body = if experiment == Some(manifest::Experiment::Navigate) {
        "base"
    } else {
        "array"
    };
    match path {
        "log/poses.csv" | "explore.csv" => body.into(),
        "path.csv" => "base".into(),
        "truth/poses.csv" => format!("{body}_true"),
        _ => path.trim_end_matches(".csv").to_string(),
    }
}
