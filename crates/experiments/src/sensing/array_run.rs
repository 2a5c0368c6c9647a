//! Physics sensing during `whisker run` (`sensing = "physics"`): the 18 whiskers follow
//! the arm's `whisker_array` link at the sensors' 2 kHz and their readings are written to
//! `whiskers.csv` (columns documented in `scenarios/README.md`).

use super::whisking_metrics::{WhiskingMetrics, WhiskingSummary};
use crate::record::SensorColumns;
use crate::record::{Recorder, Reporter};
use std::fmt::Write as _;
use std::path::Path;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::files;
use whisker_scenario::plan::Plan;
use whisker_sim::environment::Environment;
use whisker_sim::kinematics::Chain;
use whisker_sim::sensing::calibration::calibrate_array_rcp;
use whisker_sim::sensing::physics::PhysicsArray;
use whisker_sim::whisker::control::{RcpThreshold, WhiskingPattern};

/// The array being simulated along a run.
pub struct ArraySimulation {
    array: PhysicsArray,
    /// Chain from the arm's base to the array link.
    chain: Chain,
    dt: f64,
    steps: u64,
    csv: String,
    /// The signal front end (thesis Ch 4) on the simulated streams.
    frontend: super::frontend::FrontEnd,
    /// The 2 kHz streams not yet in the recording.
    columns: Option<SensorColumns>,
    /// What the whisking strategy does to the contacts, on whisker A1's cycles.
    metrics: WhiskingMetrics,
    clock: WhiskingPattern,
}

impl ArraySimulation {
    /// Builds the array of `scenario` at the plan's start, calibrating RCP thresholds.
    pub fn new(
        file: &ScenarioFile,
        plan: &Plan,
        environment: &Environment,
        recording: Option<&dyn Recorder>,
        reporter: &dyn Reporter,
    ) -> Result<Self> {
        let scenario = &file.scenario;
        let mut configs = file.whisker_configs()?;
        let chain = super::array::array_chain(file, plan)?;
        let dt = whisker_sim::sensing::physics::DT;
        if let Some(mode) = scenario.array.contact_mode() {
            calibrate_array_rcp(&mut configs, mode, scenario.seed, dt);
            for c in &configs {
                if let (RcpThreshold::NoiseMultiple(_), Some(t)) = (mode, c.contact_threshold)
                    && t >= c.sensor.saturation_counts
                {
                    reporter.note(&format!(
                        "warning    whisker {}: contact threshold {t:.0} counts (from free whisking) is at or above saturation: RCP and the whisking strategies cannot fire",
                        c.module.pixel()
                    ));
                }
            }
        }
        // The metrics' contact level: 20 × the free-whisking σ in every condition (the RCP
        // thresholds themselves when RCP is calibrated so).
        let metric_thresholds = match scenario.array.contact_mode() {
            Some(RcpThreshold::NoiseMultiple(20.0)) => {
                configs.iter().filter_map(|c| c.contact_threshold).collect()
            }
            _ => {
                let mut free = configs.clone();
                calibrate_array_rcp(
                    &mut free,
                    RcpThreshold::NoiseMultiple(20.0),
                    scenario.seed,
                    dt,
                );
                free.iter().filter_map(|c| c.contact_threshold).collect()
            }
        };
        let clock = configs[0].pattern;
        let mut csv = String::from("t_s");
        for c in &configs {
            let p = c.module.pixel();
            let _ = write!(csv, ",{p}_angle_rad,{p}_x,{p}_y");
        }
        csv.push('\n');
        let start = chain.fk(&plan.waypoints[0]);
        let frontend = super::frontend::FrontEnd::new(file, &configs)?;
        let columns = match recording {
            Some(rec) => {
                let labels: Vec<String> = configs.iter().map(|c| c.module.pixel()).collect();
                Some(SensorColumns::new(rec, "sensors", &labels)?)
            }
            None => None,
        };
        let array = PhysicsArray::new(
            configs,
            &environment.physics_pieces(),
            &start,
            scenario.seed,
            dt,
        );
        Ok(Self {
            array,
            chain,
            dt,
            steps: 0,
            csv,
            frontend,
            columns,
            metrics: WhiskingMetrics::new(metric_thresholds),
            clock,
        })
    }

    /// Simulates up to time `t` (s), the arm following the plan's trajectory; the front
    /// end processes every whisk cycle completed.
    ///
    /// The array's poses follow from the plan alone, so every whisker runs all the
    /// samples up to `t` in one task ([`PhysicsArray::run_with_state`]: the same samples as
    /// a step per sample, without a barrier per sample; issue #18, scheduling), and the
    /// samples are then written and passed to the front end in time order.
    pub fn advance_to(&mut self, plan: &Plan, t: f64, recording: Option<&dyn Recorder>) -> Result {
        let mut end = self.steps;
        while (end + 1) as f64 * self.dt <= t + 1e-9 {
            end += 1;
        }
        if end == self.steps {
            return Ok(());
        }
        let times: Vec<f64> = (self.steps + 1..=end).map(|k| k as f64 * self.dt).collect();
        self.steps = end;
        let poses: Vec<_> = times
            .iter()
            .map(|&time| self.chain.fk(&plan.trajectory.sample(time)))
            .collect();
        let streams = self.array.run_keeping(&poses, |u, s| {
            (s, u.control_state(), u.whisker.max_curvature(&u.world))
        });
        for (k, (&time, pose)) in times.iter().zip(&poses).enumerate() {
            let samples: Vec<_> = streams.iter().map(|w| w[k].0).collect();
            let rcp: Vec<_> = streams.iter().map(|w| w[k].1).collect();
            let ys: Vec<f64> = samples.iter().map(|s| s.y).collect();
            let curvatures: Vec<f64> = streams.iter().map(|w| w[k].2).collect();
            self.metrics
                .push(time, self.clock.cycle(time), &ys, &curvatures);
            let _ = write!(self.csv, "{time}");
            for s in &samples {
                let _ = write!(self.csv, ",{},{},{}", s.angle_rad, s.x, s.y);
            }
            self.csv.push('\n');
            if let (Some(cols), Some(rec)) = (&mut self.columns, recording) {
                cols.push(rec, time, &samples, Some(&rcp))?;
            }
            self.frontend.push(time, pose, &samples, recording)?;
        }
        Ok(())
    }

    /// Contacts the front end has detected.
    pub fn frontend_contacts(&self) -> u64 {
        self.frontend.contacts()
    }

    /// What the whisking strategy did to the contacts (`summary.json`'s `whisking`).
    pub fn whisking(&self) -> WhiskingSummary {
        self.metrics.summary()
    }

    /// Number of 2 kHz samples simulated.
    pub fn samples(&self) -> u64 {
        self.steps
    }

    /// Every whisker's shaft now (world), base to tip.
    pub fn shafts(&self) -> Vec<Vec<[f64; 3]>> {
        self.array.units.iter().map(|u| u.shaft()).collect()
    }

    /// Writes `whiskers.csv` and `frontend.csv` into `dir` and the last streams into the
    /// recording.
    pub fn finish(mut self, dir: &Path, recording: Option<&dyn Recorder>) -> Result {
        if let (Some(cols), Some(rec)) = (&mut self.columns, recording) {
            cols.send(rec)?;
        }
        files::write_atomic(&dir.join("whiskers.csv"), self.csv.as_bytes())?;
        self.frontend.finish(dir)
    }
}
