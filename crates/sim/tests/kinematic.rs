//! Kinematic sensing ("anticipated intersect", thesis §4.1.2.3) against analytic planes,
//! and the contact-feature noise of §6.1.3.1.2.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::RngExt;
use whisker_sim::environment::Mesh;
use whisker_sim::environment::shapes::{cuboid, transformed};
use whisker_sim::sensing::kinematic::{KinematicArray, RigidWhisker, SweepTarget};
use whisker_sim::sensing::noise::{ContactNoise, PointNoise};
use whisker_sim::whisker::array::modules;
use whisker_sim::whisker::control::WhiskingPattern;

const BASE_OFFSET: f64 = 3.0e-3;

/// A slab 4 × 4 m wide and 0.5 m thick whose top face is the plane through `q` with
/// outward unit normal `n`.
fn plane_slab(q: Point3<f64>, n: Vector3<f64>) -> SweepTarget {
    SweepTarget::new(plane_slab_mesh(q, n))
}

/// The mesh of [`plane_slab`].
fn plane_slab_mesh(q: Point3<f64>, n: Vector3<f64>) -> Mesh {
    let slab = cuboid(Point3::new(-2.0, -2.0, -0.5), Point3::new(2.0, 2.0, 0.0));
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &n).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    let pose = Isometry3::from_parts(Translation3::from(q.coords), rotation);
    transformed(&slab, &pose)
}

/// The analytic anticipated contact of a straight whisker with the plane (q, n): the
/// first 1° step whose shaft segment [b, b + L] from the pivot crosses the plane, and
/// the distance along it.
fn analytic(
    w: &RigidWhisker,
    pose: &Isometry3<f64>,
    q: &Point3<f64>,
    n: &Vector3<f64>,
) -> Option<(usize, f64, f64)> {
    let reach = w.base_offset + w.module.beam.length;
    for k in 0..=w.steps() {
        let f = pose * w.module.whisker_pose(w.angle(k));
        let p = Point3::from(f.translation.vector);
        let d = f.rotation * Vector3::z();
        let height = n.dot(&(p - q));
        let r = if height <= 0.0 {
            0.0
        } else if n.dot(&d) < 0.0 {
            height / -n.dot(&d)
        } else {
            continue;
        };
        if r <= reach {
            // Eq 6.12–6.14 in the base frame F at the contact angle.
            let slope =
                (-n.dot(&(f.rotation * Vector3::y()))) / (-n.dot(&(f.rotation * Vector3::x())));
            return Some((k, r - w.base_offset, slope));
        }
    }
    None
}

fn random_pose(rng: &mut impl rand::Rng) -> Isometry3<f64> {
    Isometry3::new(
        Vector3::new(
            rng.random_range(-0.3..0.3),
            rng.random_range(-0.3..0.3),
            rng.random_range(0.2..0.6),
        ),
        Vector3::new(
            rng.random_range(-3.0..3.0),
            rng.random_range(-3.0..3.0),
            rng.random_range(-3.0..3.0),
        ),
    )
}

/// A plane (point, outward unit normal) at a random tilt and a random distance (0.05–1.2
/// reach) from the whisker's pivot, facing it.
fn random_plane(
    rng: &mut impl rand::Rng,
    w: &RigidWhisker,
    pose: &Isometry3<f64>,
) -> (Point3<f64>, Vector3<f64>) {
    let pivot = pose * w.module.whisker_pose(w.retracted) * Point3::origin();
    let n = Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
    .normalize();
    let reach = w.base_offset + w.module.beam.length;
    (pivot - n * rng.random_range(0.05..1.2) * reach, n)
}

#[test]
fn sweep_against_a_plane_gives_the_analytic_contact() {
    let mut rng = whisker_slam::rng::substream(7, "test/kinematic-plane");
    let mut contacts = 0;
    let mut misses = 0;
    for trial in 0..60 {
        let pose = random_pose(&mut rng);
        for m in modules() {
            let w = RigidWhisker::new(m, BASE_OFFSET);
            let (q, n) = random_plane(&mut rng, &w, &pose);
            let target = plane_slab(q, n);
            let expected = analytic(&w, &pose, &q, &n);
            let got = target.sweep(&w, &pose);
            match (expected, got) {
                (None, None) => misses += 1,
                (Some((k, r, slope)), Some(hit)) => {
                    contacts += 1;
                    assert_eq!(hit.step, k, "trial {trial} whisker {}", w.module.index);
                    assert!((hit.angle - w.angle(k)).abs() < 1e-12);
                    assert!(
                        (hit.radial_distance - r).abs() < 1e-9,
                        "r {} vs {r}",
                        hit.radial_distance
                    );
                    assert!(
                        (hit.slope() - slope).abs() <= 1e-9 * slope.abs().max(1.0),
                        "slope {} vs {slope}",
                        hit.slope()
                    );
                    assert!((hit.normal - n).norm() < 1e-9);
                    // The point lies on the plane and on the shaft.
                    assert!(n.dot(&(hit.point - q)).abs() < 1e-9);
                    let base = hit.base_frame * Point3::origin();
                    assert!(((hit.point - base).norm() - hit.radial_distance).abs() < 1e-9);
                }
                (e, g) => panic!(
                    "trial {trial} whisker {}: expected {e:?}, got {g:?}",
                    w.module.index
                ),
            }
        }
    }
    // Both outcomes must have been exercised.
    assert!(
        contacts > 100 && misses > 100,
        "contacts {contacts}, misses {misses}"
    );
}

#[test]
fn a_soups_triangles_are_two_sided() {
    // The plane slab turned inside out: as a solid its "outward" normals point into the
    // slab; as a triangle soup (winding meaningless) each contact takes the normal facing
    // the whisker, which is the plane's true normal n. Contacts are the same either way.
    let mut rng = whisker_slam::rng::substream(8, "test/kinematic-soup");
    let mut contacts = 0;
    for _ in 0..20 {
        let pose = random_pose(&mut rng);
        for m in modules() {
            let w = RigidWhisker::new(m, BASE_OFFSET);
            let (q, n) = random_plane(&mut rng, &w, &pose);
            let mut mesh = plane_slab_mesh(q, n);
            for t in &mut mesh.triangles {
                t.swap(1, 2);
            }
            let flags = vec![true; mesh.triangles.len()];
            let solid = SweepTarget::new(mesh.clone()).sweep(&w, &pose);
            let soup = SweepTarget::with_two_sided(mesh, flags).sweep(&w, &pose);
            match (solid, soup) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    contacts += 1;
                    assert_eq!(a.step, b.step);
                    assert_eq!(a.point, b.point);
                    assert!((a.normal + n).norm() < 1e-9, "as wound: into the slab");
                    assert!(
                        (b.normal - n).norm() < 1e-9,
                        "two-sided: facing the whisker"
                    );
                }
                (a, b) => panic!("{a:?} vs {b:?}"),
            }
        }
    }
    assert!(contacts > 50, "{contacts}");
}

#[test]
fn whisker_pointing_into_a_face_at_a_known_distance() {
    // A plane facing the pivot squarely at 40 mm along the 90° direction of a 100 mm
    // whisker: contact at step 50 (90°), radial distance 40 mm − base offset.
    let m = modules().into_iter().find(|m| m.ring == 1).unwrap();
    let w = RigidWhisker::new(m, BASE_OFFSET);
    let pose = Isometry3::identity();
    let f = w.module.whisker_pose(std::f64::consts::FRAC_PI_2);
    let d = f.rotation * Vector3::z();
    let q = Point3::from(f.translation.vector) + d * 0.04;
    let hit = plane_slab(q, -d).sweep(&w, &pose).expect("contact");
    // The tip (103 mm from the pivot) first reaches the plane where cos(ψ) = 40/103.
    let expected_step = (50.0 - (0.04f64 / 0.103).acos().to_degrees())
        .ceil()
        .max(0.0) as usize;
    assert_eq!(hit.step, expected_step);
    let psi = (50.0 - hit.step as f64).to_radians();
    assert!((hit.radial_distance - (0.04 / psi.cos() - BASE_OFFSET)).abs() < 1e-12);
}

#[test]
fn noise_matches_the_configured_distributions() {
    // One whisker against a fixed plane; 10,000 whisk cycles with noise.
    let m = modules().into_iter().find(|m| m.ring == 2).unwrap();
    let length = m.beam.length;
    let w = RigidWhisker::new(m, BASE_OFFSET);
    let pose = Isometry3::identity();
    let f = w.module.whisker_pose(std::f64::consts::FRAC_PI_2);
    let d = f.rotation * Vector3::z();
    let n = (-d + f.rotation * Vector3::x() * 0.4).normalize();
    let q = Point3::from(f.translation.vector) + d * 0.08;
    let target = plane_slab(q, n);
    let exact = target.sweep(&w, &pose).expect("contact");
    // The shaft at the contact: the noise's direction along the whisker.
    let shaft = exact.base_frame.rotation * Vector3::z();
    for model in [PointNoise::AlongWhisker, PointNoise::PerCoordinate] {
        let noise = ContactNoise {
            point_model: model,
            ..ContactNoise::default()
        };
        let mut array =
            KinematicArray::new(vec![w.clone()], vec![WhiskingPattern::default()], noise, 11);
        let cycles = 10_000;
        let mut offsets: Vec<[f64; 4]> = Vec::new();
        for i in 0..cycles {
            let c = array.sense(&target, i, i as f64, &pose);
            if let Some(c) = c.contacts.first() {
                assert_eq!(c.angle_rad, exact.angle);
                assert_eq!(c.radial_distance, exact.radial_distance);
                let o = c.point - exact.point;
                if model == PointNoise::AlongWhisker {
                    // Along the shaft: the offset is the shaft times one N(0, r_η) draw,
                    // kept in its first column.
                    assert!(o.cross(&shaft).norm() < 1e-12 * (1.0 + o.norm()));
                    offsets.push([o.dot(&shaft), 0.0, 0.0, c.slope - exact.slope()]);
                } else {
                    offsets.push([o.x, o.y, o.z, c.slope - exact.slope()]);
                }
            }
        }
        let rate = offsets.len() as f64 / cycles as f64;
        assert!((rate - 0.98).abs() <= 0.005, "detection rate {rate}");
        let n = offsets.len() as f64;
        let sigmas: &[(usize, f64)] = match model {
            PointNoise::AlongWhisker => &[(0, 0.25 * length), (3, 0.33)],
            PointNoise::PerCoordinate => &[
                (0, 0.25 * length),
                (1, 0.25 * length),
                (2, 0.25 * length),
                (3, 0.33),
            ],
        };
        for &(k, sigma) in sigmas {
            let mean = offsets.iter().map(|o| o[k]).sum::<f64>() / n;
            let sd =
                (offsets.iter().map(|o| (o[k] - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            assert!(
                mean.abs() < 3.0 * sigma / n.sqrt(),
                "{model:?} component {k}: mean {mean}"
            );
            assert!(
                (sd - sigma).abs() < 3.0 * sigma / (2.0 * (n - 1.0)).sqrt(),
                "{model:?} component {k}: sd {sd} vs {sigma}"
            );
        }
    }
    // Noise off: exact, every time.
    let mut quiet = KinematicArray::new(
        vec![w],
        vec![WhiskingPattern::default()],
        ContactNoise::NONE,
        11,
    );
    let c = quiet.sense(&target, 0, 0.0, &pose);
    assert_eq!(c.contacts.len(), 1);
    assert!((c.contacts[0].point - exact.point).norm() < 1e-12);
    assert_eq!(c.contacts[0].slope, exact.slope());
}

#[test]
fn sweep_matches_brute_force_ray_casts_on_catalogue_objects() {
    use parry3d_f64::math::Vector as V;
    use parry3d_f64::query::Ray;
    use whisker_sim::environment::assets::{CATALOGUE, generate};
    let mut rng = whisker_slam::rng::substream(3, "test/kinematic-assets");
    let mut contacts = 0;
    for asset in CATALOGUE
        .iter()
        .filter(|a| ["mug", "skull", "box_stack"].contains(&a.name))
    {
        let mesh = generate(asset);
        let shape = whisker_sim::environment::solids::shape(&mesh).unwrap();
        let target = SweepTarget::new(mesh);
        for _ in 0..60 {
            // The array 5–25 cm from the object's centre, facing it, randomly rolled.
            let centre = Vector3::new(0.0, 0.0, 0.5 * asset.size[2]);
            let dir = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-0.5..0.5),
            )
            .normalize();
            let at = centre
                + dir * (0.5 * asset.size[0].max(asset.size[1]) + rng.random_range(0.02..0.12));
            let facing = UnitQuaternion::rotation_between(&Vector3::z(), &-dir).unwrap();
            let roll = UnitQuaternion::from_axis_angle(
                &Vector3::z_axis(),
                rng.random_range(0.0..std::f64::consts::TAU),
            );
            let pose = Isometry3::from_parts(Translation3::from(at), facing * roll);
            for m in modules() {
                let w = RigidWhisker::new(m, BASE_OFFSET);
                let reach = w.base_offset + w.module.beam.length;
                let brute = (0..=w.steps()).find_map(|k| {
                    let f = pose * w.module.whisker_pose(w.angle(k));
                    let (p, d) = (f.translation.vector, f.rotation * Vector3::z());
                    let ray = Ray::new(V::new(p.x, p.y, p.z), V::new(d.x, d.y, d.z));
                    shape
                        .cast_local_ray(&ray, reach, false)
                        .map(|r| (k, r - BASE_OFFSET))
                });
                let got = target.sweep(&w, &pose).map(|h| (h.step, h.radial_distance));
                match (brute, got) {
                    (None, None) => {}
                    (Some((k, r)), Some((gk, gr))) => {
                        contacts += 1;
                        assert_eq!(k, gk, "{}: step", asset.name);
                        assert!(
                            (r.max(0.0) - gr).abs() < 1e-9,
                            "{}: r {r} vs {gr}",
                            asset.name
                        );
                    }
                    (b, g) => panic!("{}: brute force {b:?}, sweep {g:?}", asset.name),
                }
            }
        }
    }
    assert!(contacts > 250, "only {contacts} contacts");
}

/// The whole array (noise off) facing a tilted plane 6 cm ahead, and the open-loop
/// contacts of one whisk there.
fn array_before_a_plane(
    control: whisker_sim::whisker::strategies::WhiskingControl,
) -> (KinematicArray, SweepTarget, Isometry3<f64>) {
    let whiskers: Vec<RigidWhisker> = modules()
        .into_iter()
        .map(|m| RigidWhisker::new(m, BASE_OFFSET))
        .collect();
    let patterns = vec![WhiskingPattern::default(); whiskers.len()];
    let n = -Vector3::new(0.3, 0.2, 1.0).normalize();
    let target = plane_slab(Point3::new(0.0, 0.0, 0.06), n);
    let array =
        KinematicArray::new(whiskers, patterns, ContactNoise::NONE, 1).with_control(control);
    (array, target, Isometry3::identity())
}

#[test]
fn asymmetry_keeps_each_side_s_first_contacts_only() {
    use whisker_sim::whisker::strategies::WhiskingControl;
    let (mut open, target, pose) = array_before_a_plane(WhiskingControl::default());
    let all = open.sense(&target, 0, 0.0, &pose).contacts;
    let control = WhiskingControl {
        asymmetry: true,
        ..Default::default()
    };
    let (mut cia, _, _) = array_before_a_plane(control);
    let kept = cia.sense(&target, 0, 0.0, &pose).contacts;
    // Sides as documented: columns A–C (whiskers with index % 6 < 3) and D–F.
    let side = |w: usize| usize::from(w % 6 >= 3);
    let first = |s: usize| {
        all.iter()
            .filter(|c| side(c.whisker) == s)
            .map(|c| c.time_s)
            .fold(f64::INFINITY, f64::min)
    };
    let expected: Vec<usize> = all
        .iter()
        .filter(|c| c.time_s <= first(side(c.whisker)))
        .map(|c| c.whisker)
        .collect();
    assert_eq!(kept.iter().map(|c| c.whisker).collect::<Vec<_>>(), expected);
    assert!(
        first(0).is_finite() && first(1).is_finite(),
        "both sides touch"
    );
    assert!(expected.len() < all.len(), "later contacts were cut");
    assert_eq!(cia.intersects.len(), kept.len());
}

#[test]
fn spread_reduction_sweeps_the_narrowed_stroke_after_a_contact() {
    use whisker_sim::whisker::strategies::{SpreadReduction, WhiskingControl};
    let control = WhiskingControl {
        spread_reduction: Some(SpreadReduction::default()),
        ..Default::default()
    };
    let (mut open, target, pose) = array_before_a_plane(WhiskingControl::default());
    let (mut sr, _, _) = array_before_a_plane(control);
    let full = open.sense(&target, 0, 0.0, &pose).contacts;
    assert_eq!(
        sr.sense(&target, 0, 0.0, &pose).contacts,
        full,
        "whisk 0 is open loop"
    );
    let deg = f64::to_radians;
    // The contacts of a stroke from `lo` to `hi` (1° steps from lo): the open-loop
    // angle if the stroke reaches it, the stroke's start if the shaft starts inside.
    let expect = |lo: f64, hi: f64, start_s: f64| -> Vec<(usize, f64, f64)> {
        let stroke = WhiskingPattern {
            retracted: deg(lo),
            protracted: deg(hi),
            ..WhiskingPattern::default()
        };
        full.iter()
            .filter(|c| c.angle_rad <= deg(hi) + 1e-9)
            .map(|c| {
                let a = c.angle_rad.max(deg(lo));
                (c.whisker, a, start_s + stroke.protraction_time(a))
            })
            .collect()
    };
    let got = |cs: &[whisker_slam::contact::Contact]| -> Vec<(usize, f64, f64)> {
        cs.iter()
            .map(|c| (c.whisker, c.angle_rad, c.time_s))
            .collect()
    };
    let close = |a: &[(usize, f64, f64)], b: &[(usize, f64, f64)]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() < 1e-9 && (x.2 - y.2).abs() < 1e-9)
    };
    // Whisks 1 and 2 at the plane: the narrowed stroke 85°–135°.
    for k in 1..3 {
        let c = sr.sense(&target, k, k as f64, &pose).contacts;
        let e = expect(85.0, 135.0, k as f64);
        assert!(close(&got(&c), &e), "whisk {k}: {:?} vs {e:?}", got(&c));
        assert!(
            full.iter()
                .any(|c| c.angle_rad < deg(85.0) || c.angle_rad > deg(135.0))
        );
    }
    // Two whisks away from it: released after them; whisk 5 back at the plane protracts
    // from 85° (where the last narrowed retraction ended) to 140°, touches and engages
    // spread reduction again: whisk 6 is narrowed.
    let away = Isometry3::translation(0.0, 0.0, -10.0);
    for k in 3..5 {
        assert!(sr.sense(&target, k, k as f64, &away).contacts.is_empty());
    }
    assert!(!sr.narrowed());
    let c = sr.sense(&target, 5, 5.0, &pose).contacts;
    assert!(close(&got(&c), &expect(85.0, 140.0, 5.0)));
    let c = sr.sense(&target, 6, 6.0, &pose).contacts;
    assert!(close(&got(&c), &expect(85.0, 135.0, 6.0)));
}
