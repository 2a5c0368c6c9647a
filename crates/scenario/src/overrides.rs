//! Changing one field of a scenario by its dotted path (`explore.strategy`,
//! `explore.placement.min_contacts`, `seed`): `whisker run --set PATH=VALUE` and the
//! factors of `[trials]` (see the `trials` module). The change is made to the scenario's TOML
//! table, merged over its base, before it is read, so it is checked exactly as if it had
//! been written in the file.

use toml::{Table, Value};
use whisker_slam::invalid::Invalid;

/// One change: the path's keys and the new value.
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    /// The keys from the top table down (`["explore", "strategy"]`).
    pub path: Vec<String>,
    /// The value set there.
    pub value: Value,
}

impl Override {
    /// The dotted path as written.
    pub fn dotted(&self) -> String {
        self.path.join(".")
    }

    /// Parses `PATH=VALUE`: VALUE is a TOML value (`3`, `0.5`, `true`, `"feh"`, `[1, 2]`,
    /// `{ min_contacts = 3 }`); anything that does not parse as one is a string (`feh`).
    pub fn parse(arg: &str) -> Result<Self, Invalid> {
        let (path, value) = arg.split_once('=').ok_or_else(|| {
            format!("expected PATH=VALUE (e.g. explore.strategy=feh), got \"{arg}\"")
        })?;
        let path = split_path(path.trim())?;
        let text = value.trim();
        let value = toml::from_str::<Table>(&format!("v = {text}"))
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| Value::String(text.to_string()));
        Ok(Self { path, value })
    }

    /// Sets the value in `table`, creating missing tables on the way; an error when a key
    /// on the way holds something other than a table.
    pub fn apply(&self, table: &mut Table) -> Result<(), Invalid> {
        let (last, parents) = self.path.split_last().expect("paths are not empty");
        let mut at = table;
        for (i, key) in parents.iter().enumerate() {
            let next = at
                .entry(key.clone())
                .or_insert_with(|| Value::Table(Table::new()));
            at = match next {
                Value::Table(t) => t,
                other => {
                    return Err(format!(
                        "`{}` is a {}, not a table: cannot set `{}` under it",
                        self.path[..=i].join("."),
                        other.type_str(),
                        self.dotted()
                    )
                    .into());
                }
            };
        }
        at.insert(last.clone(), self.value.clone());
        Ok(())
    }
}

/// `a.b.c` → `["a", "b", "c"]`; an error for an empty path or an empty key.
pub fn split_path(path: &str) -> Result<Vec<String>, Invalid> {
    let keys: Vec<String> = path.split('.').map(|k| k.trim().to_string()).collect();
    if keys.iter().any(String::is_empty) {
        return Err(format!(
            "expected a dotted path of scenario fields (e.g. explore.strategy), got \"{path}\""
        )
        .into());
    }
    Ok(keys)
}

/// A value as one short line of TOML (strings without quotes), for keys and tables.
pub fn show(value: &Value) -> String {
    match value {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_parse_as_toml_or_else_as_strings() {
        let o = Override::parse("explore.strategy=feh").unwrap();
        assert_eq!(o.path, ["explore", "strategy"]);
        assert_eq!(o.value, Value::String("feh".into()));
        assert_eq!(Override::parse("seed=7").unwrap().value, Value::Integer(7));
        assert_eq!(
            Override::parse("a.b = [1, 2]").unwrap().value,
            Value::Array(vec![Value::Integer(1), Value::Integer(2)])
        );
        assert_eq!(
            Override::parse("a=\"x y\"").unwrap().value,
            Value::String("x y".into())
        );
        assert!(Override::parse("novalue").is_err());
        assert!(Override::parse("a..b=1").is_err());
    }

    #[test]
    fn apply_creates_tables_and_refuses_to_descend_into_values() {
        let mut t: Table = toml::from_str("seed = 1\n[explore]\ntask = 'map'\n").unwrap();
        Override::parse("explore.placement.min_contacts=3")
            .unwrap()
            .apply(&mut t)
            .unwrap();
        Override::parse("explore.task=recognise")
            .unwrap()
            .apply(&mut t)
            .unwrap();
        let want: Table = toml::from_str(
            "seed = 1\n[explore]\ntask = 'recognise'\n[explore.placement]\nmin_contacts = 3\n",
        )
        .unwrap();
        assert_eq!(t, want);
        let e = Override::parse("seed.x=1")
            .unwrap()
            .apply(&mut t)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`seed` is a integer"), "{e}");
    }
}
