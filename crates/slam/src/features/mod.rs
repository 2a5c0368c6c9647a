//! Whisker-array features of one whisk (thesis §5.1.1.1): the point feature histogram of
//! the contact cloud ([`pfh`], §2.5.1.1), the slope distribution array ([`sda`],
//! §5.1.1.1.3), and the similarity measures and matching rule between observations
//! ([`similarity`], Eq 2.45, 5.3–5.5); both of one whisk together ([`whisk`]).

pub mod pfh;
pub mod sda;
pub mod similarity;
pub mod whisk;
