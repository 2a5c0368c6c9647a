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

use crate::characterize::BendingArg;
use crate::error::{CliError, CliResult};
use crate::object_slam::SensingArg;
use crate::scenario::array::{BendingConfig, RcpConfig};
use crate::scenario::maze_slam::AngleEstimate;
use crate::scenario::overrides::Override;
use crate::scenario::{Scenario, Sensing};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use path::Sample;
use serde_json::json;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::physics::WhiskerConfig;
use whisker_sim::whisker::array;
use whisker_sim::whisker::control::{RcpThreshold, WhiskingPattern};
use whisker_slam::ratslam::experience_map::{Pose2, wrap};
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::metrics::{
    ExperienceMetric, consecutive, energy_metric, experience_metric,
};
use whisker_slam::ratslam::{RatSlam, RatSlamParams};
use whisker_slam::rng::{substream, substream_key};

pub mod images;
pub mod path;
pub mod physics;

/// Options of `whisker maze-slam`; every one but the scenario overrides the scenario.
#[derive(clap::Args, Debug)]
pub struct Options {
    /// Scenario with a `[maze]`, pose waypoints (the loop's corners) and optionally
    /// `[maze_slam]`.
    #[arg(default_value = "scenarios/maze.toml")]
    pub scenario: PathBuf,
    /// Seeds (comma-separated): one run per seed [default: the scenario's `seed`].
    #[arg(long, value_delimiter = ',')]
    pub seeds: Option<Vec<u64>>,
    /// Also run the kidnapped variant of every seed (§3.3.1) [scenario:
    /// `maze_slam.kidnap`].
    #[arg(long)]
    pub kidnap: bool,
    /// Local-view matching threshold (Eq 3.1) [scenario:
    /// `maze_slam.ratslam.local_view.match_threshold`]. Several (comma-separated) run
    /// RatSLAM once per value on the same images and odometry — a tuning sweep at the
    /// cost of one physics run.
    #[arg(long, value_delimiter = ',')]
    pub match_threshold: Option<Vec<f64>>,
    /// Pose-cell injection energy (Eq 5.8) [scenario:
    /// `maze_slam.ratslam.local_view.inject_energy`]; several as for `--match-threshold`.
    #[arg(long, value_delimiter = ',')]
    pub inject_energy: Option<Vec<f64>>,
    /// Directory for `trajectory-<images>-<variant>-<seed>.csv` and `images-….csv`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Read each seed's tactile images from the `images-….csv` an earlier `--out` wrote
    /// to this directory, instead of sensing (re-running RatSLAM on recorded images).
    #[arg(long)]
    pub images: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// How tactile images are made [scenario: `sensing`]: the kinematic sweep's contact
    /// angles, or physics whiskers through the front end.
    #[arg(long, value_enum)]
    pub sensing: Option<SensingArg>,
    /// Physics: whisk with RCP at 20 × the free-whisking σ (§3.2.2) [scenario:
    /// `array.rcp`].
    #[arg(long)]
    pub rcp: bool,
    /// Physics: shaft joint model [scenario: `array.bending`].
    #[arg(long, value_enum)]
    pub bending: Option<BendingArg>,
    /// Physics: segments per whisker [scenario: `array.segments`].
    #[arg(long)]
    pub segments: Option<usize>,
    /// Physics: Rapier substeps per 0.5 ms step [scenario: `array.substeps`].
    #[arg(long)]
    pub substeps: Option<usize>,
    /// Change a scenario field by its dotted path, as `whisker run --set` (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
    pub set: Vec<Override>,
}

/// Updates per second (§3.1.2).
pub const UPDATE_HZ: f64 = 1.5;

/// Where the array flies and how tactile images are scaled.
pub struct Geometry {
    /// Height of the array plane (world z, m).
    pub plane_z: f64,
    /// Height of the board (world z, m).
    pub board_z: f64,
    /// Yaw of the array at heading 0 (rad).
    pub yaw0: f64,
}

impl Geometry {
    /// The array's pose at a path sample: facing down from the plane, turned about the
    /// vertical by the heading.
    pub fn pose(&self, p: &Sample) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(p.x, p.y, self.plane_z),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), p.th)
                * UnitQuaternion::from_euler_angles(PI, 0.0, self.yaw0),
        )
    }

    /// The height above the board of `whisker`'s straight shaft tip at whisk angle `angle`
    /// with the array at `pose` (forward kinematics, §3.1.1), at least 0.
    pub fn tip_height(&self, whisker: &RigidWhisker, pose: &Isometry3<f64>, angle: f64) -> f64 {
        let tip = whisker.shaft_point(pose, angle, whisker.module.beam.length);
        (tip.z - self.board_z).max(0.0)
    }

    /// The tactile image of per-whisker heights, full scale the array's height.
    pub fn image(&self, heights: &[Option<f64>]) -> TactileImage {
        TactileImage::from_heights(heights, self.plane_z - self.board_z)
    }
}

/// Tactile images of every update from the kinematic sweep (the scenario's detection
/// probability applies; sub-stream `maze-slam/sensing` of the seed, as `key`).
fn kinematic_images(
    truth: &[Sample],
    target: &SweepTarget,
    noise: whisker_sim::sensing::noise::ContactNoise,
    key: u64,
    g: &Geometry,
) -> Vec<TactileImage> {
    let whiskers: Vec<RigidWhisker> = array::modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, 3.0e-3))
        .collect();
    let mut sensing = KinematicArray::new(
        whiskers.clone(),
        vec![WhiskingPattern::default(); whiskers.len()],
        noise,
        key,
    );
    truth
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let pose = g.pose(p);
            let cycle = sensing.sense(target, k as u64, k as f64, &pose);
            let mut heights = vec![None; whiskers.len()];
            for c in &cycle.contacts {
                heights[c.whisker] = Some(g.tip_height(&whiskers[c.whisker], &pose, c.angle_rad));
            }
            g.image(&heights)
        })
        .collect()
}

/// One RatSLAM run over a sequence of images and odometry, and its metrics.
struct Evaluation {
    /// The current experience after each update.
    log: Vec<usize>,
    /// Each update's estimate: the final relaxed map's pose of the experience current
    /// then, relative to the first update's experience, placed at the first true pose.
    estimate: Vec<Pose2>,
    metric: ExperienceMetric,
    energy: f64,
    templates: usize,
    experiences: usize,
}

impl Evaluation {
    /// RatSLAM with `params` over `images` and `steps` (distance, turn), scored against
    /// `truth` with the base set ending at update `base_end`.
    fn of(
        params: RatSlamParams,
        images: &[TactileImage],
        steps: &[(f64, f64)],
        truth: &[Sample],
        base_end: usize,
    ) -> Self {
        let mut slam = RatSlam::new(params);
        let log: Vec<usize> = images
            .iter()
            .zip(steps)
            .map(|(img, &(d, t))| slam.step(img, d, t).experience)
            .collect();
        // Relaxation moves the whole map (its links fix only relative poses): anchor it
        // at the first update's experience, placed at the first true pose.
        let anchor = slam.map.experiences[log[0]].pose;
        let estimate: Vec<Pose2> = log
            .iter()
            .map(|&e| truth[0].compose(&anchor.relative(&slam.map.experiences[e].pose)))
            .collect();
        let metric = experience_metric(&log, truth, base_end, 0.1, 25f64.to_radians());
        let energy = energy_metric(&estimate, truth, &consecutive(truth.len())).unwrap_or(f64::NAN);
        Self {
            log,
            estimate,
            metric,
            energy,
            templates: slam.view.templates.len(),
            experiences: slam.map.experiences.len(),
        }
    }

    /// `trajectory-….csv`: true and estimated poses and the experience of each update.
    fn trajectory_csv(&self, truth: &[Sample]) -> String {
        let mut csv = String::from(
            "update,true_x_m,true_y_m,true_heading_rad,est_x_m,est_y_m,est_heading_rad,experience\n",
        );
        for (k, (t, e)) in truth.iter().zip(&self.estimate).enumerate() {
            csv += &format!(
                "{k},{},{},{},{},{},{},{}\n",
                t.x, t.y, t.th, e.x, e.y, e.th, self.log[k]
            );
        }
        csv
    }
}

/// The loop's corners (x, y) from the scenario's pose waypoints, and the geometry: the
/// array plane at the first waypoint's height, its yaw at heading 0 from its `rpy_deg`,
/// the board's top at `board_z`.
fn corners(
    scenario: &Scenario,
    file: &Path,
    board_z: f64,
) -> CliResult<(Vec<(f64, f64)>, Geometry)> {
    let poses: Vec<([f64; 3], [f64; 3])> = scenario
        .trajectory
        .waypoints
        .iter()
        .filter_map(|w| Some((w.position_m?, w.rpy_deg?)))
        .collect();
    if poses.len() < 3 {
        return Err(CliError::field(
            file,
            "trajectory.waypoints",
            "maze-slam needs at least 3 pose waypoints (the loop's corners)",
        ));
    }
    let mut corners: Vec<(f64, f64)> = poses.iter().map(|(p, _)| (p[0], p[1])).collect();
    if corners.len() > 3 && corners.first() == corners.last() {
        corners.pop();
    }
    let geometry = Geometry {
        plane_z: poses[0].0[2],
        board_z,
        yaw0: poses[0].1[2].to_radians(),
    };
    Ok((corners, geometry))
}

/// The RatSLAM parameter sets to run: the scenario's, or one per pair of the
/// command line's lists.
fn tunings(base: RatSlamParams, o: &Options) -> CliResult<Vec<RatSlamParams>> {
    let lv = base.local_view;
    let thresholds = o
        .match_threshold
        .clone()
        .unwrap_or(vec![lv.match_threshold]);
    let energies = o.inject_energy.clone().unwrap_or(vec![lv.inject_energy]);
    if let Some(bad) = thresholds
        .iter()
        .chain(&energies)
        .find(|v| !(v.is_finite() && **v > 0.0))
    {
        return Err(CliError::Input(format!(
            "--match-threshold / --inject-energy: expected positive numbers, got {bad}"
        )));
    }
    let mut out = Vec::new();
    for &threshold in &thresholds {
        for &energy in &energies {
            let mut p = base;
            p.local_view.match_threshold = threshold;
            p.local_view.inject_energy = energy;
            out.push(p);
        }
    }
    Ok(out)
}

/// The physics whiskers: the scenario's `[array]` with the command line's overrides,
/// checked as the scenario's own values are.
fn physics_configs(
    scenario: &Scenario,
    file: &Path,
    o: &Options,
) -> CliResult<(Vec<WhiskerConfig>, Option<RcpThreshold>)> {
    let mut array = scenario.array.clone();
    if let Some(b) = o.bending {
        array.bending = match b {
            BendingArg::Spatial => BendingConfig::Spatial,
            BendingArg::SweepPlane => BendingConfig::SweepPlane,
        };
    }
    array.segments = o.segments.or(array.segments);
    array.substeps = o.substeps.or(array.substeps);
    if o.rcp {
        array.rcp = RcpConfig::Noise;
        array.rcp_noise_multiple = Some(20.0);
    }
    let overridden = o.bending.is_some() || o.segments.is_some() || o.substeps.is_some();
    let configs = array.whisker_configs(file).map_err(|e| match e {
        CliError::Input(m) if overridden => CliError::Input(format!(
            "{m} (with --bending / --segments / --substeps from the command line)"
        )),
        e => e,
    })?;
    Ok((configs, array.rcp_mode()))
}

/// `v` without the items in `cut`.
fn without<T: Copy>(v: &[T], cut: &std::ops::Range<usize>) -> Vec<T> {
    (0..v.len())
        .filter(|k| !cut.contains(k))
        .map(|k| v[k])
        .collect()
}

/// One data set: a name and the tactile image of every update.
type ImageSet = (String, Vec<TactileImage>);

/// `whisker maze-slam`.
pub fn run(o: &Options) -> CliResult {
    let scenario = Scenario::load_with(&o.scenario, &o.set)?;
    let results = evaluate(o, &scenario)?;
    report(&results, o.json);
    Ok(())
}

/// One trial of a batch (`trials.experiment = "maze-slam"`): `whisker maze-slam` of the
/// scenario's seed with `--out dir`, and `summary.json`: each run's figures under
/// `<variant>.<images>` (e.g. `normal.kinematic.arr`).
pub fn trial(
    file: &Path,
    scenario: &Scenario,
    dir: &Path,
    say: &mut dyn std::io::Write,
) -> CliResult {
    let o = Options {
        scenario: file.to_path_buf(),
        seeds: Some(vec![scenario.seed]),
        kidnap: false,
        match_threshold: None,
        inject_energy: None,
        out: Some(dir.to_path_buf()),
        images: None,
        json: true,
        sensing: None,
        rcp: false,
        bending: None,
        segments: None,
        substeps: None,
        set: Vec::new(),
    };
    let results = evaluate(&o, scenario)?;
    let mut summary = serde_json::Map::new();
    summary.insert("seed".into(), json!(scenario.seed));
    for r in &results {
        let name = format!(
            "{}.{}",
            r["variant"].as_str().unwrap_or(""),
            r["images"].as_str().unwrap_or("")
        );
        let mut figures = r.as_object().cloned().unwrap_or_default();
        for k in ["seed", "variant", "images"] {
            figures.remove(k);
        }
        summary.insert(name, serde_json::Value::Object(figures));
    }
    let text = serde_json::to_string_pretty(&summary).expect("plain JSON") + "\n";
    crate::output::write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    let _ = writeln!(say, "{}", json!({ "runs": results }));
    Ok(())
}

/// The runs of `whisker maze-slam` with options `o` on `scenario` (read from `o.scenario`):
/// one JSON object per seed, variant, image set and tuning.
pub fn evaluate(o: &Options, scenario: &Scenario) -> CliResult<Vec<serde_json::Value>> {
    let file = o.scenario.as_path();
    let maze = scenario
        .maze
        .as_ref()
        .ok_or_else(|| CliError::field(file, "maze", "maze-slam needs a [maze] section"))?;
    let config = &scenario.maze_slam;
    let (loop_corners, geometry) = corners(scenario, file, maze.position_m[2])?;
    let sensing = match (o.sensing, scenario.sensing) {
        (Some(s), _) => s,
        (None, Sensing::Physics) => SensingArg::Physics,
        (None, Sensing::Kinematic) => SensingArg::Kinematic,
        (None, Sensing::None) => {
            return Err(CliError::field(
                file,
                "sensing",
                "maze-slam needs \"physics\" or \"kinematic\" (or --sensing)",
            ));
        }
    };
    let environment = scenario.environment(file)?.environment;
    let tunings = tunings(config.ratslam, o)?;
    let sweep = tunings.len() > 1;
    let physics = match sensing {
        SensingArg::Physics => Some(physics_configs(scenario, file, o)?),
        SensingArg::Kinematic => None,
    };
    let (truth_path, starts) = path::path(&loop_corners);
    let kidnap = o.kidnap || config.kidnap;
    let seeds = o.seeds.clone().unwrap_or(vec![scenario.seed]);
    // The image sets, named as in reports and file names.
    let set_names: Vec<String> = match &physics {
        None => vec!["kinematic".into()],
        Some((_, rcp)) => {
            let control = if rcp.is_some() { "rcp" } else { "open-loop" };
            config
                .images
                .iter()
                .map(|e| format!("{control}/{}", e.name()))
                .collect()
        }
    };
    // The kinematic sweep's target (a BVH of the world mesh), built once for all seeds.
    let target = std::cell::OnceCell::new();
    let mut results = Vec::new();
    for &seed in &seeds {
        let image_sets: Vec<ImageSet> = match (&o.images, &physics) {
            (Some(dir), _) => set_names
                .iter()
                .map(|name| {
                    Ok((
                        name.clone(),
                        images::read(&images::path(dir, name, seed), truth_path.len())?,
                    ))
                })
                .collect::<CliResult<_>>()?,
            (None, None) => {
                let target = target.get_or_init(|| environment.sweep_target());
                let noise = scenario.kinematic.noise(file)?;
                let key = substream_key(seed, "maze-slam/sensing");
                let images = kinematic_images(&truth_path, target, noise, key, &geometry);
                vec![(set_names[0].clone(), images)]
            }
            (None, Some((configs, rcp))) => {
                let (max, contact) = physics::images(
                    &truth_path,
                    &environment.physics_pieces(),
                    configs.clone(),
                    *rcp,
                    &scenario.frontend.detection,
                    substream_key(seed, "maze-slam/physics"),
                    &geometry,
                );
                config
                    .images
                    .iter()
                    .zip(&set_names)
                    .map(|(e, name)| {
                        let images = match e {
                            AngleEstimate::MaxAngle => max.clone(),
                            AngleEstimate::ContactAngle => contact.clone(),
                        };
                        (name.clone(), images)
                    })
                    .collect()
            }
        };
        let mut rng = substream(seed, "maze-slam/odometry");
        let steps: Vec<(f64, f64)> = (0..truth_path.len())
            .map(|k| {
                let (d, t) = match k {
                    0 => (0.0, 0.0),
                    _ => {
                        let (p, q) = (truth_path[k], truth_path[k - 1]);
                        ((p.x - q.x).hypot(p.y - q.y), wrap(p.th - q.th))
                    }
                };
                config.odometry.apply(d, t, &mut rng)
            })
            .collect();
        if let Some(dir) = &o.out {
            crate::output::create_dir(dir)?;
            for (images_name, images) in &image_sets {
                crate::output::write_atomic(
                    &images::path(dir, images_name, seed),
                    images::to_csv(images).as_bytes(),
                )?;
            }
        }
        let variants: &[bool] = if kidnap { &[false, true] } else { &[false] };
        for &kidnapped in variants {
            let name = if kidnapped { "kidnapped" } else { "normal" };
            // The kidnapped data set is the normal one with a quarter circuit cut out: the
            // array jumps forward while odometry reports the ordinary step that follows.
            let cut = if kidnapped {
                path::kidnapping(&starts)
            } else {
                0..0
            };
            let truth: Vec<Sample> = without(&truth_path, &cut);
            let steps = without(&steps, &cut);
            for (images_name, images) in &image_sets {
                let images = without(images, &cut);
                for params in &tunings {
                    let run = Evaluation::of(*params, &images, &steps, &truth, starts[1] - 1);
                    if let Some(dir) = &o.out {
                        let mut tag = images_name.replace('/', "-");
                        if sweep {
                            let lv = params.local_view;
                            tag += &format!("-t{}-e{}", lv.match_threshold, lv.inject_energy);
                        }
                        crate::output::write_atomic(
                            &dir.join(format!("trajectory-{tag}-{name}-{seed}.csv")),
                            run.trajectory_csv(&truth).as_bytes(),
                        )?;
                    }
                    eprintln!("seed {seed} {name} {images_name}: {} updates", truth.len());
                    results.push(json!({
                        "seed": seed,
                        "variant": name,
                        "images": images_name,
                        "match_threshold": params.local_view.match_threshold,
                        "inject_energy": params.local_view.inject_energy,
                        "updates": truth.len(),
                        "templates": run.templates,
                        "experiences": run.experiences,
                        "arr": run.metric.arr,
                        "arcr": run.metric.arcr,
                        "relocalisations": run.metric.relocalisations,
                        "energy_metric": run.energy,
                    }));
                }
            }
        }
    }
    Ok(results)
}

/// Prints the runs: one JSON object, or a table.
fn report(results: &[serde_json::Value], as_json: bool) {
    if as_json {
        println!("{}", json!({ "runs": results }));
        return;
    }
    println!("Planar RatSLAM on the maze (§3.3)");
    println!(
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
    );
    for r in results {
        println!(
            "  {:>5} {:<10} {:<26} {:>6} {:>6} {:>7} {:>9} {:>11} {:>7.4} {:>7.4} {:>9.4}",
            r["seed"].as_u64().unwrap_or(0),
            r["variant"].as_str().unwrap_or(""),
            r["images"].as_str().unwrap_or(""),
            r["match_threshold"].as_f64().unwrap_or(f64::NAN),
            r["inject_energy"].as_f64().unwrap_or(f64::NAN),
            r["updates"].as_u64().unwrap_or(0),
            r["templates"].as_u64().unwrap_or(0),
            r["experiences"].as_u64().unwrap_or(0),
            r["arr"].as_f64().unwrap_or(f64::NAN),
            r["arcr"].as_f64().unwrap_or(f64::NAN),
            r["energy_metric"].as_f64().unwrap_or(f64::NAN),
        );
    }
}
