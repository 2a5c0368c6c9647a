//! `whisker bench recording`: what the Rerun recording costs a run (docs/recording.md).
//! The scenario runs twice into `--out`, once with `--no-rrd` and once with its recording,
//! alternately `--repeats` times; reported: the wall time of each (the fastest of the
//! repeats), their ratio, and the recording's size per simulated second. Timing is a
//! benchmark, never a test.

use crate::error::CliResult;
use crate::record::{Context, Target};
use crate::scenario::Scenario;
use crate::scenario::overrides::Override;
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// Options of `whisker bench recording`.
#[derive(clap::Args, Debug)]
pub struct Options {
    /// The scenario (a physics run is the case the recording's 2 kHz streams weigh on).
    #[arg(default_value = "scenarios/whisking.toml")]
    pub scenario: PathBuf,
    /// Output directory (`without/`, `with/` below it).
    #[arg(long, default_value = "out/bench-recording")]
    pub out: PathBuf,
    /// Runs of each kind; the fastest counts.
    #[arg(long, default_value_t = 1)]
    pub repeats: usize,
    /// Change a scenario field, as `whisker run --set` (repeatable), e.g.
    /// `--set 'trajectory.waypoints=[{joints_deg=[0,-90,90,-90,-90,0],hold_s=60}]'`.
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `whisker bench recording`.
pub fn recording(o: &Options, ctx: Context) -> CliResult {
    let mut scenario = Scenario::load_with(&o.scenario, &o.set)?;
    scenario.output.recording = true;
    let (without_dir, with_dir) = (o.out.join("without"), o.out.join("with"));
    let mut best = [f64::INFINITY; 2];
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
            let quiet = Context {
                reporter: &crate::record::Silent,
                ..ctx
            };
            crate::run::execute(&o.scenario, &scenario, dir, &rrd, quiet)?;
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
    let ratio = best[1] / best[0];
    let mb_per_s = bytes as f64 / 1e6 / simulated;
    if o.json {
        println!(
            "{}",
            json!({
                "scenario": o.scenario.display().to_string(),
                "sensing": scenario.sensing.name(),
                "simulated_s": simulated,
                "wall_without_s": best[0],
                "wall_with_s": best[1],
                "ratio": ratio,
                "rrd_bytes": bytes,
                "rrd_mb_per_simulated_s": mb_per_s,
            })
        );
    } else {
        println!(
            "{} ({} sensing, {simulated:.2} s simulated)",
            o.scenario.display(),
            scenario.sensing.name()
        );
        println!("  without recording  {:8.2} s wall", best[0]);
        println!(
            "  with recording     {:8.2} s wall   ratio {ratio:.3} ({:+.1} %)",
            best[1],
            (ratio - 1.0) * 100.0
        );
        println!(
            "  run.rrd            {:8.2} MB       {mb_per_s:.2} MB per simulated second",
            bytes as f64 / 1e6
        );
    }
    Ok(())
}
