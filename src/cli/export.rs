//! `whisker export --mcap FILE DIR`: a dataset or a run's output as a ROS 2 bag (MCAP),
//! and the `--mcap` inputs of the replays.

use std::path::{Path, PathBuf};
use whisker_experiments::ros2_bag::{self, Unpacked};
use whisker_scenario::{Error, Result};

/// Write a dataset (or a run's output directory) as a ROS 2 bag in MCAP (docs/dataset.md,
/// "ROS 2 bags").
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The dataset's directory (with `dataset.json`) or a run's `--out` directory.
    pub dir: PathBuf,
    /// The MCAP file to write (must not exist).
    #[arg(long, required = true)]
    pub mcap: PathBuf,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs it.
pub fn run(a: &Args) -> Result {
    let exported = ros2_bag::export(&a.dir, &a.mcap)?;
    match a.json {
        true => super::print_json(&exported, false),
        false => print!("{exported}"),
    }
    Ok(())
}

/// Refuses an existing `--mcap` before a long dataset write.
pub fn check_new(mcap: Option<&PathBuf>) -> Result {
    match mcap {
        Some(f) if f.exists() => Err(Error::Input(format!(
            "{}: already exists; an export is never written over a file (choose a new --mcap)",
            f.display()
        ))),
        _ => Ok(()),
    }
}

/// Exports the dataset just written to `dir` when `--mcap` asks for it.
pub fn also(dir: &Path, mcap: Option<&PathBuf>) -> Result {
    if let Some(f) = mcap {
        eprint!("{}", ros2_bag::export(dir, f)?);
    }
    Ok(())
}

/// The dataset a replay reads, if any: `dir` itself, or the bag `mcap` unpacked (kept while
/// the returned guard lives).
pub fn dataset(
    dir: Option<&PathBuf>,
    mcap: Option<&PathBuf>,
) -> Result<(Option<PathBuf>, Option<Unpacked>)> {
    match (dir, mcap) {
        (_, Some(f)) => {
            let u = ros2_bag::unpack(f)?;
            Ok((Some(u.dir.clone()), Some(u)))
        }
        (d, None) => Ok((d.cloned(), None)),
    }
}
