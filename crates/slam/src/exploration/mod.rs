//! Active exploration for fast shape recognition (thesis Chapter 6): the algorithms on
//! the map that choose where the array whisks next, free of any simulator, so that a real
//! robot could run them.
//!
//! - [`placement`]: the surface placement controller (SPC, §6.1.1, Alg 7–8);
//! - [`goal_mesh`]: the ellipsoid of map building (§6.1.3) and the sphere of the default
//!   trajectory (§6.1.3.2);
//! - [`feh`]: follow experience history (§6.1.2.2);
//! - [`lsr`]: least similar region (§6.1.2.3, Eq 6.1–6.3);
//! - [`tour`]: the goal meshes' faces visited in turn, and the steps between experiences
//!   cut into segments (§6.1.2.1–§6.1.3);
//! - [`odometry_noise`]: the simulations' odometry noise (§6.1.3.1.1, Eq 6.4–6.11).
//!
//! Recognition (raw and integrated confidence, SRT, IM) is in [`crate::recognition`].

pub mod feh;
pub mod goal_mesh;
pub mod lsr;
pub mod odometry_noise;
pub mod placement;
pub mod tour;
