//! Which of the vendored Rapier's multibody code paths steps a whisker chain
//! (`vendor/PATCHES.md`): chosen per whisker, measured side by side by `whisker bench
//! physics`.

use rapier3d_f64::prelude::{IntegrationParameters, MultibodyMassMatrix};

/// Which of the vendored Rapier's multibody code paths steps a whisker (`vendor/PATCHES.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverPath {
    /// Rapier 0.36.1 as released: the dense mass matrix, assembled and factorised at every
    /// substep. Kept for `whisker bench physics`' before/after comparison.
    Released,
    /// Patches 1–2: the mass matrix restricted to each link's ancestors, copied for
    /// factorisation in one block. Bit-identical to `Released`, ~2× faster. The default
    /// until speed-adaptive steps made the tunnelling statistics below moot.
    Exact,
    /// Patches 1, 2 and 5: the same matrices as `Exact` assembled the composite-rigid-body
    /// way (each link's forces summed over its subtree, one dot product per entry): the
    /// same model and the same factorisations, equal to `Exact` up to rounding (matrices
    /// within 6e-15 of their scale, free whisking bodies within 1e-16 m,
    /// `tests/solver_paths.rs`), ~1.5× faster than `Exact`. The default from speed-adaptive
    /// steps until `OncePerStep` passed the suite and the soaks.
    ///
    /// In contact, rounding-level differences grow as any perturbation does (stick-slip
    /// is chaotic), so single runs are coin flips: moving the array by nanometres, with one
    /// world step per sample whisker D1 over the Mug's handle went deeper than 1 mm or
    /// non-finite within 10 s in 59 of 140 runs with this path and 50 of 140 with `Exact`
    /// (= Rapier as released), non-finite in 12 and 6 of them (Fisher's exact test,
    /// one-sided p ≈ 0.16 and 0.11), which kept `Exact` the default. With speed-adaptive
    /// steps (`sensing::adaptive_step`) neither tunnels: 0 of 20 runs each (`whisker soak
    /// --objects mug --whiskers D1 --duration 10 --nudges 19 --path …`; deepest 0.0 mm
    /// here, 0.61 mm with `Exact`).
    Composite,
    /// Patches 1–3 and 5: as `Composite`, the mass matrix assembled and factorised once
    /// per step instead of at each of its substeps (~2.3× faster again). Against
    /// `Released`, free whisking at 10 Hz agrees within 0.12 % RMS and contacts start at
    /// the same samples with mean deflection within 0.1 % (`tests/solver_paths.rs`). With
    /// one world step per sample, 3 of 20 nudged Mug runs as above went non-finite (7
    /// failed in all; `Exact`: 6 of 140); with speed-adaptive steps 0 of 20 (deepest
    /// 0.0 mm). The default from 2026-12-03 until `Articulated` (#34): with it the whole
    /// workspace suite passed (245 tests) and so did the 60-s soaks of the Box, Barrel and
    /// Mug (0.0 mm, finite; 1,513 CPU-s against 2,673 with `Composite`, 1.77× less).
    OncePerStep,
    /// Patches 1–5: as `OncePerStep`, the gyroscopic and Coriolis terms explicit, so one
    /// mass matrix and one factorisation instead of two (~1.6× faster again). 5 of 12
    /// nudged Mug runs went non-finite (`Exact`: 6 of 140) with one world step per sample;
    /// with speed-adaptive steps 0 of 20. The articulated default uses the same explicit
    /// terms ([`Lever::ExplicitCoriolis`]).
    ExplicitCoriolis,
    /// Patches 3 and 6–9: as `OncePerStep`, with the mass matrices factorised the
    /// articulated-body way (O(n) in the chain's DoFs, no dense matrix): the same
    /// matrices' inverses up to rounding (`tests/articulated.rs`: energy-norm error 2e-15
    /// on bent whiskers; free whisking within 2e-15 m of `OncePerStep` after 0.3 s), and
    /// the weld's root rows (with [`Lever::DrivenRoot`] off) from kept columns of `M⁻¹`.
    /// **The default** (#34): ~1.7–2× faster than `OncePerStep` (`whisker bench physics`);
    /// with it the workspace suite passes and so do the 60-s soaks of the Box, Barrel and
    /// Mug and 20 nudged Mug runs, with and without the driven root.
    /// Patch 8 ([`Lever::ReuseStepKinematics`]) changes no bit of its results; patch 9
    /// ([`Lever::LazyJacobians`], ~1.1–1.2× faster) changes them by rounding; explicit
    /// gyroscopic and Coriolis terms ([`Lever::ExplicitCoriolis`], patch 4, ~1.2–1.6×
    /// faster) change the integrator (the soaks and nudged runs pass with it).
    #[default]
    Articulated,
}

/// A speed-up of the default path that can be switched off on its own, so that `whisker
/// bench physics` measures what each one brings (after the default path, a row per lever
/// with that lever off; #34: "each lever measured on its own, kept only if it pays"). Each
/// says whether it changes bits of the results, and how it is tested.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lever {
    /// Patch 8: a step starts from the kinematics its predecessor's last substep left
    /// (forward kinematics three times a step instead of four with 3 substeps), unless
    /// something the kinematics depend on changed in between
    /// (`IntegrationParameters::multibody_reuse_step_kinematics`).
    ReuseStepKinematics,
    /// Patch 9: forward kinematics without the dense body Jacobians (6 × 57 per link,
    /// rebuilt three times a step); the generalised forces by one pass from the tips and a
    /// constraint row by one pass up its link's branch
    /// (`IntegrationParameters::multibody_lazy_jacobians`). The same sums in another order:
    /// equal up to rounding (`tests/articulated.rs`).
    LazyJacobians,
    /// Patch 4 on the articulated path: the gyroscopic and Coriolis terms as explicit
    /// forces, so only the plain matrix is factorised (one 6-wide factorisation a step
    /// instead of a 6- and a 12-wide one) and the energy guard is not needed
    /// (`IntegrationParameters::multibody_semi_implicit_coriolis` false). Changes the
    /// integrator, not only rounding.
    ExplicitCoriolis,
    /// The array's whiskers run in chunks of steps, the dearest (by their last chunk)
    /// first, one at a time from a queue (`sensing::schedule`); without it, each
    /// whisker runs all its steps in one task in rayon's split. Changes only which thread
    /// runs what: the samples are identical.
    LoadBalance,
    /// The follicle's root, a heavy body, pushed onto the driver's pose by a force held over
    /// each step ([`crate::whisker::body::RootDrive::Driven`]) instead of welded to it by an
    /// impulse fixed joint: six constraint rows fewer at every substep and no root columns
    /// of `M⁻¹` to keep (patch 10), ~1.2–1.4× faster (`whisker bench physics`). Changes how the base's motion is discretised within a
    /// step (a constant force over it, not the weld's velocity jump at its start), so not
    /// bits only: in free whisking at 10 Hz the follicle's stream moves by ~3 % RMS, less
    /// than either root's own discretisation error (13 % and 8 % RMS for the shortest and
    /// longest whisker against an eighth of the step, where the two roots agree within
    /// 0.04 %; `tests/root_drive.rs`); against poles contacts start at the same samples as
    /// with Rapier as released and the mean deflection per whisk agrees within 1 %
    /// (`tests/solver_paths.rs`).
    DrivenRoot,
}

impl Lever {
    /// Every lever.
    pub const ALL: [Lever; 5] = [
        Self::ReuseStepKinematics,
        Self::LazyJacobians,
        Self::ExplicitCoriolis,
        Self::LoadBalance,
        Self::DrivenRoot,
    ];

    /// Its name in benchmarks.
    pub fn name(self) -> &'static str {
        match self {
            Self::ReuseStepKinematics => "reuse-step-kinematics",
            Self::LazyJacobians => "lazy-jacobians",
            Self::ExplicitCoriolis => "explicit-coriolis",
            Self::LoadBalance => "load-balance",
            Self::DrivenRoot => "driven-root",
        }
    }
}

impl SolverPath {
    /// Every path, oldest first.
    pub const ALL: [SolverPath; 6] = [
        Self::Released,
        Self::Exact,
        Self::Composite,
        Self::OncePerStep,
        Self::ExplicitCoriolis,
        Self::Articulated,
    ];

    /// Sets the path's Rapier parameters.
    pub fn apply(self, p: &mut IntegrationParameters) {
        self.apply_without(p, None);
    }

    /// The switchable levers this path uses (none but the default's).
    pub fn levers(self) -> &'static [Lever] {
        match self {
            Self::Articulated => &Lever::ALL,
            _ => &[],
        }
    }

    /// Whether `lever` is on for this path with lever `off` switched off.
    pub fn uses(self, lever: Lever, off: Option<Lever>) -> bool {
        self.levers().contains(&lever) && off != Some(lever)
    }

    /// Sets the path's Rapier parameters with lever `off` switched off, to measure what it
    /// brings (the `articulated −<lever>` rows of `whisker bench physics`).
    pub fn apply_without(self, p: &mut IntegrationParameters, off: Option<Lever>) {
        let on = |lever: Lever| self.uses(lever, off);
        p.multibody_reuse_step_kinematics = on(Lever::ReuseStepKinematics);
        p.multibody_lazy_jacobians = on(Lever::LazyJacobians);
        p.multibody_mass_matrix = match self {
            Self::Released => MultibodyMassMatrix::Dense,
            Self::Exact => MultibodyMassMatrix::Truncated,
            Self::Articulated => MultibodyMassMatrix::Articulated,
            _ => MultibodyMassMatrix::Composite,
        };
        p.multibody_mass_matrix_once_per_step = matches!(
            self,
            Self::OncePerStep | Self::ExplicitCoriolis | Self::Articulated
        );
        p.multibody_semi_implicit_coriolis =
            self != Self::ExplicitCoriolis && !on(Lever::ExplicitCoriolis);
    }

    /// Its name in benchmarks.
    pub fn name(self) -> &'static str {
        match self {
            Self::Released => "released",
            Self::Exact => "exact",
            Self::Composite => "composite",
            Self::OncePerStep => "once-per-step",
            Self::ExplicitCoriolis => "explicit-coriolis",
            Self::Articulated => "articulated",
        }
    }
}
