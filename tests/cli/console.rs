//! What a newcomer reads on the console, command by command: a header (the command's
//! description and the command line), the explanation of every column or line of results,
//! and `wrote` lines that name every file the command left in its output directory
//! (checked against a walk of the directory, not against the command's own list), with
//! the recording's `rerun` command or the reason there is none.

use super::*;

/// Every file under `dir`, recursively (hidden ones too: a leftover temporary would show).
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        match e.path().is_dir() {
            true => out.extend(files_under(&e.path())),
            false => out.push(e.path()),
        }
    }
    out
}

/// Whether the `wrote` lines cover `file`: listed by name in its directory's line, as the
/// line's single file, or inside a directory summarised with its file count.
fn covered(wrote: &[&str], file: &Path) -> bool {
    let dir = file.parent().unwrap().display().to_string();
    let name = file.file_name().unwrap().to_string_lossy().into_owned();
    wrote.iter().any(|l| {
        if *l == file.display().to_string() {
            return true;
        }
        if let Some(list) = l.strip_prefix(&format!("{dir}/{{")) {
            return list.trim_end_matches('}').split(", ").any(|n| n == name);
        }
        // `D/ (N files…)`: D an ancestor of the file holding exactly N files.
        l.split_once("/ (").is_some_and(|(d, rest)| {
            let n: usize = rest.split(' ').next().unwrap().parse().unwrap();
            file.starts_with(d) && files_under(Path::new(d)).len() == n
        })
    })
}

/// Checks a command's console output: the header naming `what` and the command line
/// (on stderr for `--json`), each name of `legend` explained on its own line, and, with
/// `dir`, every file in it covered by a `wrote` line and its `run.rrd` given with the
/// command that opens it.
pub fn assert_console(o: &Output, what: &str, legend: &[&str], dir: Option<&Path>) {
    assert!(o.status.success(), "{}", stderr(o));
    let out = stdout(o);
    let json = out.trim_start().starts_with(['{', '[']);
    let text = if json { stderr(o) } else { out.clone() };
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    assert!(
        first.starts_with("━━ ") && first.contains(what),
        "header: {text}"
    );
    assert!(
        lines.next().unwrap_or_default().starts_with("   whisker "),
        "{text}"
    );
    for name in legend {
        assert!(
            out.lines()
                .any(|l| l.starts_with(&format!("    {name} ")) && l.len() > name.len() + 10),
            "{name} not explained:\n{out}"
        );
    }
    let wrote: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("wrote      "))
        .collect();
    let Some(dir) = dir else {
        return;
    };
    let files = files_under(dir);
    assert!(!files.is_empty());
    for f in &files {
        assert!(covered(&wrote, f), "{} not listed:\n{text}", f.display());
    }
    let rrd = dir.join("run.rrd");
    if rrd.is_file() {
        let line = format!(
            "recording  {}  (open it: rerun {}",
            rrd.display(),
            rrd.display()
        );
        assert!(text.contains(&line), "{text}");
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn the_quickstart_explains_its_results_and_lists_every_file() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("q");
    let o = whisker(&[
        "run",
        s(&repo("scenarios/quickstart.toml")),
        "--out",
        s(&out),
        "--set",
        "explore.max_iterations=120",
    ]);
    assert_console(
        &o,
        "Run a scenario",
        &[
            "whisks",
            "fallbacks",
            "recognised",
            "SRT",
            "IM",
            "map error",
            "revisits",
        ],
        Some(&out),
    );
    assert!(
        stdout(&o).contains("trajectory none scripted"),
        "{}",
        stdout(&o)
    );
    // Without a recording the reason is given.
    let quiet = tmp.path().join("quiet");
    let o = whisker(&[
        "run",
        s(&repo("scenarios/quickstart.toml")),
        "--out",
        s(&quiet),
        "--set",
        "explore.max_iterations=5",
        "--no-rrd",
    ]);
    assert_console(&o, "Run a scenario", &[], Some(&quiet));
    assert!(
        stdout(&o).contains("recording  none (switched off"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn maze_and_object_slam_explain_their_tables_and_say_where_the_recording_is() {
    let tmp = tempfile::tempdir().unwrap();
    let maze = repo("scenarios/maze_kinematic.toml");
    let o = whisker(&["maze-slam", s(&maze), "--seeds", "0"]);
    let legend = [
        "variant",
        "images",
        "thresh",
        "energy",
        "templates",
        "ARR",
        "ARCR",
        "EM",
    ];
    assert_console(&o, "Planar RatSLAM", &legend, None);
    assert!(
        stdout(&o).contains("recording  none: give --out DIR"),
        "{}",
        stdout(&o)
    );
    let out = tmp.path().join("maze");
    let o = whisker(&["maze-slam", s(&maze), "--seeds", "0", "--out", s(&out)]);
    assert_console(&o, "Planar RatSLAM", &legend, Some(&out));
    let out = tmp.path().join("objects");
    let o = whisker(&["object-slam", "--objects", "mug", "--out", s(&out)]);
    assert_console(
        &o,
        "WhiskerRatSLAM",
        &[
            "parameters",
            "exps",
            "step",
            "nA/true",
            "nB/true",
            "confidence",
        ],
        Some(&out),
    );
}

#[test]
fn datasets_and_their_slam_list_what_they_wrote() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("walks");
    let o = whisker(&[
        "dataset",
        "object-slam",
        "--objects",
        "mug",
        "--out",
        s(&data),
    ]);
    assert_console(&o, "dataset", &[], None);
    let n = files_under(&data).len();
    assert!(
        stdout(&o).contains(&format!("wrote      {}/ ({n} files)", data.display())),
        "{}",
        stdout(&o)
    );
    let out = tmp.path().join("slam");
    let o = whisker(&["slam", s(&data), "--out", s(&out)]);
    assert_console(&o, "SLAM", &["parameters", "confidence"], Some(&out));
}

#[test]
fn tools_and_benchmarks_have_headers_and_explanations() {
    let tmp = tempfile::tempdir().unwrap();
    let urdf = repo("assets/urdf/ur5_whisker_array.urdf");
    assert_console(&whisker(&["urdf", "info", s(&urdf)]), "URDF", &[], None);
    let o = whisker(&["urdf", "fk", s(&urdf), "--joints", "0,0,0,0,0,0", "--json"]);
    assert_console(&o, "Forward kinematics", &[], None);
    let meshes = tmp.path().join("meshes");
    let o = whisker(&["assets", "generate", "--out", s(&meshes)]);
    assert_console(&o, "meshes", &[], Some(&meshes));
    let o = whisker(&["check", s(&repo("scenarios/quickstart.toml"))]);
    assert_console(&o, "Validate a scenario", &[], None);
    let o = whisker(&["characterize", "--length", "0.06", "--segments", "8"]);
    assert_console(
        &o,
        "Characterise",
        &[
            "deflections",
            "base moment",
            "follicle reading",
            "first frequency",
            "damping ratio",
        ],
        None,
    );
    let o = whisker(&["bench", "slam", "--updates", "5"]);
    assert_console(&o, "pose-cell networks", &["ratio", "times"], None);
    let o = whisker(&["bench", "sensing", "--cycles", "20"]);
    assert_console(&o, "kinematic sensing", &["ratio", "times"], None);
    let o = whisker(&[
        "soak",
        "--duration",
        "0.02",
        "--objects",
        "box",
        "--whiskers",
        "D1",
    ]);
    assert_console(
        &o,
        "Long physics runs",
        &["centre-line depth", "finite", "world steps/sample"],
        None,
    );
    assert!(
        stdout(&o).contains("recording  none: give --rrd FILE"),
        "{}",
        stdout(&o)
    );
}
