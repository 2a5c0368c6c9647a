//! A CSV table of a dataset or a run as ROS 2 messages, one message per row, and back to
//! the same bytes: each column becomes a field of the type that writes its text back
//! exactly — `int64` (integers as written), `float64` (the shortest text that reads back
//! as the same number, Rust's `{:?}` or `{}`: the two forms the writers use), or `string`
//! for anything else (empty fields, names). The header and each column's form travel in
//! the channel's metadata.

use super::cdr::{Decoder, Encoder};

/// How a column's text is carried.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `int64`, written back in decimal.
    Int,
    /// `float64`, written back by `{:?}` (exponent for very large or small numbers).
    Debug,
    /// `float64`, written back by `{}` (never an exponent).
    Display,
    /// `string`, as written.
    Text,
}

impl Kind {
    /// The letter of the channel metadata's `csv_kinds`.
    pub fn letter(self) -> char {
        match self {
            Kind::Int => 'i',
            Kind::Debug => 'd',
            Kind::Display => 'f',
            Kind::Text => 's',
        }
    }

    pub fn of_letter(c: char) -> Option<Self> {
        Some(match c {
            'i' => Kind::Int,
            'd' => Kind::Debug,
            'f' => Kind::Display,
            's' => Kind::Text,
            _ => return None,
        })
    }

    /// Whether `text` is carried exactly by this kind.
    pub fn fits(self, text: &str) -> bool {
        match self {
            Kind::Int => text.parse::<i64>().is_ok_and(|v| v.to_string() == text),
            Kind::Debug => text
                .parse::<f64>()
                .is_ok_and(|v| !v.is_nan() && format!("{v:?}") == text),
            Kind::Display => text
                .parse::<f64>()
                .is_ok_and(|v| !v.is_nan() && format!("{v}") == text),
            Kind::Text => true,
        }
    }
}

/// One column: its CSV name, its message field's name and how it is carried.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    pub name: String,
    pub field: String,
    pub kind: Kind,
}

/// A CSV file split into its header and fields.
pub struct Table {
    pub columns: Vec<Column>,
    pub rows: Vec<Vec<String>>,
    /// The column `time_s` when every row's is a non-negative number: the rows' stamps.
    pub time: Option<usize>,
}

impl Table {
    /// `text` as a table, or `None` if it is not one this mapping carries exactly (no
    /// header, quoting, carriage returns, a row of another width, no final newline).
    pub fn parse(text: &str) -> Option<Self> {
        if !text.ends_with('\n') || text.contains(['"', '\r']) {
            return None;
        }
        let mut lines = text.lines();
        let names: Vec<&str> = lines.next()?.split(',').collect();
        if names.iter().any(|n| n.is_empty()) {
            return None;
        }
        let rows: Vec<Vec<String>> = lines
            .map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>())
            .collect();
        if rows.iter().any(|r| r.len() != names.len()) {
            return None;
        }
        let fields = field_names(&names);
        let columns: Vec<Column> = names
            .iter()
            .zip(fields)
            .enumerate()
            .map(|(i, (name, field))| {
                let kind = if rows.is_empty() {
                    Kind::Text
                } else {
                    [Kind::Int, Kind::Debug, Kind::Display]
                        .into_iter()
                        .find(|k| rows.iter().all(|r| k.fits(&r[i])))
                        .unwrap_or(Kind::Text)
                };
                Column {
                    name: name.to_string(),
                    field,
                    kind,
                }
            })
            .collect();
        let time = columns
            .iter()
            .position(|c| c.name == "time_s")
            .filter(|&i| {
                columns[i].kind != Kind::Text
                    && rows
                        .iter()
                        .all(|r| r[i].parse::<f64>().is_ok_and(|t| (0.0..4e9).contains(&t)))
            });
        Some(Self {
            columns,
            rows,
            time,
        })
    }

    /// Row `i`'s stamp in nanoseconds (0 without a time column).
    pub fn stamp(&self, i: usize) -> u64 {
        self.time
            .map_or(0, |c| stamp_ns(self.rows[i][c].parse().expect("checked")))
    }

    /// Row `i` as a CDR message of [`super::schema::row`].
    pub fn encode(&self, i: usize, frame: &str) -> Vec<u8> {
        let mut e = Encoder::new();
        e.header(self.stamp(i), frame);
        for (c, text) in self.columns.iter().zip(&self.rows[i]) {
            match c.kind {
                Kind::Int => e.i64(text.parse().expect("fits")),
                Kind::Debug | Kind::Display => e.f64(text.parse().expect("fits")),
                Kind::Text => e.string(text),
            }
        }
        e.finish()
    }

    /// The `csv_kinds` metadata: one letter per column.
    pub fn kinds(&self) -> String {
        self.columns.iter().map(|c| c.kind.letter()).collect()
    }
}

/// Seconds to nanoseconds, rounded.
pub fn stamp_ns(t: f64) -> u64 {
    (t * 1e9).round().max(0.0) as u64
}

/// Decodes one row message of columns of `kinds` back to its CSV line (with `\n`).
pub fn decode_row(data: &[u8], kinds: &[Kind]) -> Result<String, String> {
    let mut d = Decoder::new(data)?;
    d.header()?;
    let mut line = String::new();
    for (i, k) in kinds.iter().enumerate() {
        if i > 0 {
            line.push(',');
        }
        let what = format!("column {}", i + 1);
        match k {
            Kind::Int => line.push_str(&d.i64(&what)?.to_string()),
            Kind::Debug => line.push_str(&format!("{:?}", d.f64(&what)?)),
            Kind::Display => line.push_str(&format!("{}", d.f64(&what)?)),
            Kind::Text => {
                let s = d.string(&what)?;
                if s.contains([',', '\n', '"', '\r']) {
                    return Err(format!("{what}: a field holding a separator: {s:?}"));
                }
                line.push_str(&s);
            }
        }
    }
    d.end()?;
    line.push('\n');
    Ok(line)
}

/// ROS 2 field names for CSV column names: lower case, `_` for anything but letters and
/// digits, a letter first, no double or trailing `_`, unique, never `header`.
fn field_names(names: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for n in names {
        let mut f = String::new();
        for ch in n.chars() {
            let c = if ch.is_ascii_alphanumeric() {
                ch.to_ascii_lowercase()
            } else {
                '_'
            };
            if !(c == '_' && (f.is_empty() || f.ends_with('_'))) {
                f.push(c);
            }
        }
        let mut f = f.trim_end_matches('_').to_string();
        if !f.starts_with(|c: char| c.is_ascii_lowercase()) || f == "header" {
            f = format!("c_{f}").trim_end_matches('_').to_string();
        }
        let base = f.clone();
        let mut k = 2;
        while out.contains(&f) {
            f = format!("{base}_{k}");
            k += 1;
        }
        out.push(f);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every form of number the writers produce comes back as the same text; fields that
    /// no number form carries stay strings.
    #[test]
    fn rows_round_trip_to_the_same_text() {
        let text = "whisk,time_s,x_m,label,q0_rad,note\n\
                    0,0.5,1e-7,A1,0.0000001,\n\
                    12,1.0,-4.3e-17,F3,3,x y\n\
                    3,2.25,inf,B2,-0.5,z\n";
        let t = Table::parse(text).unwrap();
        let kinds: Vec<Kind> = t.columns.iter().map(|c| c.kind).collect();
        assert_eq!(
            kinds,
            [
                Kind::Int,
                Kind::Debug,
                Kind::Debug,
                Kind::Text,
                Kind::Display,
                Kind::Text
            ]
        );
        assert_eq!(t.time, Some(1));
        assert_eq!(t.stamp(3 - 1), 2_250_000_000);
        let mut back = text.lines().next().unwrap().to_string() + "\n";
        for i in 0..t.rows.len() {
            back += &decode_row(&t.encode(i, ""), &kinds).unwrap();
        }
        assert_eq!(back, text);
    }

    #[test]
    fn field_names_are_ros_names() {
        assert_eq!(
            field_names(&["A1_angle", "header", "1st", "x__y_", "x_y"]),
            ["a1_angle", "c_header", "c_1st", "x_y", "x_y_2"]
        );
    }

    #[test]
    fn quoted_or_ragged_text_is_not_a_table() {
        assert!(Table::parse("a,b\n1,\"2\"\n").is_none());
        assert!(Table::parse("a,b\n1\n").is_none());
        assert!(Table::parse("a,b\n1,2").is_none());
    }
}
