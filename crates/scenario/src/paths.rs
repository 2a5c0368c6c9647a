//! Paths in a scenario: inputs are relative to the scenario file.

use std::path::{Path, PathBuf};

/// `p`, resolved against the directory of the scenario `file` unless absolute.
pub fn relative_to(file: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        file.parent().unwrap_or(Path::new("")).join(p)
    }
}
