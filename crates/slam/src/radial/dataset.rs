//! Radial-distance data sets (thesis §4.1.2): one row per contact the front end detected,
//! with its contact features and the anticipated-intersect ground truth (§4.1.2.3).
//!
//! File format (CSV, UTF-8, one header line, then one row per contact; lengths in metres,
//! angles in radians, deflections in ADC counts, numbers in Rust's shortest round-trip
//! notation so that a file read back gives the same values to the bit):
//!
//! | column | meaning |
//! |---|---|
//! | `case` | the recording the contact comes from (e.g. `L065/r07/f1`, `wp03/w1`) |
//! | `object` | what was touched: `rod`, or a catalogue object (`box`, …) in its own frame |
//! | `whisker` | the whisker's tactile-image pixel label (e.g. `C2`) |
//! | `frequency_hz` | whisking frequency |
//! | `truth_radial_m` | anticipated radial distance from the shaft's base |
//! | `truth_angle_rad` | anticipated contact angle (rigid whisker, 1° sweep) |
//! | `onset_angle_rad` | whisk angle at the detected contact onset |
//! | `cp_s` … `wl_m` | the contact features CP, CA, DV, DA, AV, AA, WL ([`ContactFeatures`]) |
//! | `base_x/y/z` | the shaft's base at the onset angle (object frame, m) |
//! | `dir_x/y/z` | the shaft's unit direction at the onset angle |
//!
//! A contact localised at radial distance r is `base + r·dir` (Eq 5.1–5.2).

use crate::csv_records::LineError;
use crate::frontend::features::ContactFeatures;
use nalgebra::{Point3, Vector3};

/// One contact of a data set.
#[derive(Debug, Clone, PartialEq)]
pub struct RadialSample {
    /// The recording it comes from.
    pub case: String,
    /// What was touched (`rod` or a catalogue object name).
    pub object: String,
    /// Pixel label of the whisker.
    pub whisker: String,
    /// Whisking frequency (Hz).
    pub frequency_hz: f64,
    /// Anticipated radial distance (m).
    pub truth_radial_m: f64,
    /// Anticipated contact angle (rad).
    pub truth_angle_rad: f64,
    /// Whisk angle at the detected onset (rad).
    pub onset_angle_rad: f64,
    /// The contact features.
    pub features: ContactFeatures,
    /// Shaft base at the onset angle (object frame).
    pub base: Point3<f64>,
    /// Unit shaft direction at the onset angle.
    pub direction: Vector3<f64>,
}

impl RadialSample {
    /// The contact localised at radial distance `r` (Eq 5.1–5.2).
    pub fn point_at(&self, r: f64) -> Point3<f64> {
        self.base + self.direction * r
    }
}

/// The header line of the format.
pub const HEADER: &str = "case,object,whisker,frequency_hz,truth_radial_m,truth_angle_rad,\
onset_angle_rad,cp_s,ca_counts,dv_counts_per_s,da_counts_per_s2,av_rad_per_s,aa_rad_per_s2,\
wl_m,base_x,base_y,base_z,dir_x,dir_y,dir_z";

/// Writes samples in the documented format.
pub fn to_csv(samples: &[RadialSample]) -> String {
    let mut out = String::with_capacity(200 * (samples.len() + 1));
    out.push_str(HEADER);
    out.push('\n');
    for s in samples {
        let f = &s.features;
        let numbers = [
            s.frequency_hz,
            s.truth_radial_m,
            s.truth_angle_rad,
            s.onset_angle_rad,
            f.cp,
            f.ca,
            f.dv,
            f.da,
            f.av,
            f.aa,
            f.wl,
            s.base.x,
            s.base.y,
            s.base.z,
            s.direction.x,
            s.direction.y,
            s.direction.z,
        ];
        out.push_str(&format!("{},{},{}", s.case, s.object, s.whisker));
        for v in numbers {
            out.push_str(&format!(",{v}"));
        }
        out.push('\n');
    }
    out
}

/// Reads the documented format; errors name the line (1-based) and the column.
pub fn from_csv(text: &str) -> Result<Vec<RadialSample>, LineError> {
    let columns: Vec<&str> = HEADER.split(',').collect();
    match text.lines().next() {
        Some(h) if h.trim_end() == HEADER => {}
        Some(h) => {
            return Err(LineError::at(
                1,
                format!(
                    "expected the header `{HEADER}`, got `{}`",
                    h.chars().take(80).collect::<String>()
                ),
            ));
        }
        None => {
            return Err(LineError {
                line: None,
                message: "the file is empty (expected a header line)".into(),
            });
        }
    }
    let mut out = Vec::new();
    for (line, record) in crate::csv_records::records(text) {
        // Blank lines are skipped; trailing white space is not part of the last value.
        let mut cells: Vec<&str> = record.iter().collect();
        if let Some(last) = cells.last_mut() {
            *last = last.trim_end();
        }
        if cells.len() == 1 && cells[0].trim().is_empty() {
            continue;
        }
        if cells.len() != columns.len() {
            return Err(LineError::at(
                line,
                format!(
                    "expected {} comma-separated values, got {}",
                    columns.len(),
                    cells.len()
                ),
            ));
        }
        let mut v = [0.0; 17];
        for (k, cell) in cells[3..].iter().enumerate() {
            v[k] = cell
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    LineError::at(
                        line,
                        format!(
                            "column `{}`: expected a finite number, got {cell:?}",
                            columns[k + 3]
                        ),
                    )
                })?;
        }
        let direction = Vector3::new(v[14], v[15], v[16]);
        if (direction.norm() - 1.0).abs() > 1e-6 {
            return Err(LineError::at(
                line,
                format!(
                    "columns `dir_x/y/z`: expected a unit vector, got length {}",
                    direction.norm()
                ),
            ));
        }
        if !(v[1] >= 0.0 && v[10] > 0.0) {
            return Err(LineError::at(
                line,
                "expected truth_radial_m ≥ 0 and wl_m > 0",
            ));
        }
        out.push(RadialSample {
            case: cells[0].to_string(),
            object: cells[1].to_string(),
            whisker: cells[2].to_string(),
            frequency_hz: v[0],
            truth_radial_m: v[1],
            truth_angle_rad: v[2],
            onset_angle_rad: v[3],
            features: ContactFeatures {
                cp: v[4],
                ca: v[5],
                dv: v[6],
                da: v[7],
                av: v[8],
                aa: v[9],
                wl: v[10],
            },
            base: Point3::new(v[11], v[12], v[13]),
            direction,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(k: f64) -> RadialSample {
        RadialSample {
            case: format!("L065/r{k}"),
            object: "rod".into(),
            whisker: "A1".into(),
            frequency_hz: 0.1 + k / 3.0,
            truth_radial_m: 0.025 * k,
            truth_angle_rad: 1.2345678901234567,
            onset_angle_rad: std::f64::consts::PI / 3.0,
            features: ContactFeatures {
                cp: 0.1 / 3.0,
                ca: 2047.0,
                dv: 1e5 / 7.0,
                da: -3.5e-7,
                av: 1.0 / 9.0,
                aa: 12.25,
                wl: 0.065,
            },
            base: Point3::new(0.1, -0.2, 1.0 / 3.0),
            direction: Vector3::new(1.0, 2.0, 2.0) / 3.0,
        }
    }

    #[test]
    fn a_written_set_reads_back_to_the_bit() {
        let set: Vec<RadialSample> = (0..5).map(|k| sample(k as f64)).collect();
        assert_eq!(from_csv(&to_csv(&set)).unwrap(), set);
    }

    #[test]
    fn malformed_files_name_the_line_and_column() {
        let good = to_csv(&[sample(1.0)]);
        let bad_number = good.replacen("2047", "2o47", 1);
        let e = from_csv(&bad_number).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("`ca_counts`"), "{e}");
        let nan = good.replacen("2047", "NaN", 1);
        assert!(from_csv(&nan).unwrap_err().to_string().contains("finite"));
        let short = good.replacen(",0.065", "", 1);
        let e = from_csv(&short).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("expected 20"), "{e}");
        assert!(from_csv("").unwrap_err().to_string().contains("empty"));
        assert!(
            from_csv("a,b\n")
                .unwrap_err()
                .to_string()
                .contains("line 1")
        );
        let not_unit = good.replacen(&format!(",{}\n", 2.0 / 3.0), ",5\n", 1);
        assert!(
            from_csv(&not_unit)
                .unwrap_err()
                .to_string()
                .contains("unit vector")
        );
    }
}
