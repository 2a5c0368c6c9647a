//! The whiskered mobile robot in the office (issue #36, thesis Fig 5.1, §7.1;
//! `docs/navigation.md`): the base's route and odometry ([`route`]), an independent
//! collision check of its footprint ([`footprint`]), terrain mode — planar RatSLAM on the
//! whisks of the array the arm holds beside the base ([`terrain`]) — the mode-switch cue on
//! the sensed whisks ([`plan_view`]), object mode at the cue's "object" and the landmarks
//! it gives the planar map ([`object_mode`]), the arm's posture ([`posture`]), closures
//! judged against the truth ([`closures`]), and the run's files ([`outputs`], [`figure`]).

pub mod closures;
pub mod dataset;
pub mod figure;
pub mod footprint;
pub mod navigator;
pub mod object_mode;
pub mod outputs;
pub mod plan_view;
pub mod posture;
pub mod replay;
pub mod route;
pub mod terrain;
