//! End-to-end tests of the `whisker` binary and library: the closed loop (quickstart), the arm tour, `check`, `urdf fk` on
//! any standard UR5 description, `characterize`, physics runs, and bad input (exit code
//! 2, file and field named, nothing written).

mod arm_tour;
mod dataset;
mod dataset_malformed;
mod dataset_object;
mod environment;
mod explore;
mod inputs;
mod maze_slam;
mod object_slam;
mod physics;
mod radial;
mod recording;
mod trials;
mod urdf;

// Helpers shared by the test modules.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

pub fn whisker(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(args)
        .output()
        .expect("whisker runs")
}

/// The rows of a CSV file (header skipped), as strings.
pub fn rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs `scenario` with its output redirected to `out` (which is returned); must succeed.
pub fn run_into(scenario: &Path, out: &Path) -> PathBuf {
    let o = whisker(&[
        "run",
        scenario.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    out.to_path_buf()
}

/// The arm tour scenario's text with its output directory and URDF made absolute, so
/// it can be run from a temporary directory.
pub fn arm_tour_in(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repo("scenarios/arm_tour.toml")).unwrap();
    let urdf = repo("assets/urdf/ur5_whisker_array.urdf");
    let text = text
        .replace(
            "\"../assets/urdf/ur5_whisker_array.urdf\"",
            &format!("{:?}", urdf.display().to_string()),
        )
        .replace(
            "\"out/arm-tour\"",
            &format!("{:?}", dir.join("out").display().to_string()),
        );
    let path = dir.join("arm_tour.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Writes a scenario holding `body` (with `URDF` replaced by the project's arm) and runs it.
/// `body` with `URDF` replaced by the quoted path of the repository's UR5 description.
pub fn with_urdf(body: &str) -> String {
    let urdf = repo("assets/urdf/ur5_whisker_array.urdf");
    body.replace("URDF", &format!("{:?}", urdf.display().to_string()))
}

pub fn run_bad(dir: &Path, name: &str, body: &str) -> (Output, PathBuf) {
    let path = dir.join(format!("{name}.toml"));
    let text = with_urdf(body).replace(
        "OUT",
        &format!(
            "{:?}",
            dir.join(format!("out-{name}")).display().to_string()
        ),
    );
    std::fs::write(&path, text).unwrap();
    (whisker(&["run", path.to_str().unwrap()]), path)
}

pub const ARM: &str = "[arm]\nurdf = URDF\ninitial_joints_deg = [0, -90, 90, -90, -90, 0]\n";
pub const WAYPOINT: &str = "[[trajectory.waypoints]]\njoints_deg = [0, -80, 80, -90, -90, 0]\n";
pub const OUTPUT: &str = "[output]\ndir = OUT\n";
