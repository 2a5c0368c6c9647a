//! Tactile-image files of `whisker maze-slam` (`images-<images>-<seed>.csv`): one row per
//! update, `update` then the 18 pixels `A1`…`F1`, `A2`…`F2`, `A3`…`F3` (whisker order,
//! intensity 0–255, 0 = no contact; thesis §3.1.1, Fig 3.2). Written by `--out`, read
//! back by `--images` to re-run RatSLAM on recorded images without sensing again.

use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};
use whisker_slam::ratslam::local_view::{COLUMNS, ROWS, TactileImage};

/// The file of image set `name` (e.g. `open-loop/contact_angle`) and `seed` in `dir`.
pub fn path(dir: &Path, name: &str, seed: u64) -> PathBuf {
    dir.join(format!("images-{}-{seed}.csv", name.replace('/', "-")))
}

/// The header: `update,A1,…,F3`.
fn header() -> String {
    let mut h = String::from("update");
    for row in 1..=ROWS {
        for column in ['A', 'B', 'C', 'D', 'E', 'F'] {
            h += &format!(",{column}{row}");
        }
    }
    h
}

/// The file's text.
pub fn to_csv(images: &[TactileImage]) -> String {
    let mut csv = header();
    csv.push('\n');
    for (k, image) in images.iter().enumerate() {
        csv += &k.to_string();
        for p in image.pixels {
            csv += &format!(",{p}");
        }
        csv.push('\n');
    }
    csv
}

/// Reads a file of `updates` images; errors name the file, the line and what was
/// expected.
pub fn read(path: &Path, updates: usize) -> Result<Vec<TactileImage>> {
    let bad =
        |line: usize, msg: String| Error::Input(format!("{}: line {line}: {msg}", path.display()));
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Input(format!("{}: cannot read images: {e}", path.display())))?;
    if text.lines().next() != Some(header().as_str()) {
        return Err(bad(1, format!("expected the header {}", header())));
    }
    let mut images = Vec::with_capacity(updates);
    for (i, (number, fields)) in whisker_slam::csv_records::records(&text).enumerate() {
        if fields.len() != 1 + ROWS * COLUMNS {
            return Err(bad(
                number,
                format!(
                    "expected {} fields, got {}",
                    1 + ROWS * COLUMNS,
                    fields.len()
                ),
            ));
        }
        if fields[0].trim().parse::<usize>() != Ok(i) {
            return Err(bad(
                number,
                format!("expected update {i}, got {:?}", &fields[0]),
            ));
        }
        let mut image = TactileImage::default();
        for (p, f) in image.pixels.iter_mut().zip(fields.iter().skip(1)) {
            *p = f
                .trim()
                .parse()
                .map_err(|_| bad(number, format!("expected a pixel 0–255, got {f:?}")))?;
        }
        images.push(image);
    }
    if images.len() != updates {
        return Err(Error::Input(format!(
            "{}: expected {updates} updates (the scenario's path), got {}",
            path.display(),
            images.len()
        )));
    }
    Ok(images)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn images_round_trip_and_bad_files_name_the_line() {
        let tmp = tempfile::tempdir().unwrap();
        let images: Vec<TactileImage> = (0..5u8)
            .map(|k| TactileImage {
                pixels: std::array::from_fn(|i| k.wrapping_mul(37).wrapping_add(i as u8 * 14)),
            })
            .collect();
        let file = path(tmp.path(), "rcp/max_angle", 3);
        assert!(file.ends_with("images-rcp-max_angle-3.csv"));
        std::fs::write(&file, to_csv(&images)).unwrap();
        assert_eq!(read(&file, 5).unwrap(), images);
        let e = format!("{:?}", read(&file, 6).unwrap_err());
        assert!(e.contains("expected 6 updates"), "{e}");
        let text = to_csv(&images).replace("\n2,", "\n2,256,");
        std::fs::write(&file, text).unwrap();
        let e = format!("{:?}", read(&file, 5).unwrap_err());
        assert!(e.contains("line 4"), "{e}");
    }
}
