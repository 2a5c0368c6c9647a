//! `whisker bench recording`: what the Rerun recording costs a run (docs/recording.md).
//! The scenario runs twice into `--out`, once with `--no-rrd` and once with its recording,
//! alternately `--repeats` times; reported: the wall time of each (the fastest of the
//! repeats), their ratio, and the recording's size per simulated second. Timing is a
//! benchmark, never a test.

use serde::Serialize;
use std::fmt;
use std::path::PathBuf;
use std::time::Instant;
use whisker_experiments::record::{Context, Target};
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::overrides::Override;

/// What `whisker bench recording` times.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The scenario (a physics run is the case the recording's 2 kHz streams weigh on).
    pub scenario: PathBuf,
    /// Output directory (`without/`, `with/` below it).
    pub out: PathBuf,
    /// Runs of each kind; the fastest counts.
    pub repeats: usize,
    /// Changes to the scenario, as `whisker run --set`.
    pub set: Vec<Override>,
}

/// What it measured (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub scenario: String,
    pub sensing: &'static str,
    pub simulated_s: f64,
    pub wall_without_s: f64,
    pub wall_with_s: f64,
    pub ratio: f64,
    pub rrd_bytes: u64,
    pub rrd_mb_per_simulated_s: f64,
}

/// `whisker bench recording`.
pub fn recording(o: &Settings, ctx: Context) -> Result<Report> {
    let mut file = ScenarioFile::load_with(&o.scenario, &o.set)?;
    file.scenario.output.recording = true;
    let (without_dir, with_dir) = (o.out.join("without"), o.out.join("with"));
    let mut best = [f64::INFINITY; 2];
    let quiet = Context {
        reporter: &whisker_experiments::record::Silent,
        ..ctx
    };
    for _ in 0..o.repeats.max(1) {
        for (k, (dir, no_rrd)) in [(&without_dir, true), (&with_dir, false)]
            .into_iter()
            .enumerate()
        {
            let _ = std::fs::remove_dir_all(dir);
            let rrd = Target {
                no_rrd,
                ..Default::default()
            };
            let start = Instant::now();
            whisker_experiments::run::execute(&file, dir, &rrd, quiet)?;
            best[k] = best[k].min(start.elapsed().as_secs_f64());
        }
    }
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(with_dir.join("summary.json")).unwrap_or_default(),
    )
    .unwrap_or_default();
    // A run's duration, or a closed loop's simulated time.
    let simulated = summary["duration_s"]
        .as_f64()
        .or(summary["simulated_time_s"].as_f64())
        .unwrap_or(f64::NAN);
    let bytes = std::fs::metadata(with_dir.join("run.rrd")).map_or(0, |m| m.len());
    Ok(Report {
        scenario: o.scenario.display().to_string(),
        sensing: file.scenario.sensing.name(),
        simulated_s: simulated,
        wall_without_s: best[0],
        wall_with_s: best[1],
        ratio: best[1] / best[0],
        rrd_bytes: bytes,
        rrd_mb_per_simulated_s: bytes as f64 / 1e6 / simulated,
    })
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} ({} sensing, {:.2} s simulated)",
            self.scenario, self.sensing, self.simulated_s
        )?;
        writeln!(f, "  without recording  {:8.2} s wall", self.wall_without_s)?;
        writeln!(
            f,
            "  with recording     {:8.2} s wall   ratio {:.3} ({:+.1} %)",
            self.wall_with_s,
            self.ratio,
            (self.ratio - 1.0) * 100.0
        )?;
        writeln!(
            f,
            "  run.rrd            {:8.2} MB       {:.2} MB per simulated second",
            self.rrd_bytes as f64 / 1e6,
            self.rrd_mb_per_simulated_s
        )
    }
}
