//! Sensing modes: how whisker readings are produced from a world.
//!
//! - [`physics`]: Rapier simulates every whisker's compliant beam, follicle and motor.
//! - [`kinematic`]: rigid straight whiskers swept against the environment's meshes
//!   (anticipated intersect, §4.1.2.3), with the contact noise of [`noise`].
//! - [`calibration`]: contact thresholds from free whisking (§3.2.2).
//! - [`schedule`] balances the physics array's whiskers on the worker threads.
//! - [`viewpoints`] picks array poses near an object (benchmarks, soak runs, tests).

pub mod adaptive_step;
pub mod calibration;
pub mod kinematic;
pub mod noise;
pub mod physics;
pub mod schedule;
pub mod viewpoints;
