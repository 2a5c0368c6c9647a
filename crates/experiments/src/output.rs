//! Writing output files without ever leaving a half-written one: every file is written
//! to a temporary sibling and renamed into place once complete.

use crate::error::{Error, Result};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The temporary sibling of `path` that [`write_atomic`] writes first.
pub fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial-{}", std::process::id()))
}

/// Creates `dir` (and parents).
pub fn create_dir(dir: &Path) -> Result {
    fs::create_dir_all(dir).map_err(|e| {
        Error::Failure(format!(
            "cannot create output directory {}: {e}",
            dir.display()
        ))
    })
}

/// Writes `bytes` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result {
    let tmp = temporary(path);
    let result = fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        })
        .and_then(|_| fs::rename(&tmp, path));
    result.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        Error::Failure(format!("cannot write {}: {e}", path.display()))
    })
}

/// Renames a completed temporary file into place.
pub fn commit(tmp: &Path, path: &Path) -> Result {
    fs::rename(tmp, path).map_err(|e| {
        let _ = fs::remove_file(tmp);
        Error::Failure(format!("cannot write {}: {e}", path.display()))
    })
}
