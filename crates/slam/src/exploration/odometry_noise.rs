//! The odometry noise of the Chapter 6 simulations (thesis §6.1.3.1.1, Eq 6.4–6.11): the
//! true relative motion between two whisks is turned into a noisy odometry reading
//! o_η = [v_η, ω_η, Δt] for WhiskerRatSLAM.
//!
//! ```text
//! T   = T_{i−1}⁻¹·T_i                        (6.4)  true relative motion, body frame
//! ω   ~ N(ω̄, σ_ω)                                   a rotation speed (drawn again if ≤ 0)
//! R_η = eul2rotm(N(0, σ_r) ×3)  (ZYX)               rotation noise
//! R_n = R·R_η = rot(e_η, θ_η)                 (6.5–6.6)
//! ω_η = ω·e_η,  Δt = θ_η/ω                    (6.7–6.8)
//! |δ_η| = |δ| + η, η ~ N(0, σ_t),  δ_η = δ/|δ|·|δ_η|     (6.9)
//! v_η = δ_η/Δt                                (6.10)
//! ```
//! so that ω_η·Δt = θ_η·e_η and v_η·Δt = δ_η. Readings of the gaps (Eq 6.4–6.11 give no
//! units or order): ω is in rad/s and 0.0087 its standard
//! deviation; the Euler order is MATLAB's default ZYX; a motion with |δ| ≈ 0 gives δ_η = 0;
//! a negative |δ_η| flips the direction (the equation as written); a rotation θ_η ≈ 0 gives
//! Δt = 1 s and ω_η = 0. Draws are made in a fixed order (ω, the three Euler angles z, y,
//! x, then η) from the caller's stream.

use crate::invalid::Invalid;
use crate::rng::gauss;
use crate::sensor::Odometry;
use nalgebra::{Isometry3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};

/// The Eq 6.4–6.11 noise model's parameters (the thesis' values by default).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OdometryNoise {
    /// Mean rotation speed ω̄ (rad/s): 0.03.
    pub speed_mean_rad_s: f64,
    /// Standard deviation of the speed σ_ω (rad/s): 0.0087 (0.5°/s).
    pub speed_sigma_rad_s: f64,
    /// Standard deviation of each Euler angle of the rotation noise (deg): 2.5 (Eq 6.6;
    /// the Fig 6.2 demonstration used 5).
    pub rotation_sigma_deg: f64,
    /// Standard deviation of the translation length error η (m): 0.01.
    pub translation_sigma_m: f64,
}

impl Default for OdometryNoise {
    fn default() -> Self {
        Self {
            speed_mean_rad_s: 0.03,
            speed_sigma_rad_s: 0.0087,
            rotation_sigma_deg: 2.5,
            translation_sigma_m: 0.01,
        }
    }
}

impl OdometryNoise {
    /// No noise: the reading is the true motion (still in Eq 6.8's time scale).
    pub const NONE: OdometryNoise = OdometryNoise {
        speed_mean_rad_s: 0.03,
        speed_sigma_rad_s: 0.0,
        rotation_sigma_deg: 0.0,
        translation_sigma_m: 0.0,
    };

    /// Checks the values; returns the offending field and what was expected.
    pub fn validate(&self) -> Result<(), Invalid> {
        if !(self.speed_mean_rad_s.is_finite() && self.speed_mean_rad_s > 0.0) {
            return Err(Invalid::field(
                "speed_mean_rad_s",
                format!("expected a positive number, got {}", self.speed_mean_rad_s),
            ));
        }
        for (f, v) in [
            ("speed_sigma_rad_s", self.speed_sigma_rad_s),
            ("rotation_sigma_deg", self.rotation_sigma_deg),
            ("translation_sigma_m", self.translation_sigma_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::field(
                    f,
                    format!("expected a finite number ≥ 0, got {v}"),
                ));
            }
        }
        Ok(())
    }

    /// The noisy reading of the true relative motion `motion` (T_{i−1}⁻¹·T_i, Eq 6.4).
    pub fn apply(&self, motion: &Isometry3<f64>, rng: &mut impl rand::Rng) -> Odometry {
        let omega = loop {
            let w = self.speed_mean_rad_s + gauss(self.speed_sigma_rad_s, rng);
            if w > 0.0 {
                break w;
            }
        };
        let s = self.rotation_sigma_deg.to_radians();
        let (ez, ey, ex) = (gauss(s, rng), gauss(s, rng), gauss(s, rng));
        let eta = gauss(self.translation_sigma_m, rng);
        let r_eta = Rotation3::from_euler_angles(ex, ey, ez); // Rz(ez)·Ry(ey)·Rx(ex)
        let r_n = motion.rotation.to_rotation_matrix() * r_eta;
        let (axis, theta) = r_n
            .axis_angle()
            .map(|(a, t)| (a.into_inner(), t))
            .unwrap_or((Vector3::zeros(), 0.0));
        let (omega_eta, dt) = if theta > 1e-12 {
            (axis * omega, theta / omega)
        } else {
            (Vector3::zeros(), 1.0)
        };
        let delta = motion.translation.vector;
        let length = delta.norm();
        let delta_eta = if length > 1e-12 {
            delta / length * (length + eta)
        } else {
            Vector3::zeros()
        };
        let v = delta_eta / dt;
        Odometry {
            v: [v.x, v.y, v.z],
            omega: [omega_eta.x, omega_eta.y, omega_eta.z],
            dt,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::substream;
    use nalgebra::{Translation3, UnitQuaternion};

    /// Mean and standard deviation of a sample.
    fn moments(v: &[f64]) -> (f64, f64) {
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
        (m, var.sqrt())
    }

    /// Within three standard errors of the mean and of the standard deviation
    /// (SE of s ≈ σ/√(2(n−1)) for a normal sample).
    fn check(name: &str, v: &[f64], mean: f64, sigma: f64) {
        let n = v.len() as f64;
        let (m, s) = moments(v);
        assert!(
            (m - mean).abs() < 3.0 * sigma / n.sqrt(),
            "{name}: mean {m} vs {mean}"
        );
        assert!(
            (s - sigma).abs() < 3.0 * sigma / (2.0 * (n - 1.0)).sqrt(),
            "{name}: sd {s} vs {sigma}"
        );
    }

    /// 10,000 readings of one motion; the noise is recovered from each reading by
    /// inverting Eq 6.5–6.10 independently of how it was drawn.
    #[test]
    fn ten_thousand_draws_have_the_equations_moments() {
        let noise = OdometryNoise::default();
        let motion = Isometry3::from_parts(
            Translation3::new(0.02, -0.01, 0.015),
            UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3),
        );
        let truth_len = motion.translation.vector.norm();
        let mut rng = substream(3, "test/odometry-noise");
        let (mut speed, mut len, mut ex, mut ey, mut ez) = (vec![], vec![], vec![], vec![], vec![]);
        for _ in 0..10_000 {
            let o = noise.apply(&motion, &mut rng);
            let w = Vector3::from(o.omega);
            speed.push(w.norm());
            // δ_η is along δ (or against it): its signed length minus |δ| is η.
            let d = o.translation();
            let dir = motion.translation.vector / truth_len;
            assert!((d - dir * d.dot(&dir)).norm() < 1e-12);
            len.push(d.dot(&dir) - truth_len);
            // R_η = Rᵀ·R_n, read as ZYX Euler angles.
            let r_n = Rotation3::from_scaled_axis(o.rotation());
            let r_eta = motion.rotation.to_rotation_matrix().transpose() * r_n;
            let (x, y, z) = r_eta.euler_angles();
            ex.push(x.to_degrees());
            ey.push(y.to_degrees());
            ez.push(z.to_degrees());
        }
        check("ω", &speed, 0.03, 0.0087);
        check("η", &len, 0.0, 0.01);
        check("euler x", &ex, 0.0, 2.5);
        check("euler y", &ey, 0.0, 2.5);
        check("euler z", &ez, 0.0, 2.5);
    }

    #[test]
    fn without_noise_the_reading_is_the_motion_and_no_motion_reads_as_none() {
        let motion = Isometry3::from_parts(
            Translation3::new(0.03, 0.0, -0.01),
            UnitQuaternion::from_euler_angles(0.0, 0.2, 0.0),
        );
        let mut rng = substream(0, "test");
        let o = OdometryNoise::NONE.apply(&motion, &mut rng);
        assert!((o.translation() - motion.translation.vector).norm() < 1e-12);
        assert!((o.rotation() - motion.rotation.scaled_axis()).norm() < 1e-12);
        assert!((o.dt - 0.2 / 0.03).abs() < 1e-12);
        let o = OdometryNoise::NONE.apply(&Isometry3::identity(), &mut rng);
        assert_eq!((o.v, o.omega, o.dt), ([0.0; 3], [0.0; 3], 1.0));
    }
}
