//! One process per batch directory (issue #68): an advisory lock on `DIR/.lock`, held for
//! as long as a process works on the batch.
//!
//! - `whisker trials` (new or `--resume`) and `whisker trials merge … --out DIR` take it
//!   exclusively ([`Lock::exclusive`]) and write their holder — pid, host, command, start
//!   time — into the file; a second such process on the directory is refused (exit 2)
//!   with that holder named.
//! - `whisker trials report DIR` and `merge` reading its shards take it shared
//!   ([`Lock::shared`]): any number of readers, refused while a writer holds it.
//! - The lock is the operating system's (`flock(2)` through [`std::fs::File::try_lock`]):
//!   it goes with the process, so a batch killed by SIGKILL, an OOM kill or a node crash
//!   never blocks the next `--resume`; the file stays behind, harmless.
//!
//! **Shared file systems.** On Linux, `flock` on an NFS mount is sent to the server as a
//! whole-file POSIX lock (since kernel 2.6.12), so it holds between nodes of a cluster
//! when the mount has locking (NFSv4, or NFSv3 with the lock manager `lockd`/`rpc.statd`
//! running); a mount with `-o nolock` or `local_lock=all|flock` keeps locks on each node,
//! and two nodes could then both work on a batch. Lustre needs `-o flock` (with
//! `localflock` it is node-local); GPFS/Spectrum Scale and BeeGFS honour `flock` across
//! nodes. The scripts of `whisker trials slurm` give every array task its own shard
//! directory, so they do not rely on it; it guards against a person (or a requeued task
//! racing its predecessor) starting a second process on the same directory.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;
use whisker_scenario::{Error, Result};

/// The lock file of a batch directory.
pub const FILE: &str = ".lock";

/// A held lock; released when dropped (or when the process ends, however it ends).
#[derive(Debug)]
pub struct Lock {
    _file: File,
}

impl Lock {
    /// Takes `dir`'s lock exclusively, recording this process (its command line) as the
    /// holder, or says who holds it (exit 2).
    pub fn exclusive(dir: &Path) -> Result<Self> {
        let mut file = open(dir)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(held(dir, &mut file)),
            Err(TryLockError::Error(e)) => return Err(failure(dir, e)),
        }
        let command: Vec<String> = std::env::args().collect();
        let holder = format!(
            "pid {} on host {}, `{}`, since {}\n",
            std::process::id(),
            host(),
            command.join(" "),
            jiff::Timestamp::now().strftime("%Y-%m-%d %H:%M:%S UTC")
        );
        file.set_len(0)
            .and_then(|_| file.seek(SeekFrom::Start(0)))
            .and_then(|_| file.write_all(holder.as_bytes()))
            .map_err(|e| failure(dir, e))?;
        whisker_scenario::files::wrote(&dir.join(FILE));
        Ok(Self { _file: file })
    }

    /// Takes `dir`'s lock shared (a reader), or says who holds it exclusively (exit 2).
    pub fn shared(dir: &Path) -> Result<Self> {
        let mut file = open(dir)?;
        match file.try_lock_shared() {
            Ok(()) => Ok(Self { _file: file }),
            Err(TryLockError::WouldBlock) => Err(held(dir, &mut file)),
            Err(TryLockError::Error(e)) => Err(failure(dir, e)),
        }
    }
}

fn open(dir: &Path) -> Result<File> {
    let path = dir.join(FILE);
    OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(|e| failure(dir, e))
}

/// The refusal, naming the holder as its record says.
fn held(dir: &Path, file: &mut File) -> Error {
    let mut holder = String::new();
    let _ = file.read_to_string(&mut holder);
    let holder = holder.trim();
    Error::Input(format!(
        "{} is in use by another whisker process ({}): wait for it to end or stop it, then \
         try again (a process that was killed holds nothing: the lock goes with it)",
        dir.display(),
        if holder.is_empty() {
            "a reader, or one that has just started"
        } else {
            holder
        }
    ))
}

fn failure(dir: &Path, e: std::io::Error) -> Error {
    Error::Failure(format!("cannot lock {}: {e}", dir.join(FILE).display()))
}

/// This machine's name (`/proc/sys/kernel/hostname`, else `$HOSTNAME`).
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A second exclusive lock on a held directory is refused naming the holder's pid; a
    /// reader is refused too; after the holder drops it both succeed, and readers share.
    #[test]
    fn a_held_directory_is_refused_and_released_with_its_holder() {
        let tmp = tempfile::tempdir().unwrap();
        let first = Lock::exclusive(tmp.path()).unwrap();
        let e = Lock::exclusive(tmp.path()).unwrap_err();
        assert!(matches!(e, Error::Input(_)));
        let text = e.to_string();
        assert!(
            text.contains(&format!("pid {} on host", std::process::id())),
            "{text}"
        );
        assert!(matches!(Lock::shared(tmp.path()), Err(Error::Input(_))));
        drop(first);
        let readers = (
            Lock::shared(tmp.path()).unwrap(),
            Lock::shared(tmp.path()).unwrap(),
        );
        assert!(Lock::exclusive(tmp.path()).is_err());
        drop(readers);
        Lock::exclusive(tmp.path()).unwrap();
    }
}
