//! The array's whisking strategies (§2.3.1) in physics, read from the follicles' angle
//! sensors: spread reduction narrows every whisker's stroke about a centre moved
//! towards protraction once one whisker touches; contact-induced asymmetry stops the
//! touching side's protraction while the other side's continues.

mod common;

use nalgebra::Isometry3;
use whisker_sim::sensing::physics::{DT, PhysicsArray, WhiskerConfig};
use whisker_sim::whisker::array;
use whisker_sim::whisker::strategies::{SpreadReduction, WhiskingControl};

/// Whiskers `indices` whisking at 1 Hz under `control` (contacts at 150 counts) for
/// `seconds`, whisker `touching` against a pole at 100°, half its length out; each
/// whisker's angle and |y| streams.
fn run(
    indices: &[usize],
    touching: usize,
    control: WhiskingControl,
    seconds: f64,
) -> Vec<(Vec<f64>, Vec<f64>)> {
    let modules = array::modules();
    let configs: Vec<WhiskerConfig> = indices
        .iter()
        .map(|&i| WhiskerConfig {
            contact_threshold: Some(150.0),
            control,
            ..WhiskerConfig::with_defaults(modules[i].clone())
        })
        .collect();
    let m = &modules[touching];
    let poles = [common::pole(
        m,
        0.5 * m.beam.length,
        100f64.to_radians(),
        0.01,
    )];
    let mut array = PhysicsArray::new(configs, &poles, &Isometry3::identity(), 3, DT);
    let n = (seconds / DT).round() as usize;
    let streams = array.run(&vec![Isometry3::identity(); n]);
    streams
        .into_iter()
        .map(|s| {
            (
                s.iter().map(|x| x.angle_rad.to_degrees()).collect(),
                s.iter().map(|x| x.y.abs()).collect(),
            )
        })
        .collect()
}

/// Min and max of `v` over seconds [a, b).
fn span(v: &[f64], a: f64, b: f64) -> (f64, f64) {
    v[(a / DT) as usize..(b / DT) as usize]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

#[test]
fn spread_reduction_narrows_every_stroke_towards_protraction_after_a_contact() {
    let sr = SpreadReduction {
        range_fraction: 0.5,
        centre_shift: 20f64.to_radians(),
        release_cycles: 2,
    };
    let control = WhiskingControl {
        spread_reduction: Some(sr),
        ..WhiskingControl::default()
    };
    // B2 touches the pole at 100° on every stroke that passes it; D2, on the other side,
    // touches nothing.
    let streams = run(&[7, 9], 7, control, 3.0);
    let (b2, d2) = (&streams[0], &streams[1]);
    assert!(span(&b2.1, 0.0, 0.5).1 > 150.0, "B2 touches in cycle 0");
    assert!(span(&d2.1, 0.0, 3.0).1 < 150.0, "D2 touches nothing");
    // Cycle 0 whisks the full stroke up to 140° (angle sensor: 0.09° steps, 0.05° noise).
    for (angle, _) in [b2, d2] {
        assert!((span(angle, 0.0, 0.5).1 - 140.0).abs() < 0.5);
        // Cycles 1 and 2: 85°–135° (by hand: centre 90° + 20°, half range 50° × 0.5),
        // both limits moved in, for the whisker that touched and for the one that did not.
        for c in 1..3 {
            let (lo, hi) = span(angle, c as f64 + 0.01, c as f64 + 1.0);
            assert!((lo - 85.0).abs() < 0.5, "cycle {c}: {lo}");
            assert!((hi - 135.0).abs() < 0.5, "cycle {c}: {hi}");
        }
    }
}

#[test]
fn asymmetry_stops_the_touching_side_and_not_the_other() {
    let control = WhiskingControl {
        asymmetry: true,
        ..WhiskingControl::default()
    };
    // A2 and B2 on one side, D2 on the other; B2 touches the pole at 100°.
    let indices = [6, 7, 9];
    let streams = run(&indices, 7, control, 1.0);
    let modules = array::modules();
    let touched_at = {
        let (angle, y) = &streams[1];
        let k = y.iter().position(|&v| v >= 150.0).expect("B2 touches");
        angle[k]
    };
    assert!(
        touched_at < 110.0,
        "contact near the pole's 100°: {touched_at}"
    );
    for (&i, (angle, _)) in indices.iter().zip(&streams) {
        let top = span(angle, 0.0, 0.5).1;
        // The sides as documented: columns A–C and D–F.
        let pixel = modules[i].pixel();
        if pixel == "A2" || pixel == "B2" {
            // Held where B2's contact was read (one sample of motion at most after it).
            assert!(
                (top - touched_at).abs() < 0.5,
                "{}: {top}",
                modules[i].pixel()
            );
        } else {
            assert!((top - 140.0).abs() < 0.5, "{}: {top}", modules[i].pixel());
        }
        // All retract fully at the cycle's end.
        assert!((angle[1999] - 40.0).abs() < 0.5);
    }
}
