//! Writing output files without ever leaving a half-written one: every file is written
//! to a temporary sibling and renamed into place once complete, and what a command
//! created (directories, files that did not exist) is listed so that a command that fails
//! removes it again ([`discard_created`]): a failed command leaves nothing behind.

use crate::error::{Error, Result};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// What this process created: directories (the top-most one each [`create_dir`] made)
/// and files [`write_atomic`] or [`commit`] put where none was, in order.
static CREATED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Every file this process completed ([`commit`]), in order, whether new or replaced: what
/// the command line lists as written ([`written`]).
static WRITTEN: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The files this process has written so far, in order (each once).
pub fn written() -> Vec<PathBuf> {
    let list = WRITTEN.lock().unwrap_or_else(PoisonError::into_inner);
    let mut seen = std::collections::HashSet::new();
    list.iter().filter(|p| seen.insert(*p)).cloned().collect()
}

/// Lists `path` (a directory renamed into place whole, e.g. a dataset) as written.
pub fn wrote(path: &Path) {
    WRITTEN
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .push(path.to_path_buf());
}

fn created(path: &Path) {
    let mut list = CREATED.lock().unwrap_or_else(PoisonError::into_inner);
    list.push(path.to_path_buf());
}

/// Removes everything this process created, newest first, and forgets it: called by the
/// command line when a command fails (not after trials, whose finished trials are kept
/// for resuming). Directories go with their contents.
pub fn discard_created() {
    let list = std::mem::take(&mut *CREATED.lock().unwrap_or_else(PoisonError::into_inner));
    for path in list.iter().rev() {
        if path.is_dir() {
            let _ = fs::remove_dir_all(path);
        } else {
            let _ = fs::remove_file(path);
        }
    }
}

/// The temporary sibling of `path` that [`write_atomic`] writes first.
pub fn temporary(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial-{}", std::process::id()))
}

/// Creates `dir` (and parents). A path whose existing part is a file, not a directory,
/// is bad input (exit 2); other failures (permissions, a full disk) are failures.
pub fn create_dir(dir: &Path) -> Result {
    // The top-most directory this call creates (removed again if the command fails).
    let first_new = dir
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .take_while(|a| !a.exists())
        .last();
    if let Some(file) = dir.ancestors().find(|a| a.exists() && !a.is_dir()) {
        return Err(Error::Input(format!(
            "cannot create output directory {}: {} is a file, not a directory",
            dir.display(),
            file.display()
        )));
    }
    fs::create_dir_all(dir).map_err(|e| {
        Error::Output(format!(
            "cannot create output directory {}: {e}",
            dir.display()
        ))
    })?;
    if let Some(new) = first_new {
        created(new);
    }
    Ok(())
}

/// The fault hook of the output layer (issue #68's fault tests): with
/// `WHISKER_FAIL_WRITES_FROM=N` in the environment, the N-th [`write_atomic`] of this
/// process (counting from 1) and every later one fail as a full disk would. Never set
/// otherwise.
pub const FAULT_ENV: &str = "WHISKER_FAIL_WRITES_FROM";

/// The writes [`write_atomic`] has begun in this process.
static WRITES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// The injected failure of this write, if [`FAULT_ENV`] asks for one.
fn injected_fault() -> std::io::Result<()> {
    let n = WRITES.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
    match std::env::var(FAULT_ENV)
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        Some(from) if n >= from => Err(std::io::Error::new(
            std::io::ErrorKind::StorageFull,
            format!("No space left on device (injected by {FAULT_ENV}={from})"),
        )),
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result {
    let tmp = temporary(path);
    let result = injected_fault()
        .and_then(|_| fs::File::create(&tmp))
        .and_then(|mut f| {
            f.write_all(bytes)?;
            f.sync_all()
        });
    match result {
        Ok(()) => commit(&tmp, path),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(Error::output(path, e))
        }
    }
}

/// Writes `value` as compact JSON to `path` atomically: the format of
/// `ObjectMap::save`, the way every other output is written.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result {
    // A value that cannot be serialised is the work's failure, not the machine's.
    let text = serde_json::to_string(value)
        .map_err(|e| Error::Failure(format!("cannot write {}: {e}", path.display())))?;
    write_atomic(path, text.as_bytes())
}

/// Renames a completed temporary file into place.
pub fn commit(tmp: &Path, path: &Path) -> Result {
    let new = !path.exists();
    fs::rename(tmp, path).map_err(|e| {
        let _ = fs::remove_file(tmp);
        Error::output(path, e)
    })?;
    if new {
        created(path);
    }
    wrote(path);
    Ok(())
}
