//! The records of a comma-separated text file as the `csv` crate reads them, each with its
//! line number, for the strict readers of the project's CSV formats (datasets, images,
//! radial-distance sets, batch logs): every error there names the file, the line and the
//! column. No field of these formats is ever quoted, so quoting is off (a `"` is a
//! character like any other), and a blank line is a record of one empty field, so that a
//! reader expecting more fields refuses it rather than skipping it.

use csv::{ReaderBuilder, StringRecord};

/// The reader of every format: no header row of its own (the callers check theirs), any
/// number of fields, no quoting.
fn reader(text: &str) -> csv::Reader<&[u8]> {
    ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .quoting(false)
        .from_reader(text.as_bytes())
}

/// The fields of `text`'s first line (its header), none for an empty text.
pub fn header(text: &str) -> StringRecord {
    if text.starts_with(['\n', '\r']) {
        return StringRecord::new();
    }
    reader(text)
        .into_records()
        .next()
        .and_then(Result::ok)
        .unwrap_or_default()
}

/// Every line of `text` after the first (the header) as (line number, 1-based with the
/// header line 1; its fields).
pub fn records(text: &str) -> Records<'_> {
    let rows = reader(text).into_records();
    Records {
        text,
        rows,
        next_line: 1,
        pending: None,
        counted: 0,
        breaks: 0,
        last_line: text.lines().count(),
    }
}

/// The iterator of [`records`].
pub struct Records<'a> {
    text: &'a str,
    rows: csv::StringRecordsIntoIter<&'a [u8]>,
    /// The line the next record yielded has.
    next_line: usize,
    /// A record read ahead, past blank lines still to yield, and its line.
    pending: Option<(usize, StringRecord)>,
    /// Line breaks counted so far, up to byte `counted`.
    counted: usize,
    breaks: usize,
    /// The text's last line (`str::lines`), blank ones at the end included.
    last_line: usize,
}

impl Iterator for Records<'_> {
    type Item = (usize, StringRecord);

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if self.pending.is_none() {
                // The reader ends at the last record; blank lines after it are the text's.
                self.pending = match self.rows.next() {
                    Some(Ok(record)) => Some((self.line_of(&record), record)),
                    // A &str is UTF-8 and nothing is quoted: no record can fail.
                    Some(Err(_)) | None => None,
                };
            }
            let line = self.pending.as_ref().map_or(self.last_line + 1, |p| p.0);
            if self.next_line < line {
                // A blank line the reader passed over.
                self.next_line += 1;
                if self.next_line - 1 > 1 {
                    return Some((self.next_line - 1, StringRecord::from(vec![""])));
                }
                continue;
            }
            let (line, record) = self.pending.take()?;
            self.next_line = line + 1;
            if line > 1 {
                return Some((line, record));
            }
        }
    }
}

impl Records<'_> {
    /// The line `record` starts on. The reader's position of a record after a blank line
    /// is the blank line's: the record starts past the line breaks there.
    fn line_of(&mut self, record: &StringRecord) -> usize {
        let bytes = self.text.as_bytes();
        let mut start = record.position().map_or(0, |p| p.byte() as usize);
        while start < bytes.len() && matches!(bytes[start], b'\n' | b'\r') {
            start += 1;
        }
        self.breaks += bytes[self.counted..start]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.counted = start;
        1 + self.breaks
    }
}

/// What is wrong in a CSV file: on which line (1-based; none for the whole file) and
/// what was expected (naming the column where there is one).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineError {
    /// The line, 1-based, the header line 1.
    pub line: Option<usize>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl LineError {
    /// An error about line `line`.
    pub fn at(line: usize, message: impl Into<String>) -> Self {
        Self {
            line: Some(line),
            message: message.into(),
        }
    }
}

impl std::fmt::Display for LineError {
    /// `line N: message` (`line N, column …` where the message starts with the column).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            None => f.write_str(&self.message),
            Some(n) if self.message.starts_with("column") => {
                write!(f, "line {n}, {}", self.message)
            }
            Some(n) => write!(f, "line {n}: {}", self.message),
        }
    }
}

impl std::error::Error for LineError {}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Vec<(usize, Vec<String>)> {
        records(text)
            .map(|(l, r)| (l, r.iter().map(str::to_string).collect()))
            .collect()
    }

    #[test]
    fn lines_are_numbered_from_the_header_and_blank_lines_kept() {
        let got = read("a,b\n1,2\n\n3,\"4\n5\r\n\n");
        let want: Vec<(usize, Vec<String>)> = vec![
            (2, vec!["1".into(), "2".into()]),
            (3, vec!["".into()]),
            (4, vec!["3".into(), "\"4".into()]),
            (5, vec!["5".into()]),
            (6, vec!["".into()]),
        ];
        assert_eq!(got, want);
        assert!(read("a,b\n").is_empty());
        assert!(read("").is_empty());
        // A blank first line is the header's place: the data start on line 2.
        assert_eq!(read("\n1\n"), vec![(2, vec!["1".to_string()])]);
        assert_eq!(header("a,b\n1,2\n"), StringRecord::from(vec!["a", "b"]));
        assert!(header("\n1\n").is_empty());
    }
}
