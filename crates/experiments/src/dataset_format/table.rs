//! Strict reading of a dataset's CSV files (records by the `csv` crate,
//! `whisker_slam::csv_records`): the exact header, the same number of fields on every
//! line, numbers that parse; every error names the file, the line (1-based, the header is
//! line 1) and what was expected, and exits with code 2.

use csv::StringRecord;
use std::path::{Path, PathBuf};
use whisker_scenario::{Error, Result};

/// A CSV file of a dataset, read whole, its header checked.
pub struct Table {
    path: PathBuf,
    text: String,
    columns: Vec<String>,
}

/// One data line of a [`Table`].
pub struct Row<'a> {
    path: &'a Path,
    /// Line number in the file (1-based; the header is line 1).
    pub line: usize,
    fields: StringRecord,
    columns: &'a [String],
}

impl Table {
    /// Reads `path` and checks that its first line is exactly `columns` joined by commas.
    pub fn read(path: &Path, columns: &[String]) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::Input(format!("{}: cannot read: {e}", path.display())))?;
        let header = columns.join(",");
        if text.lines().next() != Some(header.as_str()) {
            let shown: String = header.chars().take(120).collect();
            return Err(Error::Input(format!(
                "{}: line 1: expected the header {shown}{}",
                path.display(),
                if shown.len() < header.len() {
                    "…"
                } else {
                    ""
                }
            )));
        }
        if !text.ends_with('\n') {
            return Err(Error::Input(format!(
                "{}: line {}: the last line does not end with a newline (truncated file?)",
                path.display(),
                text.lines().count()
            )));
        }
        Ok(Self {
            path: path.to_path_buf(),
            text,
            columns: columns.to_vec(),
        })
    }

    /// The data lines, each checked for its number of fields.
    pub fn rows(&self) -> impl Iterator<Item = Result<Row<'_>>> {
        whisker_slam::csv_records::records(&self.text).map(|(line, fields)| {
            if fields.len() != self.columns.len() {
                return Err(Error::Input(format!(
                    "{}: line {line}: expected {} fields, got {}",
                    self.path.display(),
                    self.columns.len(),
                    fields.len()
                )));
            }
            Ok(Row {
                path: &self.path,
                line,
                fields,
                columns: &self.columns,
            })
        })
    }

    /// Number of data lines.
    pub fn len(&self) -> usize {
        self.text.lines().count().saturating_sub(1)
    }

    /// Whether the file has no data lines.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// An error about line `line` of this file.
    pub fn error(&self, line: usize, message: impl std::fmt::Display) -> Error {
        Error::Input(format!("{}: line {line}: {message}", self.path.display()))
    }
}

impl Row<'_> {
    /// An error about this line.
    pub fn error(&self, message: impl std::fmt::Display) -> Error {
        Error::Input(format!(
            "{}: line {}: {message}",
            self.path.display(),
            self.line
        ))
    }

    /// Field `i` as text.
    pub fn text(&self, i: usize) -> &str {
        &self.fields[i]
    }

    /// Field `i` as a finite number.
    pub fn f64(&self, i: usize) -> Result<f64> {
        match self.fields[i].parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(format!(
                "column {} ({}): expected a finite number, got {:?}",
                i + 1,
                self.columns[i],
                &self.fields[i]
            ))),
        }
    }

    /// Field `i` as a number, ±infinity allowed (`inf`, `-inf`), NaN not.
    pub fn extended(&self, i: usize) -> Result<f64> {
        match self.fields[i].parse::<f64>() {
            Ok(v) if !v.is_nan() => Ok(v),
            _ => Err(self.error(format!(
                "column {} ({}): expected a number or ±inf, got {:?}",
                i + 1,
                self.columns[i],
                &self.fields[i]
            ))),
        }
    }

    /// Field `i` as an integer.
    pub fn i64(&self, i: usize) -> Result<i64> {
        self.fields[i].parse::<i64>().map_err(|_| {
            self.error(format!(
                "column {} ({}): expected an integer, got {:?}",
                i + 1,
                self.columns[i],
                &self.fields[i]
            ))
        })
    }

    /// Field `i` as an index below `limit`.
    pub fn index(&self, i: usize, limit: usize) -> Result<usize> {
        match self.fields[i].parse::<usize>() {
            Ok(v) if v < limit => Ok(v),
            _ => Err(self.error(format!(
                "column {} ({}): expected an integer 0–{}, got {:?}",
                i + 1,
                self.columns[i],
                limit.saturating_sub(1),
                &self.fields[i]
            ))),
        }
    }

    /// Field `i` must be the integer `expected` (e.g. a running index).
    pub fn expect(&self, i: usize, expected: usize) -> Result {
        if self.fields[i].parse::<usize>() == Ok(expected) {
            Ok(())
        } else {
            Err(self.error(format!(
                "column {} ({}): expected {expected}, got {:?}",
                i + 1,
                self.columns[i],
                &self.fields[i]
            )))
        }
    }
}

/// Column names from a comma-separated list.
pub fn columns(list: &str) -> Vec<String> {
    list.split(',').map(str::to_string).collect()
}
