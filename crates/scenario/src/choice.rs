//! Named choices of the command line and of files: each value with its name and one line
//! on what it means, in one place, so that the command line's parser, the help and the
//! reports agree.

use whisker_sim::sensing::noise::PointNoise;
use whisker_sim::sensing::physics::SolverPath;
use whisker_sim::whisker::beam::Bending;

/// A value chosen by name.
pub trait Choice: Copy + PartialEq + Send + Sync + 'static {
    /// Every value, its name and what it means.
    const ALL: &'static [(Self, &'static str, &'static str)];

    /// Its name.
    fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(v, ..)| *v == self)
            .map_or("?", |(_, n, _)| n)
    }

    /// The value named `name`.
    fn named(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(_, n, _)| *n == name)
            .map(|(v, ..)| *v)
    }
}

impl Choice for Bending {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            Bending::Spatial,
            "spatial",
            "Spherical joints: the shaft bends in both planes",
        ),
        (
            Bending::SweepPlane,
            "sweep-plane",
            "Revolute joints: the shaft bends in the sweep plane only (faster)",
        ),
    ];
}

impl Choice for PointNoise {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            PointNoise::PerCoordinate,
            "per-coordinate",
            "N(0, r) on each of x, y and z",
        ),
        (
            PointNoise::AlongWhisker,
            "along-whisker",
            "N(0, r) along the shaft: the radial distance's error (§6.1.3.1.2)",
        ),
    ];
}

impl Choice for SolverPath {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            SolverPath::Released,
            "released",
            "Rapier 0.36.1 as released (dense mass matrix)",
        ),
        (
            SolverPath::Exact,
            "exact",
            "Patches 1-2: bit-identical to released, faster",
        ),
        (
            SolverPath::Composite,
            "composite",
            "Patches 1, 2, 5: composite-rigid-body assembly",
        ),
        (
            SolverPath::OncePerStep,
            "once-per-step",
            "Patches 1-3, 5: factorised once per step (the default until #34)",
        ),
        (
            SolverPath::ExplicitCoriolis,
            "explicit-coriolis",
            "Patches 1-5: explicit gyroscopic and Coriolis terms",
        ),
        (
            SolverPath::Articulated,
            "articulated",
            "Patches 3, 4, 6-9: articulated-body factorisation, O(n) in the DoFs (the default)",
        ),
    ];
}
