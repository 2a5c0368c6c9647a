//! WhiskerRatSLAM (thesis Chapter 5): RatSLAM in six dimensions for tactile object
//! exploration — 6-D pose cells ([`posecells6d`]), relative pose accumulation
//! ([`relative_pose`]), the object map of complex experiences ([`object_map`]) and the
//! main loop of Alg 2 ([`slam`]); the §5.2 walks' odometry and its errors
//! ([`walk_odometry`]).

pub mod object_map;
pub mod posecells6d;
pub mod relative_pose;
pub mod slam;
pub mod walk_odometry;
