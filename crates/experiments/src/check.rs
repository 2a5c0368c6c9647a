//! `whisker check SCENARIO`: everything up to the simulation (parsing, URDF, IK of every
//! waypoint, the array, the environment, the maps, the batch) and what would run, saying
//! it and writing nothing (but `--meshes`).

use crate::record::Context;
use std::path::Path;
use whisker_scenario::Result;
use whisker_scenario::ScenarioFile;
use whisker_scenario::plan::Plan;
use whisker_scenario::{Experiment, Sensing};
use whisker_sim::environment::Environment;

/// `whisker check`: validates and describes; with `meshes`, writes each object's mesh as
/// loaded to `meshes/NAME.obj`.
pub fn check(path: &Path, meshes: Option<&Path>, ctx: Context) -> Result {
    let file = &ScenarioFile::load(path)?;
    let scenario = &file.scenario;
    let plan = Plan::new(file)?;
    ctx.say(&plan.describe(file));
    if scenario.sensing != Sensing::None {
        ctx.say(&crate::sensing::array::describe(file)?);
        crate::sensing::array::array_chain(file, &plan)?;
    }
    if scenario.sensing == Sensing::Kinematic {
        let n = scenario.kinematic.noise(path)?;
        ctx.say(&format!("kinematic  1° sweeps once per whisk cycle; noise: point σ {} × length, slope σ {}, detection {}",
            n.point_fraction, n.slope_sigma, n.detection_probability
        ));
    }
    let loaded = file.environment()?;
    for line in &loaded.report {
        ctx.say(line);
    }
    if let Experiment::Navigate(config) = &scenario.experiment {
        ctx.say(&crate::navigation::outputs::check(
            file,
            config,
            &plan,
            &loaded.environment,
        )?);
    }
    if let Some(dir) = meshes {
        write_meshes(file, &loaded.environment, dir)?;
    }
    let dir = &scenario.output.dir;
    let rrd = if scenario.output.recording {
        ", run.rrd"
    } else {
        ""
    };
    match &scenario.experiment {
        Experiment::Navigate(_) => ctx.say(&format!(
            "output     {} ({}{rrd})",
            dir.display(),
            crate::navigation::outputs::FILES
        )),
        Experiment::ClosedLoop(e) => {
            ctx.say(&crate::closed_loop::describe(file, e)?);
            ctx.say(&format!(
                "output     {} ({}, {}, contacts.csv{}{rrd})",
                dir.display(),
                crate::closed_loop::CSV_NAME,
                crate::closed_loop::SUMMARY_NAME,
                if e.task == whisker_scenario::explore::Task::Map {
                    ", map.json"
                } else {
                    ""
                }
            ));
        }
        Experiment::Scripted => ctx.say(&format!(
            "output     {} (path.csv every {} s, summary.json{rrd})",
            dir.display(),
            scenario.output.sample_period_s
        )),
    }
    if scenario.trials.is_some() {
        ctx.say(&whisker_scenario::grid::Batch::of(file)?.describe());
    }
    let skipped = whisker_sim::arm::links_without_colliders(&plan.model);
    if !skipped.is_empty() {
        ctx.say(&format!("warning    links whose collision meshes are missing or not OBJ/STL/PLY get no collider: {}",
            skipped.join(", ")
        ));
    }
    ctx.say("ok");
    Ok(())
}

/// Writes each `[[objects]]` mesh of the scenario in `file` as loaded into
/// `environment` to `dir/NAME.obj`.
fn write_meshes(file: &ScenarioFile, environment: &Environment, dir: &Path) -> Result {
    let scenario = &file.scenario;
    whisker_scenario::files::create_dir(dir)?;
    let names = scenario.object_names();
    for (i, (name, piece)) in names.iter().zip(&environment.pieces).enumerate() {
        // A file name per object: separators replaced, and the index added to a name
        // that several objects share (two copies of one mesh).
        let mut stem = name.replace(['/', '\\'], "_");
        if names.iter().filter(|n| *n == name).count() > 1 {
            stem = format!("{stem}-{i}");
        }
        let path = dir.join(format!("{stem}.obj"));
        let vertices: Vec<[f64; 3]> = piece
            .mesh
            .vertices
            .iter()
            .map(|p| [p.x, p.y, p.z])
            .collect();
        let text = whisker_sim::environment::mesh_io::obj_text(
            &vertices,
            &piece.mesh.triangles,
            &format!(
                "{name} as loaded by {} (metres, z up, its own frame)",
                file.path.display()
            ),
        );
        whisker_scenario::files::write_atomic(&path, text.as_bytes())?;
    }
    Ok(())
}
