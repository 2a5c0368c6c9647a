//! The whisk files (docs/dataset.md, level streams) as `whisker_slam_msgs/msg/HallSample`
//! messages, one per 2 kHz sample, and back to the same files; with each sample's whisk
//! angles as a `sensor_msgs/JointState` view.

use super::bag::Bag;
use super::cdr::{Decoder, Encoder};
use super::table::stamp_ns;
use super::{schema, views};
use crate::dataset_format::manifest::SensorInfo;
use crate::dataset_format::records::{whisk_columns, whisk_name};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;
use whisker_scenario::{Error, Result};

/// The Hall topic of whisk folder `folder` (`log/whisks` → `/log/whisks/hall`).
pub fn topic(folder: &str) -> String {
    super::topic(folder) + "/hall"
}

/// Writes the whisk files `files` ((whisk, path) in any order) of `folder` as one topic:
/// sample `i` of whisk `k` stamped (k + (i+1)/n)/f s; sequence numbers count samples.
pub fn put(
    bag: &mut Bag,
    dir: &Path,
    folder: &str,
    files: &[(usize, String)],
    sensor: &SensorInfo,
    labels: &[String],
) -> Result {
    let n = sensor.samples_per_whisk;
    let meta = BTreeMap::from([
        ("whisk_folder".to_string(), folder.to_string()),
        ("labels".to_string(), labels.join(",")),
        ("samples_per_whisk".to_string(), n.to_string()),
    ]);
    let hall = bag.channel(&topic(folder), &schema::hall_sample(), meta)?;
    let angles = bag.channel(
        &(super::topic(folder) + "/joint_states"),
        &schema::joint_state(),
        BTreeMap::new(),
    )?;
    let names: Vec<String> = labels.iter().map(|l| format!("whisk_{l}")).collect();
    let header = whisk_columns(labels).join(",");
    let mut files = files.to_vec();
    files.sort();
    let mut sequence = 0;
    for (k, path) in &files {
        let full = dir.join(path);
        let text = std::fs::read_to_string(&full)
            .map_err(|e| Error::Input(format!("{}: {e}", full.display())))?;
        let mut lines = text.lines();
        if lines.next() != Some(header.as_str()) {
            return Err(Error::Input(format!(
                "{}: line 1: expected the whisk file header",
                full.display()
            )));
        }
        for (i, line) in lines.enumerate() {
            let values: Vec<i32> = line
                .split(',')
                .map(|v| v.parse::<i32>().ok().filter(|p| p.to_string() == v))
                .collect::<Option<_>>()
                .filter(|v: &Vec<i32>| v.len() == 4 * labels.len())
                .ok_or_else(|| {
                    Error::Input(format!(
                        "{}: line {}: expected {} integers",
                        full.display(),
                        i + 2,
                        4 * labels.len()
                    ))
                })?;
            let stamp = stamp_ns((*k as f64 + (i + 1) as f64 / n as f64) / sensor.whisk_hz);
            let mut e = Encoder::new();
            e.header(stamp, "array");
            e.u32(*k as u32);
            e.u32(i as u32);
            for part in 0..4 {
                e.count(labels.len());
                for w in 0..labels.len() {
                    e.i32(values[4 * w + part]);
                }
            }
            bag.write(hall, sequence, stamp, &e.finish())?;
            let positions: Vec<f64> = (0..labels.len())
                .map(|w| f64::from(values[4 * w]) * sensor.angle_resolution_rad)
                .collect();
            bag.write(
                angles,
                sequence,
                stamp,
                &views::joint_state(stamp, &names, &positions),
            )?;
            sequence += 1;
        }
    }
    Ok(())
}

/// The whisk files of one Hall topic: (path, text) per whisk, from its messages in
/// sequence order and its channel's metadata.
pub fn rebuild(
    topic: &str,
    meta: &BTreeMap<String, String>,
    messages: &[&[u8]],
) -> std::result::Result<Vec<(String, String)>, String> {
    let field = |k: &str| {
        meta.get(k)
            .ok_or_else(|| format!("topic {topic}: channel metadata `{k}` missing"))
    };
    let folder = field("whisk_folder")?;
    let labels: Vec<String> = field("labels")?.split(',').map(str::to_string).collect();
    let n: usize = field("samples_per_whisk")?
        .parse()
        .map_err(|_| format!("topic {topic}: samples_per_whisk is not a number"))?;
    let header = whisk_columns(&labels).join(",") + "\n";
    // (path, text, rows so far) per whisk file.
    let mut files: Vec<(String, String, usize)> = Vec::new();
    for (s, data) in messages.iter().enumerate() {
        let bad = |m: String| format!("topic {topic}: message {s}: {m}");
        let mut d = Decoder::new(data).map_err(bad)?;
        d.header().map_err(bad)?;
        let k = d.u32("whisk").map_err(bad)? as usize;
        let i = d.u32("sample").map_err(bad)? as usize;
        let mut parts: Vec<Vec<i32>> = Vec::with_capacity(4);
        for what in ["angle", "x", "y", "spare"] {
            let len = d.count(what).map_err(bad)?;
            if len != labels.len() {
                return Err(bad(format!(
                    "{what}: {len} whiskers, expected {}",
                    labels.len()
                )));
            }
            let values = (0..len).map(|_| d.i32(what));
            parts.push(values.collect::<std::result::Result<_, _>>().map_err(bad)?);
        }
        d.end().map_err(bad)?;
        let path = format!("{folder}/{}", whisk_name(k));
        if i == 0 {
            files.push((path.clone(), header.clone(), 0));
        }
        let Some((p, text, rows)) = files
            .last_mut()
            .filter(|(p, _, r)| *p == path && *r == i && i < n)
        else {
            return Err(bad(format!(
                "whisk {k} sample {i} out of order (each whisk's {n} samples in order)"
            )));
        };
        let _ = p;
        for (w, a) in parts[0].iter().enumerate() {
            let sep = if w > 0 { "," } else { "" };
            let (x, y, z) = (parts[1][w], parts[2][w], parts[3][w]);
            let _ = write!(text, "{sep}{a},{x},{y},{z}");
        }
        text.push('\n');
        *rows += 1;
    }
    if let Some((p, _, rows)) = files.iter().find(|(_, _, r)| *r != n) {
        return Err(format!(
            "topic {topic}: {p} has {rows} samples, expected {n}: truncated"
        ));
    }
    Ok(files.into_iter().map(|(p, t, _)| (p, t)).collect())
}
