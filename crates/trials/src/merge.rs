//! `whisker trials merge DIR... --out DIR`: the shards of a batch (each a `--shard I/K`
//! directory) made into the directory one unsharded run would have written: the same
//! `trials.csv` bytes, the journal in trial order, every trial's outputs, the report.
//! Refused, naming them, when trials are missing (and which shards were not given) or
//! present twice, or when the directories come from different scenarios.

use crate::journal::{self, Entry, Meta, RUNS};
use crate::lock::Lock;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};

/// The trials found in the shard directories, by key, with the directory of each copy.
type Found<'a> = BTreeMap<String, Vec<(&'a Path, Entry)>>;

/// Merges the shard directories `dirs` into `out` (created; not one of the shards);
/// returns the number of trials.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<usize> {
    let metas: Vec<Meta> = dirs.iter().map(|d| Meta::read(d)).collect::<Result<_>>()?;
    same_batch(dirs, &metas, out)?;
    // No shard may be running, nor anything else working on `out`.
    let _shards: Vec<Lock> = dirs
        .iter()
        .map(|d| Lock::shared(d))
        .collect::<Result<_>>()?;
    whisker_scenario::files::create_dir(out)?;
    let _out = Lock::exclusive(out)?;
    let mut found: Found = BTreeMap::new();
    for d in dirs {
        for e in journal::read(d)? {
            found
                .entry(e.key.clone())
                .or_default()
                .push((d.as_path(), e));
        }
    }
    let problems = problems(&metas, &found);
    if !problems.is_empty() {
        return Err(Error::Input(format!(
            "cannot merge into {}: {}",
            out.display(),
            problems.join("; ")
        )));
    }
    write_merged(&metas[0], found, out)
}

/// Refuses shards of different batches or splits, and an `out` that is one of them.
fn same_batch(dirs: &[PathBuf], metas: &[Meta], out: &Path) -> Result {
    let first = &metas[0];
    for (d, m) in dirs.iter().zip(metas) {
        if m.scenario_hash != first.scenario_hash
            || m.keys != first.keys
            || m.factors != first.factors
        {
            return Err(Error::Input(format!(
                "{} and {} hold different batches (scenario {} vs {}, hash {} vs {})",
                dirs[0].display(),
                d.display(),
                first.scenario,
                m.scenario,
                &first.scenario_hash[..12],
                &m.scenario_hash[..12]
            )));
        }
        if m.shard.map(|s| s.count) != first.shard.map(|s| s.count) {
            return Err(Error::Input(format!(
                "{} is shard {} but {} is shard {}: not parts of one split",
                d.display(),
                m.shard.map_or("none".into(), |s| s.to_string()),
                dirs[0].display(),
                first.shard.map_or("none".into(), |s| s.to_string())
            )));
        }
        if out
            .canonicalize()
            .ok()
            .is_some_and(|out| d.canonicalize().ok() == Some(out))
        {
            return Err(Error::Input(format!(
                "--out {} is one of the shards: choose another directory",
                out.display()
            )));
        }
    }
    Ok(())
}

/// What keeps the shards from making the whole batch: shards not given, trials missing,
/// present twice or not part of the batch.
fn problems(metas: &[Meta], found: &Found) -> Vec<String> {
    let first = &metas[0];
    let mut problems = Vec::new();
    if let Some(count) = first.shard.map(|s| s.count) {
        let given: Vec<usize> = metas
            .iter()
            .filter_map(|m| m.shard.map(|s| s.index))
            .collect();
        let missing: Vec<String> = (0..count)
            .filter(|i| !given.contains(i))
            .map(|i| format!("{i}/{count}"))
            .collect();
        if !missing.is_empty() {
            problems.push(format!("shards not given: {}", missing.join(", ")));
        }
    }
    let missing: Vec<&String> = first
        .keys
        .iter()
        .filter(|k| !found.contains_key(*k))
        .collect();
    if !missing.is_empty() {
        problems.push(format!(
            "{} trials missing: {}{}",
            missing.len(),
            missing
                .iter()
                .take(10)
                .map(|k| k.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            if missing.len() > 10 { ", …" } else { "" }
        ));
    }
    for (key, copies) in found {
        if copies.len() > 1 {
            let dirs: Vec<String> = copies
                .iter()
                .map(|(d, _)| d.display().to_string())
                .collect();
            problems.push(format!("trial {key} is in {}", dirs.join(" and ")));
        }
        if !first.keys.contains(key) {
            problems.push(format!("trial {key} is not part of the batch"));
        }
    }
    problems
}

/// Writes the merged directory: every trial's outputs, the metadata without a shard, the
/// journal in trial order, `trials.csv` and the report.
fn write_merged(first: &Meta, found: Found, out: &Path) -> Result<usize> {
    whisker_scenario::files::create_dir(out)?;
    let mut entries: Vec<(&Path, Entry)> = found.into_values().flatten().collect();
    entries.sort_by_key(|(_, e)| e.index);
    for (d, e) in &entries {
        let from = d.join(RUNS).join(&e.key);
        if from.is_dir() {
            copy_dir(&from, &out.join(RUNS).join(&e.key))?;
        }
    }
    let mut meta = first.clone();
    meta.shard = None;
    meta.write(out)?;
    let entries: Vec<Entry> = entries.into_iter().map(|(_, e)| e).collect();
    journal::rewrite(out, &entries)?;
    whisker_scenario::files::write_atomic(
        &out.join(journal::CSV),
        journal::csv(&meta.factors, &entries).as_bytes(),
    )?;
    crate::report::write(out)?;
    Ok(entries.len())
}

/// Copies the directory tree `from` to `to` (replacing what is there).
fn copy_dir(from: &Path, to: &Path) -> Result {
    let fail = |p: &Path, e: std::io::Error| Error::Failure(format!("{}: {e}", p.display()));
    if to.exists() {
        std::fs::remove_dir_all(to).map_err(|e| fail(to, e))?;
    }
    std::fs::create_dir_all(to).map_err(|e| fail(to, e))?;
    for item in std::fs::read_dir(from).map_err(|e| fail(from, e))? {
        let item = item.map_err(|e| fail(from, e))?;
        let target = to.join(item.file_name());
        if item.path().is_dir() {
            copy_dir(&item.path(), &target)?;
        } else {
            std::fs::copy(item.path(), &target).map_err(|e| fail(&item.path(), e))?;
        }
    }
    Ok(())
}
