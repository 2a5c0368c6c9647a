//! The layouts recordings open on (a Rerun blueprint, saved in the `.rrd` beside the data
//! and made active, so that `rerun FILE.rrd` shows them): the 3-D scene on the left, the
//! command's own panels on the right.

use rerun::blueprint::{
    Blueprint, ContainerLike, Horizontal, Spatial2DView, Spatial3DView, Tabs, TextLogView,
    TimePanel, TimeSeriesView, Vertical,
};
use whisker_experiments::record::Layout;

fn layout(panels: Vec<ContainerLike>, timeline: &str) -> Blueprint {
    let scene: ContainerLike = Spatial3DView::new("World").with_origin("/world").into();
    let root: ContainerLike = if panels.is_empty() {
        scene
    } else {
        Horizontal::new([scene, Vertical::new(panels).into()])
            .with_column_shares([0.6, 0.4])
            .into()
    };
    Blueprint::new(root)
        .with_time_panel(TimePanel::new().with_timeline(timeline))
        .with_auto_views(false)
}

/// The whisker streams: one tab per whisker of `labels` (the first few).
fn sensor_tabs(labels: &[String]) -> ContainerLike {
    Tabs::new(labels.iter().map(|l| {
        TimeSeriesView::new(l.as_str())
            .with_origin(format!("/sensors/{l}"))
            .into()
    }))
    .into()
}

/// The blueprint of `layout`.
pub fn of(layout: &Layout) -> Blueprint {
    match layout {
        Layout::Run { physics } => run(*physics),
        Layout::Cases => cases(),
        Layout::ClosedLoop => closed_loop(),
        Layout::SlamRuns {
            runs,
            images,
            timeline,
        } => slam_runs(runs, *images, timeline),
    }
}

/// `whisker run` without a closed loop: the scene, and with physics whiskers their
/// streams (a tab per whisker). (Such runs log no events.)
fn run(physics: bool) -> Blueprint {
    let panels = if physics {
        vec![sensor_tabs(&whisker_sim::whisker::array::labels())]
    } else {
        Vec::new()
    };
    layout(panels, super::SIM_TIME)
}

/// `whisker soak` and `radial generate`: the scene (cases side by side) and every case's
/// streams in one time-series view (`sensors/<case>/<label>`).
fn cases() -> Blueprint {
    layout(
        vec![
            TimeSeriesView::new("Whisker streams")
                .with_origin("/sensors")
                .into(),
        ],
        super::SIM_TIME,
    )
}

/// A closed loop (Ch 6): the scene; confidence over time; the object map and the pose
/// cells; the event log.
fn closed_loop() -> Blueprint {
    layout(
        vec![
            TimeSeriesView::new("Confidence")
                .with_origin("/recognition")
                .into(),
            Horizontal::new([
                Spatial2DView::new("Object map")
                    .with_origin("/slam/map")
                    .into(),
                Spatial2DView::new("Pose cells")
                    .with_origin("/slam/pose_cells")
                    .into(),
            ])
            .into(),
            TextLogView::new("Events").with_origin("/events").into(),
        ],
        super::SIM_TIME,
    )
}

/// A SLAM command over several runs (`maze-slam`, `object-slam`): per run (`slam/<run>`)
/// a tab with its sensory input image (when `images`), pose cells and map.
fn slam_runs(runs: &[String], images: bool, timeline: &str) -> Blueprint {
    let tabs = Tabs::new(runs.iter().map(|r| {
        let mut row: Vec<ContainerLike> = Vec::new();
        if images {
            row.push(
                Spatial2DView::new("Tactile image")
                    .with_origin(format!("/slam/{r}/tactile_image"))
                    .into(),
            );
        }
        row.push(
            Spatial2DView::new("Pose cells")
                .with_origin(format!("/slam/{r}/pose_cells"))
                .into(),
        );
        Vertical::new([
            Horizontal::new(row).into(),
            Spatial2DView::new("Map")
                .with_origin(format!("/slam/{r}/map"))
                .into(),
        ])
        .with_name(r.as_str())
        .into()
    }));
    layout(
        vec![
            tabs.into(),
            TextLogView::new("Events").with_origin("/events").into(),
        ],
        timeline,
    )
}
