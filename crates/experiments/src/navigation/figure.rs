//! `path.svg` of a navigation run: the office's plan (walls as they stand, doors as gaps,
//! objects as the rectangles round their meshes) and the base's true path, its odometry
//! alone and the map's estimate (both placed at the true start, not fitted), to scale;
//! the whisks that touched and object mode's stops marked on the true path.

use super::terrain::TerrainRun;
use plotters::prelude::*;
use std::path::Path;
use whisker_scenario::{Error, Result};
use whisker_sim::environment::floor_plan::FloorPlan;
use whisker_slam::pose::Pose2;

/// Pixels per metre.
const SCALE: f64 = 150.0;

/// The SVG of `run` over `plan` (with `objects`: name and plan rectangle (lo, hi)), for
/// the file `path` (named in errors).
pub fn path_svg(
    path: &Path,
    plan: &FloorPlan,
    objects: &[(String, [f64; 2], [f64; 2])],
    run: &TerrainRun,
    title: &str,
) -> Result<String> {
    let failed =
        |e: &dyn std::fmt::Display| Error::Failure(format!("{}: cannot draw: {e}", path.display()));
    let mut svg = String::new();
    draw(&mut svg, plan, objects, run, title).map_err(|e| failed(&e))?;
    Ok(svg)
}

type Drawn = std::result::Result<(), Box<dyn std::error::Error>>;

fn draw(
    svg: &mut String,
    plan: &FloorPlan,
    objects: &[(String, [f64; 2], [f64; 2])],
    run: &TerrainRun,
    title: &str,
) -> Drawn {
    let [w, h] = plan.size;
    let margin = 0.3;
    let size = (
        ((w + 2.0 * margin) * SCALE) as u32 + 60,
        ((h + 2.0 * margin) * SCALE) as u32 + 110,
    );
    let root = SVGBackend::with_string(svg, size).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(-margin..w + margin, -margin..h + margin)?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .light_line_style(WHITE)
        .draw()?;
    let wall_px = |t: f64| ((t * SCALE).round() as u32).max(2);
    for span in plan.spans() {
        let [a, b] = plan.span_line(&span);
        let style = ShapeStyle::from(&RGBColor(90, 90, 90))
            .stroke_width(wall_px(plan.walls[span.wall].thickness));
        chart.draw_series(LineSeries::new([(a.x, a.y), (b.x, b.y)], style))?;
    }
    for (name, lo, hi) in objects {
        let fill = RGBColor(200, 170, 120).filled();
        chart.draw_series([Rectangle::new([(lo[0], lo[1]), (hi[0], hi[1])], fill)])?;
        chart.draw_series([Text::new(
            name.clone(),
            (lo[0], hi[1] + 0.05),
            ("sans-serif", 13),
        )])?;
    }
    let truth: Vec<Pose2> = run.updates.iter().map(|u| u.truth).collect();
    let series: [(&str, &[Pose2], RGBColor); 3] = [
        ("true path", &truth, RGBColor(0, 0, 0)),
        (
            "odometry alone (from the start)",
            &run.dead_reckoned,
            RGBColor(255, 127, 14),
        ),
        (
            "map estimate (from the start)",
            &run.estimate,
            RGBColor(31, 119, 180),
        ),
    ];
    for (label, poses, colour) in series {
        chart
            .draw_series(LineSeries::new(
                poses.iter().map(|p| (p.x, p.y)),
                colour.stroke_width(2),
            ))?
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    let touched = run.updates.iter().filter(|u| u.contacts > 0);
    chart
        .draw_series(
            touched.map(|u| Circle::new((u.truth.x, u.truth.y), 2, RGBColor(44, 160, 44).filled())),
        )?
        .label("a whisk touched")
        .legend(|(x, y)| Circle::new((x + 10, y), 3, RGBColor(44, 160, 44).filled()));
    if !run.stops.is_empty() {
        let magenta = RGBColor(200, 40, 200);
        chart
            .draw_series(
                run.stops
                    .iter()
                    .map(|s| Circle::new((s.truth.x, s.truth.y), 6, magenta.stroke_width(2))),
            )?
            .label("a stop (object mode)")
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, magenta.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    drop(root);
    Ok(())
}
