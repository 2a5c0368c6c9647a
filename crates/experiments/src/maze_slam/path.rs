//! The maze run's path (thesis §3.2, Fig 3.3): the loop through the scenario's corners,
//! 3 circuits clockwise, 3 anticlockwise, then one of each, in updates of one pose-cell
//! size (15 mm) or 10° of turn at 1.5 Hz (§3.1.2, §3.2.1).

use std::f64::consts::PI;
use whisker_slam::pose::{Pose2, wrap};

/// Pose-cell size and distance per update (m), and turn per update at corners (rad).
pub const STEP_M: f64 = 0.015;
pub const TURN_RAD: f64 = 10.0 * PI / 180.0;

/// A planar path sample: position (world x, y) and heading.
pub type Sample = Pose2;

/// One circuit of the loop through `corners` (closed), in their order or reversed,
/// starting at the first corner facing along the first edge: a turn to each edge's
/// heading in 10° updates, then the edge in 15 mm updates.
fn circuit(corners: &[(f64, f64)], reverse: bool, from: &mut Sample) -> Vec<Sample> {
    let mut c: Vec<(f64, f64)> = corners.to_vec();
    if reverse {
        c.reverse();
        c.rotate_right(1);
    }
    c.push(c[0]);
    let mut out = Vec::new();
    for w in c.windows(2) {
        let (a, b) = (w[0], w[1]);
        let heading = (b.1 - a.1).atan2(b.0 - a.0);
        let mut turn = wrap(heading - from.th);
        while turn.abs() > 1e-9 {
            let d = turn.clamp(-TURN_RAD, TURN_RAD);
            from.th = wrap(from.th + d);
            turn -= d;
            out.push(*from);
        }
        let length = (b.0 - a.0).hypot(b.1 - a.1);
        let n = (length / STEP_M).round() as usize;
        for k in 1..=n {
            let s = k as f64 / n as f64;
            from.x = a.0 + s * (b.0 - a.0);
            from.y = a.1 + s * (b.1 - a.1);
            out.push(*from);
        }
    }
    out
}

use whisker_scenario::maze_slam::CIRCUITS;

/// The whole run: the first `circuits` of [`CIRCUITS`] (all 8 by default, §3.2); the
/// index where each circuit starts.
pub fn path(corners: &[(f64, f64)], circuits: usize) -> (Vec<Sample>, Vec<usize>) {
    let (x, y) = corners[0];
    let mut at = Sample { x, y, th: 0.0 };
    let mut out = vec![at];
    let mut starts = Vec::new();
    for &reverse in &CIRCUITS[..circuits.min(CIRCUITS.len())] {
        starts.push(out.len());
        out.extend(circuit(corners, reverse, &mut at));
    }
    (out, starts)
}

/// The updates a kidnapped run skips (§3.3.1), given where each circuit starts: a quarter
/// circuit from the middle of the 3rd — the last clockwise one before the first
/// anticlockwise circuit, when the system re-localises steadily on the places of
/// circuits 1–2 (kidnapping it in the 4th, the first anticlockwise circuit, whose
/// images are all new, would test nothing: it cannot re-localise there anyway).
pub fn kidnapping(starts: &[usize]) -> std::ops::Range<usize> {
    let length = starts[3] - starts[2];
    let from = starts[2] + length / 2;
    from..from + length / 4
}
