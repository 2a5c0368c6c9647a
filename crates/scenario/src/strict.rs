//! A second reading of a scenario's TOML that refuses what serde's derived readers let
//! through: an array where a table (a struct) is expected.
//!
//! serde's derived `Deserialize` for a struct also accepts a sequence and fills the fields
//! in declaration order, and the `toml` crate offers arrays that way; so `output =
//! ["out/x", 0.01, false]` was read as `[output]` with `dir`, `sample_period_s` and
//! `recording` — a scenario that means something other than it says, and one whose meaning
//! changes silently when a field is added. The `toml` reading (with its line and column)
//! comes first; this one walks the same table with a [`serde::Deserializer`] over
//! [`toml::Value`] that keeps the dotted path of each value and refuses a non-table where a
//! struct is read, naming the field.

use serde::de::{self, DeserializeSeed, IntoDeserializer, MapAccess, SeqAccess, Visitor};
use std::fmt;
use whisker_slam::invalid::Invalid;

/// Reads `table` as a `T`, refusing arrays (or any non-table) where `T` reads a struct.
/// On failure: (dotted field, message).
pub fn check<T: de::DeserializeOwned>(table: &toml::Table) -> Result<(), Invalid> {
    let root = Strict {
        value: Borrowed::Table(table),
        path: String::new(),
    };
    match T::deserialize(root) {
        Ok(_) => Ok(()),
        Err(e) => Err(Invalid::field(e.path, e.message)),
    }
}

/// An error of the strict reading: where and what.
#[derive(Debug)]
pub struct StrictError {
    path: String,
    message: String,
}

impl fmt::Display for StrictError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "field `{}`: {}", self.path, self.message)
    }
}

impl std::error::Error for StrictError {}

impl de::Error for StrictError {
    fn custom<M: fmt::Display>(msg: M) -> Self {
        Self {
            path: String::new(),
            message: msg.to_string(),
        }
    }
}

#[derive(Clone, Copy)]
enum Borrowed<'a> {
    Table(&'a toml::Table),
    Value(&'a toml::Value),
}

/// One value and its dotted path (`arm.initial_joints_deg[2]`).
struct Strict<'a> {
    value: Borrowed<'a>,
    path: String,
}

impl Strict<'_> {
    /// The error `message` at this value's path (errors from deeper keep their own path).
    fn here(&self, mut e: StrictError) -> StrictError {
        if e.path.is_empty() {
            e.path = self.path.clone();
        }
        e
    }

    fn kind(&self) -> &'static str {
        match self.value {
            Borrowed::Table(_) => "a table",
            Borrowed::Value(v) => match v {
                toml::Value::String(_) => "a string",
                toml::Value::Integer(_) => "an integer",
                toml::Value::Float(_) => "a number",
                toml::Value::Boolean(_) => "a boolean",
                toml::Value::Datetime(_) => "a date",
                toml::Value::Array(_) => "an array",
                toml::Value::Table(_) => "a table",
            },
        }
    }

    fn table(&self) -> Option<&toml::Table> {
        match self.value {
            Borrowed::Table(t) | Borrowed::Value(toml::Value::Table(t)) => Some(t),
            Borrowed::Value(_) => None,
        }
    }
}

impl<'de> de::Deserializer<'de> for Strict<'_> {
    type Error = StrictError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, StrictError> {
        if let Some(t) = self.table() {
            let map = Entries {
                entries: t.iter(),
                value: None,
                path: self.path.clone(),
            };
            return visitor.visit_map(map).map_err(|e| self.here(e));
        }
        let Borrowed::Value(v) = self.value else {
            unreachable!("a table is handled above")
        };
        let result = match v {
            toml::Value::String(s) => visitor.visit_str(s),
            toml::Value::Integer(i) => visitor.visit_i64(*i),
            toml::Value::Float(f) => visitor.visit_f64(*f),
            toml::Value::Boolean(b) => visitor.visit_bool(*b),
            toml::Value::Datetime(d) => visitor.visit_string(d.to_string()),
            toml::Value::Array(a) => visitor.visit_seq(Items {
                items: a.iter().enumerate(),
                path: self.path.clone(),
            }),
            toml::Value::Table(_) => unreachable!("a table is handled above"),
        };
        result.map_err(|e| self.here(e))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        if self.table().is_none() {
            let message = format!(
                "expected a table ([{0}] or {0} = {{ … }}, fields by name), got {1}",
                self.path,
                self.kind()
            );
            return Err(StrictError {
                path: self.path,
                message,
            });
        }
        self.deserialize_any(visitor)
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, StrictError> {
        visitor.visit_some(self)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, StrictError> {
        match self.value {
            // Unit variants are written as strings; any other shape was refused by the
            // `toml` reading already, and is left to it.
            Borrowed::Value(toml::Value::String(s)) => visitor
                .visit_enum(s.as_str().into_deserializer())
                .map_err(|e: de::value::Error| StrictError {
                    path: self.path.clone(),
                    message: e.to_string(),
                }),
            _ => self.deserialize_any(visitor),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        unit unit_struct seq tuple tuple_struct map identifier ignored_any
    }
}

/// The items of an array, each with its index in the path.
struct Items<'a, I: Iterator<Item = (usize, &'a toml::Value)>> {
    items: I,
    path: String,
}

impl<'de, 'a, I: Iterator<Item = (usize, &'a toml::Value)>> SeqAccess<'de> for Items<'a, I> {
    type Error = StrictError;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, StrictError> {
        let Some((i, v)) = self.items.next() else {
            return Ok(None);
        };
        let value = Strict {
            value: Borrowed::Value(v),
            path: format!("{}[{i}]", self.path),
        };
        let path = value.path.clone();
        seed.deserialize(value).map(Some).map_err(|e| at(e, path))
    }
}

/// The entries of a table, each value with its key in the path.
struct Entries<'a, I: Iterator<Item = (&'a String, &'a toml::Value)>> {
    entries: I,
    value: Option<(&'a String, &'a toml::Value)>,
    path: String,
}

impl<'de, 'a, I: Iterator<Item = (&'a String, &'a toml::Value)>> MapAccess<'de> for Entries<'a, I> {
    type Error = StrictError;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, StrictError> {
        let Some((k, v)) = self.entries.next() else {
            return Ok(None);
        };
        self.value = Some((k, v));
        seed.deserialize(k.as_str().into_deserializer())
            .map(Some)
            .map_err(|e: de::value::Error| de::Error::custom(e))
    }

    fn next_value_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<T::Value, StrictError> {
        let (k, v) = self
            .value
            .take()
            .ok_or_else(|| <StrictError as de::Error>::custom("a value without its key"))?;
        let path = if self.path.is_empty() {
            k.clone()
        } else {
            format!("{}.{k}", self.path)
        };
        let value = Strict {
            value: Borrowed::Value(v),
            path: path.clone(),
        };
        // An error raised after the value was read (an untagged enum's, a derived
        // visitor's) belongs to this field too.
        seed.deserialize(value).map_err(|e| at(e, path))
    }
}

/// `e` placed at `path` unless it already has a place.
fn at(mut e: StrictError, path: String) -> StrictError {
    if e.path.is_empty() {
        e.path = path;
    }
    e
}

#[cfg(test)]
mod tests {
    use super::{Invalid, check};
    use serde::Deserialize;

    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Inner {
        a: f64,
        #[serde(default)]
        b: bool,
    }

    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Outer {
        inner: Option<Inner>,
        #[serde(default)]
        list: Vec<Inner>,
        xyz: Option<[f64; 3]>,
    }

    fn run(text: &str) -> Result<(), Invalid> {
        check::<Outer>(&toml::from_str(text).unwrap())
    }

    #[test]
    fn tables_and_plain_arrays_pass() {
        run("xyz = [1, 2.5, 3]\n[inner]\na = 1\n[[list]]\na = 2\nb = true\n").unwrap();
        run("inner = { a = 1.0 }\nlist = [{ a = 3 }]\n").unwrap();
    }

    #[test]
    fn an_array_where_a_table_is_expected_is_refused_with_its_path() {
        // Both of these are accepted by toml + serde's derive (read positionally).
        let positional = "inner = [1.0, true]\n";
        assert!(toml::from_str::<Outer>(positional).is_ok());
        let e = run(positional).unwrap_err();
        assert_eq!(e.field, "inner");
        assert!(
            e.message.contains("expected a table") && e.message.contains("an array"),
            "{e}"
        );
        let e = run("[[list]]\na = 1\n[[list]]\na = 2\nlist2 = 0\n").unwrap_err();
        assert_eq!(
            e.field, "list[1]",
            "an unknown field inside the second entry"
        );
        let e = run("list = [{ a = 1 }, [2.0]]\n").unwrap_err();
        assert_eq!(e.field, "list[1]");
    }
}
