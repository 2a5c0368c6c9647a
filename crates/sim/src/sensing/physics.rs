//! Physics sensing: the whisker array simulated in Rapier at the sensors' 2 kHz.
//!
//! Each whisker lives in a Rapier world of its own that holds the fixed environment
//! (whiskers never touch each other or the arm, so nothing couples them): worlds step
//! in parallel and each one's result depends only on its own inputs, so the streams are
//! bit-identical whatever the number of threads (Rapier's `enhanced-determinism`).
//! Every step the whisker's driver is posed at the array's pose × the module pose × the
//! commanded whisk angle, the world steps by dt, and the sensors read the follicle; the
//! controller sees each reading before the next command (RCP).
//!
//! Contact settings (docs/physics.md): stiff contacts (30 kHz natural
//! frequency, critically damped) so that mg-scale segments do not sink into surfaces,
//! no contact recycling, a length unit of 1 cm, which sets the allowed penetration to
//! 10 µm, penetration corrected at up to 1 m/s, and contacts predicted 0.5 mm ahead.

use super::adaptive_step;
use super::schedule::Balancer;
use crate::environment::solids::Solids;
use crate::sensing::kinematic::RigidWhisker;
use crate::whisker::array::Module;
use crate::whisker::beam::Bending;
use crate::whisker::body::{RootDrive, Whisker};
use crate::whisker::control::{ControlState, Controller, WhiskingPattern};
use crate::whisker::follicle::FollicleDesign;
use crate::whisker::sensor::SensorModel;
pub use crate::whisker::solver::{Lever, SolverPath};
use crate::whisker::strategies::{ArrayController, WhiskingControl};
use nalgebra::Isometry3;
use rapier3d_f64::counters::{Counters, Timer};
use rapier3d_f64::prelude::*;
use rayon::prelude::*;
use whisker_slam::rng::{self, StreamRng};
use whisker_slam::sensor::{SAMPLE_RATE_HZ, Sample, WhiskCycle};

/// Interaction group of whisker shafts.
pub const WHISKER_GROUP: Group = Group::GROUP_3;

pub use crate::environment::EnvironmentPiece;

/// Everything that configures one whisker's simulation.
#[derive(Debug, Clone)]
pub struct WhiskerConfig {
    /// The module (geometry and shaft design).
    pub module: Module,
    /// The follicle (None: rigid).
    pub follicle: Option<FollicleDesign>,
    /// The whisking pattern.
    pub pattern: WhiskingPattern,
    /// Contact threshold on |y| (counts) for RCP and the array's strategies (None:
    /// contacts are not detected, whatever `control` says).
    pub contact_threshold: Option<f64>,
    /// The whisking strategies (§2.3.1); the array's must agree for every whisker.
    pub control: WhiskingControl,
    /// The sensors.
    pub sensor: SensorModel,
    /// Rapier substeps per 0.5 ms step (its `num_solver_iterations`).
    pub substeps: usize,
    /// Which of Rapier's multibody code paths steps the whisker.
    pub solver: SolverPath,
    /// One of the path's levers switched off, to measure it (None: the path as it is).
    pub without: Option<Lever>,
    /// Split a sample's step while a segment approaches a surface faster than the
    /// speculative contacts can catch ([`super::adaptive_step`]; default true). False:
    /// one world step per sample, as before (`whisker soak --fixed-steps`).
    pub adaptive_steps: bool,
}

/// The first `count` modules' configurations: default whiskers, follicle, 1 Hz open-loop
/// whisking and sensors, with the given bending model, segments and substeps (the array
/// of `whisker bench physics`, `whisker soak` and the tests).
pub fn standard_array(
    count: usize,
    bending: Bending,
    segments: Option<usize>,
    substeps: usize,
) -> Vec<WhiskerConfig> {
    crate::whisker::array::modules()
        .into_iter()
        .take(count)
        .map(|mut module| {
            module.beam.bending = bending;
            if let Some(n) = segments {
                module.beam.segments = n;
            }
            module
        })
        .map(|module| WhiskerConfig {
            substeps,
            ..WhiskerConfig::with_defaults(module)
        })
        .collect()
}

impl WhiskerConfig {
    /// `module` with the thesis' defaults: the default follicle, 40°–140° open-loop
    /// whisking at 1 Hz, no RCP, the default sensors and [`DEFAULT_SUBSTEPS`].
    pub fn with_defaults(module: Module) -> Self {
        Self {
            module,
            follicle: Some(FollicleDesign::default()),
            pattern: WhiskingPattern::default(),
            contact_threshold: None,
            control: WhiskingControl::default(),
            sensor: SensorModel::default(),
            substeps: DEFAULT_SUBSTEPS,
            solver: SolverPath::default(),
            without: None,
            adaptive_steps: true,
        }
    }

    /// The rigid, straight twin of this whisker for the kinematic sweep (the anticipated
    /// intersect): the same module, its shaft starting the follicle's pivot depth out.
    pub fn rigid(&self) -> RigidWhisker {
        RigidWhisker::new(
            self.module.clone(),
            self.follicle.map_or(0.0, |f| f.pivot_depth),
        )
    }
}

/// Default substeps per step: 3. Against a pole (100 mm whisker, contact peak 772
/// counts including the snap-off) 1, 2 and 4 substeps give the same onset sample and
/// peak, and streams within 3.7 counts RMS of each other, and each substep costs as much
/// as a whole step; but against meshes fewer are not enough: with 1, at the Barrel's hoop
/// creases whisker C2's tip goes through the surface after 1.6 s of whisking (12.6 mm
/// deep by 3 s, `whisker soak --objects barrel --substeps 1`); with 2, the Mug's whisker
/// E1, strongly bent over the handle, ends up 1.04 mm inside at 39.4 s
/// (`whisker soak --objects mug --whiskers E1 --substeps 2`); with 3 its centre line stays
/// outside for 60 s. (Substeps reuse the step's contacts, so they cannot stop a shaft
/// that snaps off the Mug's handle and flies into it faster than the speculative contacts
/// reach: that is what speed-adaptive steps are for, [`super::adaptive_step`].)
pub const DEFAULT_SUBSTEPS: usize = 3;

/// One whisker in its own world.
pub struct WhiskerUnit {
    /// Its configuration.
    pub config: WhiskerConfig,
    /// The Rapier world.
    pub world: PhysicsWorld,
    /// The whisker's bodies.
    pub whisker: Whisker,
    /// Its motor controller.
    pub controller: Controller,
    /// Rapier's stage timers summed over every step (zero unless built with the
    /// `profiler` feature).
    pub stages: StageTimes,
    pub(crate) rng: StreamRng,
    last: Sample,
    steps: u64,
    world_steps: u64,
}

/// Seconds spent in each stage of Rapier's steps, summed (from its `profiler` counters).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Whole steps.
    pub step: f64,
    /// Propagating user changes (the driver's new pose).
    pub user_changes: f64,
    /// Updating kinematics and dynamics of bodies.
    pub update: f64,
    /// Broad phase.
    pub broad_phase: f64,
    /// Narrow phase.
    pub narrow_phase: f64,
    /// Islands and solver structures.
    pub islands: f64,
    /// Solver: assembly (first substep's multibody mass matrices, constraints).
    pub velocity_assembly: f64,
    /// Solver: substeps (PGS, later substeps' multibody updates, integration).
    pub velocity_resolution: f64,
    /// The whole solver stage.
    pub solver: f64,
    /// Continuous collision detection.
    pub ccd: f64,
}

impl StageTimes {
    /// Adds the timers of Rapier's last step.
    pub fn add(&mut self, c: &Counters) {
        let s = |t: &Timer| t.time().as_secs_f64();
        self.step += s(&c.step_time);
        self.user_changes += s(&c.stages.user_changes);
        self.update += s(&c.stages.update_time);
        self.broad_phase += s(&c.cd.broad_phase_time);
        self.narrow_phase += s(&c.cd.narrow_phase_time);
        self.islands +=
            s(&c.stages.island_construction_time) + s(&c.stages.island_constraints_collection_time);
        self.velocity_assembly += s(&c.solver.velocity_assembly_time);
        self.velocity_resolution += s(&c.solver.velocity_resolution_time);
        self.solver += s(&c.stages.solver_time);
        self.ccd += s(&c.stages.ccd_time);
    }

    /// The sum of `self` and `other`.
    pub fn plus(self, o: StageTimes) -> StageTimes {
        StageTimes {
            step: self.step + o.step,
            user_changes: self.user_changes + o.user_changes,
            update: self.update + o.update,
            broad_phase: self.broad_phase + o.broad_phase,
            narrow_phase: self.narrow_phase + o.narrow_phase,
            islands: self.islands + o.islands,
            velocity_assembly: self.velocity_assembly + o.velocity_assembly,
            velocity_resolution: self.velocity_resolution + o.velocity_resolution,
            solver: self.solver + o.solver,
            ccd: self.ccd + o.ccd,
        }
    }
}

/// Applies the contact settings described in the module documentation.
pub fn contact_parameters(p: &mut IntegrationParameters, dt: f64) {
    p.dt = dt;
    p.length_unit = 0.01;
    p.contact_softness = SpringCoefficients::new(30000.0, 1.0);
    p.static_contact_softness = SpringCoefficients::new(30000.0, 1.0);
    p.contact_recycling = false;
    // Speculative contacts 0.5 mm ahead. A longer horizon (2 mm) made constraints of faces
    // the tip had not reached yet, and a strongly bent tip sliding over the Mug's handle
    // went through it (`whisker soak --objects mug --whiskers E1`: 1.7 mm deep at 2.4 s;
    // 8.4 s with 60 kHz contacts); at 0.5 mm the centre line stays outside (10 s, all
    // touching whiskers of the Mug and of the Barrel). Whisks at 10 Hz (tips at ~3 m/s,
    // 1.5 mm per step) still do not pass through (tests/whisking.rs).
    // (With the array nudged by nanometres, composite path: horizons of 1, 2 and 3 mm let
    // D1 through the Mug's handle in 3, 3 and 10 of 10 10-s runs, against 59 of 140 at
    // 0.5 mm (fixed steps); a longer horizon does not stop fast snaps, the speed-adaptive
    // steps of `adaptive_step` do.)
    p.normalized_prediction_distance = 0.05;
    // Penetration is corrected at up to 1 m/s. Rapier's default (3 length units/s, here
    // 3 cm/s) lets a whisker tip scraping along a surface sink ~1 mm into it within a
    // few whisks (`whisker soak`: 1.36 mm into the Box's mesh, 0.63 mm into a cuboid,
    // 2.7 mm into the Barrel); at 1 m/s the shaft's centre line stays within 0.12 mm.
    p.normalized_max_corrective_velocity = 100.0;
}

impl WhiskerUnit {
    /// A whisker in a world holding `environment`, its array frame at `array_pose`,
    /// stepping at `dt`, its sensor noise drawn from the sub-stream
    /// `"sensor/whisker/NN"` of `seed`.
    pub fn new(
        config: WhiskerConfig,
        environment: &[EnvironmentPiece],
        array_pose: &Isometry3<f64>,
        seed: u64,
        dt: f64,
    ) -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        contact_parameters(&mut world.integration_parameters, dt);
        world.integration_parameters.num_solver_iterations = config.substeps.max(1);
        config
            .solver
            .apply_without(&mut world.integration_parameters, config.without);
        for (shape, pose) in environment {
            world.insert_collider(
                ColliderBuilder::new(shape.clone())
                    .position((*pose).into())
                    .collision_groups(InteractionGroups::new(
                        Group::GROUP_2,
                        Group::ALL,
                        InteractionTestMode::And,
                    )),
                None,
            );
        }
        let controller = config
            .control
            .controller(config.pattern, config.contact_threshold);
        let theta = config.pattern.angle(0.0);
        let pose = array_pose * config.module.whisker_pose(theta);
        let groups =
            InteractionGroups::new(WHISKER_GROUP, Group::GROUP_2, InteractionTestMode::And);
        let whisker = Whisker::build(
            &mut world,
            pose,
            config.module.beam,
            config.follicle,
            groups,
            match config.solver.uses(Lever::DrivenRoot, config.without) {
                true => RootDrive::Driven,
                false => RootDrive::Welded,
            },
        );
        let rng = rng::substream(seed, &format!("sensor/whisker/{:02}", config.module.index));
        Self {
            config,
            world,
            whisker,
            controller,
            stages: StageTimes::default(),
            rng,
            last: Sample {
                angle_rad: theta,
                ..Sample::default()
            },
            steps: 0,
            world_steps: 0,
        }
    }

    /// Samples stepped so far, and the world steps they took (more than one per sample
    /// where speed-adaptive steps split it).
    pub fn steps(&self) -> (u64, u64) {
        (self.steps, self.world_steps)
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.world.integration_parameters.dt
    }

    /// Advances one step with the array frame at `array_pose` at the step's end, and
    /// returns the sensors' reading.
    pub fn step(&mut self, array_pose: &Isometry3<f64>) -> Sample {
        let t = (self.steps + 1) as f64 * self.world.integration_parameters.dt;
        let theta = self.controller.command(t, self.last.y);
        let pose = array_pose * self.config.module.whisker_pose(theta);
        let dt = self.world.integration_parameters.dt;
        let mut left = dt;
        let from = Whisker::pose(&self.world, self.whisker.driver);
        while left > 0.0 {
            let h = match self.config.adaptive_steps {
                true => adaptive_step::next_step(&self.world, &self.whisker, left, dt),
                false => left,
            };
            if h == dt {
                // The whole sample in one world step (bit for bit the fixed step).
                self.whisker.drive(&mut self.world, pose);
            } else {
                let f = (1.0 - (left - h) / dt).min(1.0);
                self.world.integration_parameters.dt = h;
                self.whisker
                    .drive(&mut self.world, from.lerp_slerp(&pose, f));
            }
            self.world.step();
            self.world_steps += 1;
            self.world.integration_parameters.dt = dt;
            self.stages.add(&self.world.physics_pipeline.counters);
            left = if h >= left { 0.0 } else { left - h };
        }
        self.steps += 1;
        let magnet = self.whisker.magnet_displacement(&self.world);
        self.last = self.config.sensor.read(theta, magnet, &mut self.rng);
        self.last
    }

    /// The shaft's centre line after the last step: the points at every segment boundary
    /// from base to tip (world, m), for drawing.
    pub fn shaft(&self) -> Vec<[f64; 3]> {
        let beam = &self.whisker.beam;
        let l = beam.segment_length();
        (0..=beam.segments)
            .map(|k| {
                let p = self
                    .whisker
                    .point_at(&self.world, (k as f64 * l).min(beam.length));
                [p.x, p.y, p.z]
            })
            .collect()
    }

    /// Whether the controller is retracting early (RCP fired, §3.2.2).
    pub fn rcp_active(&self) -> bool {
        self.controller.retracting_early()
    }

    /// The whisking strategies' state after the last step.
    pub fn control_state(&self) -> ControlState {
        self.controller.state()
    }

    /// Whether any body of the world holds a non-finite value or was quarantined.
    pub fn is_broken(&self) -> bool {
        !self.world.quarantine().is_empty()
            || self.whisker.segments.iter().any(|&h| {
                let p = self.world.bodies[h].translation();
                !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite())
            })
    }

    /// How deep the shaft's centre line lies inside the environment's `solids` (m, ≥ 0),
    /// checked at every half segment from base to tip: the shaft surface may touch and
    /// overlap by the contact tolerance, but a centre line inside a solid by more than the
    /// shaft's radius means the whisker has gone through the surface (tunnelled).
    pub fn shaft_depth(&self, solids: &Solids) -> f64 {
        let beam = &self.whisker.beam;
        let half = beam.segment_length() / 2.0;
        (0..=2 * beam.segments)
            .map(|k| {
                let p = self
                    .whisker
                    .point_at(&self.world, (k as f64 * half).min(beam.length));
                solids.depth(&p)
            })
            .fold(0.0, f64::max)
    }

    /// Deepest penetration of the shaft into the environment after the last step (m, ≥ 0).
    pub fn penetration(&self) -> f64 {
        let mut deepest: f64 = 0.0;
        for &seg in &self.whisker.segments {
            for &c in self.world.bodies[seg].colliders() {
                for pair in self.world.narrow_phase.contact_pairs_with(c) {
                    if let Some((_, contact)) = pair.find_deepest_contact() {
                        deepest = deepest.max(-contact.dist);
                    }
                }
            }
        }
        deepest
    }
}

/// The whole array: one [`WhiskerUnit`] per module, stepped in parallel.
pub struct PhysicsArray {
    /// The whiskers, in module order.
    pub units: Vec<WhiskerUnit>,
    /// The strategies that couple the whiskers (spread reduction, contact-induced
    /// asymmetry), if any: then every sample's contacts reach every controller before the
    /// next.
    coupling: Option<ArrayController>,
    /// Orders the whiskers' tasks by cost ([`Balancer`]).
    balancer: Balancer,
}

impl PhysicsArray {
    /// Builds every whisker of `configs` in its own world (see [`WhiskerUnit::new`]).
    pub fn new(
        configs: Vec<WhiskerConfig>,
        environment: &[EnvironmentPiece],
        array_pose: &Isometry3<f64>,
        seed: u64,
        dt: f64,
    ) -> Self {
        let coupling = configs
            .first()
            .filter(|c| c.control.couples())
            .map(|first| {
                let columns: Vec<usize> = configs.iter().map(|c| c.module.column).collect();
                ArrayController::new(first.control, &columns, first.pattern, dt)
            });
        // The balancer is a lever of the path (as the whiskers are built alike, the first
        // one's path stands for all).
        let balancer = Balancer::new(
            configs
                .first()
                .is_none_or(|c| c.solver.uses(Lever::LoadBalance, c.without)),
        );
        let units = configs
            .into_par_iter()
            .map(|c| WhiskerUnit::new(c, environment, array_pose, seed, dt))
            .collect();
        Self {
            units,
            coupling,
            balancer,
        }
    }

    /// Advances every whisker one step; one sample per whisker, in module order.
    pub fn step(&mut self, array_pose: &Isometry3<f64>) -> Vec<Sample> {
        let samples: Vec<Sample> = self
            .units
            .par_iter_mut()
            .map(|u| u.step(array_pose))
            .collect();
        if let Some(coupling) = &mut self.coupling {
            let t = self.units[0].time();
            let contacts: Vec<bool> = self
                .units
                .iter()
                .zip(&samples)
                .map(|(u, s)| u.controller.in_contact(s.y))
                .collect();
            let mut controllers: Vec<&mut Controller> =
                self.units.iter_mut().map(|u| &mut u.controller).collect();
            coupling.update(t, &contacts, &mut controllers);
        }
        samples
    }

    /// Advances every whisker one step per pose of `poses`, the array frame at `poses[k]`
    /// at the end of step k; per whisker (module order), its samples.
    ///
    /// Each whisker runs a chunk of steps in one task, the dearest whiskers first
    /// ([`Balancer`]): the whiskers share nothing (RCP is per whisker and the poses are
    /// known in advance), so the samples are the same as from one [`Self::step`] per
    /// pose, without a barrier per sample (§2 L6 of the physics-speed note: a whisker in
    /// contact costs many times a free one) — unless a
    /// strategy couples the whiskers (spread reduction, asymmetry): then one
    /// [`Self::step`] per pose.
    pub fn run(&mut self, poses: &[Isometry3<f64>]) -> Vec<Vec<Sample>> {
        self.run_each(poses, |_, s| s)
    }

    /// As [`Self::run`], each sample with the whisker's strategies' state after its step
    /// ([`WhiskerUnit::control_state`]).
    pub fn run_with_state(&mut self, poses: &[Isometry3<f64>]) -> Vec<Vec<(Sample, ControlState)>> {
        self.run_each(poses, |u, s| (s, u.control_state()))
    }

    /// As [`Self::run`], keeping `keep(unit, sample)` after every step instead of the
    /// sample alone.
    pub fn run_keeping<T: Send>(
        &mut self,
        poses: &[Isometry3<f64>],
        keep: impl Fn(&WhiskerUnit, Sample) -> T + Sync,
    ) -> Vec<Vec<T>> {
        self.run_each(poses, keep)
    }

    /// Steps every whisker through `poses` in one task each per chunk of steps, the
    /// dearest first ([`Balancer`]), keeping `keep(unit, sample)` after every step; with
    /// coupling strategies, all whiskers a sample at a time ([`Self::step`]).
    fn run_each<T: Send>(
        &mut self,
        poses: &[Isometry3<f64>],
        keep: impl Fn(&WhiskerUnit, Sample) -> T + Sync,
    ) -> Vec<Vec<T>> {
        if self.coupling.is_some() {
            let mut out: Vec<Vec<T>> = self
                .units
                .iter()
                .map(|_| Vec::with_capacity(poses.len()))
                .collect();
            for pose in poses {
                let samples = self.step(pose);
                for ((o, u), s) in out.iter_mut().zip(&self.units).zip(samples) {
                    o.push(keep(u, s));
                }
            }
            return out;
        }
        self.balancer.run(&mut self.units, poses.len(), |u, k| {
            let s = u.step(&poses[k]);
            keep(u, s)
        })
    }

    /// Simulates one whisk cycle of the first whisker's pattern (1/f seconds; the
    /// array's whiskers share a frequency by default) with the array frame at
    /// `array_pose(t)` at time t, and returns it as a [`WhiskCycle`] numbered `index`
    /// (empty, with nothing simulated, for an array of no whiskers).
    pub fn whisk(&mut self, index: u64, array_pose: impl Fn(f64) -> Isometry3<f64>) -> WhiskCycle {
        if self.units.is_empty() {
            return WhiskCycle {
                index,
                start_s: 0.0,
                rate_hz: SAMPLE_RATE_HZ,
                samples: Vec::new(),
            };
        }
        let dt = self.units[0].world.integration_parameters.dt;
        let start_s = self.units[0].time() + dt;
        let n = (1.0 / (self.units[0].config.pattern.frequency * dt)).round() as usize;
        let poses: Vec<_> = (0..n)
            .map(|i| array_pose(start_s + i as f64 * dt))
            .collect();
        let samples = self.run(&poses);
        WhiskCycle {
            index,
            start_s,
            rate_hz: 1.0 / dt,
            samples,
        }
    }
}

/// The sensors' step (s): one Rapier step per 2 kHz sample.
pub const DT: f64 = 1.0 / SAMPLE_RATE_HZ;
