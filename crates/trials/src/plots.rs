//! The figures of a batch report, as SVG (plotters): notched box plots (the thesis'
//! Figs 6.6–6.10 style; the figures from `whisker_slam::stats::boxplot`) and curves of a
//! median with its interquartile band over iterations.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_slam::stats::boxplot::BoxStats;

/// One box: its label under the axis and its figures.
pub struct BoxGroup {
    /// Label on the x axis (the level; `n` is added).
    pub label: String,
    /// The stratum (the other factors' levels), written once under its boxes.
    pub stratum: String,
    /// The figures.
    pub stats: BoxStats,
}

/// A horizontal reference line: its value and what it is (a threshold, a perfect score).
pub struct Reference {
    pub value: f64,
    pub label: String,
}

/// One curve: a median and its interquartile band at each x.
pub struct Curve {
    /// Legend entry.
    pub label: String,
    /// Colour index (e.g. the factor level).
    pub colour: usize,
    /// x values.
    pub x: Vec<f64>,
    /// Median at each x.
    pub median: Vec<f64>,
    /// First quartile at each x.
    pub q1: Vec<f64>,
    /// Third quartile at each x.
    pub q3: Vec<f64>,
}

fn failed(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Failure(format!("{}: cannot draw: {e}", path.display()))
}

/// The colour of series `i`.
fn colour(i: usize) -> RGBColor {
    const C: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
    ];
    C[i % C.len()]
}

/// A y range around `lo..hi` with a margin (a unit range when flat).
fn padded(lo: f64, hi: f64) -> std::ops::Range<f64> {
    if !(lo.is_finite() && hi.is_finite()) {
        return 0.0..1.0;
    }
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    (lo - 0.08 * span)..(hi + 0.08 * span)
}

/// Notched box plots of `groups` side by side, written to `path` as SVG. `colours[i]`
/// picks the colour of box i (e.g. by factor level).
pub fn notched_boxes(
    path: &Path,
    title: &str,
    y_label: &str,
    groups: &[BoxGroup],
    colours: &[usize],
    reference: Option<&Reference>,
) -> Result {
    let mut svg = String::new();
    draw_boxes(&mut svg, path, (title, y_label), groups, colours, reference)?;
    whisker_scenario::files::write_atomic(path, svg.as_bytes())
}

/// Draws [`notched_boxes`] into `svg` (`path` names it in errors).
fn draw_boxes(
    svg: &mut String,
    path: &Path,
    (title, y_label): (&str, &str),
    groups: &[BoxGroup],
    colours: &[usize],
    reference: Option<&Reference>,
) -> Result {
    let lo = groups
        .iter()
        .flat_map(|g| [g.stats.whisker_low, g.stats.notch_low])
        .chain(groups.iter().flat_map(|g| g.stats.outliers.iter().copied()))
        .chain(reference.map(|r| r.value))
        .fold(f64::INFINITY, f64::min);
    let hi = groups
        .iter()
        .flat_map(|g| [g.stats.whisker_high, g.stats.notch_high])
        .chain(groups.iter().flat_map(|g| g.stats.outliers.iter().copied()))
        .chain(reference.map(|r| r.value))
        .fold(f64::NEG_INFINITY, f64::max);
    let width = (200 + 170 * groups.len()).clamp(480, 2400) as u32;
    let root = SVGBackend::with_string(svg, (width, 480)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| failed(path, e))?;
    let n = groups.len() as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(70)
        .y_label_area_size(70)
        .build_cartesian_2d(-0.5..n - 0.5, padded(lo, hi))
        .map_err(|e| failed(path, e))?;
    // Under each box its level and n; under each run of boxes of one stratum, the stratum.
    let label = |x: &f64| -> String {
        let i = x.round();
        if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < groups.len() {
            let g = &groups[i as usize];
            format!("{} (n={})", g.label, g.stats.n)
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(groups.len() * 2 + 1)
        .x_label_formatter(&label)
        .x_label_style(("sans-serif", 13))
        .y_desc(y_label)
        .draw()
        .map_err(|e| failed(path, e))?;
    let y_low = padded(lo, hi).start;
    let mut start = 0;
    while start < groups.len() {
        let stratum = &groups[start].stratum;
        let end = (start..groups.len())
            .find(|&j| groups[j].stratum != *stratum)
            .unwrap_or(groups.len());
        if !stratum.is_empty() {
            let (px, py) = chart.backend_coord(&((start + end - 1) as f64 / 2.0, y_low));
            let style = ("sans-serif", 12)
                .into_font()
                .color(&BLACK.mix(0.75))
                .pos(Pos::new(HPos::Center, VPos::Top));
            root.draw(&Text::new(stratum.clone(), (px, py + 30), style))
                .map_err(|e| failed(path, e))?;
        }
        start = end;
    }
    if let Some(r) = reference {
        reference_line(&mut chart, &root, (-0.5, n - 0.5), r, path)?;
    }
    for (i, g) in groups.iter().enumerate() {
        let s = &g.stats;
        let c = colour(colours.get(i).copied().unwrap_or(i));
        let x = i as f64;
        let (w, nw) = (0.3, 0.15);
        // The notched box: out to the quartiles, pinched to the notch at the median.
        let outline = vec![
            (x - w, s.q1),
            (x - w, s.notch_low),
            (x - nw, s.median),
            (x - w, s.notch_high),
            (x - w, s.q3),
            (x + w, s.q3),
            (x + w, s.notch_high),
            (x + nw, s.median),
            (x + w, s.notch_low),
            (x + w, s.q1),
            (x - w, s.q1),
        ];
        chart
            .draw_series([Polygon::new(outline.clone(), c.mix(0.25).filled())])
            .map_err(|e| failed(path, e))?;
        let lines = [
            outline,
            vec![(x - nw, s.median), (x + nw, s.median)],
            vec![(x, s.q3), (x, s.whisker_high)],
            vec![(x, s.q1), (x, s.whisker_low)],
            vec![(x - 0.1, s.whisker_high), (x + 0.1, s.whisker_high)],
            vec![(x - 0.1, s.whisker_low), (x + 0.1, s.whisker_low)],
        ];
        chart
            .draw_series(
                lines
                    .into_iter()
                    .map(|l| PathElement::new(l, c.stroke_width(2))),
            )
            .map_err(|e| failed(path, e))?;
        chart
            .draw_series(
                s.outliers
                    .iter()
                    .map(|&y| Circle::new((x, y), 3, RED.stroke_width(1))),
            )
            .map_err(|e| failed(path, e))?;
    }
    root.present().map_err(|e| failed(path, e))
}

/// The chart of a figure: SVG, x and y in f64.
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws `r` across `x` as a dashed line, its label above its left end.
fn reference_line(
    chart: &mut Chart,
    root: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    (x0, x1): (f64, f64),
    r: &Reference,
    path: &Path,
) -> Result {
    let dash = (x1 - x0) / 120.0;
    let dashes = (0..60)
        .map(|k| {
            let a = x0 + 2.0 * k as f64 * dash;
            vec![(a, r.value), (a + dash, r.value)]
        })
        .map(|l| PathElement::new(l, BLACK.mix(0.7).stroke_width(1)));
    chart.draw_series(dashes).map_err(|e| failed(path, e))?;
    let style = ("sans-serif", 12)
        .into_font()
        .color(&BLACK.mix(0.8))
        .pos(Pos::new(HPos::Left, VPos::Bottom));
    let (px, py) = chart.backend_coord(&(x0, r.value));
    root.draw(&Text::new(r.label.clone(), (px + 4, py - 2), style))
        .map_err(|e| failed(path, e))
}

/// Median curves with interquartile bands, written to `path` as SVG.
pub fn band_curves(
    path: &Path,
    labels: (&str, &str, &str),
    curves: &[Curve],
    reference: Option<&Reference>,
) -> Result {
    let mut svg = String::new();
    draw_bands(&mut svg, path, labels, curves, reference)?;
    whisker_scenario::files::write_atomic(path, svg.as_bytes())
}

/// Draws [`band_curves`] into `svg` (`path` names it in errors).
fn draw_bands(
    svg: &mut String,
    path: &Path,
    (title, x_label, y_label): (&str, &str, &str),
    curves: &[Curve],
    reference: Option<&Reference>,
) -> Result {
    let xs = curves.iter().flat_map(|c| c.x.iter().copied());
    let x_hi = xs.fold(1.0f64, f64::max);
    let lo = curves
        .iter()
        .flat_map(|c| c.q1.iter().copied())
        .fold(f64::INFINITY, f64::min);
    let hi = curves
        .iter()
        .flat_map(|c| c.q3.iter().copied())
        .chain(reference.map(|r| r.value))
        .fold(f64::NEG_INFINITY, f64::max);
    let root = SVGBackend::with_string(svg, (900, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| failed(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..x_hi, padded(lo.min(0.0), hi))
        .map_err(|e| failed(path, e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(|e| failed(path, e))?;
    if let Some(r) = reference {
        reference_line(&mut chart, &root, (0.0, x_hi), r, path)?;
    }
    for c in curves {
        let colour = colour(c.colour);
        let band: Vec<(f64, f64)> =
            c.x.iter()
                .zip(&c.q3)
                .map(|(&x, &y)| (x, y))
                .chain(c.x.iter().zip(&c.q1).rev().map(|(&x, &y)| (x, y)))
                .collect();
        chart
            .draw_series([Polygon::new(band, colour.mix(0.18).filled())])
            .map_err(|e| failed(path, e))?;
        chart
            .draw_series(LineSeries::new(
                c.x.iter().zip(&c.median).map(|(&x, &y)| (x, y)),
                colour.stroke_width(2),
            ))
            .map_err(|e| failed(path, e))?
            .label(c.label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(|e| failed(path, e))?;
    root.present().map_err(|e| failed(path, e))
}
