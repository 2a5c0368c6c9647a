//! Kinematic sensing: the thesis' "anticipated intersect" (§4.1.2.3, Fig 4.2a).
//!
//! Each whisker is rigid and straight. At a fixed array pose it is swept from its
//! retraction limit to its protraction limit in steps of 1°; at each step the shaft is a
//! segment from the shaft base (the follicle's pivot depth out from the pivot) to the
//! tip. The first step at which the shaft meets the environment is the contact angle,
//! and of the intersections at that step the one nearest the base is the contact point;
//! the contacted triangle's outward normal gives the slope (Eq 6.12–6.14).
//!
//! How it is computed (exactly, not by sampling rays): all shaft positions of one sweep
//! lie in the sweep plane through the pivot, normal to the whisk axis. The environment's
//! triangles near the pivot (a BVH query against the plane and the ball the shaft
//! reaches) are cut by that plane into 2-D segments; each segment, clipped to the ball,
//! covers an interval of sweep angles, which gives the first 1° step that reaches it;
//! at the first step over all segments the nearest intersection along the shaft is the
//! contact. This is what makes a whole array's sweep cost microseconds.
//!
//! This is the ground truth for physics runs and, with [`super::noise`], a sensing mode
//! of its own for fast batch trials (§6.1.3.1.2).

use super::noise::ContactNoise;
use crate::environment::{Environment, Mesh};
use crate::whisker::array::{Module, PROTRACTED, RETRACTED};
use crate::whisker::control::WhiskingPattern;
use crate::whisker::strategies::{SpreadState, WhiskingControl, side};
use nalgebra::{Isometry3, Point3, Vector2, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use whisker_slam::contact::{Contact, ContactCycle};
use whisker_slam::rng::{self, StreamRng};

/// Sweep step of the thesis (1°).
pub const STEP_RAD: f64 = std::f64::consts::PI / 180.0;

/// The environment prepared for sweeps: world-frame triangles, their outward normals and
/// a bounding-volume hierarchy over them.
pub struct SweepTarget {
    mesh: Mesh,
    normals: Vec<Vector3<f64>>,
    /// Per triangle: whether it is two-sided (a soup's, whose winding says nothing).
    two_sided: Vec<bool>,
    bvh: Bvh,
}

/// One rigid whisker of the sweep: its module and straight shaft.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidWhisker {
    /// The module (pose in the array frame, shaft length).
    pub module: Module,
    /// Distance from the pivot to the shaft's base (m): the follicle's pivot depth.
    pub base_offset: f64,
    /// Retraction limit (rad).
    pub retracted: f64,
    /// Protraction limit (rad).
    pub protracted: f64,
    /// Sweep step (rad).
    pub step: f64,
}

impl RigidWhisker {
    /// A whisker of `module` with the thesis' 40°–140° range in 1° steps.
    pub fn new(module: Module, base_offset: f64) -> Self {
        Self {
            module,
            base_offset,
            retracted: RETRACTED,
            protracted: PROTRACTED,
            step: STEP_RAD,
        }
    }

    /// Number of sweep steps after the first (100 for 40°–140° in 1°).
    pub fn steps(&self) -> usize {
        ((self.protracted - self.retracted) / self.step + 1e-9).floor() as usize
    }

    /// Whisk angle of step k.
    pub fn angle(&self, k: usize) -> f64 {
        self.retracted + k as f64 * self.step
    }

    /// The point of the straight shaft at `radial_distance` from its base (world), at
    /// whisk angle `theta` with the array at `array_pose`: contact localisation in the
    /// simulator's frames (thesis Eq 5.1–5.2; the whisker frame turns about its x axis
    /// and the shaft lies along its z axis, starting `base_offset` out from the pivot).
    pub fn shaft_point(
        &self,
        array_pose: &Isometry3<f64>,
        theta: f64,
        radial_distance: f64,
    ) -> Point3<f64> {
        array_pose
            * self.module.whisker_pose(theta)
            * Point3::new(0.0, 0.0, self.base_offset + radial_distance)
    }
}

/// An anticipated contact: where the rigid whisker first meets the environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intersect {
    /// Sweep step (0 = retraction limit).
    pub step: usize,
    /// Whisk angle (rad).
    pub angle: f64,
    /// Distance from the shaft base along the shaft (m); 0 if the environment reaches
    /// inside the follicle.
    pub radial_distance: f64,
    /// Contact point (world).
    pub point: Point3<f64>,
    /// Outward unit normal of the contacted triangle (world).
    pub normal: Vector3<f64>,
    /// Pose of the whisker base frame F at the contact angle (world): x whisk axis,
    /// y sweep direction, z along the shaft.
    pub base_frame: Isometry3<f64>,
}

impl Intersect {
    /// Slope of the contacted surface (Eq 6.12–6.14): n_x = −n·x_F, n_y = −n·y_F,
    /// slope = n_y / n_x.
    pub fn slope(&self) -> f64 {
        let r = self.base_frame.rotation;
        let nx = -self.normal.dot(&(r * Vector3::x()));
        let ny = -self.normal.dot(&(r * Vector3::y()));
        ny / nx
    }
}

fn pv(v: &Point3<f64>) -> PVector {
    PVector::new(v.x, v.y, v.z)
}

impl SweepTarget {
    /// The pieces prepared for the kinematic sweep (soups' triangles two-sided).
    pub fn of(environment: &Environment) -> Self {
        let two_sided = environment
            .pieces
            .iter()
            .flat_map(|p| std::iter::repeat_n(p.soup, p.mesh.triangles.len()))
            .collect();
        Self::with_two_sided(environment.world_mesh(), two_sided)
    }

    /// Prepares a world-frame mesh of closed solids (degenerate triangles are skipped).
    pub fn new(mesh: Mesh) -> Self {
        let n = mesh.triangles.len();
        Self::with_two_sided(mesh, vec![false; n])
    }

    /// Prepares a world-frame mesh in which the triangles flagged in `two_sided` (one
    /// flag per triangle) belong to triangle soups: a contact on one of them takes the
    /// normal facing the whisker's base, as the outward normal of a solid does.
    pub fn with_two_sided(mesh: Mesh, two_sided: Vec<bool>) -> Self {
        assert_eq!(
            two_sided.len(),
            mesh.triangles.len(),
            "one flag per triangle"
        );
        let normals: Vec<Vector3<f64>> = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
                (b - a)
                    .cross(&(c - a))
                    .try_normalize(0.0)
                    .unwrap_or_else(Vector3::zeros)
            })
            .collect();
        let leaves: Vec<Aabb> = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
                Aabb::new(pv(&a.inf(&b).inf(&c)), pv(&a.sup(&b).sup(&c)))
            })
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::default(), &leaves);
        Self {
            mesh,
            normals,
            two_sided,
            bvh,
        }
    }

    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.mesh.triangles.len()
    }

    /// Sweeps one whisker at the given array pose (world); None if it touches nothing.
    pub fn sweep(&self, whisker: &RigidWhisker, array_pose: &Isometry3<f64>) -> Option<Intersect> {
        if self.mesh.triangles.is_empty() {
            return None;
        }
        let frame = |theta: f64| array_pose * whisker.module.whisker_pose(theta);
        let start = frame(whisker.retracted);
        let pivot = Point3::from(start.translation.vector);
        let axis = start.rotation * Vector3::x();
        let e0 = start.rotation * Vector3::z();
        // F = M·Rx(π/2 − θ): as θ grows the shaft z_F turns towards y_F = z_F × x_F.
        let e1 = e0.cross(&axis);
        let reach = whisker.base_offset + whisker.module.beam.length;
        let abs_axis = axis.abs();
        let candidates = self.bvh.leaves(|node| {
            let (lo, hi) = (node.mins(), node.maxs());
            let lo = Vector3::new(lo.x, lo.y, lo.z);
            let hi = Vector3::new(hi.x, hi.y, hi.z);
            let centre = (lo + hi) / 2.0;
            let half = (hi - lo) / 2.0;
            let to_plane = axis.dot(&(centre - pivot.coords)).abs() <= abs_axis.dot(&half);
            let nearest = pivot.coords.sup(&lo).inf(&hi);
            to_plane && (nearest - pivot.coords).norm_squared() <= reach * reach
        });
        let last = whisker.steps();
        let mut best: Option<usize> = None; // the first step reached
        let mut hits: Vec<(Vector2<f64>, Vector2<f64>, usize)> = Vec::new();
        for t in candidates {
            let t = t as usize;
            let Some((a, b)) = self.cut(t, &pivot, &axis, &e0, &e1) else {
                continue;
            };
            let Some((a, b)) = clip_to_disc(a, b, reach) else {
                continue;
            };
            if let Some(k) = first_step(a, b, whisker.step, last)
                && best.is_none_or(|bk| k <= bk)
            {
                if best.is_some_and(|bk| k < bk) {
                    hits.clear();
                }
                best = Some(k);
                hits.push((a, b, t));
            }
        }
        let k = best?;
        let psi = k as f64 * whisker.step;
        let u = Vector2::new(psi.cos(), psi.sin());
        let (r, t) = hits
            .iter()
            .filter_map(|&(a, b, t)| ray_segment(u, a, b).map(|r| (r, t)))
            .min_by(|x, y| x.0.total_cmp(&y.0))?;
        let angle = whisker.angle(k);
        let base_frame = frame(angle);
        let direction = base_frame.rotation * Vector3::z();
        let point = pivot + direction * r;
        let mut normal = self.normals[t];
        let base = pivot + direction * whisker.base_offset;
        if self.two_sided[t] && normal.dot(&(base - point)) < 0.0 {
            normal = -normal;
        }
        Some(Intersect {
            step: k,
            angle,
            radial_distance: (r - whisker.base_offset).max(0.0),
            point,
            normal,
            base_frame: base_frame * Isometry3::translation(0.0, 0.0, whisker.base_offset),
        })
    }

    /// Intersection of triangle `t` with the sweep plane, in plane coordinates about the
    /// pivot (None if it does not cross the plane or lies in it).
    fn cut(
        &self,
        t: usize,
        pivot: &Point3<f64>,
        axis: &Vector3<f64>,
        e0: &Vector3<f64>,
        e1: &Vector3<f64>,
    ) -> Option<(Vector2<f64>, Vector2<f64>)> {
        let v = self.mesh.triangles[t].map(|i| self.mesh.vertices[i as usize] - pivot);
        let s = v.map(|p| axis.dot(&p));
        if s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0) || s.iter().all(|&x| x == 0.0) {
            return None;
        }
        let mut points = [Vector3::zeros(); 3];
        let mut n = 0;
        for i in 0..3 {
            let j = (i + 1) % 3;
            if s[i] == 0.0 {
                points[n] = v[i];
                n += 1;
            } else if s[i] * s[j] < 0.0 {
                let w = s[i] / (s[i] - s[j]);
                points[n] = v[i] + (v[j] - v[i]) * w;
                n += 1;
            }
        }
        let to2 = |p: &Vector3<f64>| Vector2::new(e0.dot(p), e1.dot(p));
        match n {
            0 => None,
            1 => Some((to2(&points[0]), to2(&points[0]))),
            _ => Some((to2(&points[0]), to2(&points[1]))),
        }
    }
}

/// The part of segment ab inside the disc of radius `r` about the origin.
fn clip_to_disc(a: Vector2<f64>, b: Vector2<f64>, r: f64) -> Option<(Vector2<f64>, Vector2<f64>)> {
    let d = b - a;
    let (qa, qb, qc) = (d.dot(&d), 2.0 * a.dot(&d), a.dot(&a) - r * r);
    if qa == 0.0 {
        return (qc <= 0.0).then_some((a, b));
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let t0 = ((-qb - sq) / (2.0 * qa)).max(0.0);
    let t1 = ((-qb + sq) / (2.0 * qa)).min(1.0);
    (t0 <= t1).then(|| (a + d * t0, a + d * t1))
}

/// The first sweep step k (angle k·step from e0, 0 ≤ k ≤ last) whose ray from the origin
/// crosses segment ab.
fn first_step(a: Vector2<f64>, b: Vector2<f64>, step: f64, last: usize) -> Option<usize> {
    let (pa, pb) = (a.y.atan2(a.x), b.y.atan2(b.x));
    // The segment subtends the shorter arc between its end angles (< π unless it passes
    // through the pivot).
    let mut span = pb - pa;
    if span > std::f64::consts::PI {
        span -= std::f64::consts::TAU;
    } else if span < -std::f64::consts::PI {
        span += std::f64::consts::TAU;
    }
    let (lo, hi) = if span >= 0.0 {
        (pa, pa + span)
    } else {
        (pa + span, pa)
    };
    // Bring the arc's start into (−π, π].
    let shift = if lo <= -std::f64::consts::PI {
        std::f64::consts::TAU
    } else {
        0.0
    };
    let (lo, hi) = (lo + shift, hi + shift);
    let k = if lo <= 0.0 {
        if hi >= 0.0 { 0 } else { return None }
    } else {
        (lo / step).ceil() as usize
    };
    (k <= last && k as f64 * step <= hi + 1e-15).then_some(k)
}

/// Distance along the unit ray u from the origin to segment ab (None if it misses).
fn ray_segment(u: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>) -> Option<f64> {
    let d = b - a;
    let cross = |p: Vector2<f64>, q: Vector2<f64>| p.x * q.y - p.y * q.x;
    let denom = cross(u, d);
    if denom.abs() < 1e-300 {
        // Parallel: the ray runs along the segment; the nearer end if it is on the ray.
        let on = |p: Vector2<f64>| cross(u, p).abs() <= 1e-12 && u.dot(&p) >= 0.0;
        return [a, b]
            .into_iter()
            .filter(|&p| on(p))
            .map(|p| u.dot(&p))
            .min_by(f64::total_cmp);
    }
    let r = cross(a, d) / denom;
    let s = cross(a, u) / denom;
    (r >= 0.0 && (-1e-12..=1.0 + 1e-12).contains(&s)).then_some(r)
}

/// The whole array in kinematic sensing: one rigid whisker per module, its whisking
/// pattern (for the time of contact) and the contact noise, with one random stream per
/// whisker (`kinematic/whisker/NN` of the scenario seed).
///
/// The whisking strategies ([`crate::whisker::strategies`]) change the sweep where a
/// contact-triggered change is meaningful for a rigid whisker that reports its first
/// contact: RCP changes nothing (the sweep stops at the first contact anyway); spread
/// reduction sweeps the narrowed stroke (from where the last whisk's retraction ended to
/// the half-cycle's target, as the physics controller does), which changes the angles
/// reached and the times of contact; contact-induced asymmetry stops a side's sweep at
/// the time of its first detected contact, so that a whisker of that side whose contact
/// would come later touches nothing.
pub struct KinematicArray {
    /// The whiskers, in index order.
    pub whiskers: Vec<RigidWhisker>,
    /// Each whisker's whisking pattern.
    pub patterns: Vec<WhiskingPattern>,
    /// The contact noise.
    pub noise: ContactNoise,
    /// The last whisk's anticipated intersects before any noise: (whisker index, world
    /// point), every whisker that touched (ground truth for a recording).
    pub intersects: Vec<(usize, Point3<f64>)>,
    /// The whisking strategies.
    pub control: WhiskingControl,
    /// Spread reduction's state, and where each whisker's last retraction ended.
    spread: SpreadState,
    starts: Vec<f64>,
    rngs: Vec<StreamRng>,
}

impl KinematicArray {
    /// An array of `whiskers` (with their patterns), noise and seed.
    pub fn new(
        whiskers: Vec<RigidWhisker>,
        patterns: Vec<WhiskingPattern>,
        noise: ContactNoise,
        seed: u64,
    ) -> Self {
        let rngs = (0..whiskers.len())
            .map(|i| rng::substream(seed, &format!("kinematic/whisker/{i:02}")))
            .collect();
        let starts = patterns.iter().map(|p| p.retracted).collect();
        Self {
            whiskers,
            patterns,
            noise,
            intersects: Vec::new(),
            control: WhiskingControl::default(),
            spread: SpreadState::default(),
            starts,
            rngs,
        }
    }

    /// The same array whisking under `control`.
    pub fn with_control(mut self, control: WhiskingControl) -> Self {
        self.control = control;
        self
    }

    /// Each whisker's stroke this whisk: its pattern with the limits spread reduction
    /// sets (the start where the last retraction ended, the protraction target).
    fn strokes(&self) -> Vec<WhiskingPattern> {
        self.patterns
            .iter()
            .zip(&self.starts)
            .map(|(p, &start)| match self.control.spread_reduction {
                Some(sr) if self.spread.engaged => WhiskingPattern {
                    retracted: start,
                    protracted: sr.limits(p).1,
                    ..*p
                },
                Some(_) => WhiskingPattern {
                    retracted: start,
                    ..*p
                },
                None => *p,
            })
            .collect()
    }

    /// Spread reduction after a whisk with or without a detected contact: the state, and
    /// where each whisker's retraction ends (the narrowed limit while engaged).
    fn spread_after(&mut self, touched: bool) {
        let Some(sr) = self.control.spread_reduction else {
            return;
        };
        if touched {
            self.spread.contact();
        }
        for (start, p) in self.starts.iter_mut().zip(&self.patterns) {
            *start = if self.spread.engaged {
                sr.limits(p).0
            } else {
                p.retracted
            };
        }
        self.spread.end_cycle(sr.release_cycles);
    }

    /// Whether spread reduction is engaged (for the next whisk).
    pub fn narrowed(&self) -> bool {
        self.spread.engaged
    }

    /// One whisk cycle at a fixed array pose (world): every whisker swept, its
    /// anticipated contact turned into a [`Contact`] (array frame) with noise. The time
    /// of contact is when the open-loop protraction reaches the contact angle.
    pub fn sense(
        &mut self,
        target: &SweepTarget,
        index: u64,
        start_s: f64,
        array_pose: &Isometry3<f64>,
    ) -> ContactCycle {
        let mut contacts = Vec::new();
        self.intersects.clear();
        let strokes = self.strokes();
        // Per intersect: the whisker's side and time of contact.
        let mut reached: Vec<(usize, f64)> = Vec::new();
        for (i, (w, stroke)) in self.whiskers.iter().zip(&strokes).enumerate() {
            // Without spread reduction the whisker sweeps its own limits, as before.
            let narrowed;
            let swept = match self.control.spread_reduction {
                None => w,
                Some(_) => {
                    narrowed = RigidWhisker {
                        retracted: stroke.retracted,
                        protracted: stroke.protracted,
                        ..w.clone()
                    };
                    &narrowed
                }
            };
            let Some(hit) = target.sweep(swept, array_pose) else {
                continue;
            };
            self.intersects.push((w.module.index, hit.point));
            reached.push((
                side(w.module.column),
                start_s + stroke.protraction_time(hit.angle),
            ));
            let length = w.module.beam.length;
            // The shaft's direction in the array frame (the point's frame).
            let shaft = array_pose.rotation.inverse() * (hit.base_frame.rotation * Vector3::z());
            let Some((offset, slope)) =
                self.noise
                    .draw(length, &shaft, hit.slope(), &mut self.rngs[i])
            else {
                continue;
            };
            let point = array_pose.inverse_transform_point(&hit.point) + Vector3::from(offset);
            contacts.push(Contact {
                whisker: w.module.index,
                time_s: start_s + stroke.protraction_time(hit.angle),
                angle_rad: hit.angle,
                radial_distance: hit.radial_distance,
                point,
                slope,
            });
        }
        if self.control.asymmetry {
            // Each side stops protracting at its first detected contact: later contacts of
            // that side are not reached (a tie touches).
            let side_of = |c: &Contact| {
                let w = self.whiskers.iter().find(|w| w.module.index == c.whisker);
                w.map_or(0, |w| side(w.module.column))
            };
            let mut first = [f64::INFINITY; 2];
            for c in &contacts {
                let s = side_of(c);
                first[s] = first[s].min(c.time_s);
            }
            contacts.retain(|c| c.time_s <= first[side_of(c)]);
            let mut reached = reached.iter();
            self.intersects.retain(|_| {
                let &(s, t) = reached.next().expect("one per intersect");
                t <= first[s]
            });
        }
        self.spread_after(!contacts.is_empty());
        ContactCycle {
            index,
            start_s,
            array_pose: *array_pose,
            contacts,
        }
    }
}
