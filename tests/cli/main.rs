//! End-to-end tests of the `whisker` binary and library: the closed loop (quickstart), the arm tour, `check`, `urdf fk` on
//! any standard UR5 description, `characterize`, physics runs, and bad input (exit code
//! 2, file and field named, nothing written).

mod arm_tour;
mod console;
mod dataset;
mod dataset_malformed;
mod dataset_object;
mod dataset_office;
mod docs;
mod environment;
mod explore;
mod fuzz;
mod inputs;
mod maze_slam;

mod object_slam;
mod office;
mod office_objects;
mod physics;
mod physics_loop;
mod radial;
mod recording;
mod recording_slam;
mod ros2_bag;
mod trials;
mod trials_faults;
mod urdf;

// Helpers shared by the test modules.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

pub fn whisker(args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_whisker"))
        .args(args)
        .output()
        .expect("whisker runs");
    keep_refusal(args, &o);
    o
}

/// With `WHISKER_REFUSALS=DIR` set, a failed invocation's arguments, exit code and
/// stderr are kept in DIR, one file per distinct refusal named by a hash of its text, with
/// temporary directories written `<TMP>`: `scripts/golden.sh` compares the refusals of the
/// whole suite before and after a refactor (messages byte for byte).
pub fn keep_refusal(args: &[&str], o: &Output) {
    let Some(dir) = std::env::var_os("WHISKER_REFUSALS") else {
        return;
    };
    if o.status.success() {
        return;
    }
    // Parallel work prints in no fixed order: the lines sorted, progress counters and
    // times masked.
    let mut lines: Vec<String> = stderr(o).lines().map(masked).collect();
    lines.sort();
    let text = format!(
        "args: {}\nexit: {:?}\n{}\n",
        args.join(" "),
        o.status.code(),
        lines.join("\n")
    );
    let text = without_temporary_dirs(&text).replace(env!("CARGO_MANIFEST_DIR"), "<REPO>");
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    text.hash(&mut h);
    let dir = PathBuf::from(dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(format!("{:016x}.txt", h.finish())), text).unwrap();
}

/// A line of `whisker trials`' progress (`trials     3/12 ok KEY (0.4 s; elapsed 1s, ETA
/// 2s)`) without its counter and times; any other line as it is.
fn masked(line: &str) -> String {
    let Some(rest) = line.strip_prefix("trials     ") else {
        return line.to_string();
    };
    let Some((count, rest)) = rest.split_once(' ') else {
        return line.to_string();
    };
    let Some((_, total)) = count.split_once('/') else {
        return line.to_string();
    };
    let rest = match (rest.find(" ("), rest.find("; elapsed ")) {
        (Some(a), Some(b)) if a < b => {
            let close = rest[b..].find(')').map_or(rest.len(), |c| b + c + 1);
            format!("{} (<T>){}", &rest[..a], &rest[close..])
        }
        _ => rest.to_string(),
    };
    format!("trials     <n>/{total} {rest}")
}

/// `text` with every temporary directory (`<temp>/.tmpXXXXXX`, as `tempfile` names them)
/// and process id in a partial file's name (`.partial-<pid>`) replaced by a fixed word.
fn without_temporary_dirs(text: &str) -> String {
    let prefix = std::env::temp_dir().join(".tmp").display().to_string();
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(&prefix) {
        out.push_str(&rest[..i]);
        out.push_str("<TMP>");
        let after = &rest[i + prefix.len()..];
        let n = after
            .char_indices()
            .take_while(|(_, c)| c.is_ascii_alphanumeric())
            .count();
        rest = &after[n..];
    }
    out.push_str(rest);
    let mut clean = String::new();
    let mut rest = out.as_str();
    while let Some(i) = rest.find(".partial-") {
        clean.push_str(&rest[..i + ".partial-".len()]);
        clean.push_str("<PID>");
        let after = &rest[i + ".partial-".len()..];
        rest = after.trim_start_matches(|c: char| c.is_ascii_digit());
    }
    clean.push_str(rest);
    clean
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

/// The closed loop of the scenario in `file`, run in process (it must succeed).
pub fn closed_loop(
    file: &whisker_scenario::ScenarioFile,
) -> whisker_experiments::closed_loop::Outcome {
    let plan = whisker_scenario::plan::Plan::new(file).unwrap();
    let env = file.environment().unwrap().environment;
    let config = file.scenario.experiment.explore().unwrap();
    whisker_experiments::closed_loop::run(file, config, plan, &env).unwrap()
}

/// `f` run on a rayon pool of `threads` threads.
pub fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}
