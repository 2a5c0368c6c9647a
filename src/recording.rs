//! The Rerun recording (`.rrd`) of a run, for headless inspection: open it later with
//! `rerun out/…/run.rrd`.
//!
//! Entities (all in the arm's base-link frame, metres; timeline `sim_time` in seconds):
//! - `world/arm/skeleton`: a line strip through the origins of the chain's link frames,
//! - `world/arm/tip`: the tip link's frame (a transform with axes),
//! - `world/arm/tip_path`: the path of the tip so far (static, written at the end),
//! - `world/waypoints`: the tip positions at the waypoints (static),
//! - `world/environment/<piece>`: each fixed piece of `[[objects]]` and `[maze]` as a
//!   triangle mesh (static),
//! - `world/contacts` (kinematic sensing) or `world/anticipated` (the ground truth of a
//!   physics run): the contact points of each whisk cycle, at the cycle's start time.
//!
//! The file is written to a temporary sibling and renamed into place when complete. The
//! wall-clock `log_time` timeline is turned off so that a recording holds only what the
//! simulation determines (Rerun's row identifiers remain unique per write, so two
//! recordings of one seed hold the same data but not the same bytes).

use crate::error::{CliError, CliResult};
use crate::output;
use nalgebra::Isometry3;
use std::path::{Path, PathBuf};

/// A recording being written.
pub struct Recording {
    stream: rerun::RecordingStream,
    tmp: PathBuf,
    path: PathBuf,
}

fn fail(path: &Path, e: impl std::fmt::Display) -> CliError {
    CliError::Failure(format!("cannot write recording {}: {e}", path.display()))
}

fn point(p: &Isometry3<f64>) -> [f32; 3] {
    let v = p.translation.vector;
    [v.x as f32, v.y as f32, v.z as f32]
}

impl Recording {
    /// Starts a recording to be saved at `path`, identified by `recording_id`.
    pub fn create(path: &Path, recording_id: &str) -> CliResult<Self> {
        let tmp = output::temporary(path);
        let stream = rerun::RecordingStreamBuilder::new("whisker")
            .recording_id(recording_id)
            .save(&tmp)
            .map_err(|e| fail(path, e))?;
        stream.set_log_time_enabled(false);
        stream
            .log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())
            .map_err(|e| fail(path, e))?;
        Ok(Self {
            stream,
            tmp,
            path: path.to_path_buf(),
        })
    }

    /// The recording `DIR/run.rrd` of a scenario (named after the file and the seed), or
    /// None when the scenario switches recordings off.
    pub fn for_scenario(
        file: &Path,
        scenario: &crate::scenario::Scenario,
        dir: &Path,
    ) -> CliResult<Option<Self>> {
        if !scenario.output.recording {
            return Ok(None);
        }
        let id = format!(
            "{}-seed{}",
            file.file_stem().unwrap_or_default().to_string_lossy(),
            scenario.seed
        );
        Self::create(&dir.join("run.rrd"), &id).map(Some)
    }

    /// Logs the waypoint positions of the tip (static).
    pub fn waypoints(&self, tips: &[Isometry3<f64>]) -> CliResult {
        let points: Vec<[f32; 3]> = tips.iter().map(point).collect();
        self.stream
            .log_static(
                "world/waypoints",
                &rerun::Points3D::new(points).with_radii([0.01]),
            )
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs the arm at simulated time `t`: its link frame origins along the chain and the
    /// tip frame.
    pub fn arm(&self, t: f64, links: &[Isometry3<f64>], tip: &Isometry3<f64>) -> CliResult {
        self.stream.set_duration_secs("sim_time", t);
        let strip: Vec<[f32; 3]> = links.iter().map(point).collect();
        let q = tip.rotation.quaternion();
        let transform = rerun::Transform3D::from_translation_rotation(
            point(tip),
            rerun::Quaternion::from_xyzw([q.i as f32, q.j as f32, q.k as f32, q.w as f32]),
        );
        self.stream
            .log("world/arm/skeleton", &rerun::LineStrips3D::new([strip]))
            .and_then(|_| self.stream.log("world/arm/tip", &transform))
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs the environment's pieces as static meshes (world frame).
    pub fn environment(&self, environment: &whisker_sim::environment::Environment) -> CliResult {
        for piece in &environment.pieces {
            let entity: String = piece
                .name
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            let positions: Vec<[f32; 3]> = piece
                .mesh
                .vertices
                .iter()
                .map(|v| {
                    let w = piece.pose * v;
                    [w.x as f32, w.y as f32, w.z as f32]
                })
                .collect();
            let mesh = rerun::Mesh3D::new(positions)
                .with_triangle_indices(piece.mesh.triangles.iter().copied());
            self.stream
                .log_static(format!("world/environment/{entity}"), &mesh)
                .map_err(|e| fail(&self.path, e))?;
        }
        Ok(())
    }

    /// Logs one whisk cycle's contact points (world) under `world/<entity>` at time `t`.
    pub fn contacts(&self, entity: &str, t: f64, points: &[[f64; 3]]) -> CliResult {
        self.stream.set_duration_secs("sim_time", t);
        let points: Vec<[f32; 3]> = points
            .iter()
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
            .collect();
        self.stream
            .log(
                format!("world/{entity}"),
                &rerun::Points3D::new(points).with_radii([0.004]),
            )
            .map_err(|e| fail(&self.path, e))
    }

    /// Logs the whole tip path (static) and completes the file.
    pub fn finish(self, tip_path: &[Isometry3<f64>]) -> CliResult {
        let strip: Vec<[f32; 3]> = tip_path.iter().map(point).collect();
        self.stream
            .log_static("world/arm/tip_path", &rerun::LineStrips3D::new([strip]))
            .map_err(|e| fail(&self.path, e))?;
        self.stream
            .flush_blocking()
            .map_err(|e| fail(&self.path, e))?;
        self.stream.disconnect();
        drop(self.stream);
        output::commit(&self.tmp, &self.path)
    }
}
