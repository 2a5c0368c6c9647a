//! Contacts during `whisker run` from the anticipated intersect (thesis §4.1.2.3):
//! with `sensing = "kinematic"` they are the sensing itself (with the contact noise of
//! §6.1.3.1.2, `contacts.csv`); with `sensing = "physics"` they are the noise-free ground
//! truth beside the simulated signals (`anticipated.csv`). Columns are documented in
//! `scenarios/README.md`.
//!
//! One sweep per whisk cycle of whisker A1's pattern, at the array pose of the cycle's
//! start (the thesis' simulation moved the array between whisks, §6.1.3).

use super::contact::{HEADER, append_cycle, intersects, rigid_shafts};
use crate::record::ContactKind;
use crate::record::Recorder;
use std::path::Path;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::files;
use whisker_scenario::plan::Plan;
use whisker_sim::environment::Environment;
use whisker_sim::kinematics::Chain;
use whisker_sim::sensing::kinematic::{KinematicArray, SweepTarget};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::whisker::control::WhiskingPattern;

/// Anticipated-intersect sensing along a run.
pub struct ContactSensing {
    array: KinematicArray,
    target: SweepTarget,
    chain: Chain,
    pattern: WhiskingPattern,
    next_cycle: i64,
    pixels: Vec<String>,
    csv: String,
    /// Output file name (`contacts.csv` or `anticipated.csv`).
    name: &'static str,
    /// Whether the contacts carry noise (then the recording also gets the intersect).
    noisy: bool,
    cycles: u64,
    contacts: u64,
}

impl ContactSensing {
    /// Sets up the sweep of the scenario's array against `environment`, with `noise`,
    /// written to `name`.csv.
    pub fn new(
        file: &ScenarioFile,
        plan: &Plan,
        environment: &Environment,
        noise: ContactNoise,
        name: &'static str,
    ) -> Result<Self> {
        let scenario = &file.scenario;
        let configs = file.whisker_configs()?;
        let chain = crate::sensing::array::array_chain(file, plan)?;
        let whiskers = configs
            .iter()
            .map(|c| {
                let mut w = c.rigid();
                w.retracted = c.pattern.retracted;
                w.protracted = c.pattern.protracted;
                w
            })
            .collect();
        let patterns: Vec<WhiskingPattern> = configs.iter().map(|c| c.pattern).collect();
        let pattern = patterns[0];
        Ok(Self {
            array: KinematicArray::new(whiskers, patterns, noise, scenario.seed)
                .with_control(configs[0].control),
            target: SweepTarget::of(environment),
            chain,
            pattern,
            next_cycle: pattern.cycle(0.0) + i64::from(pattern.phase != 0.0),
            pixels: configs.iter().map(|c| c.module.pixel()).collect(),
            csv: HEADER.to_string(),
            noisy: noise != ContactNoise::NONE,
            name,
            cycles: 0,
            contacts: 0,
        })
    }

    /// Start time of whisk cycle k (s).
    fn cycle_start(&self, k: i64) -> f64 {
        (k as f64 - self.pattern.phase / std::f64::consts::TAU) / self.pattern.frequency
    }

    /// Sweeps every whisk cycle that starts by time `t`.
    pub fn advance_to(&mut self, plan: &Plan, t: f64, recording: Option<&dyn Recorder>) -> Result {
        while self.cycle_start(self.next_cycle) <= t + 1e-9 {
            let start = self.cycle_start(self.next_cycle);
            let pose = self.chain.fk(&plan.trajectory.sample(start.max(0.0)));
            let cycle = self
                .array
                .sense(&self.target, self.next_cycle as u64, start, &pose);
            let world = append_cycle(&mut self.csv, &cycle, &pose, &self.pixels);
            if let Some(rec) = recording {
                let k = self.next_cycle as u64;
                if self.noisy {
                    // The ground truth of a noisy sweep: the intersect itself.
                    let truth = intersects(&self.array);
                    rec.contacts(ContactKind::True, k, start, &truth)?;
                    rec.contacts(ContactKind::Estimated, k, start, &world)?;
                } else {
                    rec.contacts(ContactKind::True, k, start, &world)?;
                }
            }
            self.cycles += 1;
            self.contacts += cycle.contacts.len() as u64;
            self.next_cycle += 1;
        }
        Ok(())
    }

    /// The rigid shafts at time `t` (world; base and tip), at the whisk angle of each
    /// whisker's pattern then, the arm following the plan.
    pub fn shafts(&self, plan: &Plan, t: f64) -> Vec<Vec<[f64; 3]>> {
        let pose = self.chain.fk(&plan.trajectory.sample(t));
        rigid_shafts(&self.array, &pose, t)
    }

    /// Whisk cycles swept and contacts found so far.
    pub fn counts(&self) -> (u64, u64) {
        (self.cycles, self.contacts)
    }

    /// Writes the CSV into `dir`.
    pub fn finish(self, dir: &Path) -> Result {
        files::write_atomic(&dir.join(self.name), self.csv.as_bytes())
    }
}
