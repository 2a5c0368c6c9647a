//! `whisker maze-slam`: planar RatSLAM on the maze with tactile images (thesis Ch 3,
//! §3.1–§3.3), kinematic (default) or physics sensing.
//!
//! The array, facing down, is carried in a plane over the maze of a scenario (its
//! `[maze]`, e.g. `scenarios/maze.toml`) around the loop through the scenario's pose
//! waypoints (their positions; the first is repeated at the end), turning about its own
//! axis to face the direction of travel, like the thesis' path of Fig 3.3: 3 clockwise
//! circuits, 3 anticlockwise, then one of each. It moves one pose-cell size (15 mm) per
//! 1.5 Hz update (§3.1.2, §3.2.1) and turns at the corners 10° per update. Each update
//! the rigid whiskers are swept (the anticipated intersect; the scenario's `[kinematic]`
//! detection probability applies) and the tactile image is made from the contact angles:
//! pixel intensity 255 × the height above the board of the shaft's tip at the contact
//! angle (forward kinematics), over the array's height (§3.1.1). Odometry is the true
//! turn and distance with the error model of §3.1.2 (sub-stream
//! `maze-slam/<variant>/odometry` of the seed).
//!
//! `--kidnap` skips the array forward along the path by a quarter circuit at the start of
//! the 4th circuit while odometry reports an ordinary step (§3.3.1). Reported: ARR and ARCR
//! (Algorithm 1, base set = the first circuit, thresholds 0.1 m and 25°) and the Energy
//! Metric (Eq 3.2 on consecutive updates, each update's estimate being the final relaxed
//! map's pose of the experience current then). `--out` writes `trajectory.csv`.
//!
//! `--sensing physics` makes the images from Rapier whiskers through the front end
//! ([`physics`]), open loop or `--rcp`, by both `max_angle` and `contact_angle` (§3.3.3–
//! §3.3.4); every run is then reported for both, on the same odometry draws.

use crate::error::{CliError, CliResult};
use crate::object_slam::SensingArg;
use crate::scenario::Scenario;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde_json::json;
use std::f64::consts::PI;
use std::path::PathBuf;
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::whisker::array;
use whisker_sim::whisker::control::WhiskingPattern;
use whisker_slam::ratslam::experience_map::{Pose2, wrap};
use whisker_slam::ratslam::local_view::TactileImage;
use whisker_slam::ratslam::metrics::{
    ExperienceMetric, consecutive, energy_metric, experience_metric,
};
use whisker_slam::ratslam::odometry::OdometryNoise;
use whisker_slam::ratslam::{RatSlam, RatSlamParams};
use whisker_slam::rng::{substream, substream_key};

pub mod physics;

/// Options of `whisker maze-slam`.
#[derive(clap::Args, Debug)]
pub struct Options {
    /// Scenario with a `[maze]` and pose waypoints (the loop's corners).
    #[arg(default_value = "scenarios/maze.toml")]
    pub scenario: PathBuf,
    /// Seeds (comma-separated): one run per seed.
    #[arg(long, value_delimiter = ',', default_value = "0")]
    pub seeds: Vec<u64>,
    /// Also run the kidnapped variant of every seed (§3.3.1).
    #[arg(long)]
    pub kidnap: bool,
    /// Local-view matching threshold (Eq 3.1); tuned on seed 0 as the thesis tuned on its
    /// first run (§3.2.1). Several (comma-separated) run RatSLAM once per value on the same
    /// images and odometry — a tuning sweep at the cost of one physics run.
    #[arg(long, value_delimiter = ',', default_value = "10")]
    pub match_threshold: Vec<f64>,
    /// Pose-cell injection energy (Eq 5.8); several as for `--match-threshold`.
    #[arg(long, value_delimiter = ',', default_value = "0.1")]
    pub inject_energy: Vec<f64>,
    /// Directory for `trajectory-<variant>-<seed>.csv`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// How tactile images are made: the kinematic sweep's contact angles, or physics
    /// whiskers through the front end (both `max_angle` and `contact_angle` images).
    #[arg(long, value_enum, default_value_t = crate::object_slam::SensingArg::Kinematic)]
    pub sensing: crate::object_slam::SensingArg,
    /// Physics: whisk with RCP (threshold 20 × the free-whisking σ, §3.2.2) instead of
    /// open loop.
    #[arg(long)]
    pub rcp: bool,
    /// Physics: shaft joint model.
    #[arg(long, value_enum, default_value_t = crate::characterize::BendingArg::Spatial)]
    pub bending: crate::characterize::BendingArg,
    /// Physics: segments per whisker [default: the array's].
    #[arg(long)]
    pub segments: Option<usize>,
    /// Physics: Rapier substeps per 0.5 ms step.
    #[arg(long, default_value_t = whisker_sim::sensing::physics::DEFAULT_SUBSTEPS)]
    pub substeps: usize,
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
/// probability applies; sub-stream `maze-slam/<variant>/sensing`).
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

/// Pose-cell size and distance per update (m), and turn per update at corners (rad).
const STEP_M: f64 = 0.015;
const TURN_RAD: f64 = 10.0 * PI / 180.0;

/// A planar path sample: position (world x, y) and heading.
pub type Sample = Pose2;

/// One circuit of the loop through `corners` (closed), in their order or reversed,
/// starting at the first corner facing along the first edge: a turn to each edge's
/// heading in 10° updates, then the edge in 15 mm updates.
fn circuit(corners: &[(f64, f64)], reverse: bool, from: &mut Sample) -> Vec<Sample> {
    let mut c: Vec<(f64, f64)> = corners.to_vec();
    if reverse {
        c.reverse();
        c.rotate_right(1);
    }
    c.push(c[0]);
    let mut out = Vec::new();
    for w in c.windows(2) {
        let (a, b) = (w[0], w[1]);
        let heading = (b.1 - a.1).atan2(b.0 - a.0);
        let mut turn = wrap(heading - from.th);
        while turn.abs() > 1e-9 {
            let d = turn.clamp(-TURN_RAD, TURN_RAD);
            from.th = wrap(from.th + d);
            turn -= d;
            out.push(*from);
        }
        let length = (b.0 - a.0).hypot(b.1 - a.1);
        let n = (length / STEP_M).round() as usize;
        for k in 1..=n {
            let s = k as f64 / n as f64;
            from.x = a.0 + s * (b.0 - a.0);
            from.y = a.1 + s * (b.1 - a.1);
            out.push(*from);
        }
    }
    out
}

/// The whole run: 3 clockwise circuits, 3 anticlockwise, one of each (§3.2); the index
/// where each circuit starts.
fn path(corners: &[(f64, f64)]) -> (Vec<Sample>, Vec<usize>) {
    let (x, y) = corners[0];
    let mut at = Sample { x, y, th: 0.0 };
    let mut out = vec![at];
    let mut starts = Vec::new();
    for reverse in [false, false, false, true, true, true, false, true] {
        starts.push(out.len());
        out.extend(circuit(corners, reverse, &mut at));
    }
    (out, starts)
}

/// One RatSLAM run over a sequence of images and odometry, and its metrics.
struct Evaluation {
    /// The current experience after each update.
    log: Vec<usize>,
    /// Each update's estimate: the final relaxed map's pose of the experience current
    /// then, in the frame of the first true pose.
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
        let first = truth[0];
        let (s, c) = first.th.sin_cos();
        let estimate: Vec<Pose2> = log
            .iter()
            .map(|&e| {
                let m = slam.map.experiences[e].pose;
                Pose2 {
                    x: first.x + c * m.x - s * m.y,
                    y: first.y + s * m.x + c * m.y,
                    th: wrap(first.th + m.th),
                }
            })
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

/// `whisker maze-slam`.
pub fn run(o: &Options) -> CliResult {
    let scenario = Scenario::load(&o.scenario)?;
    let file = &o.scenario;
    let maze = scenario
        .maze
        .as_ref()
        .ok_or_else(|| CliError::field(file, "maze", "maze-slam needs a [maze] section"))?;
    let corners: Vec<(f64, f64, f64, f64)> = scenario
        .trajectory
        .waypoints
        .iter()
        .filter_map(|w| Some((w.position_m?, w.rpy_deg?)))
        .map(|(p, r)| (p[0], p[1], p[2], r[2]))
        .collect();
    if corners.len() < 3 {
        return Err(CliError::field(
            file,
            "trajectory.waypoints",
            "maze-slam needs at least 3 pose waypoints (the loop's corners)",
        ));
    }
    let mut loop_corners: Vec<(f64, f64)> = corners.iter().map(|c| (c.0, c.1)).collect();
    if loop_corners.len() > 3 && loop_corners.first() == loop_corners.last() {
        loop_corners.pop();
    }
    let (plane_z, yaw0) = (corners[0].2, corners[0].3.to_radians());
    let environment = scenario.environment(file)?.environment;
    let board_z = maze.position_m[2];
    let target = SweepTarget::new(environment.world_mesh());
    let noise = scenario.kinematic.noise(file)?;
    let (truth_path, starts) = path(&loop_corners);
    if let Some(bad) = o
        .match_threshold
        .iter()
        .chain(&o.inject_energy)
        .find(|v| !(v.is_finite() && **v > 0.0))
    {
        return Err(CliError::Input(format!(
            "--match-threshold / --inject-energy: expected positive numbers, got {bad}"
        )));
    }
    let mut tunings = Vec::new();
    for &threshold in &o.match_threshold {
        for &energy in &o.inject_energy {
            let mut p = RatSlamParams::default();
            p.local_view.match_threshold = threshold;
            p.local_view.inject_energy = energy;
            tunings.push(p);
        }
    }
    let sweep = tunings.len() > 1;
    if o.kidnap && o.sensing == SensingArg::Physics {
        return Err(CliError::Input(
            "--kidnap: only with --sensing kinematic (a physics array cannot jump)".into(),
        ));
    }
    let geometry = Geometry {
        plane_z,
        board_z,
        yaw0,
    };
    let variants: Vec<bool> = if o.kidnap {
        vec![false, true]
    } else {
        vec![false]
    };
    let mut results = Vec::new();
    for &seed in &o.seeds {
        for &kidnapped in &variants {
            let name = if kidnapped { "kidnapped" } else { "normal" };
            // The kidnapped run skips a quarter circuit at the start of circuit 4.
            let mut truth: Vec<Sample> = truth_path.clone();
            let mut jump = None;
            if kidnapped {
                let skip = (starts[4] - starts[3]) / 4;
                truth.drain(starts[3]..starts[3] + skip);
                jump = Some(starts[3]);
            }
            let image_sets: Vec<(String, Vec<TactileImage>)> = match o.sensing {
                SensingArg::Kinematic => {
                    let key = substream_key(seed, &format!("maze-slam/{name}/sensing"));
                    vec![(
                        "kinematic".into(),
                        kinematic_images(&truth, &target, noise, key, &geometry),
                    )]
                }
                SensingArg::Physics => {
                    let configs = crate::bench::array_configs(
                        array::modules().len(),
                        o.bending.into(),
                        o.segments,
                        o.substeps,
                    );
                    let control = if o.rcp { "rcp" } else { "open-loop" };
                    let (max, contact) = physics::images(
                        &truth,
                        &environment.physics_pieces(),
                        configs,
                        o.rcp,
                        substream_key(seed, &format!("maze-slam/{name}/physics")),
                        &geometry,
                    );
                    vec![
                        (format!("{control}/max_angle"), max),
                        (format!("{control}/contact_angle"), contact),
                    ]
                }
            };
            let odometry = OdometryNoise::default();
            let mut rng = substream(seed, &format!("maze-slam/{name}/odometry"));
            let steps: Vec<(f64, f64)> = (0..truth.len())
                .map(|k| {
                    let (d, t) = if k == 0 {
                        (0.0, 0.0)
                    } else if Some(k) == jump {
                        // Kidnapped: odometry reports an ordinary step forward.
                        (STEP_M, 0.0)
                    } else {
                        let (p, q) = (truth[k], truth[k - 1]);
                        ((p.x - q.x).hypot(p.y - q.y), wrap(p.th - q.th))
                    };
                    odometry.apply(d, t, &mut rng)
                })
                .collect();
            for (images_name, images) in &image_sets {
                for params in &tunings {
                    let run = Evaluation::of(*params, images, &steps, &truth, starts[1] - 1);
                    if let Some(dir) = &o.out {
                        let mut tag = images_name.replace('/', "-");
                        if sweep {
                            let lv = params.local_view;
                            tag += &format!("-t{}-e{}", lv.match_threshold, lv.inject_energy);
                        }
                        crate::output::create_dir(dir)?;
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
    if o.json {
        println!("{}", json!({ "runs": results }));
    } else {
        println!("Planar RatSLAM on the maze (§3.3)");
        println!(
            "  {:>5} {:<10} {:<24} {:>6} {:>6} {:>7} {:>9} {:>11} {:>7} {:>7} {:>9}",
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
        for r in &results {
            println!(
                "  {:>5} {:<10} {:<24} {:>6} {:>6} {:>7} {:>9} {:>11} {:>7.4} {:>7.4} {:>9.4}",
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
    Ok(())
}
