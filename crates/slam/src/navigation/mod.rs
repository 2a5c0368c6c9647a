//! Navigation by walls and recognised objects (thesis Fig 5.1, §7.1): what a whiskered
//! mobile robot needs beyond planar RatSLAM (Ch 3) and the object closed loop (Ch 6) to
//! combine them — the cue that switches between terrain and object exploration
//! ([`mode_switch`]), the odometry of a wheeled base ([`base_odometry`]) and the error
//! of a map whose frame is arbitrary ([`map_error`]).

pub mod base_odometry;
pub mod map_error;
pub mod mode_switch;
