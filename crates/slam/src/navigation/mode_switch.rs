//! The cue that switches a whiskered mobile robot from terrain to object exploration
//! (thesis §7.1: "the challenge of identifying the cues needed to switch between modes
//! ... how the system can differentiate between obstacles and objects, such as
//! encountering a wall or when encountering a large box shaped object"; Fig 5.1).
//!
//! The thesis names the problem, not a cue. This one reads the plan view (the floor
//! plane) of what the array touched and swept through over the last whisks:
//!
//! 1. **The outline**: the contacts joined by single linkage (points closer than
//!    [`ModeSwitch::link_gap_m`]) into the cluster holding the newest contact.
//! 2. **Extent**: the cluster's diameter (largest distance between two of its contacts).
//!    An outline longer than [`ModeSwitch::max_object_m`] — more than the largest object
//!    the robot is meant to pick out — is an obstacle: a wall, a room's corner, or a box
//!    too large to be told from one ("a large box shaped object" is deliberately an
//!    obstacle here).
//! 3. **A free-standing outline**: the cluster is an object only when both of its ends
//!    (the two contacts that realise the diameter) are known to be followed by free
//!    space: a swept whisker that touched nothing ([`Outline::free`]) within
//!    [`ModeSwitch::end_window_m`] of the end, outward of it (further from the
//!    cluster's centroid than the end is, measured along the end's outward direction).
//!    A wall's end at a door is free on one side only; a room's corner on neither.
//! 4. Anything else is **undecided**: too few contacts, or a short outline whose ends
//!    are not yet both seen free — the robot keeps following its route (terrain mode)
//!    and asks again after the next whisk, when the outline has either grown past
//!    `max_object_m` (a wall) or closed (an object).
//!
//! The outline's shape ([`Shape`]: a line, an arc, a corner of two lines) is reported
//! beside the verdict for the logs and recordings; the verdict does not depend on it.

use crate::invalid::Invalid;
use nalgebra::{Point2, Vector2};

/// The cue's parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModeSwitch {
    /// The longest outline taken for an object (m): the catalogue's largest plan
    /// diagonal with a margin [0.6].
    pub max_object_m: f64,
    /// Contacts closer than this belong to one outline (m) [0.1].
    pub link_gap_m: f64,
    /// How far beyond an end of the outline a free sweep counts as its end (m) [0.1].
    pub end_window_m: f64,
    /// Fewest contacts in the outline before any verdict [6].
    pub min_contacts: usize,
    /// Largest RMS distance of the contacts from a fitted line or circle for the shape
    /// to be called a line, a corner or an arc (m) [0.01].
    pub fit_tolerance_m: f64,
    /// How many of the latest whisks the outline is built from [20]: the caller's
    /// memory of the plan, two metres of driving at 0.1 m a whisk (older contacts carry
    /// more odometric drift).
    pub window_whisks: usize,
}

impl Default for ModeSwitch {
    fn default() -> Self {
        Self {
            max_object_m: 0.6,
            link_gap_m: 0.1,
            end_window_m: 0.1,
            min_contacts: 6,
            fit_tolerance_m: 0.01,
            window_whisks: 20,
        }
    }
}

/// What the array has touched and swept through, in the plan (any planar frame fixed
/// to the floor: the world, or the robot's map).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outline {
    /// Contact points, oldest first (m).
    pub contacts: Vec<Point2<f64>>,
    /// Points a whisker swept through without touching anything (e.g. the tips of the
    /// whiskers of a whisk at their largest protraction) (m).
    pub free: Vec<Point2<f64>>,
}

/// The cue's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// An obstacle: keep following the route (terrain mode).
    Wall,
    /// A free-standing object: stop and identify it (object mode).
    Object,
    /// Not yet known: keep following the route and ask again.
    Undecided,
}

/// The plan-view shape of an outline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// One straight line (a flat face).
    Line,
    /// A circular arc (a round face).
    Arc,
    /// Two straight lines meeting (a corner: convex for a box, concave for a room).
    Corner,
    /// None of these within the tolerance.
    Irregular,
}

/// The cue's answer with what it was based on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decision {
    /// Wall, object or undecided.
    pub verdict: Verdict,
    /// The outline's shape.
    pub shape: Shape,
    /// The outline's diameter (m).
    pub extent_m: f64,
    /// Contacts in the outline.
    pub contacts: usize,
    /// Whether each end (the diameter's two contacts) was seen followed by free space.
    pub free_ends: [bool; 2],
    /// The outline's centroid (plan, m).
    pub centre: Point2<f64>,
}

impl ModeSwitch {
    /// Checks the parameters; the message names the field.
    pub fn validate(&self) -> Result<(), Invalid> {
        for (name, v) in [
            ("max_object_m", self.max_object_m),
            ("link_gap_m", self.link_gap_m),
            ("end_window_m", self.end_window_m),
            ("fit_tolerance_m", self.fit_tolerance_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} {v}: expected a positive length (m)").into());
            }
        }
        if self.window_whisks == 0 {
            return Err("window_whisks 0: expected at least 1".into());
        }
        if self.min_contacts < 2 {
            return Err(format!("min_contacts {}: expected at least 2", self.min_contacts).into());
        }
        Ok(())
    }

    /// The verdict on `outline` (see the module documentation).
    pub fn decide(&self, outline: &Outline) -> Decision {
        let cluster = newest_cluster(&outline.contacts, self.link_gap_m);
        let centre = centroid(&cluster);
        let (extent, ends) = diameter(&cluster);
        let free_ends = ends.map(|e| self.end_is_free(e, centre, &outline.free));
        let verdict = if cluster.len() < self.min_contacts {
            Verdict::Undecided
        } else if extent > self.max_object_m {
            Verdict::Wall
        } else if free_ends == [true, true] {
            Verdict::Object
        } else {
            Verdict::Undecided
        };
        Decision {
            verdict,
            shape: shape(&cluster, self.fit_tolerance_m),
            extent_m: extent,
            contacts: cluster.len(),
            free_ends,
            centre,
        }
    }

    /// Whether a free point lies within `end_window_m` of `end` and outward of it.
    fn end_is_free(&self, end: Point2<f64>, centre: Point2<f64>, free: &[Point2<f64>]) -> bool {
        let out = end - centre;
        free.iter()
            .any(|f| (f - end).norm() <= self.end_window_m && (f - end).dot(&out) > 0.0)
    }
}

/// The contacts linked (gap < `gap`) to the newest one, by single linkage.
fn newest_cluster(points: &[Point2<f64>], gap: f64) -> Vec<Point2<f64>> {
    let Some(last) = points.len().checked_sub(1) else {
        return Vec::new();
    };
    let mut member = vec![false; points.len()];
    member[last] = true;
    let mut queue = vec![last];
    while let Some(i) = queue.pop() {
        for (j, m) in member.iter_mut().enumerate() {
            if !*m && (points[j] - points[i]).norm() < gap {
                *m = true;
                queue.push(j);
            }
        }
    }
    points
        .iter()
        .zip(member)
        .filter_map(|(p, m)| m.then_some(*p))
        .collect()
}

fn centroid(points: &[Point2<f64>]) -> Point2<f64> {
    let n = points.len().max(1) as f64;
    Point2::from(points.iter().map(|p| p.coords).sum::<Vector2<f64>>() / n)
}

/// The largest distance between two points and those two points (0 and the origin for
/// an empty set).
fn diameter(points: &[Point2<f64>]) -> (f64, [Point2<f64>; 2]) {
    let mut best = (
        0.0,
        [points.first().copied().unwrap_or_else(Point2::origin); 2],
    );
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            let d = (b - a).norm();
            if d > best.0 {
                best = (d, [*a, *b]);
            }
        }
    }
    best
}

/// RMS distance of `points` from their total-least-squares line.
fn line_residual(points: &[Point2<f64>]) -> f64 {
    if points.len() < 3 {
        return 0.0;
    }
    let c = centroid(points);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = p - c;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    // The smaller eigenvalue of the scatter matrix is the sum of squared distances.
    let half_trace = (sxx + syy) / 2.0;
    let smallest = half_trace - (((sxx - syy) / 2.0).powi(2) + sxy * sxy).sqrt();
    (smallest.max(0.0) / points.len() as f64).sqrt()
}

/// RMS distance of `points` from their algebraic (Kåsa) least-squares circle, and its
/// radius; None when the points do not fix a circle.
fn circle_fit(points: &[Point2<f64>]) -> Option<(f64, f64)> {
    if points.len() < 3 {
        return None;
    }
    // x² + y² + D x + E y + F = 0, least squares in (D, E, F), centred for conditioning.
    let c = centroid(points);
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = nalgebra::Vector3::<f64>::zeros();
    for p in points {
        let d = p - c;
        let row = nalgebra::Vector3::new(d.x, d.y, 1.0);
        ata += row * row.transpose();
        atb -= row * d.norm_squared();
    }
    let s = ata.lu().solve(&atb)?;
    let centre = Vector2::new(-s.x / 2.0, -s.y / 2.0);
    let r2 = centre.norm_squared() - s.z;
    if !(r2.is_finite() && r2 > 0.0) {
        return None;
    }
    let r = r2.sqrt();
    let ss: f64 = points
        .iter()
        .map(|p| ((p - c - centre).norm() - r).powi(2))
        .sum();
    Some(((ss / points.len() as f64).sqrt(), r))
}

/// Distance from `p` to the segment from `a` to `b`.
fn to_segment(p: &Point2<f64>, a: Point2<f64>, b: Point2<f64>) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// The outline's shape: a line, else an arc (of a radius shorter than ten times its
/// extent: a flatter arc is a line), else two lines meeting at the contact farthest from
/// the chord between the ends (each contact on the nearer of the two), else irregular.
fn shape(points: &[Point2<f64>], tolerance: f64) -> Shape {
    if points.len() < 3 || line_residual(points) <= tolerance {
        return Shape::Line;
    }
    let (extent, [a, b]) = diameter(points);
    if let Some((residual, radius)) = circle_fit(points)
        && residual <= tolerance
        && radius < 10.0 * extent
    {
        return Shape::Arc;
    }
    let chord = (b - a) / extent;
    let off_chord = |p: &Point2<f64>| (p - a).perp(&chord).abs();
    let apex = points
        .iter()
        .copied()
        .max_by(|p, q| off_chord(p).total_cmp(&off_chord(q)))
        .expect("at least three points");
    let (near_a, near_b): (Vec<_>, Vec<_>) = points
        .iter()
        .partition(|p| to_segment(p, a, apex) <= to_segment(p, apex, b));
    if [near_a, near_b]
        .iter()
        .all(|side| line_residual(side) <= tolerance)
    {
        Shape::Corner
    } else {
        Shape::Irregular
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// `n` points evenly from `a` to `b`.
    fn segment(a: [f64; 2], b: [f64; 2], n: usize) -> Vec<Point2<f64>> {
        (0..n)
            .map(|i| {
                let s = i as f64 / (n - 1) as f64;
                Point2::new(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]))
            })
            .collect()
    }

    /// The contacts of a robot whisking sideways along a wall (y = 0.3) from x = 0 to
    /// `to`, and the sweeps that found nothing (beyond the wall's end, if it ends).
    fn along_wall(to: f64, ends_at: Option<f64>) -> Outline {
        let contacts = segment([0.0, 0.3], [to, 0.3], (to / 0.02) as usize + 1);
        let free = ends_at
            .map(|x| segment([x + 0.03, 0.3], [x + 0.2, 0.3], 5))
            .unwrap_or_default();
        Outline { contacts, free }
    }

    #[test]
    fn a_long_wall_is_an_obstacle() {
        let d = ModeSwitch::default().decide(&along_wall(1.0, None));
        assert_eq!(d.verdict, Verdict::Wall);
        assert_eq!(d.shape, Shape::Line);
        assert!((d.extent_m - 1.0).abs() < 1e-9, "{}", d.extent_m);
    }

    #[test]
    fn a_short_stretch_of_wall_stays_undecided_until_it_grows_even_at_a_door() {
        let cue = ModeSwitch::default();
        // 30 cm of wall, ending at a door: free beyond one end only.
        let d = cue.decide(&along_wall(0.3, Some(0.3)));
        assert_eq!(d.verdict, Verdict::Undecided);
        assert_eq!(d.free_ends.iter().filter(|f| **f).count(), 1);
        // The robot drove on: the outline now runs 0.7 m.
        let mut o = along_wall(0.3, Some(0.3));
        o.contacts = segment([-0.4, 0.3], [0.3, 0.3], 36);
        assert_eq!(cue.decide(&o).verdict, Verdict::Wall);
    }

    #[test]
    fn a_room_corner_is_never_an_object() {
        // Two 0.4 m walls meeting at (0.4, 0.3), no free space beyond either end.
        let mut contacts = segment([0.0, 0.3], [0.4, 0.3], 21);
        contacts.extend(segment([0.4, 0.3], [0.4, -0.1], 21).into_iter().skip(1));
        let cue = ModeSwitch::default();
        let d = cue.decide(&Outline {
            contacts: contacts.clone(),
            free: Vec::new(),
        });
        assert_eq!(d.shape, Shape::Corner);
        assert_eq!(d.verdict, Verdict::Undecided);
        // Longer legs: past the largest object, an obstacle.
        let mut contacts = segment([-0.2, 0.3], [0.4, 0.3], 31);
        contacts.extend(segment([0.4, 0.3], [0.4, -0.3], 31).into_iter().skip(1));
        let d = cue.decide(&Outline {
            contacts,
            free: Vec::new(),
        });
        assert_eq!((d.verdict, d.shape), (Verdict::Wall, Shape::Corner));
    }

    #[test]
    fn a_box_seen_round_its_corner_with_free_space_beyond_is_an_object() {
        // Two faces of a 0.3 m box (corner at the origin), swept free past both ends.
        let mut contacts = segment([-0.3, 0.0], [0.0, 0.0], 16);
        contacts.extend(segment([0.0, 0.0], [0.0, 0.3], 16).into_iter().skip(1));
        let free = vec![Point2::new(-0.36, 0.0), Point2::new(0.0, 0.37)];
        let cue = ModeSwitch::default();
        let d = cue.decide(&Outline {
            contacts: contacts.clone(),
            free: free.clone(),
        });
        assert_eq!((d.verdict, d.shape), (Verdict::Object, Shape::Corner));
        // Free space only on the inside of the box's end is no evidence.
        let d = cue.decide(&Outline {
            contacts: contacts.clone(),
            free: vec![Point2::new(-0.25, 0.05), Point2::new(0.0, 0.37)],
        });
        assert_eq!(d.verdict, Verdict::Undecided);
        // Without the free sweeps it is undecided (it could be a room's corner).
        let d = cue.decide(&Outline {
            contacts,
            free: Vec::new(),
        });
        assert_eq!(d.verdict, Verdict::Undecided);
    }

    #[test]
    fn a_cylinder_is_an_object_and_an_arc() {
        // 120° of a 0.1 m radius cylinder centred at (0, 0.5), free beyond both ends.
        let arc = |a: f64, r: f64| Point2::new(r * a.cos(), 0.5 - r * a.sin());
        let contacts: Vec<_> = (0..25)
            .map(|i| arc(PI / 6.0 + i as f64 * (2.0 * PI / 3.0) / 24.0, 0.1))
            .collect();
        let free = vec![arc(PI / 6.0 - 0.4, 0.12), arc(5.0 * PI / 6.0 + 0.4, 0.12)];
        let d = ModeSwitch::default().decide(&Outline { contacts, free });
        assert_eq!((d.verdict, d.shape), (Verdict::Object, Shape::Arc));
        assert!(
            (d.extent_m - 0.1 * 3f64.sqrt()).abs() < 1e-3,
            "{}",
            d.extent_m
        );
    }

    #[test]
    fn only_the_newest_outline_counts_and_few_contacts_decide_nothing() {
        let cue = ModeSwitch::default();
        // A long wall touched earlier, 0.5 m away from a small object touched now.
        let mut contacts = segment([0.0, 1.0], [1.5, 1.0], 76);
        let object = segment([0.5, 0.2], [0.7, 0.2], 11);
        contacts.extend(object.iter().copied());
        let free = vec![Point2::new(0.45, 0.2), Point2::new(0.76, 0.2)];
        let d = cue.decide(&Outline {
            contacts: contacts.clone(),
            free: free.clone(),
        });
        assert_eq!((d.verdict, d.contacts), (Verdict::Object, 11));
        assert!((d.centre - Point2::new(0.6, 0.2)).norm() < 1e-9);
        // The newest contact on the wall again: the wall's outline, an obstacle.
        contacts.push(Point2::new(1.5, 1.0));
        assert_eq!(
            cue.decide(&Outline {
                contacts,
                free: free.clone()
            })
            .verdict,
            Verdict::Wall
        );
        let few = Outline {
            contacts: object[..5].to_vec(),
            free,
        };
        assert_eq!(cue.decide(&few).verdict, Verdict::Undecided);
        assert_eq!(cue.decide(&Outline::default()).verdict, Verdict::Undecided);
    }

    #[test]
    fn a_scattered_outline_is_irregular_and_parameters_are_checked() {
        let contacts: Vec<_> = (0..20)
            .map(|i| {
                let a = i as f64 * 2.4;
                Point2::new(0.1 * a.cos() * (1.0 + 0.5 * (3.0 * a).sin()), 0.1 * a.sin())
            })
            .collect();
        assert_eq!(shape(&contacts, 0.005), Shape::Irregular);
        let bad = ModeSwitch {
            link_gap_m: -1.0,
            ..ModeSwitch::default()
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("link_gap_m")
        );
        assert!(ModeSwitch::default().validate().is_ok());
    }
}
