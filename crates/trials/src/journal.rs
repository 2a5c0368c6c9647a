//! What a batch keeps on disk (formats in scenarios/README.md, "Batch trials"):
//! - `trials.json`: the batch's metadata — the scenario, its hash, the factors, every
//!   trial key, the shard;
//! - `journal.jsonl`: one JSON line per finished trial, appended and flushed to disk as
//!   each trial ends (the durable record; a line cut short by a kill is dropped);
//! - `trials.csv`: the rows, rewritten from the journal (atomically) after every trial;
//! - `log.txt`: one line as each trial starts and ends (how resume is audited).

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::collections::BTreeSet;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;
use whisker_scenario::grid::{Batch, Shard};
use whisker_scenario::{Error, Result};

/// The metadata file.
pub const META: &str = "trials.json";
/// The journal.
pub const JOURNAL: &str = "journal.jsonl";
/// The table of rows.
pub const CSV: &str = "trials.csv";
/// The start/end log.
pub const LOG: &str = "log.txt";
/// The directory of each trial's own outputs.
pub const RUNS: &str = "runs";

/// `trials.json`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Meta {
    /// Format version (1).
    pub format: u32,
    /// The scenario file as given.
    pub scenario: String,
    /// SHA-256 of the scenario merged over its base, `[trials]` included.
    pub scenario_hash: String,
    /// `trials.experiment`.
    pub experiment: String,
    /// The factors' dotted paths, in the batch's order.
    pub factors: Vec<String>,
    /// Each factor's levels: their labels (as in keys and `trials.csv`) and values (TOML).
    pub levels: Vec<Vec<Level>>,
    /// The metrics the report analyses (`trials.report`; empty: all that vary).
    pub report: Vec<String>,
    /// Every trial key of the whole batch, in order.
    pub keys: Vec<String>,
    /// The part this directory holds, if sharded.
    pub shard: Option<Shard>,
    /// The `whisker` version that ran it.
    pub version: String,
}

impl Meta {
    /// The metadata of `batch` (shard `shard`).
    pub fn of(batch: &Batch, shard: Option<Shard>) -> Self {
        Self {
            format: 1,
            scenario: batch.file.display().to_string(),
            scenario_hash: batch.hash.clone(),
            experiment: format!("{:?}", batch.config.experiment).to_lowercase(),
            factors: batch.factors.iter().map(|f| f.path.clone()).collect(),
            levels: batch
                .factors
                .iter()
                .map(|f| {
                    f.labels
                        .iter()
                        .zip(&f.levels)
                        .map(|(label, value)| Level {
                            label: label.clone(),
                            value: value.to_string(),
                        })
                        .collect()
                })
                .collect(),
            report: batch.config.report.clone(),
            keys: batch.trials.iter().map(|t| t.key.clone()).collect(),
            shard,
            version: env!("CARGO_PKG_VERSION").into(),
        }
    }

    /// Reads `dir/trials.json`.
    pub fn read(dir: &Path) -> Result<Self> {
        let path = dir.join(META);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            Error::Input(format!(
                "{}: cannot read batch metadata: {e}",
                path.display()
            ))
        })?;
        serde_json::from_str(&text)
            .map_err(|e| Error::Input(format!("{}: not batch metadata: {e}", path.display())))
    }

    /// Writes `dir/trials.json` (atomically).
    pub fn write(&self, dir: &Path) -> Result {
        let text = serde_json::to_string_pretty(self).expect("plain JSON") + "\n";
        whisker_scenario::files::write_atomic(&dir.join(META), text.as_bytes())
    }
}

/// One level of a factor.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Level {
    /// As in trial keys and `trials.csv`.
    pub label: String,
    /// The value set (TOML).
    pub value: String,
}

/// How a trial ended.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// It ran and wrote its summary.
    Ok,
    /// It stopped with an error (recorded).
    Failed,
}

impl Status {
    /// As `trials.csv` and `log.txt` write it.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
        }
    }
}

/// One journal line: a finished trial.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Entry {
    /// Position in the batch.
    pub index: usize,
    /// The trial key.
    pub key: String,
    /// The seed.
    pub seed: u64,
    /// Each factor's level label, in the batch's factor order.
    pub levels: Vec<String>,
    /// How it ended.
    pub status: Status,
    /// The error of a failed trial.
    pub error: Option<String>,
    /// The run's summary, flattened (dotted keys).
    pub metrics: Map<String, Value>,
    /// Wall-clock seconds (not part of `trials.csv`).
    pub wall_s: f64,
}

impl Entry {
    /// The entry of a finished trial of `batch`.
    pub fn new(
        batch: &Batch,
        trial: &whisker_scenario::grid::Trial,
        result: Result<Value, String>,
        wall_s: f64,
    ) -> Self {
        let levels = batch
            .factors
            .iter()
            .zip(&trial.levels)
            .map(|(f, &l)| f.labels[l].clone())
            .collect();
        let (status, error, metrics) = match result {
            Ok(summary) => (Status::Ok, None, flatten(&summary)),
            Err(e) => (Status::Failed, Some(e), Map::new()),
        };
        Self {
            index: trial.index,
            key: trial.key.clone(),
            seed: trial.seed,
            levels,
            status,
            error,
            metrics,
            wall_s,
        }
    }
}

/// A JSON value flattened: objects into dotted keys, everything else (arrays included)
/// kept whole.
pub fn flatten(v: &Value) -> Map<String, Value> {
    fn walk(prefix: &str, v: &Value, out: &mut Map<String, Value>) {
        match v {
            Value::Object(m) if !m.is_empty() => {
                for (k, v) in m {
                    let key = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    walk(&key, v, out);
                }
            }
            other => {
                out.insert(prefix.to_string(), other.clone());
            }
        }
    }
    let mut out = Map::new();
    if v.as_object().is_none_or(|m| !m.is_empty()) {
        walk("", v, &mut out);
    }
    out
}

/// Reads `dir/journal.jsonl` (none: empty). A last line cut short (the process killed
/// while appending it) is dropped and cut off the file; any other bad line is an error.
pub fn read(dir: &Path) -> Result<Vec<Entry>> {
    let path = dir.join(JOURNAL);
    let mut file = match OpenOptions::new().read(true).write(true).open(&path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(Error::Failure(format!("{}: {e}", path.display()))),
    };
    let mut text = String::new();
    file.read_to_string(&mut text)
        .map_err(|e| Error::Input(format!("{}: {e}", path.display())))?;
    let complete = text.rfind('\n').map_or(0, |i| i + 1);
    if complete < text.len() {
        file.set_len(complete as u64)
            .and_then(|_| file.seek(SeekFrom::End(0)).map(|_| ()))
            .map_err(|e| Error::output(&path, e))?;
    }
    text[..complete]
        .lines()
        .enumerate()
        .map(|(i, line)| {
            serde_json::from_str(line)
                .map_err(|e| Error::Input(format!("{}: line {}: {e}", path.display(), i + 1)))
        })
        .collect()
}

/// Replaces `dir/journal.jsonl` with `entries` (atomically).
pub fn rewrite(dir: &Path, entries: &[Entry]) -> Result {
    let text: String = entries.iter().map(line).collect();
    whisker_scenario::files::write_atomic(&dir.join(JOURNAL), text.as_bytes())
}

/// An entry as one journal line.
fn line(entry: &Entry) -> String {
    serde_json::to_string(entry).expect("plain JSON") + "\n"
}

/// The keys `dir/log.txt` says finished (`ok` or `failed` lines).
pub fn finished_in_log(dir: &Path) -> BTreeSet<String> {
    std::fs::read_to_string(dir.join(LOG))
        .unwrap_or_default()
        .lines()
        .filter_map(|l| {
            let mut parts = l.split(' ').skip(2);
            match (parts.next(), parts.next()) {
                (Some("ok" | "failed"), Some(key)) => Some(key.to_string()),
                _ => None,
            }
        })
        .collect()
}

/// The journal and log of a batch directory, open for appending.
pub struct Journal {
    journal: File,
    log: File,
}

impl Journal {
    /// Opens (creating) `dir`'s journal and log.
    pub fn open(dir: &Path) -> Result<Self> {
        let open = |name: &str| {
            // Appended line by line (each line complete), so listed as written at once.
            whisker_scenario::files::wrote(&dir.join(name));
            OpenOptions::new()
                .create(true)
                .append(true)
                .open(dir.join(name))
                .map_err(|e| Error::output(&dir.join(name), e))
        };
        let mut log = open(LOG)?;
        // A log line cut short by a kill: end it, so the next line starts on its own.
        let text = std::fs::read(dir.join(LOG)).unwrap_or_default();
        if text.last().is_some_and(|&b| b != b'\n') {
            log.write_all(b"\n")
                .map_err(|e| Error::Output(format!("cannot write {LOG}: {e}")))?;
        }
        Ok(Self {
            journal: open(JOURNAL)?,
            log,
        })
    }

    /// Logs `what` (`start`, `ok`, `failed`) of `key`, flushed.
    pub fn log(&mut self, what: &str, key: &str) -> Result {
        let t = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0.0, |d| d.as_secs_f64());
        // One write call for the whole line: `writeln!` on a `File` writes each formatted
        // piece with its own system call, and a kill between two left a torn line.
        let line = format!("{t:.3} {} {what} {key}\n", std::process::id());
        self.log
            .write_all(line.as_bytes())
            .and_then(|_| self.log.flush())
            .map_err(|e| Error::Output(format!("cannot write {LOG}: {e}")))
    }

    /// Appends `entry` and waits until it is on disk.
    pub fn append(&mut self, entry: &Entry) -> Result {
        self.journal
            .write_all(line(entry).as_bytes())
            .and_then(|_| self.journal.sync_data())
            .map_err(|e| Error::Output(format!("cannot write {JOURNAL}: {e}")))
    }
}

/// `trials.csv` of `entries` (in trial order): `key,status,seed`, the factors, `error`,
/// then every metric any row has, sorted by name.
pub fn csv(factors: &[String], entries: &[Entry]) -> String {
    let mut entries: Vec<&Entry> = entries.iter().collect();
    entries.sort_by_key(|e| e.index);
    let metrics: BTreeSet<&String> = entries.iter().flat_map(|e| e.metrics.keys()).collect();
    let mut out = String::from("key,status,seed");
    for f in factors {
        out.push(',');
        out.push_str(&cell(f));
    }
    out.push_str(",error");
    for m in &metrics {
        out.push(',');
        out.push_str(&cell(m));
    }
    out.push('\n');
    for e in entries {
        out.push_str(&cell(&e.key));
        out.push(',');
        out.push_str(e.status.name());
        out.push(',');
        out.push_str(&e.seed.to_string());
        for l in &e.levels {
            out.push(',');
            out.push_str(&cell(l));
        }
        out.push(',');
        out.push_str(&cell(e.error.as_deref().unwrap_or("")));
        for m in &metrics {
            out.push(',');
            out.push_str(&value_cell(e.metrics.get(*m)));
        }
        out.push('\n');
    }
    out
}

/// A CSV field: quoted when it holds a comma, a quote or a line break.
fn cell(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A metric as a CSV field: numbers as JSON writes them, strings bare, null or missing
/// empty, arrays and objects as compact JSON.
fn value_cell(v: Option<&Value>) -> String {
    match v {
        None | Some(Value::Null) => String::new(),
        Some(Value::String(s)) => cell(s),
        Some(other) => cell(&other.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn flatten_makes_dotted_keys_and_keeps_arrays() {
        let f = flatten(&json!({"a": 1, "b": {"c": "x", "d": {"e": true}}, "l": [1, 2], "o": {}}));
        let keys: Vec<&str> = f.keys().map(String::as_str).collect();
        assert_eq!(keys, ["a", "b.c", "b.d.e", "l", "o"]);
        assert_eq!(f["l"], json!([1, 2]));
    }

    #[test]
    fn csv_quotes_what_needs_it_and_orders_by_index() {
        let e = |index: usize, metrics: Value, error: Option<&str>| Entry {
            index,
            key: format!("k{index}"),
            seed: index as u64,
            levels: vec!["a,b".into()],
            status: if error.is_some() {
                Status::Failed
            } else {
                Status::Ok
            },
            error: error.map(str::to_string),
            metrics: flatten(&metrics),
            wall_s: 0.0,
        };
        let text = csv(
            &["f".into()],
            &[
                e(1, json!({}), Some("bad \"x\"")),
                e(0, json!({"m": 1.5, "l": [1, 2], "s": "t"}), None),
            ],
        );
        assert_eq!(
            text,
            "key,status,seed,f,error,l,m,s\n\
             k0,ok,0,\"a,b\",,\"[1,2]\",1.5,t\n\
             k1,failed,1,\"a,b\",\"bad \"\"x\"\"\",,,\n"
        );
    }

    #[test]
    fn a_journal_line_cut_short_is_dropped_and_cut_off() {
        let dir = tempfile::tempdir().unwrap();
        let mut j = Journal::open(dir.path()).unwrap();
        let entry = Entry {
            index: 0,
            key: "k".into(),
            seed: 1,
            levels: vec![],
            status: Status::Ok,
            error: None,
            metrics: flatten(&json!({"x": 0.1})),
            wall_s: 2.0,
        };
        j.append(&entry).unwrap();
        drop(j);
        let path = dir.path().join(JOURNAL);
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str("{\"index\":1,\"ke");
        std::fs::write(&path, &text).unwrap();
        assert_eq!(read(dir.path()).unwrap(), vec![entry.clone()]);
        let after = std::fs::read_to_string(&path).unwrap();
        assert!(after.ends_with("}\n") && after.lines().count() == 1);
        // Appending after the cut gives two whole lines.
        Journal::open(dir.path()).unwrap().append(&entry).unwrap();
        assert_eq!(read(dir.path()).unwrap().len(), 2);
    }
}
