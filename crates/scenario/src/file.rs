//! A scenario file read once: the TOML table as run (its `base` chain merged in, `--set`
//! overrides applied) and the [`Scenario`] it describes, checked — with the file's path,
//! against which the scenario's relative paths resolve and which every error names.

use crate::base::{read_table, resolve};
use crate::environment::LoadedEnvironment;
use crate::error::{Error, Result};
use crate::overrides::Override;
use crate::scenario::Scenario;
use std::fmt;
use std::path::{Path, PathBuf};
use toml::Table;
use whisker_sim::sensing::physics::WhiskerConfig;

/// A scenario and the file it was read from.
#[derive(Debug, Clone)]
pub struct ScenarioFile {
    /// The file, as given.
    pub path: PathBuf,
    /// Its table as run: the base chain merged in, the overrides applied (what a dataset
    /// keeps as `truth/scenario.toml` and a batch hashes).
    pub table: Table,
    /// What it describes, checked.
    pub scenario: Scenario,
}

impl ScenarioFile {
    /// Reads and checks a scenario file (what does not depend on the URDF). Without a
    /// `base`, errors name the line; merged over a base, the field.
    pub fn load(path: &Path) -> Result<Self> {
        let (text, table) = read_table(path)?;
        if table.contains_key("base") {
            // Merged over its base: errors name the field, no longer the line.
            let merged = resolve(path, table, 0)?;
            return Self::from_table(path, merged, "merged over its base");
        }
        let mut scenario: Scenario = toml::from_str(&text).map_err(|e| {
            Error::Input(format!("{}: {}", path.display(), e.to_string().trim_end()))
        })?;
        Scenario::check_shapes(path, &table)?;
        scenario.validate(path)?;
        Ok(Self {
            path: path.to_path_buf(),
            table,
            scenario,
        })
    }

    /// Reads and checks a scenario file with `overrides` applied (`whisker run --set`).
    pub fn load_with(path: &Path, overrides: &[Override]) -> Result<Self> {
        if overrides.is_empty() {
            return Self::load(path);
        }
        let (_, table) = read_table(path)?;
        let mut table = resolve(path, table, 0)?;
        for o in overrides {
            o.apply(&mut table).map_err(|e| {
                Error::Input(format!("{}: --set {}: {e}", path.display(), o.dotted()))
            })?;
        }
        Self::from_table(path, table, "with --set")
    }

    /// The scenario of `table` (read from `path`, base merged in, then changed as
    /// `context` says), checked.
    pub fn from_table(path: &Path, table: Table, context: &str) -> Result<Self> {
        let mut scenario: Scenario = match table.clone().try_into() {
            Ok(s) => s,
            Err(e) => {
                let e: toml::de::Error = e;
                // A table has no lines, and toml names the field of only some errors
                // (not those of enums or untagged enums): the path-keeping reading does.
                return Err(match crate::strict::check::<Scenario>(&table) {
                    Err(e) if !e.field.is_empty() => Error::Input(format!(
                        "{} ({context}): field `{}`: {}",
                        path.display(),
                        e.field,
                        e.message
                    )),
                    _ => Error::Input(format!(
                        "{} ({context}): {}",
                        path.display(),
                        e.to_string().trim_end()
                    )),
                });
            }
        };
        Scenario::check_shapes(path, &table)?;
        scenario.validate(path)?;
        Ok(Self {
            path: path.to_path_buf(),
            table,
            scenario,
        })
    }

    /// An input error about `field` of this file.
    pub fn error(&self, field: &str, message: impl fmt::Display) -> Error {
        Error::field(&self.path, field, message)
    }

    /// `relative`, a path written in the scenario, resolved against its directory.
    pub fn resolve(&self, relative: &Path) -> PathBuf {
        crate::paths::relative_to(&self.path, relative)
    }

    /// The URDF path, resolved against the scenario file's directory.
    pub fn urdf_path(&self) -> PathBuf {
        self.resolve(&self.scenario.arm.urdf)
    }

    /// The package search directories, resolved against the scenario file's directory.
    pub fn package_paths(&self) -> Vec<PathBuf> {
        let arm = &self.scenario.arm;
        arm.package_paths.iter().map(|p| self.resolve(p)).collect()
    }

    /// The environment of `[[objects]]`, `[maze]` and `[office]`, loaded (mesh files read,
    /// checked and repaired; the maze built).
    pub fn environment(&self) -> Result<LoadedEnvironment> {
        let s = &self.scenario;
        crate::environment::load(
            &self.path,
            &s.objects,
            s.maze.as_ref(),
            s.office.as_ref(),
            s.seed,
        )
    }

    /// The 18 whiskers' configurations of `[array]` (RCP thresholds not yet calibrated):
    /// those checked at loading, or, for a scenario without sensing, checked now.
    pub fn whisker_configs(&self) -> Result<Vec<WhiskerConfig>> {
        self.scenario.whisker_configs(&self.path)
    }
}
