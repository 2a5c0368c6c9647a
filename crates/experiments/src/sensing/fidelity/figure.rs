//! `tip.svg` of `whisker fidelity`: where physics truly differs from the rigid sweep. Two
//! whisks of the Box in the radial models' condition (RCP at saturation), each whisker's
//! deflection y (counts) against its whisk angle: a contact on the middle of the shaft,
//! which bends the shaft and loads the follicle steeply from the anticipated onset on, and
//! one on the last 5 % of the shaft, where the compliant tip meets the surface, bends
//! and slides off, loading the follicle by a few tens of counts. The anticipated onset
//! (the rigid sweep's) and the whisker's confirmation level are drawn on each.

use super::Row;
use crate::sensing::held::PhysicsSensing;
use plotters::prelude::*;
use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_sim::sensing::kinematic::SweepTarget;
use whisker_slam::sensor::Sample;

/// One whisker's whisk, for the figure.
#[derive(Debug, Clone)]
pub struct Example {
    /// e.g. "mid-shaft: C2, pose 3, 48 % of the shaft, detected".
    pub title: String,
    /// (whisk angle °, y counts) of every sample.
    pub samples: Vec<(f64, f64)>,
    /// The rigid sweep's onset (°).
    pub anticipated_deg: f64,
    /// The whisker's confirmation level (counts).
    pub confirm: f64,
}

/// The example of whisker `i` at pose `k` of `sensing` (re-simulated on the stream the
/// comparison used, so the very whisk it compared), if the sweep anticipates a contact.
pub fn example(
    sensing: &PhysicsSensing,
    target: &SweepTarget,
    (k, pose): (usize, &nalgebra::Isometry3<f64>),
    (seed, stream): (u64, &str),
    (i, label): (usize, &str),
) -> Option<Example> {
    let w = &sensing.rigid()[i];
    let hit = target.sweep(w, pose)?;
    let stream = format!("{stream}/{k}");
    let (cycle, streams) = sensing.whisk_streams(target, k, pose, seed, &stream);
    let detected = cycle.contacts.iter().any(|c| c.whisker == i);
    let samples: Vec<(f64, f64)> = streams[i]
        .iter()
        .map(|s: &Sample| (s.angle_rad.to_degrees(), s.y))
        .collect();
    Some(Example {
        title: format!(
            "{label}: {}, pose {k}, {:.0} % of the shaft, {}",
            w.module.pixel(),
            100.0 * hit.radial_distance / w.module.beam.length,
            if detected { "detected" } else { "missed" }
        ),
        samples,
        anticipated_deg: hit.angle.to_degrees(),
        confirm: sensing.levels()[i].confirm_counts,
    })
}

/// The SVG of `examples` side by side, for the file `path` (named in errors).
pub fn svg(path: &Path, examples: &[Example]) -> Result<String> {
    let mut text = String::new();
    draw(&mut text, examples)
        .map_err(|e| Error::Failure(format!("{}: cannot draw: {e}", path.display())))?;
    Ok(text)
}

type Drawn = std::result::Result<(), Box<dyn std::error::Error>>;

fn draw(svg: &mut String, examples: &[Example]) -> Drawn {
    let n = examples.len().max(1) as u32;
    let root = SVGBackend::with_string(svg, (480 * n, 380)).into_drawing_area();
    root.fill(&WHITE)?;
    for (area, e) in root.split_evenly((1, n as usize)).iter().zip(examples) {
        let (lo, hi) = e
            .samples
            .iter()
            .fold((0f64, e.confirm), |(lo, hi), &(_, y)| {
                (lo.min(y), hi.max(y))
            });
        let pad = 0.08 * (hi - lo).max(1.0);
        let (a0, a1) = e
            .samples
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x, _)| {
                (a.min(x), b.max(x))
            });
        let mut chart = ChartBuilder::on(area)
            .caption(&e.title, ("sans-serif", 15))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(a0..a1, (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("whisk angle (°)")
            .y_desc("deflection y (counts)")
            .light_line_style(WHITE)
            .draw()?;
        let blue = RGBColor(31, 119, 180);
        chart
            .draw_series(LineSeries::new(
                e.samples.iter().copied(),
                blue.stroke_width(1),
            ))?
            .label("physics: y at the follicle")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], blue.stroke_width(2)));
        let red = RGBColor(214, 39, 40);
        chart
            .draw_series(LineSeries::new(
                [(e.anticipated_deg, lo - pad), (e.anticipated_deg, hi + pad)],
                red.stroke_width(2),
            ))?
            .label("rigid sweep: anticipated onset")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], red.stroke_width(2)));
        let grey = RGBColor(120, 120, 120);
        for level in [e.confirm, -e.confirm] {
            chart.draw_series(LineSeries::new(
                [(a0, level), (a1, level)],
                grey.stroke_width(1),
            ))?;
        }
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), u32>>())?
            .label("± confirmation (10 σ)")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], grey.stroke_width(1)));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// The whisks `tip.svg` shows: the first anticipated contact on the middle of the shaft
/// (35–65 % of its length) that was detected, and of those on its last 5 % the one with
/// the least peak deflection, both away from the stroke's ends (`stroke`: retracted and protracted
/// angle, °; the *start* and *end* classes of [`super::Miss`]).
pub(super) fn pick_examples(rows: &[Row], stroke: (f64, f64)) -> Vec<(&'static str, &Row)> {
    let fraction = |r: &&Row| r.anticipated_fraction.unwrap_or(0.0);
    let inside = |r: &&Row| {
        r.anticipated_angle_deg
            .is_some_and(|a| a > stroke.0 + 10.0 && a < stroke.1 - 2.5)
    };
    let mid = rows
        .iter()
        .filter(inside)
        .find(|r| r.detected && (0.35..=0.65).contains(&fraction(r)));
    let tips: Vec<&Row> = rows
        .iter()
        .filter(inside)
        .filter(|r| fraction(r) >= 0.95)
        .collect();
    // The tip that loaded the follicle least: one that slid off rather than pressed.
    let tip = tips
        .iter()
        .min_by(|a, b| a.peak_counts.total_cmp(&b.peak_counts))
        .copied();
    [("mid-shaft", mid), ("tip", tip)]
        .into_iter()
        .filter_map(|(label, r)| r.map(|r| (label, r)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::Mode;
    use super::*;

    /// The figure's picks: a detected contact at 35–65 % of the shaft, the tip contact
    /// (≥ 95 %) with the least peak, neither within the stroke's start or end classes.
    #[test]
    fn the_figure_picks_a_mid_shaft_and_the_weakest_tip_contact_inside_the_stroke() {
        let row = |pose: usize, angle: f64, fraction: f64, peak: f64, detected: bool| Row {
            object: "box".into(),
            mode: Mode::RcpSaturation,
            pose,
            whisker: "A1".into(),
            anticipated: true,
            detected,
            onset_error_deg: None,
            radial_error_mm: None,
            point_error_mm: None,
            slope_error: None,
            anticipated_angle_deg: Some(angle),
            anticipated_fraction: Some(fraction),
            peak_counts: peak,
            miss: None,
        };
        let rows = [
            row(0, 45.0, 0.5, 900.0, true),  // at the start: no
            row(1, 90.0, 0.5, 900.0, false), // missed: no
            row(2, 90.0, 0.4, 900.0, true),  // the mid-shaft one
            row(3, 139.0, 1.0, 5.0, true),   // at the end: no
            row(4, 120.0, 0.97, 300.0, true),
            row(5, 110.0, 0.99, 40.0, false), // the weakest tip inside the stroke
        ];
        let picked = pick_examples(&rows, (40.0, 140.0));
        let poses: Vec<(&str, usize)> = picked.iter().map(|(l, r)| (*l, r.pose)).collect();
        assert_eq!(poses, [("mid-shaft", 2), ("tip", 5)]);
    }
}
