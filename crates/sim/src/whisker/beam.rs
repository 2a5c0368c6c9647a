//! A whisker shaft as a discretised Euler–Bernoulli beam (thesis §2.2.2, §2.3.2).
//!
//! The shaft is a linearly tapered truncated cone (2 mm → 0.6 mm diameter by default,
//! §2.2.2), cut into `segments` rigid frusta of equal length l. Bending compliance is
//! lumped at the joints between them: joint j at arc length s_j = j·l gets the rotational
//! stiffness k_j = E·I(s_j)/l (the compliance of the beam over the segment length around
//! it), except the base joint, which carries only the half segment above the clamp:
//! k_0 = 2·E·I(0)/l. Against the tapered-cantilever formulas this lumping is within 0.4 %
//! at N = 10 and 0.1 % at N = 20 (docs/physics.md). Twist is stiff
//! (G·J/l with G = E/(2(1+ν))). I = π r⁴/4 (Eq 2.36).
//!
//! Damping is stiffness-proportional (Rayleigh): every joint gets c_j = β·k_j with
//! β = 2ζ/ω₁, so the first bending mode has the damping ratio ζ. ω₁ is estimated with a
//! Rayleigh quotient on the static tip-load deflection shape of the tapered cantilever.

use std::f64::consts::PI;
use whisker_slam::invalid::Invalid;

/// Poisson's ratio used for the twist stiffness (polymer resins: 0.3–0.4).
pub const POISSON_RATIO: f64 = 0.35;

/// How the shaft's joints may bend.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bending {
    /// Spherical joints: the shaft bends in both planes (and twists stiffly).
    Spatial,
    /// Revolute joints about the whisk axis: the shaft bends only in the sweep plane.
    /// The follicle still pivots on both axes, so the x deflection is still sensed, but
    /// the shaft itself is rigid out of the sweep plane. About 4× cheaper per step.
    SweepPlane,
}

/// Geometry and material of one whisker shaft (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamDesign {
    /// Length from base to tip (m).
    pub length: f64,
    /// Diameter at the base (m).
    pub base_diameter: f64,
    /// Diameter at the tip (m).
    pub tip_diameter: f64,
    /// Young's modulus (Pa).
    pub youngs_modulus: f64,
    /// Density (kg/m³).
    pub density: f64,
    /// Damping ratio of the first bending mode.
    pub damping_ratio: f64,
    /// Number of rigid segments.
    pub segments: usize,
    /// Joint model of the shaft.
    pub bending: Bending,
}

impl BeamDesign {
    /// The array's defaults for a whisker of `length` m: 2 → 0.6 mm taper (§2.2.2),
    /// E 2.5 GPa, ρ 1150 kg/m³, ζ 0.03 (ABS-like photopolymer), 16 segments:
    /// the fewest that keep the load-point deflection within 1 % of the tapered-cantilever
    /// formula for loads at 0.3–0.9 L (0.96 % at 0.3 L; 2.3 % at 10 segments, 0.5 % at
    /// 20; `tests/beam_theory.rs`). The cost of a step grows about as N³ (dense
    /// multibody mass matrix): 20 segments cost 4.6× as much as 10.
    /// The physical range of each number of a design: (field, min, max, unit). Wide
    /// enough for rat whiskers (a few mm to 5 cm, 50–200 µm thick, keratin at ~3 GPa) and
    /// artificial ones (the thesis': 6–16 cm, 2 mm at the base, a photopolymer at 2.5 GPa),
    /// narrow enough that the beam's modes and masses stay finite in f64.
    pub const RANGES: [(&'static str, f64, f64, &'static str); 5] = [
        ("length", 1e-3, 2.0, "m"),
        ("base_diameter", 1e-5, 0.05, "m"),
        ("tip_diameter", 1e-6, 0.05, "m"),
        ("youngs_modulus", 1e4, 1e12, "Pa"),
        ("density", 10.0, 25_000.0, "kg/m³"),
    ];

    pub fn with_length(length: f64) -> Self {
        Self {
            length,
            base_diameter: 2.0e-3,
            tip_diameter: 0.6e-3,
            youngs_modulus: 2.5e9,
            density: 1150.0,
            damping_ratio: 0.03,
            segments: 16,
            bending: Bending::Spatial,
        }
    }

    /// Checks that every value is finite and physical ([`BeamDesign::RANGES`]); the
    /// message names the first bad field.
    pub fn validate(&self) -> Result<(), Invalid> {
        self.check().map_err(|e| Invalid::new(e.message))
    }

    /// As [`BeamDesign::validate`], with the bad field apart (`length`, `base_diameter`,
    /// `tip_diameter`, `youngs_modulus`, `density`, `damping_ratio`, `segments`) for callers
    /// that name it their own way (a scenario field, a command-line option).
    pub fn check(&self) -> Result<(), Invalid> {
        let values = [
            self.length,
            self.base_diameter,
            self.tip_diameter,
            self.youngs_modulus,
            self.density,
        ];
        for ((name, min, max, unit), v) in Self::RANGES.iter().zip(values) {
            if !(v.is_finite() && (*min..=*max).contains(&v)) {
                return Err(Invalid::field(
                    *name,
                    format!(
                        "{name} must be a number from {} to {} {unit}, got {}",
                        super::short(*min),
                        super::short(*max),
                        super::short(v)
                    ),
                ));
            }
        }
        if self.base_diameter > self.length / 5.0 {
            return Err((
                "base_diameter",
                format!(
                    "base_diameter ({}) must be at most a fifth of length ({}): a beam model needs a slender shaft",
                    self.base_diameter, self.length
                ),
            ).into());
        }
        if self.tip_diameter > self.base_diameter {
            return Err((
                "tip_diameter",
                format!(
                    "tip_diameter ({}) must not exceed base_diameter ({})",
                    self.tip_diameter, self.base_diameter
                ),
            )
                .into());
        }
        if !(self.damping_ratio.is_finite() && (0.0..1.0).contains(&self.damping_ratio)) {
            return Err((
                "damping_ratio",
                format!(
                    "damping_ratio must be in [0, 1), got {}",
                    self.damping_ratio
                ),
            )
                .into());
        }
        if !(2..=200).contains(&self.segments) {
            return Err((
                "segments",
                format!("segments must be between 2 and 200, got {}", self.segments),
            )
                .into());
        }
        Ok(())
    }

    /// Radius at arc length `s` (m).
    pub fn radius(&self, s: f64) -> f64 {
        let (rb, rt) = (self.base_diameter / 2.0, self.tip_diameter / 2.0);
        rb + (rt - rb) * (s / self.length)
    }

    /// Second moment of area at `s` (m⁴), π r⁴ / 4.
    pub fn second_moment(&self, s: f64) -> f64 {
        PI * self.radius(s).powi(4) / 4.0
    }

    /// Length of one segment (m).
    pub fn segment_length(&self) -> f64 {
        self.length / self.segments as f64
    }

    /// Bending stiffness of joint `j` (N·m/rad), base joint j = 0.
    pub fn joint_stiffness(&self, j: usize) -> f64 {
        let l = self.segment_length();
        let s = j as f64 * l;
        let k = self.youngs_modulus * self.second_moment(s) / l;
        if j == 0 { 2.0 * k } else { k }
    }

    /// Twist stiffness of joint `j` (N·m/rad): G·J/l with J = π r⁴/2.
    pub fn twist_stiffness(&self, j: usize) -> f64 {
        let l = self.segment_length();
        let g = self.youngs_modulus / (2.0 * (1.0 + POISSON_RATIO));
        g * 2.0 * self.second_moment(j as f64 * l) / l
    }

    /// Mass properties of segment `j`: (mass kg, centre of mass along the segment from
    /// its base end m, transverse inertia about the centre of mass kg·m², axial inertia).
    pub fn segment_mass(&self, j: usize) -> (f64, f64, f64, f64) {
        let l = self.segment_length();
        let (r1, r2) = (self.radius(j as f64 * l), self.radius((j + 1) as f64 * l));
        let sum = r1 * r1 + r1 * r2 + r2 * r2;
        let mass = self.density * PI * l * sum / 3.0;
        let com = l * (r1 * r1 + 2.0 * r1 * r2 + 3.0 * r2 * r2) / (4.0 * sum);
        let r2_mean = sum / 3.0;
        let transverse = mass * (3.0 * r2_mean + l * l) / 12.0;
        let axial = mass * r2_mean / 2.0;
        (mass, com, transverse, axial)
    }

    /// Total mass (kg).
    pub fn mass(&self) -> f64 {
        (0..self.segments).map(|j| self.segment_mass(j).0).sum()
    }

    /// Estimate of the first bending natural frequency of the clamped shaft (rad/s):
    /// Rayleigh quotient ∫EI(w″)² / ∫ρA w² with the static tip-load shape w.
    pub fn first_mode_estimate(&self) -> f64 {
        let (l, n) = (self.length, 400);
        let ls = self.apex_length();
        let ei_base = self.youngs_modulus * self.second_moment(0.0);
        // Deflection under a unit tip load (notes: w(x ≤ a), a = L, divided through by
        // L_s² so that an untapered shaft, L_s = ∞, is covered) and its curvature M/EI.
        let w = |x: f64| {
            x * x * (3.0 * l - x - 2.0 * l * x / ls) / (6.0 * ei_base * (1.0 - x / ls).powi(2))
        };
        let (mut num, mut den) = (0.0, 0.0);
        let h = l / n as f64;
        for i in 0..n {
            let x = (i as f64 + 0.5) * h;
            let ei = self.youngs_modulus * self.second_moment(x);
            let area = PI * self.radius(x).powi(2);
            let curvature = (l - x) / ei;
            num += ei * curvature * curvature * h;
            den += self.density * area * w(x).powi(2) * h;
        }
        (num / den).sqrt()
    }

    /// Length from the base to the virtual apex of the cone, L·r_b/(r_b − r_t) (m);
    /// infinite for an untapered shaft.
    pub fn apex_length(&self) -> f64 {
        let (rb, rt) = (self.base_diameter, self.tip_diameter);
        if rb > rt {
            self.length * rb / (rb - rt)
        } else {
            f64::INFINITY
        }
    }

    /// Stiffness-proportional damping factor β = 2ζ/ω₁ (s).
    pub fn rayleigh_beta(&self) -> f64 {
        2.0 * self.damping_ratio / self.first_mode_estimate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lumped joints reproduce the continuous beam's compliance: under a tip force
    /// F the tip deflects by F·∫(L−x)²/EI dx; the chain gives F·Σ (L−x_j)²/k_j.
    #[test]
    fn joint_compliances_reproduce_the_tip_load_deflection() {
        for length in [0.06, 0.16] {
            let d = BeamDesign::with_length(length);
            let l = d.segment_length();
            let chain: f64 = (0..d.segments)
                .map(|j| (length - j as f64 * l).powi(2) / d.joint_stiffness(j))
                .sum();
            let n = 20_000;
            let h = length / n as f64;
            let exact: f64 = (0..n)
                .map(|i| {
                    let x = (i as f64 + 0.5) * h;
                    (length - x).powi(2) * h / (d.youngs_modulus * d.second_moment(x))
                })
                .sum();
            assert!((chain / exact - 1.0).abs() < 0.005, "{chain} vs {exact}");
        }
    }

    #[test]
    fn segment_masses_add_up_to_the_cone_frustum() {
        let d = BeamDesign::with_length(0.16);
        let (rb, rt) = (1.0e-3, 0.3e-3);
        let volume = PI * d.length * (rb * rb + rb * rt + rt * rt) / 3.0;
        assert!((d.mass() / (d.density * volume) - 1.0).abs() < 1e-12);
        // A cylinder's centre of mass is at its middle.
        let mut c = d;
        c.tip_diameter = c.base_diameter;
        let (_, com, _, _) = c.segment_mass(3);
        assert!((com - c.segment_length() / 2.0).abs() < 1e-15);
    }

    /// A uniform cantilever's first mode is 1.8751² √(EI/ρA)/L² (textbook value).
    #[test]
    fn rayleigh_estimate_matches_the_uniform_cantilever() {
        let mut d = BeamDesign::with_length(0.1);
        d.tip_diameter = d.base_diameter * (1.0 - 1e-9);
        let ei = d.youngs_modulus * d.second_moment(0.0);
        let rho_a = d.density * PI * d.radius(0.0).powi(2);
        let exact = 1.875104f64.powi(2) * (ei / rho_a).sqrt() / d.length.powi(2);
        let est = d.first_mode_estimate();
        // Rayleigh's quotient is an upper bound; with the static tip-load shape it is
        // 1.45 % high for the uniform cantilever (3.567 vs 3.516 √(EI/ρA)/L²).
        assert!(est >= exact && est < exact * 1.02, "{est} vs {exact}");
    }

    #[test]
    fn validation_names_the_bad_field() {
        let mut d = BeamDesign::with_length(0.1);
        d.density = -1.0;
        assert!(d.validate().unwrap_err().to_string().contains("density"));
        let mut d = BeamDesign::with_length(0.1);
        d.tip_diameter = 3e-3;
        assert!(
            d.validate()
                .unwrap_err()
                .to_string()
                .contains("tip_diameter")
        );
        assert!(BeamDesign::with_length(0.06).validate().is_ok());
    }

    /// Absurd magnitudes are refused with the range (#37: a 1e308 m whisker had a NaN
    /// first mode); the thesis' three lengths and a rat's macrovibrissa pass.
    #[test]
    fn values_outside_the_physical_ranges_are_refused_with_the_range() {
        for length in [0.06, 0.1, 0.16] {
            assert!(BeamDesign::with_length(length).validate().is_ok());
        }
        let mut rat = BeamDesign::with_length(0.04);
        (rat.base_diameter, rat.tip_diameter, rat.youngs_modulus) = (150e-6, 5e-6, 3e9);
        rat.density = 1300.0;
        assert!(rat.validate().is_ok());
        let e = BeamDesign::with_length(1e308)
            .validate()
            .unwrap_err()
            .to_string();
        assert!(e.contains("length") && e.contains("to 2 m"), "{e}");
        let mut d = BeamDesign::with_length(0.1);
        d.youngs_modulus = 1e300;
        assert!(
            d.validate()
                .unwrap_err()
                .to_string()
                .contains("youngs_modulus")
        );
        let mut d = BeamDesign::with_length(0.005);
        d.tip_diameter = 1e-3;
        assert!(d.validate().unwrap_err().to_string().contains("slender"));
        assert_eq!(d.check().unwrap_err().field, "base_diameter");
        d.segments = 1;
        (d.base_diameter, d.tip_diameter) = (5e-4, 1e-4);
        assert_eq!(d.check().unwrap_err().field, "segments");
    }
}
