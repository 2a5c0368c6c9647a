//! `tip.svg` of `whisker fidelity`: where physics truly differs from the rigid sweep. Two
//! whisks of the Box in the radial models' condition (RCP at saturation), each whisker's
//! deflection y (counts) against its whisk angle: a contact on the middle of the shaft,
//! which bends the shaft and loads the follicle steeply from the anticipated onset on, and
//! one on the last 5 % of the shaft, where the compliant tip meets the surface, bends
//! and slides off, loading the follicle by a few tens of counts. The anticipated onset
//! (the rigid sweep's) and the whisker's confirmation level are drawn on each.

use super::held::PhysicsSensing;
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
