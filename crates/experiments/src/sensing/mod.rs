//! How the experiments sense: the sensing runs that the scripted run, the closed loop,
//! datasets and benches share.
//!
//! - [`array`]: the scenario's array on its arm (its description, the chain placing it);
//! - [`contact`]: one whisk's contacts from any sensing — the physics contact pipeline
//!   (detect → radial distance → shaft point), the `contacts.csv` rows, the anticipated
//!   intersect for the recordings;
//! - [`sweep`]: the kinematic sweep along a run (`contacts.csv`, `anticipated.csv`);
//! - [`detection`]: the detection levels every physics path uses, per whisker;
//! - [`fidelity`]: the physics front end against the anticipated contacts;
//! - [`frontend`]: the signal front end along a physics run (`frontend.csv`);
//! - [`array_run`]: the physics array along a run (`whiskers.csv`), and
//!   [`whisking_metrics`], what its whisking strategy did to its contacts;
//! - [`held`]: the physics array held still for one whisk at each pose (object walks, the
//!   closed loop, physics datasets).

pub mod array;
pub mod array_run;
pub mod contact;
pub mod detection;
pub mod fidelity;
pub mod frontend;
pub mod held;
pub mod sweep;
pub mod whisking_metrics;
