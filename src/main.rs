//! `whisker`: the command line of the whisker-slam testbed (see README.md). Clap's
//! arguments become the library's settings; the library's reports are printed here, its
//! recordings are Rerun files and what it says goes to the console.

mod cli;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;
use whisker_experiments::record::Context;
use whisker_recording::Rerun;
use whisker_scenario::Error;
use whisker_scenario::console::NoRecording;

/// Tactile SLAM and object recognition testbed for an actively whisked artificial
/// whisker array on a UR5 arm.
#[derive(Parser)]
#[command(name = "whisker", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario: simulate it and write its results and Rerun recording.
    Run(cli::run::RunArgs),
    /// Validate a scenario and print what would run; writes nothing.
    Check(cli::run::CheckArgs),
    /// Characterise one whisker design: static point load, then ring-down.
    Characterize(cli::characterize::Args),
    /// The physics front end against the anticipated contacts of kinematic sensing, per
    /// whisking mode: recall, precision and the errors of onset, radial distance, point, slope.
    Fidelity(cli::fidelity::Args),
    /// Benchmarks (timing; never part of the tests).
    Bench {
        #[command(subcommand)]
        command: cli::bench::Command,
    },
    /// Batch trials: a scenario's `[trials]` over seeds and factors, resumable, sharded,
    /// with statistics and plots.
    Trials(cli::trials::Args),
    /// Long physics runs against every object and the maze: no tunnelling, no NaN.
    Soak(cli::soak::Args),
    /// WhiskerRatSLAM on the catalogue objects (thesis §5.2): localisation and identification.
    ObjectSlam(cli::object_slam::Args),
    /// Planar RatSLAM on the maze with tactile images (thesis Ch 3): ARR, ARCR, EM.
    MazeSlam(cli::maze_slam::Args),
    /// Write a seeded dataset in the lab's log layout with ground truth beside it
    /// (docs/dataset.md), or add noise to a clean one (`dataset noise`).
    Dataset(cli::dataset::Args),
    /// Run the front end and the SLAM a dataset's manifest names, from the dataset alone.
    Slam(cli::dataset::SlamArgs),
    /// Write a dataset or a run's output as a ROS 2 bag (MCAP), readable by the ROS 2 tools;
    /// `whisker slam --mcap` replays a dataset's bag.
    Export(cli::export::Args),
    /// Radial distance to contact (thesis Ch 4): data sets, the Table 4.1 models, validation.
    Radial {
        #[command(subcommand)]
        command: cli::radial::Command,
    },
    /// The generated object meshes of `assets/meshes`.
    Assets {
        #[command(subcommand)]
        command: cli::tools::AssetsCommand,
    },
    /// Inspect a URDF robot description.
    Urdf {
        #[command(subcommand)]
        command: cli::tools::UrdfCommand,
    },
}

fn main() -> ExitCode {
    // With --json stdout is the JSON alone: the header, the account and the file list go
    // to stderr.
    let console = cli::console::Console::new(std::env::args().any(|a| a == "--json"));
    let ctx = Context {
        recordings: &Rerun,
        reporter: &console,
    };
    let matches = Cli::command().get_matches();
    let command = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli.command,
        Err(e) => e.exit(),
    };
    let header = cli::console::header(&Cli::command(), &matches);
    let missing = missing_recording(&command);
    console.account(&header);
    // A failed batch keeps its finished trials (they are resumed); any other failed
    // command removes what it created, panics included.
    let keep_on_failure = matches!(command, Command::Trials(_));
    // Nothing the command touched is used after a panic but the list of what it created.
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| dispatch(command, ctx)));
    let failed = !matches!(result, Ok(Ok(())));
    if failed && !keep_on_failure {
        whisker_scenario::files::discard_created();
    }
    match result {
        Ok(Ok(())) => {
            console.account(&cli::console::closing(missing));
            ExitCode::SUCCESS
        }
        Ok(Err(e)) => {
            eprintln!("error: {e}");
            // Bad input exits with 2, anything else with 1.
            ExitCode::from(match e {
                Error::Input(_) => 2,
                Error::Failure(_) | Error::Output(_) => 1,
                // 143 for SIGTERM, 130 for SIGINT, as a shell reports a signalled process.
                Error::Interrupted { signal, .. } => (128 + signal).clamp(1, 255) as u8,
            })
        }
        // The panic's message is printed by the default hook.
        Err(_) => ExitCode::from(101),
    }
}

/// Why a command that can record wrote no recording, should it write none.
fn missing_recording(command: &Command) -> Option<NoRecording> {
    let slam = |rrd: &cli::RrdArgs| match rrd.no_rrd {
        true => NoRecording::SwitchedOff,
        false => NoRecording::NoOut,
    };
    match command {
        Command::Run(_) => Some(NoRecording::SwitchedOff),
        Command::ObjectSlam(a) => Some(slam(&a.rrd)),
        Command::MazeSlam(a) => Some(slam(&a.rrd)),
        Command::Soak(_) => Some(NoRecording::NoFile),
        Command::Radial {
            command: cli::radial::Command::Generate(_),
        } => Some(NoRecording::SwitchedOff),
        _ => None,
    }
}

/// Runs one command.
fn dispatch(command: Command, ctx: Context) -> whisker_scenario::Result {
    match command {
        Command::Run(a) => cli::run::run(&a, ctx),
        Command::Check(a) => cli::run::check(&a, ctx),
        Command::Characterize(a) => cli::characterize::run(&a),
        Command::Fidelity(a) => cli::fidelity::run(&a, ctx),
        Command::Bench { command } => cli::bench::run(&command, ctx),
        Command::Trials(a) => cli::trials::run(&a, ctx),
        Command::Soak(a) => cli::soak::run(&a, ctx),
        Command::ObjectSlam(a) => cli::object_slam::run(&a, ctx),
        Command::MazeSlam(a) => cli::maze_slam::run(&a, ctx),
        Command::Dataset(a) => cli::dataset::run(&a, ctx),
        Command::Slam(a) => cli::dataset::slam(&a, ctx),
        Command::Export(a) => cli::export::run(&a),
        Command::Radial { command } => cli::radial::run(&command, ctx),
        Command::Assets { command } => cli::tools::assets(&command, ctx),
        Command::Urdf { command } => cli::tools::urdf(&command, ctx),
    }
}
