//! The sensor data model: what the whisker array reports, in simulation and on hardware
//! (thesis §2.2.2, §3.1.3).
//!
//! Each whisker module reports, at 2 kHz, its whisk angle θ and the two components of
//! the Hall-effect deflection reading at the follicle: `y`, parallel to the sweep, and
//! `x`, perpendicular to it (Fig 2.7). Deflections are in ADC counts (the sensor's raw
//! unit, as logged by the hardware); the whisk angle in radians, 40°–140° from the
//! module's base plane (Fig 2.8). A positive `y` is the reading of a shaft pushed back
//! against its protraction (what a contact during protraction gives).
//!
//! The simulator (`whisker-sim`) fills these types; converted hardware logs fill the
//! same ones.

/// Sampling rate of the array's sensors (Hz), §2.2.2.
pub const SAMPLE_RATE_HZ: f64 = 2000.0;

/// Number of whiskers in the array (3 rings of 6, §2.2.2).
pub const WHISKERS: usize = 18;

/// One sample of one whisker's sensors.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Whisk angle (rad), measured from the module's base plane.
    pub angle_rad: f64,
    /// Deflection perpendicular to the sweep (ADC counts).
    pub x: f64,
    /// Deflection parallel to the sweep (ADC counts).
    pub y: f64,
}

/// The samples of every whisker over one whisk cycle (retraction to retraction).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WhiskCycle {
    /// Index of the cycle since the start of the recording.
    pub index: u64,
    /// Time of the cycle's first sample (s).
    pub start_s: f64,
    /// Sampling rate (Hz).
    pub rate_hz: f64,
    /// `samples[w]` holds whisker `w`'s samples in time order; all of equal length.
    pub samples: Vec<Vec<Sample>>,
}

impl WhiskCycle {
    /// Number of samples per whisker.
    pub fn len(&self) -> usize {
        self.samples.first().map_or(0, Vec::len)
    }

    /// Whether the cycle holds no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Time of sample `i` (s).
    pub fn time(&self, i: usize) -> f64 {
        self.start_s + i as f64 / self.rate_hz
    }
}
