//! The whiskered mobile robot in the office (issue #36, thesis Fig 5.1, §7.1;
//! `docs/navigation.md`): the base's route and odometry ([`route`]) and an independent
//! collision check of its footprint ([`footprint`]). The terrain and object modes, the
//! switch between them and the evaluation are built on these next.

pub mod figure;
pub mod footprint;
pub mod outputs;
pub mod plan_view;
pub mod route;
pub mod terrain;
