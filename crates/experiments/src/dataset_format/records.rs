//! The record files shared by every experiment's dataset (docs/dataset.md): whisk files
//! (one whisk cycle's 2 kHz samples of every whisker, the lab layout of §3.1.3), contact
//! files (the contacts of every whisk) and the 1 Hz pose log (§3.1.2).

use super::table::{Row, Table, columns};
use nalgebra::{Isometry3, Point3};
use std::fmt::Write;
use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_slam::contact::{Contact, ContactCycle};
use whisker_slam::sensor::Sample as Reading;

/// The name of whisk file `c` (`whisk_000012.csv`).
pub fn whisk_name(c: usize) -> String {
    format!("whisk_{c:06}.csv")
}

/// The header of a whisk file: `<label>_angle,<label>_x,<label>_y,<label>_spare` for
/// each whisker in order.
pub fn whisk_columns(labels: &[String]) -> Vec<String> {
    labels
        .iter()
        .flat_map(|l| ["angle", "x", "y", "spare"].map(|c| format!("{l}_{c}")))
        .collect()
}

/// A whisk file's text: one row per sample, every value an integer — the angle in
/// counts of `angle_resolution` (rad), the deflections in ADC counts, the spare column 0.
/// An error if a value is not a whole number of counts (the sensor model quantises).
pub fn whisk_csv(
    labels: &[String],
    streams: &[Vec<Reading>],
    angle_resolution: f64,
) -> Result<String> {
    let n = streams.first().map_or(0, Vec::len);
    let mut csv = whisk_columns(labels).join(",");
    csv.reserve(n * streams.len() * 14);
    csv.push('\n');
    let count = |v: f64| -> Result<i64> {
        let k = v.round();
        if k == v && k.abs() < 9.0e15 {
            Ok(k as i64)
        } else {
            Err(Error::Failure(format!(
                "a reading of {v} is not a whole number of counts"
            )))
        }
    };
    for i in 0..n {
        for (w, s) in streams.iter().enumerate() {
            let r = s[i];
            let k = (r.angle_rad / angle_resolution).round();
            if k * angle_resolution != r.angle_rad {
                return Err(Error::Failure(format!(
                    "angle {} rad is not a whole number of {angle_resolution} rad counts",
                    r.angle_rad
                )));
            }
            let sep = if w == 0 { "" } else { "," };
            let _ = write!(csv, "{sep}{},{},{},0", k as i64, count(r.x)?, count(r.y)?);
        }
        csv.push('\n');
    }
    Ok(csv)
}

/// Reads a whisk file of `whiskers` whiskers and exactly `samples` rows.
pub fn read_whisk(
    path: &Path,
    labels: &[String],
    samples: usize,
    angle_resolution: f64,
) -> Result<Vec<Vec<Reading>>> {
    let table = Table::read(path, &whisk_columns(labels))?;
    if table.len() != samples {
        return Err(table.error(
            table.len() + 1,
            format!(
                "expected {samples} samples (rows), got {}: truncated or too long",
                table.len()
            ),
        ));
    }
    let mut streams = vec![Vec::with_capacity(samples); labels.len()];
    for row in table.rows() {
        let row = row?;
        for (w, s) in streams.iter_mut().enumerate() {
            s.push(Reading {
                angle_rad: row.i64(4 * w)? as f64 * angle_resolution,
                x: row.i64(4 * w + 1)? as f64,
                y: row.i64(4 * w + 2)? as f64,
            });
            row.f64(4 * w + 3)?;
        }
    }
    Ok(streams)
}

/// The header of a contacts file.
pub const CONTACT_COLUMNS: &str =
    "whisk,time_s,whisker,label,angle_rad,radial_distance_m,x_m,y_m,z_m,slope";

/// A contacts file's text: one row per contact of every whisk (whisk = the cycle's
/// index; the point in the array frame; the slope may be `inf` or `-inf`: Eq 6.14 is
/// unbounded when the contacted normal lies in the sweep plane).
pub fn contacts_csv(cycles: &[ContactCycle], labels: &[String]) -> String {
    let mut csv = String::from(CONTACT_COLUMNS);
    csv.push('\n');
    for (k, cycle) in cycles.iter().enumerate() {
        for c in &cycle.contacts {
            let p = c.point;
            let _ = writeln!(
                csv,
                "{k},{:?},{},{},{:?},{:?},{:?},{:?},{:?},{:?}",
                c.time_s,
                c.whisker,
                labels[c.whisker],
                c.angle_rad,
                c.radial_distance,
                p.x,
                p.y,
                p.z,
                c.slope
            );
        }
    }
    csv
}

/// Reads a contacts file of `whisks` whisks of `whiskers` whiskers: whisks in
/// non-decreasing order, at most one contact per whisker and whisk, in whisker order.
pub fn read_contacts(path: &Path, whisks: usize, labels: &[String]) -> Result<Vec<ContactCycle>> {
    let table = Table::read(path, &columns(CONTACT_COLUMNS))?;
    let mut cycles: Vec<ContactCycle> = (0..whisks)
        .map(|k| ContactCycle {
            index: k as u64,
            start_s: 0.0,
            array_pose: Isometry3::identity(),
            contacts: Vec::new(),
        })
        .collect();
    let mut last = (0, None::<usize>);
    for row in table.rows() {
        let row = row?;
        let k = row.index(0, whisks)?;
        let w = row.index(2, labels.len())?;
        if row.text(3) != labels[w] {
            return Err(row.error(format!(
                "column 4 (label): expected {} for whisker {w}, got {:?}",
                labels[w],
                row.text(3)
            )));
        }
        if (k, Some(w)) <= last {
            return Err(row
                .error("rows must be in order of whisk, then whisker, one per whisker and whisk"));
        }
        last = (k, Some(w));
        cycles[k].contacts.push(contact(&row, w)?);
    }
    Ok(cycles)
}

fn contact(row: &Row, w: usize) -> Result<Contact> {
    Ok(Contact {
        whisker: w,
        time_s: row.f64(1)?,
        angle_rad: row.f64(4)?,
        radial_distance: row.f64(5)?,
        point: Point3::new(row.f64(6)?, row.f64(7)?, row.f64(8)?),
        slope: row.extended(9)?,
    })
}

/// The header of a true-pose file (object walks, closed loops).
pub const TRUTH_POSE_COLUMNS: &str = "whisk,time_s,x_m,y_m,z_m,qx,qy,qz,qw";

/// A true-pose file's text: each whisk's pose at its time.
pub fn truth_poses_csv(poses: &[Isometry3<f64>], times: &[f64]) -> String {
    let mut csv = String::from(TRUTH_POSE_COLUMNS) + "\n";
    for (k, (p, t)) in poses.iter().zip(times).enumerate() {
        let (v, q) = (p.translation.vector, p.rotation.coords);
        let _ = writeln!(
            csv,
            "{k},{t:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?}",
            v.x, v.y, v.z, q.x, q.y, q.z, q.w
        );
    }
    csv
}

/// The header of the pose log.
pub const POSE_COLUMNS: &str = "time_s,x_m,y_m,z_m,qx,qy,qz,qw,whisk_file";

/// One pose-log row.
pub fn pose_row(time_s: f64, pose: &Isometry3<f64>, whisk: &str) -> String {
    let (t, q) = (pose.translation.vector, pose.rotation.coords);
    format!(
        "{time_s:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{whisk}\n",
        t.x, t.y, t.z, q.x, q.y, q.z, q.w
    )
}

/// Reads the pose log: (time, pose, whisk file) per row, times increasing, quaternions
/// of unit norm (within 1e-6).
pub fn read_poses(path: &Path) -> Result<Vec<(f64, Isometry3<f64>, String)>> {
    let table = Table::read(path, &columns(POSE_COLUMNS))?;
    let mut out: Vec<(f64, Isometry3<f64>, String)> = Vec::with_capacity(table.len());
    for row in table.rows() {
        let row = row?;
        let v: Vec<f64> = (0..8).map(|i| row.f64(i)).collect::<Result<_>>()?;
        if out.last().is_some_and(|p| p.0 >= v[0]) {
            return Err(row.error("column 1 (time_s): times must increase"));
        }
        let q = nalgebra::Quaternion::new(v[7], v[4], v[5], v[6]);
        if (q.norm() - 1.0).abs() > 1e-6 {
            return Err(row.error(format!(
                "columns 5–8 (qx, qy, qz, qw): expected a unit quaternion, norm {}",
                q.norm()
            )));
        }
        // Unit to rounding: taken as written (the same numbers back); else normalised.
        let rotation = if (q.norm() - 1.0).abs() <= 1e-12 {
            nalgebra::UnitQuaternion::new_unchecked(q)
        } else {
            nalgebra::UnitQuaternion::from_quaternion(q)
        };
        let pose = Isometry3::from_parts(nalgebra::Translation3::new(v[1], v[2], v[3]), rotation);
        out.push((v[0], pose, row.text(8).to_string()));
    }
    if out.is_empty() {
        return Err(table.error(2, "expected at least one pose"));
    }
    Ok(out)
}
