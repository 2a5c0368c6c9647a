//! Contacts during `whisker run` from the anticipated intersect (thesis §4.1.2.3):
//! with `sensing = "kinematic"` they are the sensing itself (with the contact noise of
//! §6.1.3.1.2, `contacts.csv`); with `sensing = "physics"` they are the noise-free ground
//! truth beside the simulated signals (`anticipated.csv`). Columns are documented in
//! `scenarios/README.md`.
//!
//! One sweep per whisk cycle of whisker A1's pattern, at the array pose of the cycle's
//! start (the thesis' simulation moved the array between whisks, §6.1.3).

use crate::error::CliResult;
use crate::output;
use crate::plan::Plan;
use crate::record::Recorder;
use crate::record::{Contact, ContactKind};
use crate::scenario::Scenario;
use nalgebra::Isometry3;
use std::fmt::Write as _;
use std::path::Path;
use whisker_sim::environment::Environment;
use whisker_sim::kinematics::Chain;
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::contact::ContactCycle;

/// Header of `contacts.csv` / `anticipated.csv`.
pub const HEADER: &str = "cycle,t_cycle_s,whisker,pixel,t_contact_s,angle_deg,radial_distance_m,\
                          x_m,y_m,z_m,world_x_m,world_y_m,world_z_m,slope\n";

/// Appends the rows of one whisk cycle's contacts, made with the array at `pose`, to a
/// `contacts.csv` text (`pixels`: each whisker's tactile-image label); returns the contacts
/// in the world.
pub fn append_cycle(
    csv: &mut String,
    cycle: &ContactCycle,
    pose: &Isometry3<f64>,
    pixels: &[String],
) -> Vec<Contact> {
    let mut world = Vec::with_capacity(cycle.contacts.len());
    for c in &cycle.contacts {
        let w = pose * c.point;
        world.push(Contact {
            whisker: c.whisker,
            point: [w.x, w.y, w.z],
        });
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            cycle.index,
            cycle.start_s,
            c.whisker,
            pixels[c.whisker],
            c.time_s,
            c.angle_rad.to_degrees(),
            c.radial_distance,
            c.point.x,
            c.point.y,
            c.point.z,
            w.x,
            w.y,
            w.z,
            c.slope
        );
    }
    world
}

/// The anticipated intersects of `whiskers` with the array at `pose`: the noise-free
/// contacts (world), for the recording's ground truth.
pub fn anticipated(
    target: &SweepTarget,
    whiskers: &[RigidWhisker],
    pose: &Isometry3<f64>,
) -> Vec<Contact> {
    whiskers
        .iter()
        .filter_map(|w| {
            let hit = target.sweep(w, pose)?;
            Some(Contact {
                whisker: w.module.index,
                point: [hit.point.x, hit.point.y, hit.point.z],
            })
        })
        .collect()
}

/// The anticipated intersects of a kinematic `array`'s last whisk, before noise (world).
pub fn intersects(array: &KinematicArray) -> Vec<Contact> {
    array
        .intersects
        .iter()
        .map(|(w, p)| Contact {
            whisker: *w,
            point: [p.x, p.y, p.z],
        })
        .collect()
}

/// The straight shafts of a kinematic `array` at time `t` with the array at `pose` (world;
/// base and tip of each), at each whisker's pattern angle.
pub fn rigid_shafts(array: &KinematicArray, pose: &Isometry3<f64>, t: f64) -> Vec<Vec<[f64; 3]>> {
    array
        .whiskers
        .iter()
        .zip(&array.patterns)
        .map(|(w, p)| {
            let theta = p.angle(t);
            [0.0, w.module.beam.length]
                .map(|r| {
                    let q = w.shaft_point(pose, theta, r);
                    [q.x, q.y, q.z]
                })
                .to_vec()
        })
        .collect()
}

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
        scenario: &Scenario,
        file: &Path,
        plan: &Plan,
        environment: &Environment,
        noise: ContactNoise,
        name: &'static str,
    ) -> CliResult<Self> {
        let configs = scenario.array.whisker_configs(file)?;
        let chain = crate::whiskers::array_chain(scenario, file, plan)?;
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
            array: KinematicArray::new(whiskers, patterns, noise, scenario.seed),
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
    pub fn advance_to(
        &mut self,
        plan: &Plan,
        t: f64,
        recording: Option<&dyn Recorder>,
    ) -> CliResult {
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
    pub fn finish(self, dir: &Path) -> CliResult {
        output::write_atomic(&dir.join(self.name), self.csv.as_bytes())
    }
}
