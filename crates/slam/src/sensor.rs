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

/// Self-motion over one interval (thesis Eq 5.7): o = [v, ω, Δt], with the translational
/// velocity `v` (m/s) and the angular velocity `ω` as a rotation vector (rad/s, axis ×
/// rate), both in the body (array) frame at the interval's start.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Odometry {
    /// Translational velocity (m/s, body frame).
    pub v: [f64; 3],
    /// Angular velocity, a rotation vector (rad/s, body frame).
    pub omega: [f64; 3],
    /// Duration (s).
    pub dt: f64,
}

impl Odometry {
    /// The exact odometry of moving from pose `a` to pose `b` in `dt`: the motion
    /// a⁻¹·b expressed as a velocity in a's frame and a constant body rotation rate.
    pub fn between(a: &nalgebra::Isometry3<f64>, b: &nalgebra::Isometry3<f64>, dt: f64) -> Self {
        let d = a.inverse() * b;
        let v = d.translation.vector / dt;
        let w = d.rotation.scaled_axis() / dt;
        Self {
            v: [v.x, v.y, v.z],
            omega: [w.x, w.y, w.z],
            dt,
        }
    }

    /// The translation over the interval (m, body frame).
    pub fn translation(&self) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::from(self.v) * self.dt
    }

    /// The rotation vector over the interval (rad, body frame).
    pub fn rotation(&self) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::from(self.omega) * self.dt
    }
}
