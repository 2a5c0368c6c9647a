//! The console: a header saying what ran, the experiment's account on stdout, progress
//! and notes on stderr (a bar with a time estimate on a terminal, a line every tenth
//! otherwise), and the closing list of files written with the recording's open command.

use clap::ArgMatches;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::Instant;
use whisker_experiments::record::Reporter;
use whisker_scenario::console::{self, NoRecording};

/// The progress being shown: what, since when, the last tenth printed and the bar.
struct Shown {
    what: String,
    started: Instant,
    tenth: u64,
    bar: Option<ProgressBar>,
}

/// The console reporter. With `json` stdout is the command's JSON alone: what the
/// experiment says goes to stderr.
pub struct Console {
    json: bool,
    progress: Mutex<Option<Shown>>,
}

impl Console {
    pub fn new(json: bool) -> Self {
        Self {
            json,
            progress: Mutex::new(None),
        }
    }

    /// Prints `text` (several lines) on stdout, or on stderr when stdout is JSON.
    pub fn account(&self, text: &str) {
        match self.json {
            true => eprint!("{text}"),
            false => print!("{text}"),
        }
    }
}

impl Reporter for Console {
    fn say(&self, line: &str) {
        self.account(&format!("{line}\n"));
    }
    fn note(&self, line: &str) {
        let shown = self.progress.lock().unwrap_or_else(|e| e.into_inner());
        match shown.as_ref().and_then(|s| s.bar.as_ref()) {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }
    /// A line rewritten in place on a terminal; off one (a log file) nothing, so the
    /// results are not run together with it.
    fn status(&self, text: &str) {
        if std::io::stderr().is_terminal() {
            eprint!("\r{text}\x1b[K");
        }
    }
    fn progress(&self, what: &str, done: u64, total: u64) {
        let mut shown = self.progress.lock().unwrap_or_else(|e| e.into_inner());
        if shown.as_ref().is_none_or(|s| s.what != what) {
            if let Some(bar) = shown.take().and_then(|s| s.bar) {
                bar.finish_and_clear();
            }
            let bar = std::io::stderr().is_terminal().then(|| {
                let bar = ProgressBar::new(total);
                bar.set_style(
                    ProgressStyle::with_template(&format!(
                        "{{bar:40}} {{pos}}/{{len}} {what}  {{elapsed}} elapsed, about {{eta}} left"
                    ))
                    .expect("a valid template"),
                );
                bar
            });
            *shown = Some(Shown {
                what: what.to_owned(),
                started: Instant::now(),
                tenth: 0,
                bar,
            });
        }
        let s = shown.as_mut().expect("set above");
        match &s.bar {
            Some(bar) => {
                bar.set_length(total);
                bar.set_position(done);
            }
            None => {
                // Off a terminal (a log file): a line at each tenth.
                let tenth = (done * 10).checked_div(total).unwrap_or(10);
                if tenth > s.tenth && done < total {
                    s.tenth = tenth;
                    let elapsed = s.started.elapsed();
                    let left = elapsed.mul_f64((total - done) as f64 / done.max(1) as f64);
                    eprintln!(
                        "progress   {done}/{total} {what} ({} elapsed, about {} left)",
                        indicatif::HumanDuration(elapsed),
                        indicatif::HumanDuration(left)
                    );
                }
            }
        }
        if done >= total
            && let Some(bar) = shown.take().and_then(|s| s.bar)
        {
            bar.finish_and_clear();
        }
    }
}

/// The header: the (sub)command's description and the command line as given.
pub fn header(root: &clap::Command, matches: &ArgMatches) -> String {
    // Each level's description: `bench` — `bench slam`.
    let (mut command, mut matches) = (root, matches);
    let mut what = Vec::new();
    while let Some((name, sub)) = matches.subcommand() {
        match command.find_subcommand(name) {
            Some(c) => command = c,
            None => break,
        }
        let about = command
            .get_about()
            .map_or_else(|| command.get_name().to_owned(), |a| a.to_string());
        what.push(about.trim_end_matches('.').to_owned());
        matches = sub;
    }
    let what = what.join(" — ");
    let line: Vec<String> = std::iter::once("whisker".to_owned())
        .chain(std::env::args().skip(1))
        .collect();
    console::header(&what, &line.join(" "))
}

/// The closing lines: the files written (those still there) and the recording.
pub fn closing(missing: Option<NoRecording>) -> String {
    let written: Vec<_> = whisker_scenario::files::written()
        .into_iter()
        .filter(|p| p.exists())
        .collect();
    console::outputs(&written, missing)
}
