//! The settings of `whisker object-slam` and Table 5.1's parameter sets.

use super::trajectory::Placement;
use crate::record::Target;
use std::path::PathBuf;
use whisker_scenario::SensingMode;
use whisker_scenario::choice::Choice;
use whisker_sim::sensing::noise::PointNoise;
use whisker_slam::features::similarity::FeatureSet;
use whisker_slam::whisker_ratslam::slam::Params;

/// The object left out of the appended maps (§5.2.2.2).
pub const UNMAPPED: &str = "skull";
/// Identification decay per whisk.
pub const DECAY: f64 = 0.9;

/// What `whisker object-slam` runs.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Catalogue objects [default: all eight].
    pub objects: Vec<String>,
    /// Seed of every random draw.
    pub seed: u64,
    /// Directory for object maps and CSV results (created; files written atomically).
    pub out: Option<PathBuf>,
    /// How contacts are sensed: the kinematic sweep with the noise of §6.1.3.1.2, or
    /// physics whiskers through the signal front end and a radial-distance model.
    pub sensing: SensingMode,
    /// With physics sensing: the radial-distance model file [default: the built-in svr10].
    pub radial_model: Option<PathBuf>,
    /// Which WhiskerRatSLAM.
    pub slam: SlamVersion,
    /// Where each object sits relative to its trajectories (§5.2.2.1).
    pub placement: Placement,
    /// Kinematic sensing: which way the contact noise displaces a point (§6.1.3.1.2).
    pub point_noise: PointNoise,
    /// Where the recording goes.
    pub rrd: Target,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            objects: Vec::new(),
            seed: 0,
            out: None,
            sensing: SensingMode::Kinematic,
            radial_model: None,
            slam: SlamVersion::Corrected,
            placement: Placement::Thesis,
            point_noise: PointNoise::default(),
            rrd: Target::default(),
        }
    }
}

/// Which WhiskerRatSLAM: with the corrections of issue #19, or Alg 2 as printed (the
/// closed loop's default; robust relaxation on in both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlamVersion {
    /// Ω relative to the packet's peak, the test before the injection, phase-exact path
    /// integration, the odometry anchor (`Params::corrected`).
    Corrected,
    /// Alg 2 as printed (`Params::default`).
    Printed,
}

impl Choice for SlamVersion {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            SlamVersion::Corrected,
            "corrected",
            "Ω relative to the packet's peak, the test before the injection, phase-exact path integration, the odometry anchor",
        ),
        (SlamVersion::Printed, "printed", "Alg 2 as printed"),
    ];
}

/// How contact points are placed (Table 5.1 "contact algorithm").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactEstimate {
    Tip,
    Svr,
}

/// One of Table 5.1's parameter sets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Combo {
    pub features: FeatureSet,
    pub merge: bool,
    pub contact: ContactEstimate,
}

impl Combo {
    pub fn name(&self) -> String {
        let f = match self.features {
            FeatureSet::Pfh => "pfh",
            FeatureSet::Sda => "sda",
            FeatureSet::Both => "both",
        };
        let c = match self.contact {
            ContactEstimate::Tip => "tip",
            ContactEstimate::Svr => "svr",
        };
        format!("{f}/{}/{c}", if self.merge { "merged" } else { "unmerged" })
    }

    pub fn all() -> Vec<Combo> {
        let mut out = Vec::new();
        for features in [FeatureSet::Pfh, FeatureSet::Sda, FeatureSet::Both] {
            for merge in [true, false] {
                for contact in [ContactEstimate::Tip, ContactEstimate::Svr] {
                    out.push(Combo {
                        features,
                        merge,
                        contact,
                    });
                }
            }
        }
        out
    }

    pub const BEST: Combo = Combo {
        features: FeatureSet::Both,
        merge: false,
        contact: ContactEstimate::Svr,
    };
}

/// The thesis' step for an object (m, degrees): the pass mark of §5.2.2.1.
pub fn thesis_step(object: &str) -> (f64, f64) {
    if object == "box" {
        (0.03, 3.0)
    } else {
        (0.11, 12.0)
    }
}
/// The WhiskerRatSLAM parameters of `combo` for version `slam`.
pub fn params(combo: Combo, slam: SlamVersion) -> Params {
    let mut p = match slam {
        SlamVersion::Corrected => Params::corrected(),
        SlamVersion::Printed => Params::default(),
    };
    p.matching.features = combo.features;
    p.merge_features = combo.merge;
    p
}
