//! Mutations as proptest values: byte-level edits of any file, replacements of the
//! numbers in a text file, and structured edits of a TOML or JSON tree. Positions are
//! drawn as plain numbers and taken modulo what the input has, so that one strategy
//! serves every input and shrinking moves towards the first position and the mildest edit.

use proptest::prelude::*;

/// Values that have broken parsers: the limits of the number types, non-finite numbers,
/// signs, absurd magnitudes, text where a number goes and the empty string.
pub const HOSTILE: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-320",
    "4294967295",
    "4294967296",
    "18446744073709551616",
    "9223372036854775807",
    "-9223372036854775808",
    "1e400",
    "0.5",
    "x",
    "",
    "65535",
    "2147483648",
];

/// One byte-level edit.
#[derive(Debug, Clone)]
pub enum ByteEdit {
    /// XOR a byte with a mask.
    Flip(usize, u8),
    /// Insert bytes.
    Insert(usize, Vec<u8>),
    /// Delete up to n bytes.
    Delete(usize, usize),
    /// Repeat a stretch of up to n bytes k times.
    Repeat(usize, usize, usize),
    /// Cut the file.
    Truncate(usize),
}

/// One to four byte-level edits.
pub fn byte_edits() -> impl Strategy<Value = Vec<ByteEdit>> {
    let edit = prop_oneof![
        (any::<usize>(), 1..=255u8).prop_map(|(a, m)| ByteEdit::Flip(a, m)),
        (
            any::<usize>(),
            prop_oneof![
                prop::collection::vec(any::<u8>(), 1..8),
                prop::sample::select(HOSTILE).prop_map(|h| h.as_bytes().to_vec()),
                Just(b"\n".to_vec()),
                Just(vec![0xff, 0xff, 0xff, 0xff]),
            ]
        )
            .prop_map(|(a, b)| ByteEdit::Insert(a, b)),
        (any::<usize>(), 1..64usize).prop_map(|(a, n)| ByteEdit::Delete(a, n)),
        (any::<usize>(), 1..256usize, 2..2000usize).prop_map(|(a, n, k)| ByteEdit::Repeat(a, n, k)),
        any::<usize>().prop_map(ByteEdit::Truncate),
    ];
    prop::collection::vec(edit, 1..=4)
}

/// `bytes` with `edits` applied.
pub fn apply_bytes(bytes: &[u8], edits: &[ByteEdit]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    for e in edits {
        let at = |a: usize| if b.is_empty() { 0 } else { a % (b.len() + 1) };
        match e {
            ByteEdit::Flip(a, m) if !b.is_empty() => {
                let i = a % b.len();
                b[i] ^= m;
            }
            ByteEdit::Flip(..) => {}
            ByteEdit::Insert(a, x) => {
                let i = at(*a);
                b.splice(i..i, x.iter().copied());
            }
            ByteEdit::Delete(a, n) => {
                let i = at(*a);
                let j = (i + n).min(b.len());
                b.drain(i..j);
            }
            ByteEdit::Repeat(a, n, k) => {
                let i = at(*a);
                let j = (i + n).min(b.len());
                let piece = b[i..j].to_vec();
                for _ in 1..*k {
                    b.splice(j..j, piece.iter().copied());
                }
            }
            ByteEdit::Truncate(a) => {
                let i = at(*a);
                b.truncate(i);
            }
        }
    }
    b
}

/// Replacements of numbers in a text: (which number, by what).
pub fn number_edits() -> impl Strategy<Value = Vec<(usize, &'static str)>> {
    prop::collection::vec((any::<usize>(), prop::sample::select(HOSTILE)), 1..=3)
}

/// `text` with the chosen numbers (maximal runs of digits, signs, dots and exponents that
/// hold a digit) replaced.
pub fn apply_numbers(text: &str, edits: &[(usize, &str)]) -> String {
    let mut t = text.to_string();
    for (k, value) in edits {
        let spans = numbers(&t);
        if spans.is_empty() {
            break;
        }
        let (a, b) = spans[k % spans.len()];
        t.replace_range(a..b, value);
    }
    t
}

fn numbers(t: &str) -> Vec<(usize, usize)> {
    let bytes = t.as_bytes();
    let part = |c: u8| c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+' | b'e' | b'E');
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if part(bytes[i]) && (i == 0 || !bytes[i - 1].is_ascii_alphabetic()) {
            let j = (i..bytes.len())
                .find(|&j| !part(bytes[j]))
                .unwrap_or(bytes.len());
            if bytes[i..j].iter().any(u8::is_ascii_digit) {
                out.push((i, j));
            }
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// A structured edit of a tree (a TOML table or a JSON document): which node (in the
/// order of a depth-first walk), and what happens to it.
#[derive(Debug, Clone)]
pub enum TreeEdit {
    /// Replace the node by a hostile value.
    Replace(usize, Value),
    /// Remove the node from its parent.
    Remove(usize),
    /// Add an unknown key to a table (or the node's parent table).
    Unknown(usize),
    /// Wrap the node in an array.
    Wrap(usize),
    /// Repeat an array's first element (or the node) k times.
    Repeat(usize, usize),
}

/// The kinds of replacement value (turned into TOML or JSON).
#[derive(Debug, Clone)]
pub enum Value {
    /// A number written as one of [`HOSTILE`] (non-numbers as strings).
    Hostile(&'static str),
    /// An integer.
    Int(i64),
    /// A boolean.
    Bool(bool),
    /// An empty array.
    EmptyArray,
    /// An empty table.
    EmptyTable,
    /// A path-like string.
    Text(&'static str),
    /// JSON null (in TOML: an empty string).
    Null,
}

/// One to three tree edits.
pub fn tree_edits() -> impl Strategy<Value = Vec<TreeEdit>> {
    let value = prop_oneof![
        prop::sample::select(HOSTILE).prop_map(Value::Hostile),
        prop::sample::select(&[i64::MIN, -1, 0, 1, 2, 3, 81, 1 << 31, 1 << 40, i64::MAX][..])
            .prop_map(Value::Int),
        any::<bool>().prop_map(Value::Bool),
        Just(Value::EmptyArray),
        Just(Value::EmptyTable),
        prop::sample::select(
            &[
                "",
                ".",
                "..",
                "/",
                "../../x",
                "box",
                "nowhere.obj",
                "a\u{0}b"
            ][..]
        )
        .prop_map(Value::Text),
        Just(Value::Null),
    ];
    let edit = prop_oneof![
        4 => (any::<usize>(), value).prop_map(|(n, v)| TreeEdit::Replace(n, v)),
        2 => any::<usize>().prop_map(TreeEdit::Remove),
        1 => any::<usize>().prop_map(TreeEdit::Unknown),
        1 => any::<usize>().prop_map(TreeEdit::Wrap),
        1 => (any::<usize>(), 0..3000usize).prop_map(|(n, k)| TreeEdit::Repeat(n, k)),
    ];
    prop::collection::vec(edit, 1..=3)
}

/// A tree the edits apply to.
pub trait Tree: Clone {
    /// The children of a table or array (none for a leaf), with keys for tables.
    fn children_mut(&mut self) -> Vec<(Option<String>, &mut Self)>;
    /// A replacement value.
    fn from_value(v: &Value) -> Self;
    /// An array holding `items`.
    fn array(items: Vec<Self>) -> Self;
    /// Removes child `key` (table) or `index` (array); adds `key` = an integer to a table.
    fn remove_child(&mut self, key: Option<&str>, index: usize);
    /// Adds an unknown field, if a table.
    fn add_unknown(&mut self) -> bool;
    /// The first element repeated `k` times, if a non-empty array.
    fn repeat_first(&mut self, k: usize) -> bool;
}

/// The number of nodes of `t` (itself included).
fn count<T: Tree>(t: &mut T) -> usize {
    1 + t
        .children_mut()
        .into_iter()
        .map(|(_, c)| count(c))
        .sum::<usize>()
}

/// Applies `edit` to node `n` (depth-first order) of `t`.
fn apply_at<T: Tree>(t: &mut T, n: usize, edit: &TreeEdit) {
    // Find the parent holding node n as a direct child, or n = 0 (the root itself).
    fn visit<T: Tree>(t: &mut T, n: &mut usize, edit: &TreeEdit) -> bool {
        let children = t.children_mut();
        let keys: Vec<Option<String>> = children.iter().map(|(k, _)| k.clone()).collect();
        let mut target = None;
        for (i, (_, c)) in children.into_iter().enumerate() {
            if *n == 0 {
                target = Some(i);
                break;
            }
            *n -= 1;
            if visit(c, n, edit) {
                return true;
            }
        }
        let Some(i) = target else {
            return false;
        };
        match edit {
            TreeEdit::Remove(_) => t.remove_child(keys[i].as_deref(), i),
            TreeEdit::Unknown(_) => {
                let mut children = t.children_mut();
                if !children[i].1.add_unknown() {
                    drop(children);
                    t.add_unknown();
                }
            }
            _ => {
                let mut children = t.children_mut();
                let node = &mut *children[i].1;
                match edit {
                    TreeEdit::Replace(_, v) => *node = T::from_value(v),
                    TreeEdit::Wrap(_) => *node = T::array(vec![node.clone()]),
                    TreeEdit::Repeat(_, k) => {
                        if !node.repeat_first(*k) {
                            *node = T::array(vec![node.clone(); *k]);
                        }
                    }
                    TreeEdit::Remove(_) | TreeEdit::Unknown(_) => unreachable!(),
                }
            }
        }
        true
    }
    if n == 0 {
        match edit {
            TreeEdit::Unknown(_) => {
                t.add_unknown();
            }
            TreeEdit::Repeat(_, k) => {
                t.repeat_first(*k);
            }
            _ => {}
        }
        return;
    }
    let mut k = n - 1;
    visit(t, &mut k, edit);
}

/// `t` with `edits` applied (each at its node modulo the tree's current size).
pub fn apply_tree<T: Tree>(t: &T, edits: &[TreeEdit]) -> T {
    let mut t = t.clone();
    for e in edits {
        let n = match e {
            TreeEdit::Replace(n, _)
            | TreeEdit::Remove(n)
            | TreeEdit::Unknown(n)
            | TreeEdit::Wrap(n)
            | TreeEdit::Repeat(n, _) => *n,
        };
        let size = count(&mut t);
        apply_at(&mut t, n % size, e);
    }
    t
}

impl Tree for serde_json::Value {
    fn children_mut(&mut self) -> Vec<(Option<String>, &mut Self)> {
        match self {
            serde_json::Value::Object(m) => {
                m.iter_mut().map(|(k, v)| (Some(k.clone()), v)).collect()
            }
            serde_json::Value::Array(a) => a.iter_mut().map(|v| (None, v)).collect(),
            _ => Vec::new(),
        }
    }
    fn from_value(v: &Value) -> Self {
        match v {
            Value::Hostile(h) => match h.parse::<f64>() {
                Ok(x) if x.is_finite() => serde_json::from_str(h).unwrap_or(serde_json::json!(x)),
                _ => serde_json::json!(h),
            },
            Value::Int(i) => serde_json::json!(i),
            Value::Bool(b) => serde_json::json!(b),
            Value::EmptyArray => serde_json::json!([]),
            Value::EmptyTable => serde_json::json!({}),
            Value::Text(t) => serde_json::json!(t),
            Value::Null => serde_json::Value::Null,
        }
    }
    fn array(items: Vec<Self>) -> Self {
        serde_json::Value::Array(items)
    }
    fn remove_child(&mut self, key: Option<&str>, index: usize) {
        match self {
            serde_json::Value::Object(m) => {
                m.remove(key.unwrap_or_default());
            }
            serde_json::Value::Array(a) => {
                a.remove(index);
            }
            _ => {}
        }
    }
    fn add_unknown(&mut self) -> bool {
        match self {
            serde_json::Value::Object(m) => {
                m.insert("zz_unknown".into(), serde_json::json!(1));
                true
            }
            _ => false,
        }
    }
    fn repeat_first(&mut self, k: usize) -> bool {
        match self {
            serde_json::Value::Array(a) if !a.is_empty() => {
                let first = a[0].clone();
                a.splice(0..0, std::iter::repeat_n(first, k));
                true
            }
            _ => false,
        }
    }
}

impl Tree for toml::Value {
    fn children_mut(&mut self) -> Vec<(Option<String>, &mut Self)> {
        match self {
            toml::Value::Table(m) => m.iter_mut().map(|(k, v)| (Some(k.clone()), v)).collect(),
            toml::Value::Array(a) => a.iter_mut().map(|v| (None, v)).collect(),
            _ => Vec::new(),
        }
    }
    fn from_value(v: &Value) -> Self {
        match v {
            Value::Hostile(h) => match h.parse::<i64>() {
                Ok(i) => toml::Value::Integer(i),
                Err(_) => match h.parse::<f64>() {
                    Ok(x) => toml::Value::Float(x),
                    Err(_) => toml::Value::String(h.to_string()),
                },
            },
            Value::Int(i) => toml::Value::Integer(*i),
            Value::Bool(b) => toml::Value::Boolean(*b),
            Value::EmptyArray => toml::Value::Array(Vec::new()),
            Value::EmptyTable => toml::Value::Table(toml::Table::new()),
            Value::Text(t) => toml::Value::String(t.to_string()),
            Value::Null => toml::Value::String(String::new()),
        }
    }
    fn array(items: Vec<Self>) -> Self {
        toml::Value::Array(items)
    }
    fn remove_child(&mut self, key: Option<&str>, index: usize) {
        match self {
            toml::Value::Table(m) => {
                m.remove(key.unwrap_or_default());
            }
            toml::Value::Array(a) => {
                a.remove(index);
            }
            _ => {}
        }
    }
    fn add_unknown(&mut self) -> bool {
        match self {
            toml::Value::Table(m) => {
                m.insert("zz_unknown".into(), toml::Value::Integer(1));
                true
            }
            _ => false,
        }
    }
    fn repeat_first(&mut self, k: usize) -> bool {
        match self {
            toml::Value::Array(a) if !a.is_empty() => {
                let first = a[0].clone();
                a.splice(0..0, std::iter::repeat_n(first, k));
                true
            }
            _ => false,
        }
    }
}

#[test]
fn edits_reach_every_node_and_keep_the_rest() {
    let t: serde_json::Value = serde_json::json!({"a": [1, 2], "b": {"c": 3}});
    // Depth-first: root, a, a[0], a[1], b, b.c (serde_json's map is ordered by key).
    let cases = [
        (2, serde_json::json!({"a": [9, 2], "b": {"c": 3}})),
        (5, serde_json::json!({"a": [1, 2], "b": {"c": 9}})),
        (7, serde_json::json!({"a": [1, 9], "b": {"c": 3}})), // 7 mod 6 = 1 … a itself
    ];
    for (n, want) in &cases[..2] {
        assert_eq!(
            &apply_tree(&t, &[TreeEdit::Replace(*n, Value::Int(9))]),
            want
        );
    }
    let whole = apply_tree(&t, &[TreeEdit::Replace(cases[2].0, Value::Int(9))]);
    assert_eq!(whole, serde_json::json!({"a": 9, "b": {"c": 3}}));
    let removed = apply_tree(&t, &[TreeEdit::Remove(4)]);
    assert_eq!(removed, serde_json::json!({"a": [1, 2]}));
    assert_eq!(
        apply_numbers("v 1.5 -2 x3 4e-1\n", &[(2, "inf"), (1, "nan")]),
        "v 1.5 nan x3 inf\n"
    );
    assert_eq!(
        apply_bytes(b"abcdef", &[ByteEdit::Repeat(1, 2, 3)]),
        b"abcbcbcdef"
    );
}
