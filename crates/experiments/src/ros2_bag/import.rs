//! Reading a bag back into the dataset it was exported from: each table rebuilt from its
//! row messages, each whisk file from its Hall samples, every other file from its
//! attachment — then checked, file by file, against the SHA-256 its `dataset.json` lists,
//! so a replay from the bag is a replay of the very dataset.

use super::scan::{self, Contents};
use super::table::{Kind, decode_row};
use crate::dataset_format::manifest::{self, Manifest};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result, files};

/// The files a bag carries: path → (bytes, where they came from).
type Rebuilt = BTreeMap<String, (Vec<u8>, String)>;

/// Rebuilds every file of the bag `contents` (read from `file`).
fn rebuild(file: &Path, contents: &Contents) -> Result<Rebuilt> {
    let bad = |m: String| Error::Input(format!("{}: {m}", file.display()));
    let mut out = Rebuilt::new();
    let mut put = |path: String, bytes: Vec<u8>, from: String| -> Result {
        if path.split('/').any(|p| p.is_empty() || p == "..") || path.starts_with('/') {
            return Err(bad(format!("{from}: {path:?} is not a relative path")));
        }
        if out.insert(path.clone(), (bytes, from.clone())).is_some() {
            return Err(bad(format!("{from}: {path} is carried twice")));
        }
        Ok(())
    };
    let mut by_channel: BTreeMap<u16, Vec<&scan::Message>> = BTreeMap::new();
    for m in &contents.messages {
        by_channel.entry(m.channel).or_default().push(m);
    }
    for (id, channel) in &contents.channels {
        let mut messages = by_channel.remove(id).unwrap_or_default();
        let meta = &channel.metadata;
        let topic = &channel.topic;
        if !meta.contains_key("csv_path") && !meta.contains_key("whisk_folder") {
            continue;
        }
        messages.sort_by_key(|m| m.sequence);
        if let Some((i, m)) = messages
            .iter()
            .enumerate()
            .find(|(i, m)| m.sequence as usize != *i)
        {
            return Err(bad(format!(
                "byte {}: topic {topic}: message {i} missing (sequence {} follows)",
                m.offset, m.sequence
            )));
        }
        let data: Vec<&[u8]> = messages.iter().map(|m| m.data.as_slice()).collect();
        if meta.contains_key("whisk_folder") {
            for (path, text) in super::hall::rebuild(topic, meta, &data).map_err(&bad)? {
                put(path, text.into_bytes(), format!("topic {topic}"))?;
            }
            continue;
        }
        let field = |k: &str| {
            meta.get(k)
                .ok_or_else(|| bad(format!("topic {topic}: channel metadata `{k}` missing")))
        };
        let (path, header) = (field("csv_path")?, field("csv_header")?);
        let kinds: Vec<Kind> = field("csv_kinds")?
            .chars()
            .map(Kind::of_letter)
            .collect::<Option<_>>()
            .filter(|k: &Vec<Kind>| k.len() == header.split(',').count())
            .ok_or_else(|| {
                bad(format!(
                    "topic {topic}: csv_kinds does not match csv_header"
                ))
            })?;
        let mut text = format!("{header}\n");
        for (i, m) in messages.iter().enumerate() {
            let line = decode_row(&m.data, &kinds).map_err(|e| {
                bad(format!(
                    "byte {}: topic {topic}: message {i}: {e}",
                    m.offset
                ))
            })?;
            text.push_str(&line);
        }
        put(path.clone(), text.into_bytes(), format!("topic {topic}"))?;
    }
    for (name, data) in &contents.attachments {
        put(name.clone(), data.clone(), format!("attachment {name}"))?;
    }
    Ok(out)
}

/// Writes the dataset a bag carries to `out` (which must not exist), each file checked
/// against its manifest: the same bytes as the dataset exported. Exit 2 for a bag that is
/// not a dataset's export, is damaged, or rebuilds a file that differs.
pub fn import(file: &Path, out: &Path) -> Result<Manifest> {
    if out.exists() {
        return Err(Error::Input(format!(
            "{}: already exists; a dataset is never written over another",
            out.display()
        )));
    }
    let contents = scan::read(file)?;
    let mut rebuilt = rebuild(file, &contents)?;
    let bad = |m: String| Error::Input(format!("{}: {m}", file.display()));
    let Some((text, _)) = rebuilt.remove(manifest::FILE) else {
        return Err(bad(format!(
            "no {} attachment: not the export of a dataset (a run's export is for the ROS \
             tools, it cannot be replayed)",
            manifest::FILE
        )));
    };
    let listed: Manifest = serde_json::from_slice(&text)
        .map_err(|e| bad(format!("attachment {}: {e}", manifest::FILE)))?;
    for entry in &listed.files {
        match rebuilt.get(&entry.path) {
            Some((bytes, from)) => {
                let got = manifest::FileEntry::of(&entry.path, entry.role, bytes);
                if got != *entry {
                    return Err(bad(format!(
                        "{from} rebuilds {} as {} bytes, SHA-256 {}; {} lists {} bytes, {}",
                        entry.path,
                        got.bytes,
                        got.sha256,
                        manifest::FILE,
                        entry.bytes,
                        entry.sha256
                    )));
                }
            }
            None if entry.role == manifest::Role::Truth => {}
            None => {
                return Err(bad(format!(
                    "{} lists the log file {} but the bag carries it nowhere",
                    manifest::FILE,
                    entry.path
                )));
            }
        }
    }
    if let Some((path, (_, from))) = rebuilt
        .iter()
        .find(|(p, _)| listed.entry(p.as_str()).is_none())
    {
        return Err(bad(format!(
            "{from}: {path} is not listed in {}",
            manifest::FILE
        )));
    }
    let staging = files::temporary(out);
    let _ = std::fs::remove_dir_all(&staging);
    let written = (|| {
        files::create_dir(&staging)?;
        for (path, (bytes, _)) in rebuilt
            .iter()
            .chain([(&manifest::FILE.to_string(), &(text.clone(), String::new()))])
        {
            let full = staging.join(path);
            files::create_dir(full.parent().expect("inside staging"))?;
            std::fs::write(&full, bytes).map_err(|e| Error::output(&full, e))?;
        }
        let m = Manifest::read(&staging)?;
        std::fs::rename(&staging, out).map_err(|e| Error::output(out, e))?;
        Ok(m)
    })();
    if written.is_err() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    written
}

/// A bag unpacked into a temporary dataset directory, removed when dropped.
pub struct Unpacked {
    root: PathBuf,
    /// The dataset's directory.
    pub dir: PathBuf,
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.root);
    }
}

/// Unpacks the bag `file` into a temporary directory ([`import`]) for a replay.
pub fn unpack(file: &Path) -> Result<Unpacked> {
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let root = std::env::temp_dir().join(format!("whisker-mcap-{}-{stamp}", std::process::id()));
    let dir = root.join(
        file.file_stem()
            .map_or("dataset".into(), |s| s.to_string_lossy().into_owned()),
    );
    let unpacked = Unpacked {
        root: root.clone(),
        dir: dir.clone(),
    };
    std::fs::create_dir_all(&root).map_err(|e| Error::output(&root, e))?;
    import(file, &dir)?;
    Ok(unpacked)
}
