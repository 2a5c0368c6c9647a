//! `[navigate]` of a scenario (documented in `scenarios/README.md`): a whiskered mobile
//! robot driving a route round an `[office]` (thesis Fig 5.1, §7.1) — the route, the
//! wheeled base under the arm, its odometry error model and the cue that switches
//! between terrain and object exploration.
//!
//! The base is a disc on the floor with the arm's base link at its centre; its planar
//! pose (x, y, yaw) in the office is the robot's "virtual joint" (a mobile base's planar
//! joint to the world, as robot descriptions of mobile manipulators state it). The route
//! is driven leg by leg: a turn in place towards the next waypoint, then straight, back
//! to the first waypoint at the end of each lap.

use crate::error::{Error, Result};
use crate::object_mode::ObjectModeConfig;
use nalgebra::Point2;
use serde::Deserialize;
use std::path::Path;
use whisker_sim::environment::Environment;
use whisker_sim::environment::floor_plan::{FloorPlan, segment_distance};
use whisker_slam::invalid::Invalid;
use whisker_slam::navigation::base_odometry::BaseOdometryNoise;
use whisker_slam::navigation::mode_switch::ModeSwitch;
use whisker_slam::ratslam::RatSlamParams;

/// The most laps of a route.
pub const MAX_LAPS: usize = 100;

/// `[navigate]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NavigateConfig {
    /// The route's waypoints (x, y) on the office floor (m), driven in order and back to
    /// the first.
    pub route_m: Vec<[f64; 2]>,
    /// Times round the route [2].
    #[serde(default = "two")]
    pub laps: usize,
    /// `[navigate.base]`.
    #[serde(default)]
    pub base: BaseConfig,
    /// `[navigate.odometry]`: the base's odometry error model.
    #[serde(default)]
    pub odometry: BaseOdometryNoise,
    /// `[navigate.switch]`: the terrain/object mode-switch cue.
    #[serde(default)]
    pub switch: ModeSwitch,
    /// `[navigate.terrain]`: the arm's posture in terrain mode.
    #[serde(default)]
    pub terrain: TerrainConfig,
    /// `[navigate.ratslam]`: planar RatSLAM in the office; fields left out take
    /// [`office_ratslam`]'s values.
    #[serde(default = "office_ratslam", deserialize_with = "over_office_ratslam")]
    pub ratslam: RatSlamParams,
    /// `[navigate.object]`: object mode at the cue's "object"; absent, the cue only
    /// reports.
    #[serde(default)]
    pub object: Option<ObjectModeConfig>,
    /// Whether a recognised object becomes a landmark in the planar map [true]; false is
    /// the terrain-only baseline, with the same stops (only the fusion differs).
    #[serde(default = "yes")]
    pub fusion: bool,
    /// The kidnapped robot [false]: at the start of the last lap the base is carried from
    /// the first waypoint to the middle one (the office: from the corridor into the east
    /// room), the legs between cut out and the odometry reading no motion.
    #[serde(default)]
    pub kidnap: bool,
}

/// `[navigate.terrain]`: how the arm holds the array while the base drives (terrain
/// mode, thesis Ch 3 in the office).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TerrainConfig {
    /// Height of the arm's base link above the floor, on the wheeled base (m) [0.35].
    pub mount_height_m: f64,
    /// The array's position in the arm's base frame (m) [0, −0.48, −0.1]: beside the
    /// base on its right, 0.25 m above the floor, 0.12 m from a wall the route keeps
    /// 0.65 m from.
    pub array_position_m: [f64; 3],
    /// The array's roll, pitch, yaw in the arm's base frame (deg) [−90, 0, −90]: its
    /// snout (whisking forward, the array's +z) along the base's heading and the A–C
    /// whiskers (its +x side) towards the base's right (−y), where the route keeps the
    /// walls it follows, like a rat running along a wall.
    pub array_rpy_deg: [f64; 3],
}

impl Default for TerrainConfig {
    fn default() -> Self {
        Self {
            mount_height_m: 0.35,
            array_position_m: [0.0, -0.48, -0.1],
            array_rpy_deg: [-90.0, 0.0, -90.0],
        }
    }
}

impl TerrainConfig {
    /// Checks the fields; names the field.
    fn validate(&self) -> std::result::Result<(), Invalid> {
        let finite = self.array_position_m.iter().chain(&self.array_rpy_deg);
        if !finite.clone().all(|v| v.is_finite()) {
            return Err(Invalid::field(
                "array_position_m / array_rpy_deg",
                "expected finite numbers",
            ));
        }
        let h = self.mount_height_m;
        if !(h.is_finite() && h > 0.0) {
            return Err(Invalid::field(
                "mount_height_m",
                format!("{h}: expected a length > 0 (m)"),
            ));
        }
        Ok(())
    }
}

/// Planar RatSLAM's parameters in the office: Table 3.1's, with pose cells of 0.1 m (one
/// update's drive at the base's default speed, as the maze's 15 mm cells are one of its
/// updates, §3.1.2) and 60 × 60 of them (a 6 m wrap).
pub fn office_ratslam() -> RatSlamParams {
    let mut p = RatSlamParams::default();
    p.pose_cells.cell_size_m = 0.1;
    p.pose_cells.dim_xy = 60;
    p
}

/// `[navigate.ratslam]` over [`office_ratslam`]: the fields given replace the office's.
fn over_office_ratslam<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<RatSlamParams, D::Error> {
    use serde::de::Error as _;
    let given = toml::Table::deserialize(d)?;
    let mut table = toml::Table::try_from(office_ratslam()).map_err(D::Error::custom)?;
    crate::base::merge(&mut table, given);
    table
        .try_into()
        .map_err(|e: toml::de::Error| D::Error::custom(e.message()))
}

/// `[navigate.base]`: the wheeled base.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BaseConfig {
    /// Radius of the base's footprint (m) [0.3].
    pub radius_m: f64,
    /// Driving speed (m/s) [0.1].
    pub speed_m_s: f64,
    /// Turning rate in place (deg/s) [30].
    pub turn_rate_deg_s: f64,
    /// Least clearance kept from walls, posts and objects along the route (m) [0.05].
    pub clearance_m: f64,
}

impl Default for BaseConfig {
    fn default() -> Self {
        Self {
            radius_m: 0.3,
            speed_m_s: 0.1,
            turn_rate_deg_s: 30.0,
            clearance_m: 0.05,
        }
    }
}

fn two() -> usize {
    2
}
fn yes() -> bool {
    true
}

impl NavigateConfig {
    /// Checks every field that does not need the environment; names the field.
    pub fn validate(&self, file: &Path, office: Option<&FloorPlan>) -> Result {
        let bad =
            |field: &str, msg: String| Err(Error::field(file, &format!("navigate.{field}"), msg));
        let Some(plan) = office else {
            return Err(Error::field(
                file,
                "navigate",
                "[navigate] drives round an office: expected an [office] section",
            ));
        };
        if self.route_m.len() < 2 {
            return bad(
                "route_m",
                format!(
                    "{} waypoint(s): expected at least 2 [x, y] points",
                    self.route_m.len()
                ),
            );
        }
        for (i, p) in self.route_m.iter().enumerate() {
            if let Some(msg) = plan.off_floor(*p, "floor") {
                return bad(&format!("route_m[{i}]"), msg);
            }
            let next = self.route_m[(i + 1) % self.route_m.len()];
            if next == *p {
                return bad(
                    &format!("route_m[{i}]"),
                    "the same point as the next waypoint".into(),
                );
            }
        }
        if !(1..=MAX_LAPS).contains(&self.laps) {
            return bad("laps", format!("{}: expected 1 to {MAX_LAPS}", self.laps));
        }
        if self.kidnap && self.laps < 2 {
            return bad(
                "kidnap",
                format!(
                    "the robot is kidnapped at the start of the last lap, after a first lap to \
                     know the office by: expected laps ≥ 2, got {}",
                    self.laps
                ),
            );
        }
        let b = &self.base;
        for (name, v) in [
            ("radius_m", b.radius_m),
            ("speed_m_s", b.speed_m_s),
            ("turn_rate_deg_s", b.turn_rate_deg_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(
                    &format!("base.{name}"),
                    format!("{v}: expected a number > 0"),
                );
            }
        }
        if !(b.clearance_m.is_finite() && b.clearance_m >= 0.0) {
            return bad(
                "base.clearance_m",
                format!("{}: expected a length ≥ 0 (m)", b.clearance_m),
            );
        }
        self.odometry
            .validate()
            .map_err(|e| Error::field(file, "navigate.odometry", e))?;
        self.switch
            .validate()
            .map_err(|e| Error::field(file, "navigate.switch", e))?;
        self.terrain
            .validate()
            .map_err(|e| Error::field(file, &format!("navigate.terrain.{}", e.field), e.message))?;
        self.ratslam
            .validate()
            .map_err(|e| Error::field(file, "navigate.ratslam", e))
    }

    /// The route's legs: each waypoint to the next, the last back to the first.
    pub fn legs(&self) -> Vec<(Point2<f64>, Point2<f64>)> {
        let n = self.route_m.len();
        (0..n)
            .map(|i| {
                (
                    Point2::from(self.route_m[i]),
                    Point2::from(self.route_m[(i + 1) % n]),
                )
            })
            .collect()
    }

    /// Checks that the base's footprint keeps `base.clearance_m` from the office's walls
    /// and posts and from each object's plan outline (the bounding rectangle of its
    /// mesh in the world, `objects` its pieces) all along the route; names the leg and
    /// what it comes too close to.
    pub fn check_route(&self, file: &Path, plan: &FloorPlan, objects: &Environment) -> Result {
        let need = self.base.radius_m + self.base.clearance_m;
        for (i, (a, b)) in self.legs().into_iter().enumerate() {
            let walls = plan.clearance(a, b);
            let things = objects.pieces.iter().map(|p| {
                let (lo, hi) = plan_rectangle(p);
                let corners = [lo, Point2::new(hi.x, lo.y), hi, Point2::new(lo.x, hi.y)];
                let inside = [a, b]
                    .iter()
                    .any(|q| (lo.x..=hi.x).contains(&q.x) && (lo.y..=hi.y).contains(&q.y));
                let d = match inside {
                    true => 0.0,
                    false => (0..4)
                        .map(|k| segment_distance(a, b, corners[k], corners[(k + 1) % 4]))
                        .fold(f64::INFINITY, f64::min),
                };
                (d, p.name.clone())
            });
            let nearest = walls
                .into_iter()
                .chain(things)
                .min_by(|x, y| x.0.total_cmp(&y.0));
            if let Some((d, what)) = nearest
                && d < need
            {
                let to = (i + 1) % self.route_m.len();
                return Err(Error::field(
                    file,
                    &format!("navigate.route_m[{i}]"),
                    format!(
                        "the leg from waypoint {i} to {to} passes {d:.3} m from {what}: the \
                         base needs {need:.3} m (navigate.base.radius_m {} + clearance_m {})",
                        self.base.radius_m, self.base.clearance_m
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The heading of each leg (rad, from +x towards +y).
    pub fn headings(&self) -> Vec<f64> {
        self.legs()
            .iter()
            .map(|(a, b)| (b.y - a.y).atan2(b.x - a.x))
            .collect()
    }

    /// The route's length (m) and the time a lap takes at the base's speeds (s): the
    /// legs driven straight, a turn in place at each waypoint.
    pub fn lap(&self) -> (f64, f64) {
        let length: f64 = self.legs().iter().map(|(a, b)| (b - a).norm()).sum();
        let h = self.headings();
        let turns: f64 = (0..h.len())
            .map(|i| whisker_slam::pose::wrap(h[(i + 1) % h.len()] - h[i]).abs())
            .sum();
        let time = length / self.base.speed_m_s + turns.to_degrees() / self.base.turn_rate_deg_s;
        (length, time)
    }

    /// What `whisker check` says of the route, the base, its odometry and the cue.
    pub fn describe(&self) -> String {
        let (length, time) = self.lap();
        let b = &self.base;
        let s = &self.switch;
        format!(
            "navigate   route of {} waypoints, {length:.2} m a lap, {} laps: {:.1} min of driving \
             (base r {} m at {} m/s, turns {}°/s)\n           odometry {} (Thrun et al. 2005 \
             §5.4); mode switch: an object is an outline ≤ {} m with free space past both \
             ends, a wall longer (§7.1)",
            self.route_m.len(),
            self.laps,
            time * self.laps as f64 / 60.0,
            b.radius_m,
            b.speed_m_s,
            b.turn_rate_deg_s,
            match self.odometry.enabled {
                true => format!("α = {:?}", self.odometry.alpha),
                false => "noise-free".into(),
            },
            s.max_object_m
        ) + &self.describe_object_mode()
    }

    /// The lines of [`describe`](Self::describe) on object mode, the fusion and the kidnap.
    fn describe_object_mode(&self) -> String {
        let mut out = match &self.object {
            None => "\nobject     none: the cue only reports (no [navigate.object])".to_string(),
            Some(o) => format!(
                "\nobject     at \"object\" the base stops, {} and the Ch 6 closed loop identifies \
                 it against {:?} in ≤ {} whisks; {}",
                match o.dock {
                    crate::object_mode::DockBy::Arm => "the arm turns to face it",
                    crate::object_mode::DockBy::Base => "the base turns and drives up to it",
                },
                o.explore.maps.keys().collect::<Vec<_>>(),
                o.explore.max_iterations,
                match self.fusion {
                    true => "an identity becomes a landmark in the planar map (fusion)",
                    false => "identities are not fed to the planar map (terrain-only baseline)",
                }
            ),
        };
        if self.kidnap {
            out += "\nkidnap     at the start of the last lap the base is carried from the first \
                    waypoint to the middle one, the odometry reading no motion";
        }
        out
    }
}

/// The axis-aligned rectangle (plan) round a piece's mesh in the world.
pub fn plan_rectangle(p: &whisker_sim::environment::Piece) -> (Point2<f64>, Point2<f64>) {
    let mut lo = Point2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for v in &p.mesh.vertices {
        let w = p.pose * v;
        lo = Point2::new(lo.x.min(w.x), lo.y.min(w.y));
        hi = Point2::new(hi.x.max(w.x), hi.y.max(w.y));
    }
    (lo, hi)
}
