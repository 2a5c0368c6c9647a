//! What a command shows a reader on the console, in one shape for every command: a header
//! saying what ran, results in tables whose columns are explained once (units, what good
//! looks like, where the thesis' figure is), the files written and the recording with the
//! command that opens it. The texts are built here; the `whisker` binary prints them.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The header of a command's output: `what` it is (one line) and the command line as run.
pub fn header(what: &str, command_line: &str) -> String {
    let what = what.trim_end_matches('.');
    format!("━━ {what}\n   {command_line}\n")
}

/// The explanation of a table's columns or of a report's lines, printed once below it:
/// `(name, meaning)` pairs, the names aligned.
pub fn legend(title: &str, entries: &[(&str, &str)]) -> String {
    let width = entries
        .iter()
        .map(|(n, _)| n.chars().count())
        .max()
        .unwrap_or(0);
    let mut out = format!("  {title}:\n");
    for (name, meaning) in entries {
        let pad = width - name.chars().count();
        let _ = writeln!(out, "    {name}{:pad$}  {meaning}", "");
    }
    out
}

/// Why a command wrote no recording, when it could have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoRecording {
    /// `--no-rrd` or the scenario's `output.recording = false`.
    SwitchedOff,
    /// The command writes one only with an output directory or `--rrd FILE`.
    NoOut,
    /// The command writes one only with `--rrd FILE`.
    NoFile,
}

/// The closing lines: each directory's files written (`wrote`), then the recording and how
/// to open it, or why there is none (`missing`, for commands that record). Paths are shown
/// as the command was given them. Directories with many files are summarised.
pub fn outputs(written: &[PathBuf], missing: Option<NoRecording>) -> String {
    let mut out = String::new();
    let mut by_dir: BTreeMap<&Path, Vec<String>> = BTreeMap::new();
    for p in written {
        if p.is_dir() {
            // A directory renamed into place whole (a dataset).
            let _ = writeln!(
                out,
                "wrote      {}/ ({} files)",
                p.display(),
                count_files(p)
            );
            continue;
        }
        let dir = p.parent().unwrap_or(Path::new(""));
        let name = p
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let names = by_dir.entry(dir).or_default();
        if !names.contains(&name) {
            names.push(name);
        }
    }
    // Directories that are many siblings (a batch's trials) are summarised under their
    // parent; the others are listed file by file.
    let mut siblings: BTreeMap<&Path, (usize, usize)> = BTreeMap::new();
    for (dir, names) in &by_dir {
        if let Some(parent) = dir.parent() {
            let e = siblings.entry(parent).or_default();
            e.0 += 1;
            e.1 += names.len();
        }
    }
    let mut summarised = Vec::new();
    for (dir, names) in &by_dir {
        if let Some(parent) = dir.parent().filter(|p| siblings[p].0 > 6) {
            if !summarised.contains(&parent) {
                summarised.push(parent);
                let (dirs, files) = siblings[parent];
                let _ = writeln!(
                    out,
                    "wrote      {}/ ({files} files in {dirs} directories)",
                    show(parent)
                );
            }
            continue;
        }
        let joined = names.join(", ");
        let line = match names.len() {
            1 => format!("{}{joined}", prefix(dir)),
            n if n <= 8 && joined.len() <= 100 => format!("{}{{{joined}}}", prefix(dir)),
            n => format!("{}/ ({n} files, e.g. {})", show(dir), names[0]),
        };
        let _ = writeln!(out, "wrote      {line}");
    }
    let rrds: Vec<&PathBuf> = written
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "rrd"))
        .collect();
    match (rrds.as_slice(), missing) {
        ([], Some(NoRecording::SwitchedOff)) => {
            out.push_str("recording  none (switched off: --no-rrd or output.recording = false)\n");
        }
        ([], Some(NoRecording::NoOut)) => out.push_str(
            "recording  none: give --out DIR (it writes DIR/run.rrd) or --rrd FILE to write one\n",
        ),
        ([], Some(NoRecording::NoFile)) => {
            out.push_str("recording  none: give --rrd FILE to write one\n");
        }
        ([], None) => {}
        ([one], _) => {
            let _ = writeln!(
                out,
                "recording  {}  (open it: rerun {}; what is in it: docs/recording.md)",
                one.display(),
                one.display()
            );
        }
        (many, _) => {
            // The run's own recording first, when there is one among them.
            let shown = many
                .iter()
                .find(|p| p.file_name().is_some_and(|n| n == "run.rrd"))
                .unwrap_or(&many[0]);
            let _ = writeln!(
                out,
                "recording  {} recordings, e.g. {}  (open one: rerun FILE; docs/recording.md)",
                many.len(),
                shown.display()
            );
        }
    }
    out
}

/// Files under `dir`, recursively.
fn count_files(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |entries| {
        entries
            .flatten()
            .map(|e| match e.path().is_dir() {
                true => count_files(&e.path()),
                false => 1,
            })
            .sum()
    })
}

/// `dir/` as a prefix of a file name (nothing for the working directory).
fn prefix(dir: &Path) -> String {
    match dir.as_os_str().is_empty() {
        true => String::new(),
        false => format!("{}/", dir.display()),
    }
}

fn show(dir: &Path) -> String {
    match dir.as_os_str().is_empty() {
        true => ".".to_owned(),
        false => dir.display().to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_grouped_by_directory_and_the_recording_says_how_to_open_it() {
        let w: Vec<PathBuf> = ["out/a.csv", "out/b.json", "out/run.rrd", "other.txt"]
            .iter()
            .map(PathBuf::from)
            .collect();
        let text = outputs(&w, Some(NoRecording::NoOut));
        assert!(text.contains("wrote      other.txt\n"), "{text}");
        assert!(
            text.contains("wrote      out/{a.csv, b.json, run.rrd}\n"),
            "{text}"
        );
        assert!(
            text.contains("recording  out/run.rrd  (open it: rerun out/run.rrd"),
            "{text}"
        );
    }

    #[test]
    fn without_a_recording_the_reason_is_given_and_many_directories_are_summarised() {
        let mut w: Vec<PathBuf> = (0..8)
            .map(|i| PathBuf::from(format!("b/trials/t{i}/summary.json")))
            .collect();
        w.push(PathBuf::from("b/trials.csv"));
        let text = outputs(&w, Some(NoRecording::SwitchedOff));
        assert!(
            text.contains("wrote      b/trials/ (8 files in 8 directories)"),
            "{text}"
        );
        assert!(text.contains("wrote      b/trials.csv\n"), "{text}");
        assert!(text.contains("recording  none (switched off"), "{text}");
        assert_eq!(outputs(&[], None), "");
        assert!(outputs(&[], Some(NoRecording::NoOut)).contains("give --out DIR"));
    }

    #[test]
    fn legend_aligns_the_names() {
        let text = legend("columns", &[("ARR", "rate"), ("EM", "energy")]);
        assert_eq!(text, "  columns:\n    ARR  rate\n    EM   energy\n");
    }
}
