//! The signal front end (thesis Chapter 4, §5.1.1.1): from one whisk cycle's 2 kHz
//! angle and deflection streams to contacts — smoothing ([`smoothing`]), `findpeaks`
//! ([`peaks`]), contact onset/offset and angles ([`contact`]), contact features and slope
//! ([`features`]), and contact localisation ([`localise`]).

pub mod contact;
pub mod features;
pub mod localise;
pub mod peaks;
pub mod smoothing;
