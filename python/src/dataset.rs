//! A dataset (docs/dataset.md) read into numpy arrays by the Rust readers that `whisker
//! slam` uses — the same checks, the same values, no copying through CSV in Python.

use crate::raise;
use numpy::IntoPyArray;
use numpy::ndarray::{Array2, Array4};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;
use whisker_experiments::dataset_format::manifest::{FILE, Manifest, Role};
use whisker_experiments::dataset_format::records::{CONTACT_COLUMNS, read_poses};
use whisker_experiments::dataset_format::table::Table;
use whisker_experiments::dataset_format::whisk_streams;

/// The dataset in `path`: a dict with `manifest` (dataset.json's text), `streams` ({folder:
/// (whisks, samples, whiskers, 3) array of whisk angle in rad and x, y deflection in Hall
/// counts}; level `streams` only), `contacts` ({file: {column: array}} for every
/// `contacts.csv` of the log; `point_m` (n, 3) in the array frame) and `poses` ({file: {"time_s": (n,),
/// "pose": (n, 7) [x, y, z, qx, qy, qz, qw], "whisk": [str]}} for every `poses.csv` of the log; ground truth is left to the files). Every
/// file is checked as `whisker slam` checks it; errors raise `InputError` naming the file
/// and line. The GIL is released while it reads.
#[pyfunction]
pub fn load_dataset<'py>(py: Python<'py>, path: String) -> PyResult<Bound<'py, PyDict>> {
    let dir = PathBuf::from(&path);
    let read = py.detach(|| read(&dir)).map_err(raise)?;
    let d = PyDict::new(py);
    d.set_item("manifest", read.manifest)?;
    let streams = PyDict::new(py);
    for (folder, a) in read.streams {
        streams.set_item(folder, a.into_pyarray(py))?;
    }
    d.set_item("streams", streams)?;
    let contacts = PyDict::new(py);
    for (file, c) in read.contacts {
        let t = PyDict::new(py);
        t.set_item("whisk", c.whisk.into_pyarray(py))?;
        t.set_item("time_s", c.time_s.into_pyarray(py))?;
        t.set_item("whisker", c.whisker.into_pyarray(py))?;
        t.set_item("label", c.label)?;
        t.set_item("angle_rad", c.angle_rad.into_pyarray(py))?;
        t.set_item("radial_distance_m", c.radial.into_pyarray(py))?;
        t.set_item("point_m", c.point.into_pyarray(py))?;
        t.set_item("slope", c.slope.into_pyarray(py))?;
        contacts.set_item(file, t)?;
    }
    d.set_item("contacts", contacts)?;
    let poses = PyDict::new(py);
    for (file, (time, pose, whisk)) in read.poses {
        let t = PyDict::new(py);
        t.set_item("time_s", time.into_pyarray(py))?;
        t.set_item("pose", pose.into_pyarray(py))?;
        t.set_item("whisk", whisk)?;
        poses.set_item(file, t)?;
    }
    d.set_item("poses", poses)?;
    Ok(d)
}

/// One contacts file's columns.
struct Contacts {
    whisk: Vec<i64>,
    time_s: Vec<f64>,
    whisker: Vec<i64>,
    label: Vec<String>,
    angle_rad: Vec<f64>,
    radial: Vec<f64>,
    point: Array2<f64>,
    slope: Vec<f64>,
}

type Poses = (Vec<f64>, Array2<f64>, Vec<String>);

/// What [`load_dataset`] returns, read without the GIL.
struct Read {
    manifest: String,
    streams: BTreeMap<String, Array4<f64>>,
    contacts: BTreeMap<String, Contacts>,
    poses: BTreeMap<String, Poses>,
}

fn read(dir: &std::path::Path) -> whisker_scenario::Result<Read> {
    let m = Manifest::read(dir)?;
    let manifest = std::fs::read_to_string(dir.join(FILE)).map_err(|e| {
        whisker_scenario::Error::Input(format!("{}: {e}", dir.join(FILE).display()))
    })?;
    // Whisk files by folder, numbered from 0.
    let mut folders: BTreeMap<String, usize> = BTreeMap::new();
    for f in &m.files {
        if let Some((folder, name)) = f.path.rsplit_once('/')
            && name.starts_with("whisk_")
        {
            *folders.entry(folder.to_string()).or_default() += 1;
        }
    }
    let mut streams = BTreeMap::new();
    for (folder, n) in folders {
        let mut flat = Vec::new();
        let (mut samples, mut whiskers) = (0, 0);
        for k in 0..n {
            // A gap in the numbering is named by the missing file (`Manifest::file`).
            let s = whisk_streams(dir, &m, &folder, k)?;
            whiskers = s.len();
            samples = s.first().map_or(0, Vec::len);
            for i in 0..samples {
                for w in &s {
                    flat.extend([w[i].angle_rad, w[i].x, w[i].y]);
                }
            }
        }
        let a = Array4::from_shape_vec((n, samples, whiskers, 3), flat)
            .expect("every whisk file has the manifest's samples and whiskers");
        streams.insert(folder, a);
    }
    let mut contacts = BTreeMap::new();
    let mut poses = BTreeMap::new();
    for f in m.files.iter().filter(|f| f.role == Role::Log) {
        let path = m.file(dir, &f.path)?;
        if f.path.ends_with("contacts.csv") {
            contacts.insert(f.path.clone(), read_contacts(&path)?);
        } else if f.path.ends_with("poses.csv") {
            let rows = read_poses(&path)?;
            let flat: Vec<f64> = rows
                .iter()
                .flat_map(|(_, p, _)| super::pose::to_array(p))
                .collect();
            let pose = Array2::from_shape_vec((rows.len(), 7), flat).expect("7 numbers a pose");
            poses.insert(
                f.path.clone(),
                (
                    rows.iter().map(|r| r.0).collect(),
                    pose,
                    rows.into_iter().map(|r| r.2).collect(),
                ),
            );
        }
    }
    Ok(Read {
        manifest,
        streams,
        contacts,
        poses,
    })
}

fn read_contacts(path: &std::path::Path) -> whisker_scenario::Result<Contacts> {
    let columns: Vec<String> = CONTACT_COLUMNS.split(',').map(String::from).collect();
    let table = Table::read(path, &columns)?;
    let mut c = Contacts {
        whisk: Vec::new(),
        time_s: Vec::new(),
        whisker: Vec::new(),
        label: Vec::new(),
        angle_rad: Vec::new(),
        radial: Vec::new(),
        point: Array2::zeros((table.len(), 3)),
        slope: Vec::new(),
    };
    for (i, row) in table.rows().enumerate() {
        let row = row?;
        c.whisk.push(row.i64(0)?);
        c.time_s.push(row.f64(1)?);
        c.whisker.push(row.i64(2)?);
        c.label.push(row.text(3).to_string());
        c.angle_rad.push(row.f64(4)?);
        c.radial.push(row.f64(5)?);
        for j in 0..3 {
            c.point[(i, j)] = row.f64(6 + j)?;
        }
        c.slope.push(row.f64(9)?);
    }
    Ok(c)
}
