//! The closed loop of thesis Chapter 6: the robot decides where to whisk next, moves there
//! with the arm, whisks, runs WhiskerRatSLAM, updates its confidence in each known object
//! and either builds an object map (§6.1.3) or stops once it has recognised the object
//! (§6.2). This is a library API: `whisker run` with an `[explore]` section, the tests and
//! batch trials all call [`run`] ([`run_logged`]).
//!
//! One iteration (one whisk, one SLAM step):
//! 1. the goal: the surface placement controller's correction when the last region is not
//!    settled (SPC on, at most K per region), otherwise the strategy's next goal — the
//!    ellipsoid's next face (map building), the sphere's next face (default), or the next
//!    segment of a step to an experience (FEH, LSR);
//! 2. the arm: IK from the current joints, a joint move at the speed limit, checked for
//!    collisions; a goal that is unreachable or would touch the object is dropped (the
//!    arm stays; counted) and the strategy's next goal tried, up to 8 times;
//! 3. one whisk cycle at the reached pose: kinematic sensing with the §6.1.3.1.2 contact
//!    noise (sub-streams `kinematic/whisker/NN`), or physics whiskers through the signal
//!    front end (`state::Sensor`);
//! 4. odometry since the last whisk with the Eq 6.4–6.11 noise (sub-stream
//!    `explore/odometry`), features (PFH + SDA), one WhiskerRatSLAM step (Alg 2);
//! 5. recognition: a re-localisation into an experience of a loaded map feeds that
//!    object's raw confidence; IC integrates it (§6.2);
//! 6. the SPC's decision on this whisk's contacts (world points: the robot knows its own
//!    arm) and the strategy's bookkeeping (re-planning on re-localisation).
//!
//! Fallbacks, all counted in `summary.json`: `unreachable` and `collision` goals (dropped;
//! a face goal that would touch the object is first pushed back along its axis, 2 cm at a
//! time up to 10 cm: `pushed_back`),
//! `lost_contact` (a whisk with no contact: FEH/LSR give way to the default trajectory),
//! `spc_limit` (a region left unsettled after K adjustments).

pub mod dataset;
mod episode;
mod goal;
mod iteration;
mod log;
mod map_accuracy;
mod outputs;
mod placement;
pub mod robot;
mod session;
mod setup;
mod state;
mod strategy;
mod whisk_recording;

pub use crate::sensing::array::array_chain;
pub use episode::{Episode, LastWhisk, Refused};
pub use log::{CSV_NAME, SUMMARY_NAME};
pub use outputs::{describe, record_arm, write};
pub use session::{episode, run, run_knowing, run_logged, run_recorded};
pub use setup::sensor;
pub use state::{Outcome, Sensor};
