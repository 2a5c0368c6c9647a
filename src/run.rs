//! `whisker run SCENARIO`: plans the arm motion of a scenario, drives the arm's kinematic bodies through it
//! in a Rapier world at the output sample period, and writes to the output directory:
//! - `path.csv`: one row per sample (columns documented in `scenarios/README.md`),
//! - `summary.json`: the run's figures,
//! - `run.rrd`: the Rerun recording (`docs/recording.md`; unless `output.recording =
//!   false` or `--no-rrd`; `--rrd FILE` writes it elsewhere),
//! - `whiskers.csv` (physics sensing), `contacts.csv` (kinematic sensing) or
//!   `anticipated.csv` (the anticipated contacts of a physics run with an environment).

use crate::error::Result;
use crate::output;
use crate::plan::Plan;
use crate::record::{Context, Layout, Target};
use crate::scenario::overrides::Override;
use crate::scenario::{Scenario, Sensing};
use crate::sensing::array_run::ArraySimulation;
use crate::sensing::sweep::ContactSensing;
use nalgebra::Isometry3;
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use whisker_sim::sensing::noise::ContactNoise;
use whisker_sim::world::World;
use whisker_slam::pose;

/// Arm samples between the recording's checkpoints.
const CHECKPOINT_SAMPLES: usize = 100;

/// `whisker run`: simulate and write the outputs; `seed` replaces the scenario's seed,
/// `overrides` change fields (`--set`), `out` the output directory, `rrd` the recording.
pub fn run(
    file: &Path,
    out: Option<PathBuf>,
    seed: Option<u64>,
    overrides: &[Override],
    rrd: &Target,
    ctx: Context,
) -> Result {
    let mut scenario = Scenario::load_with(file, overrides)?;
    if let Some(seed) = seed {
        scenario.seed = seed;
    }
    let dir = out.unwrap_or_else(|| scenario.output.dir.clone());
    execute(file, &scenario, &dir, rrd, ctx)
}

/// Runs `scenario` (read from `file`) into `dir` (created), saying what it does to
/// `ctx`: `whisker run` and each trial of `whisker trials`; the recording goes where
/// `rrd` and the scenario's `output.recording` say.
pub fn execute(file: &Path, scenario: &Scenario, dir: &Path, rrd: &Target, ctx: Context) -> Result {
    let plan = Plan::new(scenario, file)?;
    ctx.say(&plan.describe(file, scenario));
    let loaded = scenario.environment(file)?;
    for line in &loaded.report {
        ctx.say(line);
    }
    let environment = loaded.environment;
    if let Some(e) = &scenario.explore {
        // Loads the object maps: a bad one stops the run before anything is written.
        ctx.say(&crate::closed_loop::describe(file, scenario, e)?);
    }
    output::create_dir(dir)?;

    if scenario.explore.is_some() {
        return crate::closed_loop::write(file, scenario, plan, &environment, dir, rrd, ctx);
    }
    let dt = scenario.output.sample_period_s;
    let chain = &plan.chain;
    let model = &plan.model;
    let skeleton_links = plan.skeleton();

    let layout = Layout::Run {
        physics: scenario.sensing == Sensing::Physics,
    };
    let recording = ctx.scenario_recording(
        file,
        scenario.seed,
        scenario.output.recording,
        dir,
        rrd,
        layout,
    )?;
    if let Some(rec) = &recording {
        let tips: Vec<Isometry3<f64>> = plan.waypoints.iter().map(|q| chain.fk(q)).collect();
        rec.waypoints(&tips)?;
        rec.environment(&environment)?;
    }
    let array_chain = match scenario.sensing {
        Sensing::None => None,
        _ => Some(crate::sensing::array::array_chain(scenario, file, &plan)?),
    };

    let mut whiskers = match scenario.sensing {
        Sensing::Physics => Some(ArraySimulation::new(
            scenario,
            file,
            &plan,
            &environment,
            recording.as_deref(),
            ctx.reporter,
        )?),
        _ => None,
    };
    let mut contacts = match scenario.sensing {
        Sensing::Kinematic => Some(ContactSensing::new(
            scenario,
            file,
            &plan,
            &environment,
            scenario.kinematic.noise(file)?,
            "contacts.csv",
        )?),
        Sensing::Physics if !environment.pieces.is_empty() => Some(ContactSensing::new(
            scenario,
            file,
            &plan,
            &environment,
            ContactNoise::NONE,
            "anticipated.csv",
        )?),
        _ => None,
    };
    let mut world = World::new(model.clone(), plan.model_joints(&plan.waypoints[0]), dt);
    world.add_environment(&environment);
    let mut csv = String::from("t_s");
    for (name, &angular) in chain.joint_names.iter().zip(&chain.angular) {
        let _ = write!(csv, ",{name}_{}", if angular { "rad" } else { "m" });
    }
    csv.push_str(",tip_x_m,tip_y_m,tip_z_m,tip_qx,tip_qy,tip_qz,tip_qw,arm_collision\n");

    let steps = (plan.trajectory.duration() / dt).ceil() as usize;
    let mut tip_path = Vec::with_capacity(steps + 1);
    let mut collision_samples = 0usize;
    let mut collided_links: Vec<String> = Vec::new();
    for k in 0..=steps {
        let t = (k as f64 * dt).min(plan.trajectory.duration());
        let q = plan.trajectory.sample(t);
        let all = plan.model_joints(&q);
        if k > 0 {
            world.step(&all);
        }
        if let Some(w) = &mut whiskers {
            w.advance_to(&plan, t, recording.as_deref())?;
        }
        if let Some(c) = &mut contacts {
            c.advance_to(&plan, t, recording.as_deref())?;
        }
        let tip = chain.fk(&q);
        let hits = world.arm_collisions();
        let collided = !hits.is_empty();
        if collided {
            collision_samples += 1;
            for h in hits {
                if !collided_links.contains(&h) {
                    collided_links.push(h);
                }
            }
        }
        let _ = write!(csv, "{t}");
        for v in &q {
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
        if let Some(rec) = &recording {
            rec.arm(t, &plan.link_frames(&q, &skeleton_links), &tip)?;
            if let Some(a) = &array_chain {
                rec.array(t, &a.fk(&q))?;
            }
            if let Some(w) = &whiskers {
                rec.shafts(t, &w.shafts())?;
            } else if let Some(c) = &contacts {
                rec.shafts(t, &c.shafts(&plan, t))?;
            }
            // A fixed point every simulated second: the recording's chunks do not depend
            // on timing.
            if k % CHECKPOINT_SAMPLES == 0 {
                rec.checkpoint()?;
            }
        }
        tip_path.push(tip);
    }

    let whisker_samples = whiskers.as_ref().map_or(0, ArraySimulation::samples);
    let frontend_contacts = whiskers.as_ref().map(ArraySimulation::frontend_contacts);
    let length: f64 = tip_path
        .windows(2)
        .map(|w| (w[1].translation.vector - w[0].translation.vector).norm())
        .sum();
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
    let summary = json!({
        "scenario": file.display().to_string(),
        "seed": scenario.seed,
        "urdf": scenario.urdf_path(file).display().to_string(),
        "base_link": chain.base,
        "tip_link": chain.tip,
        "joint_names": chain.joint_names,
        "duration_s": plan.trajectory.duration(),
        "sample_period_s": dt,
        "samples": steps + 1,
        "tip_path_length_m": length,
        "waypoints": waypoints,
        "arm_collision_samples": collision_samples,
        "arm_collision_links": collided_links,
        "sensing": scenario.sensing.name(),
        "whisker_samples": whisker_samples,
        "environment_pieces": environment.pieces.iter().map(|p| p.name.clone()).collect::<Vec<_>>(),
        "whisk_cycles_swept": contacts.as_ref().map_or(0, |c| c.counts().0),
        "contacts": contacts.as_ref().map_or(0, |c| c.counts().1),
        "frontend_contacts": frontend_contacts.unwrap_or(0),
    });

    output::write_atomic(&dir.join("path.csv"), csv.as_bytes())?;
    let text = serde_json::to_string_pretty(&summary).expect("plain JSON") + "\n";
    output::write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    if let Some(w) = whiskers {
        w.finish(dir, recording.as_deref())?;
    }
    let contacts_file = contacts.as_ref().map(|c| c.counts());
    if let Some(c) = contacts {
        c.finish(dir)?;
    }
    if let Some(rec) = recording {
        rec.tip_path(&tip_path)?;
        rec.finish()?;
    }
    ctx.say(&format!(
        "simulated  {} samples every {dt} s; tip travelled {length:.3} m; arm–environment collisions: {}",
        steps + 1,
        if collision_samples == 0 {
            "none".to_string()
        } else {
            format!(
                "{collision_samples} samples ({})",
                collided_links.join(", ")
            )
        }
    ));
    let rrd = rrd.wrote(dir, scenario.output.recording);
    let csv = match (scenario.sensing, contacts_file.is_some()) {
        (Sensing::Physics, true) => ", whiskers.csv, frontend.csv, anticipated.csv",
        (Sensing::Physics, false) => ", whiskers.csv, frontend.csv",
        (Sensing::Kinematic, _) => ", contacts.csv",
        (Sensing::None, _) => "",
    };
    if let (Some((cycles, n)), Sensing::Kinematic) = (contacts_file, scenario.sensing) {
        ctx.say(&format!("sensed     {n} contacts in {cycles} whisk cycles"));
    }
    if let Some(n) = frontend_contacts {
        ctx.say(&format!(
            "front end  {n} contacts detected in the whisker streams"
        ));
    }
    ctx.say(&format!(
        "wrote      {}/{{path.csv, summary.json{csv}{rrd}}}",
        dir.display()
    ));
    Ok(())
}
