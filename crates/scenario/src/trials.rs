//! `[trials]`: a batch of runs of the scenario over seeds and factors (scenarios/README.md,
//! "Batch trials"; run by `whisker trials`, see the `trials` module).

use serde::Deserialize;
use toml::Table;
use whisker_slam::invalid::Invalid;

/// `[trials]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrialsConfig {
    /// The seeds: a list (`[0, 1, 2]`) or an inclusive range (`{ from = 0, to = 9 }`).
    pub seeds: Seeds,
    /// `[trials.factors]`: for any scenario field by its dotted path, the list of values
    /// it takes (`explore.strategy = ["default", "feh", "lsr"]`); the trials are the
    /// product of all the lists and the seeds.
    #[serde(default)]
    pub factors: Table,
    /// What one trial runs: `"run"` (what `whisker run` does) or `"maze-slam"` (one seed of
    /// `whisker maze-slam`).
    #[serde(default)]
    pub experiment: TrialCommand,
    /// What each trial keeps in `runs/<key>/`: `"light"` (the summary, `explore.csv` or
    /// `path.csv`, maze trajectories, `stdout.txt`) or `"all"` (also the recording and the
    /// heavy streams: see [`HEAVY`]).
    #[serde(default)]
    pub outputs: Outputs,
    /// The summary metrics the report analyses, by their flattened names
    /// (`recognition.srt`); default: every metric that varies.
    #[serde(default)]
    pub report: Vec<String>,
}

/// `trials.seeds`.
#[derive(Debug, Clone, Deserialize)]
#[serde(
    untagged,
    expecting = "expected a list of seeds ([0, 1, 2]) or a range ({ from = 0, to = 9 }), whole numbers ≥ 0"
)]
pub enum Seeds {
    /// `[0, 1, 2]`.
    List(Vec<u64>),
    /// `{ from = 0, to = 9 }`: both ends included.
    Range {
        /// The first seed.
        from: u64,
        /// The last seed.
        to: u64,
    },
}

impl Seeds {
    /// The seeds in order; an error for an empty, reversed or repeating list.
    pub fn list(&self) -> Result<Vec<u64>, Invalid> {
        let v = match self {
            Seeds::List(v) => v.clone(),
            Seeds::Range { from, to } if from <= to && to - from < 1_000_000 => {
                (*from..=*to).collect()
            }
            Seeds::Range { from, to } => {
                return Err(format!(
                    "expected from ≤ to and fewer than a million seeds, got from = {from}, to = {to}"
                ).into());
            }
        };
        if v.is_empty() {
            return Err("expected at least one seed".into());
        }
        let mut sorted = v.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!("seed {} is listed twice", w[0]).into());
        }
        Ok(v)
    }
}

/// `trials.outputs`.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Outputs {
    /// Without the recording and the files named in [`HEAVY`].
    #[default]
    Light,
    /// Everything `whisker run` writes.
    All,
}

/// The heavy outputs a light trial does not keep (prefixes of file names): the Rerun
/// recording, every contact (`contacts.csv`, `anticipated.csv`), the 2 kHz whisker
/// streams and the front end's contacts, the maze's tactile images.
pub const HEAVY: [&str; 6] = [
    "run.rrd",
    "contacts.csv",
    "anticipated.csv",
    "whiskers.csv",
    "frontend.csv",
    "images-",
];

/// `trials.experiment`.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TrialCommand {
    /// One `whisker run` of the scenario (scripted trajectory or closed loop).
    #[default]
    Run,
    /// One seed of `whisker maze-slam` (thesis §3.3).
    MazeSlam,
}
