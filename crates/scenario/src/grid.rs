//! The batch a scenario's `[trials]` describes (scenarios/README.md, "Batch trials"): the
//! grid of trials over seeds and factor levels, each with a stable key, and its shards.
//! Running it is `whisker-trials`' work.
//!
//! A trial is exactly one `whisker run` of the scenario with the trial's factor levels set
//! by their dotted paths and its seed (`whisker run --seed S --set PATH=VALUE…` gives the
//! same result bytes). The trial list is fixed by the scenario alone (factors in path
//! order, the first outermost; seeds innermost), each trial with a stable key, and a shard
//! is every K-th trial of it: rows depend on neither the number of workers, nor the order
//! trials finish, nor the sharding.
use crate::error::{Error, Result};
use crate::file::ScenarioFile;
use crate::overrides::{Override, show, split_path};
use crate::trials::{Outputs, TrialCommand, TrialsConfig};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use toml::{Table, Value};
use whisker_slam::invalid::Invalid;

/// One factor: a scenario field and the values it takes.
#[derive(Debug, Clone)]
pub struct Factor {
    /// The field's dotted path.
    pub path: String,
    /// The same path, key by key.
    pub keys: Vec<String>,
    /// The levels, in the order written.
    pub levels: Vec<Value>,
    /// How each level appears in trial keys.
    pub labels: Vec<String>,
}

impl Factor {
    /// The change that sets this factor to `level`.
    pub fn set(&self, level: usize) -> Override {
        Override {
            path: self.keys.clone(),
            value: self.levels[level].clone(),
        }
    }
}

/// One trial of a batch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trial {
    /// Position in the batch's fixed order.
    pub index: usize,
    /// Stable key: `path=level+…+seed=S` (file-name safe).
    pub key: String,
    /// The seed.
    pub seed: u64,
    /// The level of each factor (indices into [`Factor::levels`]).
    pub levels: Vec<usize>,
}

/// A scenario's `[trials]`, expanded.
#[derive(Debug, Clone)]
pub struct Batch {
    /// The scenario file.
    pub file: PathBuf,
    /// Its table, merged over its base, without `[trials]`.
    pub table: Table,
    /// `[trials]`.
    pub config: TrialsConfig,
    /// The factors, by path.
    pub factors: Vec<Factor>,
    /// Every trial, in order.
    pub trials: Vec<Trial>,
    /// SHA-256 of the merged scenario (with `[trials]`), hex.
    pub hash: String,
}

impl Batch {
    /// Reads `file`'s `[trials]` and checks every factor level by reading the scenario
    /// with it set (errors name the factor and the level).
    pub fn load(file: &Path) -> Result<Self> {
        Self::of(&ScenarioFile::load(file)?)
    }

    /// The batch of `read`'s `[trials]`, every factor level checked as in [`Batch::load`].
    pub fn of(read: &ScenarioFile) -> Result<Self> {
        let file = read.path.as_path();
        let config =
            read.scenario.trials.clone().ok_or_else(|| {
                Error::field(file, "trials", "the scenario has no [trials] section")
            })?;
        let mut table = read.table.clone();
        let hash = hex(&Sha256::digest(
            toml::to_string(&table).expect("a table").as_bytes(),
        ));
        table.remove("trials");
        let seeds = config
            .seeds
            .list()
            .map_err(|e| Error::field(file, "trials.seeds", e))?;
        let mut factors = Vec::new();
        collect(file, &config.factors, &[], &mut factors)?;
        factors.sort_by(|a, b| a.path.cmp(&b.path));
        for f in &factors {
            for (i, level) in f.levels.iter().enumerate() {
                let mut t = table.clone();
                let o = f.set(i);
                let field = format!("trials.factors.{}[{i}]", f.path);
                o.apply(&mut t).map_err(|e| Error::field(file, &field, e))?;
                let s = ScenarioFile::from_table(
                    file,
                    t,
                    &format!("with {} = {}", f.path, show(level)),
                )
                .map_err(|e| Error::field(file, &field, e))?;
                // The environment's fields are checked as it loads (meshes, poses): a
                // level that changes it is loaded once here, so that a bad value (a NaN
                // position) is refused now, not by every trial at run time.
                let root = f.path.split('.').next().unwrap_or_default();
                if root == "objects" || root == "maze" {
                    s.environment().map_err(|e| Error::field(file, &field, e))?;
                }
            }
        }
        let trials = expand(&factors, &seeds);
        if config.experiment == TrialCommand::MazeSlam && read.scenario.maze.is_none() {
            return Err(Error::field(
                file,
                "trials.experiment",
                "\"maze-slam\" needs a [maze] section",
            ));
        }
        Ok(Self {
            file: file.to_path_buf(),
            table,
            config,
            factors,
            trials,
            hash,
        })
    }

    /// One line for `whisker check`: how many trials, of which factors and seeds.
    pub fn describe(&self) -> String {
        let mut parts: Vec<String> = self
            .factors
            .iter()
            .map(|f| format!("{} ({})", f.path, f.labels.join(", ")))
            .collect();
        let seeds: std::collections::BTreeSet<u64> = self.trials.iter().map(|t| t.seed).collect();
        parts.push(format!("{} seeds", seeds.len()));
        format!(
            "trials     {} trials ({:?}): {}",
            self.trials.len(),
            self.config.experiment,
            parts.join(" × ")
        )
    }

    /// The changes a trial makes to the scenario (its seed excluded).
    pub fn overrides(&self, trial: &Trial) -> Vec<Override> {
        self.factors
            .iter()
            .zip(&trial.levels)
            .map(|(f, &l)| f.set(l))
            .collect()
    }

    /// The scenario of a trial: its levels set, its seed, no recording with light
    /// outputs.
    pub fn scenario(&self, trial: &Trial) -> Result<ScenarioFile> {
        let mut table = self.table.clone();
        for o in self.overrides(trial) {
            o.apply(&mut table)
                .map_err(|e| Error::Input(e.to_string()))?;
        }
        table.insert("seed".into(), Value::Integer(trial.seed as i64));
        let mut file =
            ScenarioFile::from_table(&self.file, table, &format!("trial {}", trial.key))?;
        if self.config.outputs == Outputs::Light {
            file.scenario.output.recording = false;
        }
        Ok(file)
    }

    /// The `whisker` command line that runs the same as `trial` (shell-quoted).
    pub fn command(&self, trial: &Trial) -> String {
        let (verb, seed) = match self.config.experiment {
            TrialCommand::Run => ("run", "--seed"),
            TrialCommand::MazeSlam => ("maze-slam", "--json --seeds"),
        };
        let mut s = format!(
            "whisker {verb} {} {seed} {}",
            quote(&self.file.display().to_string()),
            trial.seed
        );
        for o in self.overrides(trial) {
            s += &format!(" --set {}", quote(&format!("{}={}", o.dotted(), o.value)));
        }
        s
    }

    /// The trials of shard `i` of `k` (every k-th, from the i-th).
    pub fn shard(&self, shard: Option<Shard>) -> Vec<&Trial> {
        self.trials
            .iter()
            .filter(|t| shard.is_none_or(|s| t.index % s.count == s.index))
            .collect()
    }
}

/// `--shard I/K`: the I-th (from 0) of K parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// I.
    pub index: usize,
    /// K.
    pub count: usize,
}

impl Shard {
    /// Parses `I/K` with 0 ≤ I < K.
    pub fn parse(s: &str) -> Result<Self, Invalid> {
        let bad = || {
            Invalid::new(format!(
                "expected I/K with 0 ≤ I < K (e.g. 0/4), got \"{s}\""
            ))
        };
        let (i, k) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse().map_err(|_| bad())?,
            k.trim().parse().map_err(|_| bad())?,
        );
        if index >= count {
            return Err(bad());
        }
        Ok(Self { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Single-quotes `s` for the shell.
pub fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// Lower-case hex of `bytes`.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The factors of `table` (under `trials.factors.<prefix>`): nested tables down to the
/// lists of levels.
fn collect(file: &Path, table: &Table, prefix: &[String], out: &mut Vec<Factor>) -> Result {
    for (key, value) in table {
        let mut path = prefix.to_vec();
        path.extend(
            split_path(key).map_err(|e| {
                Error::field(file, &format!("trials.factors.{}", prefix.join(".")), e)
            })?,
        );
        let dotted = path.join(".");
        let field = format!("trials.factors.{dotted}");
        match value {
            Value::Table(t) => collect(file, t, &path, out)?,
            Value::Array(levels) if !levels.is_empty() => {
                if dotted == "seed" || path[0] == "trials" {
                    return Err(Error::field(
                        file,
                        &field,
                        "seeds are `trials.seeds`, and [trials] cannot vary itself",
                    ));
                }
                if out.iter().any(|f: &Factor| f.path == dotted) {
                    return Err(Error::field(file, &field, "the factor is given twice"));
                }
                out.push(Factor {
                    path: dotted,
                    keys: path,
                    labels: labels(levels),
                    levels: levels.clone(),
                });
            }
            other => {
                return Err(Error::field(
                    file,
                    &field,
                    format!("expected a non-empty list of the values the field takes, got {other}"),
                ));
            }
        }
    }
    Ok(())
}

/// File-name-safe labels of the levels: the value itself for distinct short scalars,
/// tables and lists of tables by their `name` fields, else `#0`, `#1`…
fn labels(levels: &[Value]) -> Vec<String> {
    let safe = |v: &Value| -> Option<String> {
        let s = match v {
            Value::String(s) => s.clone(),
            Value::Integer(_) | Value::Float(_) | Value::Boolean(_) => v.to_string(),
            // Tables (e.g. `[[objects]]` entries) by their `name`s.
            Value::Table(t) => t.get("name")?.as_str()?.to_string(),
            Value::Array(items) => items
                .iter()
                .map(|i| Some(i.as_table()?.get("name")?.as_str()?.to_string()))
                .collect::<Option<Vec<_>>>()?
                .join("-"),
            _ => return None,
        };
        (!s.is_empty()
            && s.len() <= 40
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "._-".contains(c)))
        .then_some(s)
    };
    let named: Option<Vec<String>> = levels.iter().map(safe).collect();
    match named {
        Some(n) if n.iter().collect::<std::collections::BTreeSet<_>>().len() == n.len() => n,
        _ => (0..levels.len()).map(|i| format!("#{i}")).collect(),
    }
}

/// The product of the factors' levels (first factor outermost) and the seeds (innermost).
fn expand(factors: &[Factor], seeds: &[u64]) -> Vec<Trial> {
    let mut combos: Vec<Vec<usize>> = vec![vec![]];
    for f in factors {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                (0..f.levels.len()).map(move |l| {
                    let mut c = c.clone();
                    c.push(l);
                    c
                })
            })
            .collect();
    }
    let mut trials = Vec::new();
    for levels in combos {
        for &seed in seeds {
            let mut parts: Vec<String> = factors
                .iter()
                .zip(&levels)
                .map(|(f, &l)| format!("{}={}", f.path, f.labels[l]))
                .collect();
            parts.push(format!("seed={seed}"));
            trials.push(Trial {
                index: trials.len(),
                key: parts.join("+"),
                seed,
                levels: levels.clone(),
            });
        }
    }
    trials
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trials_are_the_product_with_seeds_innermost() {
        let f = |path: &str, v: &[&str]| Factor {
            path: path.into(),
            keys: vec![path.into()],
            levels: v.iter().map(|s| Value::String(s.to_string())).collect(),
            labels: v.iter().map(|s| s.to_string()).collect(),
        };
        let t = expand(&[f("a", &["x", "y"]), f("b", &["u", "v", "w"])], &[5, 9]);
        assert_eq!(t.len(), 12);
        assert_eq!(t[0].key, "a=x+b=u+seed=5");
        assert_eq!(t[1].key, "a=x+b=u+seed=9");
        assert_eq!(t[2].key, "a=x+b=v+seed=5");
        assert_eq!(t[11].key, "a=y+b=w+seed=9");
        assert!(t.iter().enumerate().all(|(i, t)| t.index == i));
        assert_eq!(expand(&[], &[1, 2]).len(), 2);
    }

    #[test]
    fn labels_fall_back_to_indices_for_values_unfit_for_file_names() {
        let v = |s: &str| Value::String(s.into());
        assert_eq!(labels(&[v("feh"), Value::Integer(3)]), ["feh", "3"]);
        assert_eq!(labels(&[v("a/b"), v("c")]), ["#0", "#1"]);
        assert_eq!(
            labels(&[Value::Float(0.5), Value::Boolean(true)]),
            ["0.5", "true"]
        );
        let objects: Value =
            toml::from_str::<Table>("o = [[{ name = 'box' }], [{ name = 'box_stack' }]]")
                .unwrap()
                .remove("o")
                .unwrap();
        let objects = objects.as_array().unwrap().clone();
        assert_eq!(labels(&objects), ["box", "box_stack"]);
    }

    #[test]
    fn shards_parse_and_split_round_robin() {
        assert_eq!(Shard::parse("1/4").unwrap(), Shard { index: 1, count: 4 });
        assert!(Shard::parse("4/4").is_err());
        assert!(Shard::parse("x").is_err());
    }
}
