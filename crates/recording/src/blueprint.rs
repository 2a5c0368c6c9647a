//! The layouts recordings open on (a Rerun blueprint, saved in the `.rrd` beside the data
//! and made active, so that `rerun FILE.rrd` shows them): the 3-D scene on the left with its
//! camera framing the scene, the command's own panels on the right, each plot one unit with
//! its series coloured and named, on the timeline that tells the command's story.
//!
//! The Rust blueprint builder sets no view properties (a 3-D view's camera, a plot's time
//! range); [`Viewer`] keeps them beside the blueprint by the views' blueprint paths, and
//! `Recording::create` sends both as one blueprint.

use rerun::AsComponents;
use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, Spatial3DView, Tabs, TextDocumentView,
    TextLogView, TimePanel, TimeSeriesView, Vertical,
};
use rerun::external::re_sdk_types::blueprint::archetypes::{
    EyeControls3D, TimeAxis, VisualBounds2D,
};
use rerun::{Color, SeriesLines};
use whisker_experiments::record::{CASE_TABS, Eye, Layout, SENSOR_SERIES};
use whisker_slam::ratslam::local_view::{COLUMNS, ROWS};

/// A blueprint and the view properties it cannot carry: (entity path in the blueprint
/// store, the property's components).
pub struct Viewer {
    pub blueprint: Blueprint,
    pub properties: Vec<(String, Vec<rerun::SerializedComponentBatch>)>,
}

/// Builds a [`Viewer`]: views are registered with their properties as they are made.
#[derive(Default)]
struct Views {
    properties: Vec<(String, Vec<rerun::SerializedComponentBatch>)>,
}

impl Views {
    /// `view` as a container entry, with `properties` (archetype name, value) kept.
    fn add(
        &mut self,
        view: impl Into<ContainerLike>,
        properties: &[(&str, &dyn AsComponents)],
    ) -> ContainerLike {
        let view = view.into();
        if let ContainerLike::View(v) = &view {
            for (name, value) in properties {
                self.properties.push((
                    format!("{}/{name}", v.blueprint_path()),
                    value.as_serialized_batches(),
                ));
            }
        }
        view
    }

    /// The 3-D scene, its camera at `eye`.
    fn scene(&mut self, eye: Option<&Eye>) -> ContainerLike {
        let view = Spatial3DView::new("World").with_origin("/world");
        match eye {
            Some(e) => {
                let f = |v: [f64; 3]| v.map(|x| x as f32);
                let controls = EyeControls3D::new()
                    .with_position(f(e.position))
                    .with_look_target(f(e.target))
                    .with_eye_up([0.0f32, 0.0, 1.0]);
                self.add(view, &[("EyeControls3D", &controls)])
            }
            None => self.add(view, &[]),
        }
    }

    /// A plot of everything under `origin` over the whole run (not a recent window).
    fn plot(&mut self, name: &str, origin: &str, defaults: Option<&SeriesLines>) -> ContainerLike {
        let mut view = TimeSeriesView::new(name).with_origin(origin);
        if let Some(d) = defaults {
            view = view.with_defaults(d);
        }
        self.add(view, &[("TimeAxis", &whole_run())])
    }

    /// The layout: the scene left (0.6), `panels` stacked right, on `timeline`.
    fn layout(self, scene: ContainerLike, panels: Vec<ContainerLike>, timeline: &str) -> Viewer {
        let root: ContainerLike = if panels.is_empty() {
            scene
        } else {
            Horizontal::new([scene, Vertical::new(panels).into()])
                .with_column_shares([0.6, 0.4])
                .into()
        };
        Viewer {
            blueprint: Blueprint::new(root)
                .with_time_panel(TimePanel::new().with_timeline(timeline))
                .with_auto_views(false),
            properties: self.properties,
        }
    }
}

/// What the scene's colours mean (the markdown logged at `legend`).
pub const LEGEND: &str = "**Colours in the 3-D scene**\n\n\
- green: ground truth — true contacts (the rigid sweep's anticipated intersect), true paths\n\
- orange: estimates — estimated contacts, estimated paths; in a closed loop also the SPC's goals\n\
- blue: goals — the strategy's in a closed loop, the scenario's waypoints (numbered) in a scripted run; in maps the target experience\n\
- magenta: where the array truly was when SLAM re-localised\n\
- thin white lines: the whisker shafts; the thick line: the arm, with its frames' axes\n\
- red node (maps): the current experience\n\n\
Entity paths and rates: docs/recording.md.";

/// The events and the colour legend, as tabs.
fn events_and_legend(v: &mut Views) -> ContainerLike {
    Tabs::new([
        v.add(TextLogView::new("Events").with_origin("/events"), &[]),
        legend(v),
    ])
    .into()
}

/// The colour legend's view.
fn legend(v: &mut Views) -> ContainerLike {
    v.add(TextDocumentView::new("Legend").with_origin("/legend"), &[])
}

/// A plot's time axis showing the whole run rather than a recent window.
fn whole_run() -> TimeAxis {
    use rerun::blueprint::components::{LinkAxis, TimeRange};
    TimeAxis::new()
        .with_link(LinkAxis::Independent)
        .with_view_range(TimeRange(rerun::datatypes::TimeRange::EVERYTHING))
}

/// The colour of each of the [`SENSOR_SERIES`]: the angle light grey (the viewer's
/// background is dark), x blue, y orange, the strategies' states green, purple, red.
const SENSOR_COLOURS: [[u8; 3]; 6] = [
    [220, 220, 220],
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [148, 103, 189],
    [214, 39, 40],
];

/// The series defaults of a plot of the whisker streams that shows the series `shown`
/// (indices into [`SENSOR_SERIES`]): one unit per plot.
fn sensor_series(shown: &[usize]) -> SeriesLines {
    SeriesLines::new()
        .with_names(SENSOR_SERIES)
        .with_colors(SENSOR_COLOURS.map(|[r, g, b]| Color::from_rgb(r, g, b)))
        .with_visible_series((0..SENSOR_SERIES.len()).map(|i| shown.contains(&i)))
}

/// `plots` (a [`sensor_plots`] column) as the tab `name`.
fn named(plots: ContainerLike, name: &str) -> ContainerLike {
    match plots {
        ContainerLike::Vertical(c) => c.with_name(name).into(),
        other => other,
    }
}

/// The whisker streams under `origin`, one plot per unit: the whisk angle (degrees), the
/// deflections (ADC counts), the strategies' 0/1 states.
fn sensor_plots(v: &mut Views, origin: &str) -> ContainerLike {
    Vertical::new([
        v.plot("Whisk angle (°)", origin, Some(&sensor_series(&[0]))),
        v.plot(
            "Deflection x, y (ADC counts)",
            origin,
            Some(&sensor_series(&[1, 2])),
        ),
        v.plot(
            "Strategy states (1 = on): RCP, SR, CIA hold",
            origin,
            Some(&sensor_series(&[3, 4, 5])),
        ),
    ])
    .with_row_shares([0.3, 0.45, 0.25])
    .into()
}

/// The viewer layout of `layout`.
pub fn of(layout: &Layout) -> Viewer {
    match layout {
        Layout::Run { physics, eye } => run(*physics, eye.as_ref()),
        Layout::Cases { cases: c, eye } => cases(c, eye.as_ref()),
        Layout::ClosedLoop { eye } => closed_loop(eye.as_ref()),
        Layout::SlamRuns {
            runs,
            images,
            timeline,
            eye,
        } => slam_runs(runs, *images, timeline, eye.as_ref()),
    }
}

/// `whisker run` without a closed loop: the scene, and with physics whiskers their
/// streams, a tab per whisker with one plot per unit. (Such runs log no events.)
fn run(physics: bool, eye: Option<&Eye>) -> Viewer {
    let mut v = Views::default();
    let scene = v.scene(eye);
    let mut panels = Vec::new();
    if physics {
        let tabs: Vec<ContainerLike> = whisker_sim::whisker::array::labels()
            .iter()
            .map(|l| named(sensor_plots(&mut v, &format!("/sensors/{l}")), l))
            .collect();
        panels.push(Tabs::new(tabs).into());
    }
    panels.push(legend(&mut v));
    v.layout(scene, panels, super::SIM_TIME)
}

/// `whisker soak` and `radial generate`: the scene (cases side by side, the camera on the
/// first), a tab per case with its whiskers' streams (`sensors/<case>/<label>`), one plot
/// per unit, and the legend.
fn cases(cases: &[String], eye: Option<&Eye>) -> Viewer {
    let mut v = Views::default();
    let scene = v.scene(eye);
    let tabs: Vec<ContainerLike> = cases
        .iter()
        .take(CASE_TABS)
        .map(|c| named(sensor_plots(&mut v, &format!("/sensors/{c}")), c))
        .collect();
    let mut panels = Vec::new();
    if !tabs.is_empty() {
        panels.push(Tabs::new(tabs).into());
    }
    panels.push(legend(&mut v));
    v.layout(scene, panels, super::SIM_TIME)
}

/// A closed loop (Ch 6), on the whisk timeline: the scene; the raw and the integrated
/// confidence in separate plots (the latter with its threshold); the object map and the
/// pose cells; the event log.
fn closed_loop(eye: Option<&Eye>) -> Viewer {
    let mut v = Views::default();
    let scene = v.scene(eye);
    let panels = vec![
        v.plot("Raw confidence RC (§6.1.2.4)", "/recognition/raw", None),
        // The threshold a dashed-grey reference rather than a third object's colour.
        v.add(
            TimeSeriesView::new("Integrated confidence IC and its threshold (Fig 6.7)")
                .with_origin("/recognition/integrated")
                .with_override(
                    "/recognition/integrated/threshold",
                    &SeriesLines::new()
                        .with_colors([Color::from_rgb(150, 150, 150)])
                        .with_widths([1.0f32]),
                ),
            &[("TimeAxis", &whole_run())],
        ),
        Horizontal::new([
            v.add(
                Spatial2DView::new("Object map").with_origin("/slam/map"),
                &[],
            ),
            v.add(
                Spatial2DView::new("Pose cells").with_origin("/slam/pose_cells"),
                &[],
            ),
        ])
        .into(),
        events_and_legend(&mut v),
    ];
    v.layout(scene, panels, "whisk")
}

/// A SLAM command over several runs (`maze-slam`, `object-slam`): per run (`slam/<run>`)
/// a tab with its sensory input image (when `images`), pose cells and map.
fn slam_runs(runs: &[String], images: bool, timeline: &str, eye: Option<&Eye>) -> Viewer {
    let mut v = Views::default();
    let scene = v.scene(eye);
    let tabs: Vec<ContainerLike> = runs
        .iter()
        .map(|r| {
            let mut row: Vec<ContainerLike> = Vec::new();
            if images {
                // The whole 6 × 3 image in view (the default zoom cropped it).
                let bounds = VisualBounds2D::new(rerun::blueprint::components::VisualBounds2D(
                    rerun::datatypes::Range2D {
                        x_range: rerun::datatypes::Range1D([-0.5, COLUMNS as f64 + 0.5]),
                        y_range: rerun::datatypes::Range1D([-0.5, ROWS as f64 + 0.5]),
                    },
                ));
                row.push(
                    v.add(
                        Spatial2DView::new("Tactile image (§3.1.1)")
                            .with_origin(format!("/slam/{r}/tactile_image")),
                        &[("VisualBounds2D", &bounds)],
                    ),
                );
            }
            row.push(v.add(
                Spatial2DView::new("Pose cells").with_origin(format!("/slam/{r}/pose_cells")),
                &[],
            ));
            let map = v.add(
                Spatial2DView::new("Map").with_origin(format!("/slam/{r}/map")),
                &[],
            );
            Vertical::new([Horizontal::new(row).into(), map])
                .with_name(r.as_str())
                .into()
        })
        .collect();
    let mut panels: Vec<ContainerLike> = vec![Tabs::new(tabs).into()];
    if !images {
        // object-slam: the identification runs' confidence in each mapped object.
        panels.push(v.plot("Identification confidence (§5.2.2.2)", "/recognition", None));
    }
    panels.push(events_and_legend(&mut v));
    v.layout(scene, panels, timeline)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The view properties of `viewer` named `name` (by the archetype's last path part).
    fn count(viewer: &Viewer, name: &str) -> usize {
        viewer
            .properties
            .iter()
            .filter(|(p, _)| p.ends_with(&format!("/{name}")))
            .count()
    }

    /// A soak or data-set recording: the camera on the first case, three whole-run plots
    /// (angle, deflections, states) in each case's tab, at most [`CASE_TABS`] tabs.
    #[test]
    fn cases_get_a_camera_and_a_tab_each_up_to_the_limit() {
        let eye = Eye::framing([0.0; 3], [0.2, 0.2, 0.2]);
        for (n, tabs) in [(0, 0), (1, 1), (8, 8), (CASE_TABS + 5, CASE_TABS)] {
            let layout = Layout::Cases {
                cases: (0..n).map(|k| format!("case_{k}")).collect(),
                eye: Some(eye),
            };
            let viewer = of(&layout);
            assert_eq!(count(&viewer, "EyeControls3D"), 1, "{n} cases");
            assert_eq!(count(&viewer, "TimeAxis"), 3 * tabs, "{n} cases");
        }
        let viewer = of(&Layout::Cases {
            cases: vec!["box".into()],
            eye: None,
        });
        assert_eq!(count(&viewer, "EyeControls3D"), 0);
    }
}
