//! RatSLAM's parameters per run, and their tuning (§3.2.1: "the tactile-image changes,
//! which in turn requires the OpenRatSLAM parameters ... to be re-tuned" for every image
//! set and whisking control). A run's parameters are, in order: the command line's grid
//! (`--match-threshold`, `--inject-energy`: every pair), the scenario's `[maze_slam.tuned]`
//! entry for its image set and variant, or `[maze_slam.ratslam]`. `--tune FILE` picks,
//! per image set and variant, from the grid's pairs whose mean Energy Metric over the seeds
//! run is within [`EM_TOLERANCE`] of the grid's lowest, the one with the highest mean rate
//! of correct re-localisation ARR · ARCR (ties: the lower EM), and writes it as a scenario
//! over the one run — §3.2.1's "balance ... to make sure that occasional false matches do
//! not cause too much influence [the EM near its best] while still allowing for occasional
//! correct matches to cause regular re-localization [the most correct ones]". Either
//! criterion alone runs to an edge of the grid on physics (seed 100): the lowest EM
//! switches re-localisation all but off (the least inject energy won every variant), the
//! most correct re-localisations quadruple the EM (the loosest threshold won).

use super::{RunResult, Settings};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;
use whisker_scenario::maze_slam::Tuned;
use whisker_scenario::{Error, Result};
use whisker_slam::ratslam::RatSlamParams;

/// Each run's RatSLAM parameters.
pub struct Tunings {
    base: RatSlamParams,
    /// The command line's grid, when it gives one.
    grid: Option<Vec<RatSlamParams>>,
    tuned: BTreeMap<String, Tuned>,
}

impl Tunings {
    /// `base` (the scenario's or dataset's `ratslam`), its `tuned` entries, and the grid
    /// of `o`'s lists (each defaulting to `base`'s value).
    pub fn of(base: RatSlamParams, tuned: &BTreeMap<String, Tuned>, o: &Settings) -> Result<Self> {
        let grid = match (&o.match_threshold, &o.inject_energy) {
            (None, None) => None,
            _ => Some(grid(base, o)?),
        };
        Ok(Self {
            base,
            grid,
            tuned: tuned.clone(),
        })
    }

    /// The tuned entries whose image set is none of `sets` (another whisking control's,
    /// as when a batch varies `array.rcp` over one tuned scenario — or a typo): said on the
    /// console, since their runs are not in this one.
    pub fn unused(&self, sets: &[String]) -> Vec<String> {
        self.tuned
            .keys()
            .filter(|key| {
                let images = key.rsplit_once('/').map_or(key.as_str(), |(i, _)| i);
                !sets.iter().any(|s| s == images)
            })
            .cloned()
            .collect()
    }

    /// Whether runs differ by their parameters only (their names then carry them).
    pub fn sweep(&self) -> bool {
        self.grid.as_ref().is_some_and(|g| g.len() > 1)
    }

    /// The parameters of the runs of image set `images`, variant `variant`.
    pub fn for_run(&self, images: &str, variant: &str) -> Vec<RatSlamParams> {
        if let Some(g) = &self.grid {
            return g.clone();
        }
        let tuned = self.tuned.get(&key(images, variant));
        vec![tuned.map_or(self.base, |t| t.over(self.base))]
    }
}

/// The `[maze_slam.tuned]` key of a run.
pub fn key(images: &str, variant: &str) -> String {
    format!("{images}/{variant}")
}

/// Every (threshold, energy) pair of `o`'s lists over `base`, checked.
fn grid(base: RatSlamParams, o: &Settings) -> Result<Vec<RatSlamParams>> {
    let lv = base.local_view;
    let thresholds = o
        .match_threshold
        .clone()
        .unwrap_or(vec![lv.match_threshold]);
    let energies = o.inject_energy.clone().unwrap_or(vec![lv.inject_energy]);
    // Only the options' values: the scenario's or dataset's were checked where read (and
    // an injection energy of 0 is allowed there).
    let mut given = o.match_threshold.iter().chain(&o.inject_energy).flatten();
    if let Some(bad) = given.find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(Error::Input(format!(
            "--match-threshold / --inject-energy: expected positive numbers, got {}",
            whisker_sim::whisker::short(*bad)
        )));
    }
    let mut out = Vec::new();
    for &threshold in &thresholds {
        for &energy in &energies {
            let mut p = base;
            p.local_view.match_threshold = threshold;
            p.local_view.inject_energy = energy;
            p.validate()
                .map_err(|e| Error::Input(format!("--match-threshold / --inject-energy: {e}")))?;
            out.push(p);
        }
    }
    Ok(out)
}

/// The tag of a tuning in a sweep (`-t<threshold>-e<energy>`), or nothing.
pub fn tag(params: &RatSlamParams, sweep: bool) -> String {
    if !sweep {
        return String::new();
    }
    let lv = params.local_view;
    // Short in any case: a file name holds at most 255 bytes, 1e308 written out 309.
    let short = |v: f64| {
        let plain = v.to_string();
        if plain.len() <= 12 {
            plain
        } else {
            format!("{v:e}")
        }
    };
    format!(
        "-t{}-e{}",
        short(lv.match_threshold),
        short(lv.inject_energy)
    )
}

/// The tuning chosen for one image set and variant, and how it scored.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Choice {
    /// `<images>/<variant>`.
    pub key: String,
    pub tuned: Tuned,
    /// Means over the seeds: ARR · ARCR (correct re-localisations per update after the
    /// base set), Energy Metric, ARR, ARCR.
    pub correct_rate: f64,
    pub energy_metric: f64,
    pub arr: f64,
    pub arcr: f64,
    /// Seeds and candidate pairs it was chosen from.
    pub seeds: usize,
    pub candidates: usize,
}

/// How far above the grid's lowest mean Energy Metric a chosen pair's may be (a fraction).
pub const EM_TOLERANCE: f64 = 0.25;

/// Per image set and variant, among the pairs whose mean Energy Metric is within
/// [`EM_TOLERANCE`] of the lowest, the one with the highest mean ARR · ARCR over the seeds
/// (ties: the lower mean EM; then the lower threshold, then energy). Needs ground truth.
pub fn choose(runs: &[RunResult]) -> Result<Vec<Choice>> {
    // key → (threshold, energy) → [(EM, ARR, ARCR)] over seeds.
    type Scores = BTreeMap<(u64, u64), Vec<(f64, f64, f64)>>;
    let mut by_key: BTreeMap<String, Scores> = BTreeMap::new();
    for r in runs {
        let (Some(em), Some(arr), Some(arcr)) = (r.energy_metric, r.arr, r.arcr) else {
            return Err(Error::Input(
                "--tune: the runs have no ground truth to score them (a dataset without truth/)"
                    .into(),
            ));
        };
        let pair = (r.match_threshold.to_bits(), r.inject_energy.to_bits());
        by_key
            .entry(key(&r.images, r.variant))
            .or_default()
            .entry(pair)
            .or_default()
            .push((em, arr, arcr));
    }
    let mean = |v: &[(f64, f64, f64)], f: fn(&(f64, f64, f64)) -> f64| {
        v.iter().map(f).sum::<f64>() / v.len() as f64
    };
    let mut out = Vec::new();
    for (key, pairs) in by_key {
        let candidates = pairs.len();
        if candidates < 2 {
            return Err(Error::Input(format!(
                "--tune: one parameter pair for {key}: give lists to --match-threshold and/or \
                 --inject-energy to choose from"
            )));
        }
        let scored: Vec<Choice> = pairs
            .iter()
            .map(|(&(t, e), v)| {
                let em = mean(v, |s| s.0);
                Choice {
                    key: key.clone(),
                    tuned: Tuned {
                        match_threshold: f64::from_bits(t),
                        inject_energy: f64::from_bits(e),
                    },
                    correct_rate: mean(v, |s| s.1 * s.2),
                    energy_metric: if em.is_nan() { f64::INFINITY } else { em },
                    arr: mean(v, |s| s.1),
                    arcr: mean(v, |s| s.2),
                    seeds: v.len(),
                    candidates,
                }
            })
            .collect();
        let lowest = scored
            .iter()
            .map(|c| c.energy_metric)
            .fold(f64::INFINITY, f64::min);
        let best = scored
            .into_iter()
            .filter(|c| c.energy_metric <= lowest * (1.0 + EM_TOLERANCE))
            .min_by(|a, b| {
                b.correct_rate
                    .total_cmp(&a.correct_rate)
                    .then(a.energy_metric.total_cmp(&b.energy_metric))
                    .then(a.tuned.match_threshold.total_cmp(&b.tuned.match_threshold))
                    .then(a.tuned.inject_energy.total_cmp(&b.tuned.inject_energy))
            })
            .expect("the lowest EM's pair is admissible");
        out.push(best);
    }
    Ok(out)
}

/// Writes `choices` to `out` as a scenario over `scenario` (which must lie in the same
/// directory: a scenario's base does), naming the `command` and `seeds` that chose them.
pub fn write(
    out: &Path,
    scenario: &Path,
    choices: &[Choice],
    command: &str,
    seeds: &[u64],
) -> Result {
    let dir = |p: &Path| {
        p.parent()
            .map(|d| {
                if d.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    d
                }
            })
            .and_then(|d| d.canonicalize().ok())
    };
    if dir(out).is_none() || dir(out) != dir(scenario) {
        return Err(Error::Input(format!(
            "--tune {}: expected a file beside the scenario {} (it becomes the tuned \
             scenario's base)",
            out.display(),
            scenario.display()
        )));
    }
    let base = scenario
        .file_name()
        .expect("a scenario file")
        .to_string_lossy();
    let list: Vec<String> = seeds.iter().map(u64::to_string).collect();
    let mut text = format!(
        "# RatSLAM tuned per image set and variant (thesis §3.2.1) by\n#\n#   {command}\n#\n\
         # on seeds {} (tune on seeds that are not reported): for each, among the grid's pairs\n\
         # whose mean Energy Metric is within 25 % of the lowest, the one with the highest mean\n\
         # ARR x ARCR (the rate of correct re-localisation; ties: the lower mean EM).\n",
        list.join(",")
    );
    for c in choices {
        let _ = writeln!(
            text,
            "#   {}: ARR x ARCR {:.4}, EM {:.4}, ARR {:.4}, ARCR {:.4} (best of {} pairs)",
            c.key, c.correct_rate, c.energy_metric, c.arr, c.arcr, c.candidates
        );
    }
    let _ = writeln!(text, "base = {base:?}");
    for c in choices {
        let _ = write!(
            text,
            "\n[maze_slam.tuned.{:?}]\nmatch_threshold = {:?}\ninject_energy = {:?}\n",
            c.key, c.tuned.match_threshold, c.tuned.inject_energy
        );
    }
    whisker_scenario::files::write_atomic(out, text.as_bytes())
}

/// `--tune FILE`: [`choose`] over `runs`, [`write`] beside `scenario`; the choices.
pub fn tune(out: &Path, scenario: &Path, runs: &[RunResult], command: &str) -> Result<Vec<Choice>> {
    let choices = choose(runs)?;
    let mut seeds: Vec<u64> = runs.iter().map(|r| r.seed).collect();
    seeds.sort_unstable();
    seeds.dedup();
    write(out, scenario, &choices, command, &seeds)?;
    Ok(choices)
}

impl std::fmt::Display for Choice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: match_threshold {}, inject_energy {} (mean over {} seeds: ARR x ARCR {:.4}, \
             EM {:.4}, ARR {:.4}, ARCR {:.4}; best of {} pairs)",
            self.key,
            self.tuned.match_threshold,
            self.tuned.inject_energy,
            self.seeds,
            self.correct_rate,
            self.energy_metric,
            self.arr,
            self.arcr,
            self.candidates
        )
    }
}
