//! `base = "other.toml"`: a scenario written as the changes to another (e.g. the maze
//! variants of thesis §3.3 over `scenarios/maze.toml`). The base is read first (its own
//! `base` too, up to 8 deep), then the scenario's tables are merged over it key by key;
//! a value that is not a table — a number, a string, an array, an array of tables such
//! as `[[maze.walls]]` — replaces the base's whole. The base must sit in the scenario's
//! own directory, so that relative paths (`arm.urdf`, meshes, the radial model) mean the
//! same in both.

use crate::error::{Error, Result};
use std::path::Path;
use toml::{Table, Value};

/// How many bases may be chained.
const MAX_DEPTH: usize = 8;

/// Reads `path` as a TOML table, syntax errors naming the file, line and column.
pub fn read_table(path: &Path) -> Result<(String, Table)> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::Input(format!("{}: cannot read scenario: {e}", path.display())))?;
    let table: Table = toml::from_str(&text)
        .map_err(|e| Error::Input(format!("{}: {}", path.display(), e.to_string().trim_end())))?;
    Ok((text, table))
}

/// `table` (read from `path`) merged over its base, recursively; `base` removed.
pub fn resolve(path: &Path, mut table: Table, depth: usize) -> Result<Table> {
    let Some(base) = table.remove("base") else {
        return Ok(table);
    };
    let bad = |msg: String| Error::field(path, "base", msg);
    let Value::String(name) = base else {
        return Err(bad(format!("expected a file name, got {base}")));
    };
    let mut components = Path::new(&name).components();
    let one_file = matches!(
        (components.next(), components.next()),
        (Some(std::path::Component::Normal(_)), None)
    );
    if !one_file {
        return Err(bad(format!(
            "expected a file in the scenario's own directory, got \"{name}\""
        )));
    }
    if depth >= MAX_DEPTH {
        return Err(bad(format!(
            "more than {MAX_DEPTH} bases in a chain (a cycle?) at \"{name}\""
        )));
    }
    let base_path = path.with_file_name(&name);
    if !base_path.is_file() {
        return Err(bad(format!(
            "\"{name}\": no such file in the scenario's directory ({})",
            base_path.display()
        )));
    }
    let (_, base_table) = read_table(&base_path)?;
    let mut merged = resolve(&base_path, base_table, depth + 1)?;
    merge(&mut merged, table);
    Ok(merged)
}

/// Merges `over` into `under`: tables key by key, anything else replaced.
pub fn merge(under: &mut Table, over: Table) {
    for (key, value) in over {
        match (under.get_mut(&key), value) {
            (Some(Value::Table(u)), Value::Table(o)) => merge(u, o),
            (_, value) => {
                under.insert(key, value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_merge_key_by_key_and_everything_else_is_replaced() {
        let mut under: Table = toml::from_str(
            "seed = 1\n[a]\nx = 1\ny = [1, 2]\n[a.b]\nz = 'u'\n[[w]]\nk = 1\n[[w]]\nk = 2\n",
        )
        .unwrap();
        let over: Table =
            toml::from_str("seed = 2\n[a]\ny = [3]\n[a.b]\nq = 4\n[[w]]\nk = 9\n").unwrap();
        merge(&mut under, over);
        let want: Table =
            toml::from_str("seed = 2\n[a]\nx = 1\ny = [3]\n[a.b]\nz = 'u'\nq = 4\n[[w]]\nk = 9\n")
                .unwrap();
        assert_eq!(under, want);
    }
}
