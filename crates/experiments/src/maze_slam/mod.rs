//! `whisker maze-slam`: planar RatSLAM on the maze with tactile images (thesis Ch 3,
//! §3.1–§3.3); the experiment is a scenario's `[maze_slam]` (scenarios/README.md).
//!
//! The array, facing down, is carried in a plane over the maze of a scenario (its
//! `[maze]`, e.g. `scenarios/maze.toml`) around the loop through the scenario's pose
//! waypoints (their positions; the first is repeated at the end), turning about its own
//! axis to face the direction of travel, like the thesis' path of Fig 3.3 ([`path`]): 3
//! clockwise circuits, 3 anticlockwise, then one of each, one pose-cell size (15 mm) or
//! 10° of turn per 1.5 Hz update (§3.1.2, §3.2.1). Each update gets a tactile image:
//! pixel intensity 255 × the height above the board of the straight shaft's tip at the
//! contact angle (forward kinematics), over the array's height (§3.1.1). The contact
//! angles come from physics whiskers through the front end ([`physics`]; the scenario's
//! `sensing = "physics"`: open loop or RCP after `[array]`, images by `max_angle` and by
//! `contact_angle`, §3.3.3–§3.3.4), or from the kinematic sweep (`"kinematic"`: the
//! anticipated intersect, with the `[kinematic]` detection noise). Odometry is the true
//! turn and distance with the error model of §3.1.2. Random draws: sub-streams
//! `maze-slam/sensing`, `maze-slam/physics` and `maze-slam/odometry` of each seed.
//!
//! The kidnapped variant (§3.3.1) is the same data set with a quarter circuit cut out
//! ([`path::kidnapping`]): the array jumps forward while odometry reports the ordinary
//! step that follows. Reported: ARR and ARCR (Algorithm 1, base set = the first circuit,
//! thresholds 0.1 m and 25°) and the Energy Metric (Eq 3.2 on consecutive updates, each
//! update's estimate being the final relaxed map's pose of the experience current then).
//! `--out` writes each image set and each run's true and estimated trajectory (CSV).
//! `--dataset DIR` runs RatSLAM from a dataset (`whisker dataset`, docs/dataset.md) instead
//! of sensing: the same [`Sensed`] input, so the same bytes out.

use crate::record::{Context, Layout, Recorder, Target};
use path::Sample;
use run_recording::RunRecording;
use serde::Serialize;
use serde_json::json;
use std::fmt;
use std::path::Path;
use whisker_scenario::ScenarioFile;
use whisker_scenario::{Error, Result};
use whisker_slam::pose::Pose2;
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::metrics::{
    ExperienceMetric, consecutive, energy_metric, experience_metric,
};
use whisker_slam::ratslam::{RatSlam, RatSlamParams};

pub mod dataset;
mod geometry;
pub mod images;
pub mod path;
pub mod physics_images;
pub mod run_recording;
mod sensed;
mod settings;
pub mod tuning;

pub use geometry::{Geometry, UPDATE_HZ};
pub use sensed::{
    ImageSet, Sensed, Setup, image_set_names, kinematic_contacts, kinematic_whiskers, physics_sets,
};
pub use settings::Settings;
pub use tuning::Tunings;

/// The figures of one RatSLAM run: one seed, variant, image set and tuning.
#[derive(Debug, Clone, Serialize)]
pub struct RunResult {
    pub seed: u64,
    /// `normal` or `kidnapped`.
    pub variant: &'static str,
    /// The image set (`kinematic`, `open-loop/max_angle` …).
    pub images: String,
    pub match_threshold: f64,
    pub inject_energy: f64,
    pub updates: usize,
    pub templates: usize,
    pub experiences: usize,
    /// ARR and ARCR (Algorithm 1) and the re-localisations they count; absent without
    /// ground truth.
    pub arr: Option<f64>,
    pub arcr: Option<f64>,
    pub relocalisations: Option<usize>,
    /// The Energy Metric (Eq 3.2); absent without ground truth.
    pub energy_metric: Option<f64>,
}

/// What `whisker maze-slam` found: every run (`--json`: `{"runs": […]}`).
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub runs: Vec<RunResult>,
}

/// One RatSLAM run over a sequence of images and odometry, and its metrics.
struct Evaluation {
    /// The current experience after each update.
    log: Vec<usize>,
    /// Each update's estimate: the final relaxed map's pose of the experience current
    /// then, relative to the first update's experience, placed at the start pose.
    estimate: Vec<Pose2>,
    /// ARR and ARCR (None without ground truth).
    metric: Option<ExperienceMetric>,
    /// The Energy Metric (None without ground truth).
    energy: Option<f64>,
    templates: usize,
    experiences: usize,
}

impl Evaluation {
    /// RatSLAM with `params` over `images` and `steps` (distance, turn), the estimate
    /// placed at `start`, scored against `truth` (when known) with the base set ending at
    /// update `base_end`.
    fn of(
        params: RatSlamParams,
        images: &[TactileImage],
        steps: &[(f64, f64)],
        start: Sample,
        truth: Option<&[Sample]>,
        base_end: usize,
        mut record: Option<&mut RunRecording>,
    ) -> Result<Self> {
        let mut slam = RatSlam::new(params);
        let mut log: Vec<usize> = Vec::with_capacity(images.len());
        for (k, (img, &(d, t))) in images.iter().zip(steps).enumerate() {
            let step = slam.step(img, d, t);
            log.push(step.experience);
            if let Some(r) = record.as_deref_mut() {
                let last = k + 1 == images.len();
                r.update(k, img, &slam, &step, truth.map(|t| &t[k]), last)?;
            }
        }
        let estimate = slam.map.placed(&log, &start);
        let metric = truth.map(|t| experience_metric(&log, t, base_end, 0.1, 25f64.to_radians()));
        let energy =
            truth.map(|t| energy_metric(&estimate, t, &consecutive(t.len())).unwrap_or(f64::NAN));
        if let Some(r) = record {
            r.finish(truth, &estimate)?;
        }
        Ok(Self {
            log,
            estimate,
            metric,
            energy,
            templates: slam.view.templates.len(),
            experiences: slam.map.experiences.len(),
        })
    }

    /// `trajectory-….csv`: true (empty without ground truth) and estimated poses and the
    /// experience of each update.
    fn trajectory_csv(&self, truth: Option<&[Sample]>) -> String {
        let mut csv = String::from(
            "update,true_x_m,true_y_m,true_heading_rad,est_x_m,est_y_m,est_heading_rad,experience\n",
        );
        for (k, e) in self.estimate.iter().enumerate() {
            let t = match truth {
                Some(t) => format!("{},{},{}", t[k].x, t[k].y, t[k].th),
                None => ",,".into(),
            };
            csv += &format!("{k},{t},{},{},{},{}\n", e.x, e.y, e.th, self.log[k]);
        }
        csv
    }
}

/// `v` without the items in `cut`.
fn without<T: Copy>(v: &[T], cut: &std::ops::Range<usize>) -> Vec<T> {
    (0..v.len())
        .filter(|k| !cut.contains(k))
        .map(|k| v[k])
        .collect()
}

/// `whisker maze-slam`.
pub fn run(o: &Settings, ctx: Context) -> Result<Report> {
    let file = ScenarioFile::load_with(&o.scenario, &o.set)?;
    ctx.say(&format!(
        "odometry   {}",
        file.scenario.maze_slam.odometry.describe(path::STEP_M)
    ));
    let runs = evaluate(o, &file, ctx)?;
    Ok(Report { runs })
}

/// `whisker maze-slam --dataset DIR` (and `whisker slam DIR`): RatSLAM from the dataset
/// in `dir`, whose manifest is `manifest`; the tunings and `--kidnap` of `o` apply.
pub fn replay(
    o: &Settings,
    dir: &Path,
    manifest: &crate::dataset_format::manifest::Manifest,
    ctx: Context,
) -> Result<Report> {
    if manifest.experiment != crate::dataset_format::manifest::Experiment::MazeSlam {
        return Err(Error::Input(format!(
            "{}: not a maze-slam dataset",
            dir.join(crate::dataset_format::manifest::FILE).display()
        )));
    }
    let (sensed, params, tuned, kidnap) = dataset::read(dir, manifest)?;
    if o.kidnap && sensed.starts.len() < 4 {
        return Err(Error::Input(format!(
            "--kidnap: the dataset {} has {} circuits; the kidnapped variant needs 4",
            dir.display(),
            sensed.starts.len()
        )));
    }
    let tunings = Tunings::of(params, &tuned, o)?;
    let kidnap = kidnap || o.kidnap;
    let sets: Vec<String> = sensed.image_sets.iter().map(|(n, _)| n.clone()).collect();
    note_unused(&tunings, &sets, ctx);
    let stem = dir.file_name().unwrap_or_default().to_string_lossy();
    let runs = run_names(&[sensed.seed], &sets, &tunings, kidnap);
    let recording = open_recording(o, ctx, true, &stem, &[sensed.seed], runs, None)?;
    let plane = Plane {
        z: 0.0,
        recording: recording.as_deref(),
    };
    let runs = run_sensed(&sensed, &tunings, kidnap, o.out.as_deref(), &plane, ctx)?;
    if let Some(rec) = recording {
        rec.finish()?;
    }
    Ok(Report { runs })
}

/// Where a maze-slam's recording draws and goes.
pub struct Plane<'a> {
    /// Height of the array's plane (m; 0 from a dataset).
    pub z: f64,
    pub recording: Option<&'a dyn Recorder>,
}

/// Says which `[maze_slam.tuned]` entries name none of the run's image `sets`.
fn note_unused(tunings: &Tunings, sets: &[String], ctx: Context) {
    for key in tunings.unused(sets) {
        ctx.note(&format!(
            "[maze_slam.tuned] {key:?}: not used (this run's image sets: {})",
            sets.join(", ")
        ));
    }
}

/// The names of the runs of `seeds` × variants × image `sets` × `tunings`, as
/// [`slam_runs`] names them.
fn run_names(seeds: &[u64], sets: &[String], tunings: &Tunings, kidnap: bool) -> Vec<String> {
    let variants: &[&str] = if kidnap {
        &["normal", "kidnapped"]
    } else {
        &["normal"]
    };
    let mut names = Vec::new();
    for &seed in seeds {
        for variant in variants {
            for set in sets {
                for params in tunings.for_run(set, variant) {
                    names.push(run_recording::run_name(
                        set,
                        variant,
                        &tuning::tag(&params, tunings.sweep()),
                        seed,
                    ));
                }
            }
        }
    }
    names
}

/// The recording of a maze-slam (`--rrd`, else `run.rrd` in `--out` when `default_on`).
fn open_recording(
    o: &Settings,
    ctx: Context,
    default_on: bool,
    stem: &str,
    seeds: &[u64],
    runs: Vec<String>,
    eye: Option<crate::record::Eye>,
) -> Result<Option<Box<dyn Recorder>>> {
    let Some(path) = o.rrd.path(o.out.as_deref(), default_on) else {
        return Ok(None);
    };
    let layout = Layout::SlamRuns {
        runs,
        images: true,
        timeline: "update",
        eye,
    };
    let seeds: Vec<String> = seeds.iter().map(u64::to_string).collect();
    let id = o
        .rrd
        .id
        .clone()
        .unwrap_or_else(|| format!("{stem}-seed{}", seeds.join(",")));
    ctx.recordings.create(&path, &id, layout).map(Some)
}

/// One trial of a batch (`trials.experiment = "maze-slam"`): `whisker maze-slam` of the
/// scenario's seed with `--out dir` (the recording as `rrd` says), and `summary.json`: each run's figures under
/// `<variant>.<images>` (e.g. `normal.kinematic.arr`).
pub fn trial(file: &ScenarioFile, dir: &Path, rrd: &Target, ctx: Context) -> Result {
    let scenario = &file.scenario;
    let mut o = Settings::of(&file.path);
    o.rrd = rrd.clone();
    o.seeds = Some(vec![scenario.seed]);
    o.out = Some(dir.to_path_buf());
    let report = Report {
        runs: evaluate(&o, file, ctx)?,
    };
    let mut summary = serde_json::Map::new();
    summary.insert("seed".into(), json!(scenario.seed));
    for r in &report.runs {
        // Keyed by the image estimate, not the whisking control (a factor of the batch,
        // in the trial's key): the levels' figures share their columns.
        let estimate = match r.images.starts_with("kinematic") {
            true => "kinematic",
            false => r.images.rsplit('/').next().unwrap_or(&r.images),
        };
        let name = format!("{}.{estimate}", r.variant);
        let mut figures = match serde_json::to_value(r) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        };
        for k in ["seed", "variant", "images"] {
            figures.remove(k);
        }
        summary.insert(name, serde_json::Value::Object(figures));
    }
    let text = serde_json::to_string_pretty(&summary).expect("plain JSON") + "\n";
    whisker_scenario::files::write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    let line = serde_json::to_value(&report).map_err(|e| Error::Failure(e.to_string()))?;
    ctx.say(&line.to_string());
    Ok(())
}

/// The runs of `whisker maze-slam` with settings `o` on the scenario of `file`: one per
/// seed, variant, image set and tuning.
pub fn evaluate(o: &Settings, file: &ScenarioFile, ctx: Context) -> Result<Vec<RunResult>> {
    let scenario = &file.scenario;
    let setup = Setup::new(o, file)?;
    let environment = file.environment()?.environment;
    let tunings = Tunings::of(scenario.maze_slam.ratslam, &scenario.maze_slam.tuned, o)?;
    note_unused(&tunings, &setup.set_names, ctx);
    let kidnap = o.kidnap || scenario.maze_slam.kidnap;
    let seeds = o.seeds.clone().unwrap_or(vec![scenario.seed]);
    let stem = o.scenario.file_stem().unwrap_or_default().to_string_lossy();
    let runs = run_names(&seeds, &setup.set_names, &tunings, kidnap);
    let eye = crate::record::Eye::of(&environment, &[]);
    let recording = open_recording(o, ctx, scenario.output.recording, &stem, &seeds, runs, eye)?;
    if let Some(rec) = &recording {
        rec.environment(&environment)?;
    }
    let plane = Plane {
        z: setup.geometry.plane_z,
        recording: recording.as_deref(),
    };
    // The kinematic sweep's target (a BVH of the world mesh), built once for all seeds.
    let target = std::cell::OnceCell::new();
    let mut results = Vec::new();
    for &seed in &seeds {
        let sensed = sensed::sense(o, file, &setup, &environment, &target, seed, ctx)?;
        results.extend(run_sensed(
            &sensed,
            &tunings,
            kidnap,
            o.out.as_deref(),
            &plane,
            ctx,
        )?);
    }
    if let Some(rec) = recording {
        rec.finish()?;
    }
    Ok(results)
}

/// One seed's RatSLAM runs ([`slam_runs`]), its image files written to `out` first.
fn run_sensed(
    sensed: &Sensed,
    tunings: &Tunings,
    kidnap: bool,
    out: Option<&Path>,
    plane: &Plane,
    ctx: Context,
) -> Result<Vec<RunResult>> {
    if let Some(dir) = out {
        whisker_scenario::files::create_dir(dir)?;
        for (images_name, images) in &sensed.image_sets {
            whisker_scenario::files::write_atomic(
                &images::path(dir, images_name, sensed.seed),
                images::to_csv(images).as_bytes(),
            )?;
        }
    }
    slam_runs(sensed, tunings, kidnap, out, plane, ctx)
}

/// RatSLAM over one seed's data: the normal variant (and, with `kidnap`, the kidnapped
/// one) of every image set with every tuning; trajectories written to `out`.
pub fn slam_runs(
    sensed: &Sensed,
    tunings: &Tunings,
    kidnap: bool,
    out: Option<&Path>,
    plane: &Plane,
    ctx: Context,
) -> Result<Vec<RunResult>> {
    let seed = sensed.seed;
    let sweep = tunings.sweep();
    let starts = &sensed.starts;
    let mut results = Vec::new();
    let variants: &[bool] = if kidnap { &[false, true] } else { &[false] };
    for &kidnapped in variants {
        let name = if kidnapped { "kidnapped" } else { "normal" };
        // The kidnapped data set is the normal one with a quarter circuit cut out: the
        // array jumps forward while odometry reports the ordinary step that follows.
        let cut = if kidnapped {
            path::kidnapping(starts)
        } else {
            0..0
        };
        let truth: Option<Vec<Sample>> = sensed.truth.as_ref().map(|t| without(t, &cut));
        let steps = without(&sensed.steps, &cut);
        let updates = steps.len();
        for (images_name, images) in &sensed.image_sets {
            let images = without(images, &cut);
            for params in &tunings.for_run(images_name, name) {
                let tuning = tuning::tag(params, sweep);
                let mut record = plane.recording.map(|rec| RunRecording {
                    rec,
                    name: run_recording::run_name(images_name, name, &tuning, seed),
                    z: plane.z,
                    hz: UPDATE_HZ,
                    graph: Default::default(),
                    landmarks: Vec::new(),
                });
                let run = Evaluation::of(
                    *params,
                    &images,
                    &steps,
                    sensed.start,
                    truth.as_deref(),
                    starts[1] - 1,
                    record.as_mut(),
                )?;
                if let Some(dir) = out {
                    let tag = images_name.replace('/', "-") + &tuning;
                    whisker_scenario::files::write_atomic(
                        &dir.join(format!("trajectory-{tag}-{name}-{seed}.csv")),
                        run.trajectory_csv(truth.as_deref()).as_bytes(),
                    )?;
                }
                ctx.note(&format!(
                    "seed {seed} {name} {images_name}: {updates} updates"
                ));
                results.push(RunResult {
                    seed,
                    variant: name,
                    images: images_name.clone(),
                    match_threshold: params.local_view.match_threshold,
                    inject_energy: params.local_view.inject_energy,
                    updates,
                    templates: run.templates,
                    experiences: run.experiences,
                    arr: run.metric.as_ref().map(|m| m.arr),
                    arcr: run.metric.as_ref().map(|m| m.arcr),
                    relocalisations: run.metric.as_ref().map(|m| m.relocalisations),
                    energy_metric: run.energy,
                });
            }
        }
    }
    Ok(results)
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "Planar RatSLAM on the maze (§3.3)")?;
        writeln!(
            f,
            "  {:>5} {:<10} {:<26} {:>6} {:>6} {:>7} {:>9} {:>11} {:>7} {:>7} {:>9}",
            "seed",
            "variant",
            "images",
            "thresh",
            "energy",
            "updates",
            "templates",
            "experiences",
            "ARR",
            "ARCR",
            "EM"
        )?;
        // Metrics that need ground truth are absent without it: shown as n/a.
        let metric = |v: Option<f64>, width: usize| match v.filter(|x| !x.is_nan()) {
            Some(x) => format!("{x:>width$.4}"),
            None => format!("{:>width$}", "n/a"),
        };
        for r in &self.runs {
            writeln!(
                f,
                "  {:>5} {:<10} {:<26} {:>6} {:>6} {:>7} {:>9} {:>11} {} {} {}",
                r.seed,
                r.variant,
                r.images,
                r.match_threshold,
                r.inject_energy,
                r.updates,
                r.templates,
                r.experiences,
                metric(r.arr, 7),
                metric(r.arcr, 7),
                metric(r.energy_metric, 9),
            )?;
        }
        f.write_str(&whisker_scenario::console::legend(
            "columns",
            &[
                ("variant", "normal, or kidnapped (carried ahead mid-run, §3.3.1)"),
                ("images", "how each whisk became a tactile image: whisking control / contact-angle estimate (max_angle or contact_angle, §3.1.1)"),
                ("thresh", "local-view match threshold (§3.2.1; lower = stricter)"),
                ("energy", "pose-cell inject energy (§3.2.1)"),
                ("updates", "whisks = RatSLAM updates"),
                ("templates", "distinct tactile images kept as local-view templates"),
                ("experiences", "nodes of the experience map"),
                ("ARR", "average re-localisation rate (§3.2.3.1, Alg 1): re-localisations per experience after the first loop; 0–1, higher = the loop is recognised more often"),
                ("ARCR", "average rate of correct re-localisation: the share of re-localisations within 0.1 m and 25° of the truth; 0–1, higher is better"),
                ("EM", "Energy Metric (Eq 3.2–3.3): mean over consecutive poses of the squared error of their relative pose (m² + rad²); lower is better, 0 = no error (Figs 3.7–3.8)"),
                ("n/a", "the metric needs ground truth (a dataset without it)"),
            ],
        ))
    }
}
