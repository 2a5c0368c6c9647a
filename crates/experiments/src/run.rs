//! `whisker run SCENARIO`: plans the arm motion of a scenario, drives the arm's kinematic bodies through it
//! in a Rapier world at the output sample period, and writes to the output directory:
//! - `path.csv`: one row per sample (columns documented in `scenarios/README.md`),
//! - `summary.json`: the run's figures,
//! - `run.rrd`: the Rerun recording (`docs/recording.md`; unless `output.recording =
//!   false` or `--no-rrd`; `--rrd FILE` writes it elsewhere),
//! - `whiskers.csv` (physics sensing), `contacts.csv` (kinematic sensing) or
//!   `anticipated.csv` (the anticipated contacts of a physics run with an environment).

use crate::record::{Context, Layout, Recorder, Target};
use crate::sensing::array_run::ArraySimulation;
use crate::sensing::sweep::ContactSensing;
use crate::sensing::whisking_metrics::WhiskingSummary;
use nalgebra::Isometry3;
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::files;
use whisker_scenario::overrides::Override;
use whisker_scenario::plan::Plan;
use whisker_scenario::{Experiment, Sensing};
use whisker_sim::environment::Environment;
use whisker_sim::kinematics::Chain;
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::world::World;
use whisker_slam::pose;

/// Arm samples between the recording's checkpoints.
const CHECKPOINT_SAMPLES: usize = 100;

/// `whisker run`: simulate and write the outputs; `seed` replaces the scenario's seed,
/// `overrides` change fields (`--set`), `out` the output directory, `rrd` the recording.
pub fn run(
    path: &Path,
    out: Option<PathBuf>,
    seed: Option<u64>,
    overrides: &[Override],
    rrd: &Target,
    ctx: Context,
) -> Result {
    let mut file = ScenarioFile::load_with(path, overrides)?;
    if let Some(seed) = seed {
        file.scenario.seed = seed;
    }
    let dir = out.unwrap_or_else(|| file.scenario.output.dir.clone());
    execute(&file, &dir, rrd, ctx)
}

/// Runs the scenario of `file` into `dir` (created), saying what it does to `ctx`:
/// `whisker run` and each trial of `whisker trials`; the recording goes where `rrd` and
/// the scenario's `output.recording` say.
pub fn execute(file: &ScenarioFile, dir: &Path, rrd: &Target, ctx: Context) -> Result {
    let plan = Plan::new(file)?;
    ctx.say(&plan.describe(file));
    let loaded = file.environment()?;
    for line in &loaded.report {
        ctx.say(line);
    }
    let environment = loaded.environment;
    let experiment = &file.scenario.experiment;
    match experiment {
        Experiment::Navigate(config) => ctx.say(&crate::navigation::outputs::check(
            file,
            config,
            &plan,
            &environment,
        )?),
        // Loads the object maps: a bad one stops the run before anything is written.
        Experiment::ClosedLoop(e) => ctx.say(&crate::closed_loop::describe(file, e)?),
        Experiment::Scripted => {}
    }
    files::create_dir(dir)?;
    match experiment {
        Experiment::Navigate(config) => {
            crate::navigation::outputs::write(file, config, (&plan, &environment), dir, rrd, ctx)
        }
        Experiment::ClosedLoop(e) => {
            crate::closed_loop::write(file, e, plan, &environment, dir, rrd, ctx)
        }
        Experiment::Scripted => scripted(file, &plan, &environment, dir, rrd, ctx),
    }
}

/// The scripted run: the arm along the planned trajectory through the waypoints, sensing
/// as the scenario says; `path.csv`, `summary.json`, the sensors' files and the recording.
fn scripted(
    file: &ScenarioFile,
    plan: &Plan,
    environment: &Environment,
    dir: &Path,
    rrd: &Target,
    ctx: Context,
) -> Result {
    let scenario = &file.scenario;
    // The camera frames the objects, the arm's base and the whole arm at every waypoint.
    let mut framed: Vec<[f64; 3]> = vec![[0.0; 3]];
    for q in &plan.waypoints {
        framed.extend(plan.chain.joint_origins(q));
        framed.push(plan.chain.fk(q).translation.vector.into());
    }
    let layout = Layout::Run {
        physics: scenario.sensing == Sensing::Physics,
        eye: crate::record::Eye::of(environment, &framed),
    };
    let recording = ctx.scenario_recording(
        &file.path,
        scenario.seed,
        scenario.output.recording,
        dir,
        rrd,
        layout,
    )?;
    if let Some(rec) = &recording {
        let tips: Vec<Isometry3<f64>> = plan.waypoints.iter().map(|q| plan.chain.fk(q)).collect();
        rec.waypoints(&tips)?;
        rec.environment(environment)?;
    }
    let mut sensors = Sensors::new(file, plan, environment, recording.as_deref(), ctx)?;
    let dt = scenario.output.sample_period_s;
    let mut world = World::new(
        plan.model.clone(),
        plan.model_joints(&plan.waypoints[0]),
        dt,
    );
    world.add_environment(environment);
    let mut log = PathLog::new(plan);
    let skeleton = plan.skeleton();
    let steps = (plan.trajectory.duration() / dt).ceil() as usize;
    for k in 0..=steps {
        whisker_scenario::stop::check()?;
        let t = (k as f64 * dt).min(plan.trajectory.duration());
        let q = plan.trajectory.sample(t);
        if k > 0 {
            world.step(&plan.model_joints(&q));
        }
        sensors.advance_to(plan, t, recording.as_deref())?;
        let tip = plan.chain.fk(&q);
        log.sample(t, &q, &tip, world.arm_collisions());
        if scenario.sensing == Sensing::Physics {
            ctx.progress("samples simulated", k as u64, steps as u64);
        }
        if let Some(rec) = recording.as_deref() {
            sensors.record(rec, (plan, &skeleton), t, &q, &tip)?;
            // A fixed point every simulated second: the recording's chunks do not depend
            // on timing.
            if k % CHECKPOINT_SAMPLES == 0 {
                rec.checkpoint()?;
            }
        }
    }
    let summary = log.summary(file, plan, environment, &sensors);
    files::write_atomic(&dir.join("path.csv"), log.csv.as_bytes())?;
    let text = serde_json::to_string_pretty(&summary).expect("plain JSON") + "\n";
    files::write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    let finished = sensors.finish(dir, recording.as_deref())?;
    if let Some(rec) = recording {
        rec.tip_path(&log.tip_path)?;
        rec.finish()?;
    }
    ctx.say(&log.simulated(dt));
    ctx.say(&finished.lines(scenario.sensing));
    Ok(())
}

/// The whiskers of a run: the chain placing the array, and physics or the kinematic sweep
/// (or, beside physics in an environment, the anticipated contacts as ground truth).
struct Sensors {
    array_chain: Option<Chain>,
    whiskers: Option<ArraySimulation>,
    contacts: Option<ContactSensing>,
}

impl Sensors {
    fn new(
        file: &ScenarioFile,
        plan: &Plan,
        environment: &Environment,
        recording: Option<&dyn Recorder>,
        ctx: Context,
    ) -> Result<Self> {
        let scenario = &file.scenario;
        let array_chain = match scenario.sensing {
            Sensing::None => None,
            _ => Some(crate::sensing::array::array_chain(file, plan)?),
        };
        let whiskers = match scenario.sensing {
            Sensing::Physics => Some(ArraySimulation::new(
                file,
                plan,
                environment,
                recording,
                ctx.reporter,
            )?),
            _ => None,
        };
        let sweep = |noise, name| ContactSensing::new(file, plan, environment, noise, name);
        let contacts = match scenario.sensing {
            Sensing::Kinematic => Some(sweep(
                scenario.kinematic.noise(&file.path)?,
                "contacts.csv",
            )?),
            Sensing::Physics if !environment.pieces.is_empty() => {
                Some(sweep(ContactNoise::NONE, "anticipated.csv")?)
            }
            _ => None,
        };
        Ok(Self {
            array_chain,
            whiskers,
            contacts,
        })
    }

    /// Senses up to time `t` (s).
    fn advance_to(&mut self, plan: &Plan, t: f64, recording: Option<&dyn Recorder>) -> Result {
        if let Some(w) = &mut self.whiskers {
            w.advance_to(plan, t, recording)?;
        }
        if let Some(c) = &mut self.contacts {
            c.advance_to(plan, t, recording)?;
        }
        Ok(())
    }

    /// Records the arm (`skeleton`: its links drawn), the array and the shafts at time `t`
    /// (configuration `q`, the tip at `tip`).
    fn record(
        &self,
        rec: &dyn Recorder,
        (plan, skeleton): (&Plan, &[usize]),
        t: f64,
        q: &[f64],
        tip: &Isometry3<f64>,
    ) -> Result {
        rec.arm(t, &plan.link_frames(q, skeleton), tip)?;
        if let Some(a) = &self.array_chain {
            rec.array(t, &a.fk(q))?;
        }
        if let Some(w) = &self.whiskers {
            rec.shafts(t, &w.shafts())?;
        } else if let Some(c) = &self.contacts {
            rec.shafts(t, &c.shafts(plan, t))?;
        }
        Ok(())
    }

    /// Writes the sensors' files into `dir`; what they sensed.
    fn finish(self, dir: &Path, recording: Option<&dyn Recorder>) -> Result<Sensed> {
        let frontend_contacts = self
            .whiskers
            .as_ref()
            .map(ArraySimulation::frontend_contacts);
        let whisking = self.whiskers.as_ref().map(ArraySimulation::whisking);
        if let Some(w) = self.whiskers {
            w.finish(dir, recording)?;
        }
        let counts = self.contacts.as_ref().map(|c| c.counts());
        if let Some(c) = self.contacts {
            c.finish(dir)?;
        }
        Ok(Sensed {
            counts,
            frontend_contacts,
            whisking,
        })
    }
}

/// What a run's sensors sensed.
struct Sensed {
    /// Whisk cycles swept and contacts found (kinematic sweep or anticipated contacts).
    counts: Option<(u64, u64)>,
    /// Contacts the front end detected (physics).
    frontend_contacts: Option<u64>,
    /// What the whisking strategy did to the contacts (physics).
    whisking: Option<WhiskingSummary>,
}

impl Sensed {
    /// The lines a run ends with: what was sensed.
    fn lines(&self, sensing: Sensing) -> String {
        let mut out = String::new();
        if let (Some((cycles, n)), Sensing::Kinematic) = (self.counts, sensing) {
            let _ = writeln!(out, "sensed     {n} contacts in {cycles} whisk cycles");
        }
        if let Some(n) = self.frontend_contacts {
            let _ = writeln!(
                out,
                "front end  {n} contacts detected in the whisker streams"
            );
        }
        if let Some(w) = &self.whisking {
            let _ = writeln!(out, "{}", w.line());
        }
        let mut legend = vec![(
            "simulated",
            "the planned path sampled for the arm's kinematic bodies (one row each in path.csv); tip = the array's tool point; collisions = samples in which a link with a collider touches the environment (a planned path should have none)",
        )];
        if sensing == Sensing::Kinematic {
            legend.push(("sensed", "contacts of the rigid whiskers' anticipated-intersect sweep (§4.1.2.3) with the scenario's contact noise; one row each in contacts.csv"));
        }
        if self.frontend_contacts.is_some() {
            legend.push(("front end", "contacts the signal front end found in the 2 kHz deflection streams (§3.1.1: onset, peak, offset; frontend.csv); 0 with objects in reach means the detection threshold is above the peaks"));
        }
        if self.whisking.is_some() {
            legend.push(("whisking", "what the whisking strategy did (§2.3.1), first whisk left out: touching = |deflection| above 20 × the free-whisking noise; spread = range of first-contact times across the array (SR narrows it); curvature = the shafts' bending at contact (SR lowers it)"));
        }
        out.push_str(&whisker_scenario::console::legend(
            "what the lines mean",
            &legend,
        ));
        out
    }
}

/// The arm's path: `path.csv`'s text, the tip's poses and the collisions.
struct PathLog {
    csv: String,
    tip_path: Vec<Isometry3<f64>>,
    collision_samples: usize,
    collided_links: Vec<String>,
}

impl PathLog {
    /// An empty log with `path.csv`'s header for the chain of `plan`.
    fn new(plan: &Plan) -> Self {
        let chain = &plan.chain;
        let mut csv = String::from("t_s");
        for (name, &angular) in chain.joint_names.iter().zip(&chain.angular) {
            let _ = write!(csv, ",{name}_{}", if angular { "rad" } else { "m" });
        }
        csv.push_str(",tip_x_m,tip_y_m,tip_z_m,tip_qx,tip_qy,tip_qz,tip_qw,arm_collision\n");
        Self {
            csv,
            tip_path: Vec::new(),
            collision_samples: 0,
            collided_links: Vec::new(),
        }
    }

    /// Logs the sample of time `t`: configuration `q`, the tip at `tip`, the links `hits`
    /// touching the environment.
    fn sample(&mut self, t: f64, q: &[f64], tip: &Isometry3<f64>, hits: Vec<String>) {
        let collided = !hits.is_empty();
        if collided {
            self.collision_samples += 1;
            for h in hits {
                if !self.collided_links.contains(&h) {
                    self.collided_links.push(h);
                }
            }
        }
        let csv = &mut self.csv;
        let _ = write!(csv, "{t}");
        for v in q {
            let _ = write!(csv, ",{v}");
        }
        let p = tip.translation.vector;
        let [qx, qy, qz, qw] = pose::quaternion_xyzw(&tip.rotation);
        let _ = writeln!(
            csv,
            ",{},{},{},{qx},{qy},{qz},{qw},{}",
            p.x,
            p.y,
            p.z,
            u8::from(collided)
        );
        self.tip_path.push(*tip);
    }

    /// The length of the tip's path (m).
    fn length(&self) -> f64 {
        self.tip_path
            .windows(2)
            .map(|w| (w[1].translation.vector - w[0].translation.vector).norm())
            .sum()
    }

    /// `summary.json` of the run.
    fn summary(
        &self,
        file: &ScenarioFile,
        plan: &Plan,
        environment: &Environment,
        sensors: &Sensors,
    ) -> serde_json::Value {
        let scenario = &file.scenario;
        let chain = &plan.chain;
        let waypoints: Vec<_> = plan
            .waypoints
            .iter()
            .map(|q| {
                let tip = chain.fk(q);
                json!({
                    "joints_rad": q,
                    "tip_position_m": tip.translation.vector.as_slice(),
                    "tip_rpy_deg": pose::rpy(&tip.rotation).map(f64::to_degrees),
                })
            })
            .collect();
        let whiskers = sensors.whiskers.as_ref();
        let contacts = sensors.contacts.as_ref();
        json!({
            "scenario": file.path.display().to_string(),
            "seed": scenario.seed,
            "urdf": file.urdf_path().display().to_string(),
            "base_link": chain.base,
            "tip_link": chain.tip,
            "joint_names": chain.joint_names,
            "duration_s": plan.trajectory.duration(),
            "sample_period_s": scenario.output.sample_period_s,
            "samples": self.tip_path.len(),
            "tip_path_length_m": self.length(),
            "waypoints": waypoints,
            "arm_collision_samples": self.collision_samples,
            "arm_collision_links": self.collided_links,
            "sensing": scenario.sensing.name(),
            "whisker_samples": whiskers.map_or(0, ArraySimulation::samples),
            "environment_pieces": environment.pieces.iter().map(|p| p.name.clone()).collect::<Vec<_>>(),
            "whisk_cycles_swept": contacts.map_or(0, |c| c.counts().0),
            "contacts": contacts.map_or(0, |c| c.counts().1),
            "frontend_contacts": whiskers.map_or(0, ArraySimulation::frontend_contacts),
            "whisking": whiskers.map(ArraySimulation::whisking),
        })
    }

    /// The line saying what was simulated, every `dt` s.
    fn simulated(&self, dt: f64) -> String {
        format!(
            "simulated  {} samples every {dt} s; tip travelled {:.3} m; arm–environment collisions: {}",
            self.tip_path.len(),
            self.length(),
            if self.collision_samples == 0 {
                "none".to_string()
            } else {
                format!(
                    "{} samples ({})",
                    self.collision_samples,
                    self.collided_links.join(", ")
                )
            }
        )
    }
}
