//! `whisker`: the command line of the whisker-slam testbed (see README.md). Only the
//! argument parsing lives here; every command is a call into the `whisker` library.

use whisker::{
    assets_cmd, bench, bench_sensing, bench_slam, characterize, maze_slam, object_slam, radial,
    run, soak, urdf_cmd,
};

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use whisker::record::{Context, Reporter};
use whisker::recording::Rerun;
use whisker::scenario::overrides::Override;

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
    Run {
        /// The scenario TOML file.
        scenario: PathBuf,
        /// Output directory (overrides `output.dir` of the scenario).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Seed of every random sub-stream (overrides `seed` of the scenario).
        #[arg(long)]
        seed: Option<u64>,
        /// Change a scenario field by its dotted path, e.g. `--set explore.strategy=feh`
        /// (VALUE is TOML; a bare word is a string). Repeatable.
        #[arg(long = "set", value_name = "PATH=VALUE", value_parser = Override::parse)]
        set: Vec<Override>,
        #[command(flatten)]
        rrd: whisker::record::Target,
    },
    /// Validate a scenario and print what would run; writes nothing.
    Check {
        /// The scenario TOML file.
        scenario: PathBuf,
        /// Also write each `[[objects]]` mesh as loaded (repaired or replaced, in its own
        /// frame, metres, z up) to DIR/NAME.obj, to look at what the repair made of it.
        #[arg(long, value_name = "DIR")]
        meshes: Option<PathBuf>,
    },
    /// Characterise one whisker design: static point load, then ring-down.
    Characterize(characterize::Options),
    /// Benchmarks (timing; never part of the tests).
    Bench {
        #[command(subcommand)]
        command: BenchCommand,
    },
    /// Batch trials: a scenario's `[trials]` over seeds and factors, resumable, sharded,
    /// with statistics and plots.
    Trials(whisker::trials::command::Args),
    /// Long physics runs against every object and the maze: no tunnelling, no NaN.
    Soak(soak::Options),
    /// WhiskerRatSLAM on the catalogue objects (thesis §5.2): localisation and identification.
    ObjectSlam(object_slam::Options),
    /// Planar RatSLAM on the maze with tactile images (thesis Ch 3): ARR, ARCR, EM.
    MazeSlam(maze_slam::Options),
    /// Write a seeded dataset in the lab's log layout with ground truth beside it
    /// (docs/dataset.md), or add noise to a clean one (`dataset noise`).
    Dataset(whisker::dataset::Args),
    /// Run the front end and the SLAM a dataset's manifest names, from the dataset alone.
    Slam(whisker::dataset::SlamOptions),
    /// Radial distance to contact (thesis Ch 4): data sets, the Table 4.1 models, validation.
    Radial {
        #[command(subcommand)]
        command: radial::RadialCommand,
    },
    /// The generated object meshes of `assets/meshes`.
    Assets {
        #[command(subcommand)]
        command: AssetsCommand,
    },
    /// Inspect a URDF robot description.
    Urdf {
        #[command(subcommand)]
        command: UrdfCommand,
    },
}

#[derive(Subcommand)]
enum BenchCommand {
    /// Real-time factor of the physics sensing mode (1 and 18 whiskers, free and in contact).
    Physics(bench::Options),
    /// Whisk cycles per second of kinematic sensing (the full array near an object).
    Sensing(bench_sensing::Options),
    /// WhiskerRatSLAM's core: one 6-D pose-cell update against a naive dense convolution.
    Slam(bench_slam::Options),
    /// What the Rerun recording costs a run: wall time with and without, and its size.
    Recording(whisker::bench_recording::Options),
    /// Batch trials on 1 against 2 worker threads (speed-up; same trials.csv).
    Trials(whisker::trials::command::BenchOptions),
}

#[derive(Subcommand)]
enum AssetsCommand {
    /// Generate the object catalogue (deterministic) as OBJ files.
    Generate {
        /// Output directory.
        #[arg(long, default_value = "assets/meshes")]
        out: PathBuf,
    },
}

#[derive(Subcommand)]
enum UrdfCommand {
    /// Links, joints, limits and the default chain.
    Info {
        /// The URDF file.
        urdf: PathBuf,
        /// Directory searched for `package://` meshes (repeatable).
        #[arg(long = "package-path")]
        package_paths: Vec<PathBuf>,
    },
    /// Forward kinematics: the pose of a link in another link's frame.
    Fk {
        /// The URDF file.
        urdf: PathBuf,
        /// Joint positions of the chain from --base to --link, comma-separated (rad; m for prismatic).
        #[arg(long, allow_hyphen_values = true)]
        joints: String,
        /// Frame the pose is expressed in [default: base_link, else the root link].
        #[arg(long)]
        base: Option<String>,
        /// Link whose pose is computed [default: tool0, else the only leaf link].
        #[arg(long)]
        link: Option<String>,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Directory searched for `package://` meshes (repeatable).
        #[arg(long = "package-path")]
        package_paths: Vec<PathBuf>,
    },
}

/// The console: an experiment's account on stdout, its notes on stderr.
struct Console;

impl Reporter for Console {
    fn say(&self, line: &str) {
        println!("{line}");
    }
    fn note(&self, line: &str) {
        eprintln!("{line}");
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let ctx = Context {
        recordings: &Rerun,
        reporter: &Console,
    };
    let result = match cli.command {
        Command::Run {
            scenario,
            out,
            seed,
            set,
            rrd,
        } => run::run(&scenario, out, seed, &set, &rrd, ctx),
        Command::Check { scenario, meshes } => run::check(&scenario, meshes.as_deref()),
        Command::Characterize(options) => characterize::run(&options),
        Command::Bench {
            command: BenchCommand::Physics(options),
        } => bench::physics(&options),
        Command::Bench {
            command: BenchCommand::Sensing(options),
        } => bench_sensing::sensing(&options),
        Command::Bench {
            command: BenchCommand::Recording(options),
        } => whisker::bench_recording::recording(&options, ctx),
        Command::Bench {
            command: BenchCommand::Slam(options),
        } => bench_slam::slam(&options),
        Command::Bench {
            command: BenchCommand::Trials(options),
        } => whisker::trials::command::bench(&options, &Rerun),
        Command::Trials(args) => whisker::trials::command::run(&args, &Rerun),
        Command::Soak(options) => soak::soak(&options, ctx),
        Command::ObjectSlam(options) => object_slam::run(&options, ctx),
        Command::Radial { command } => radial::run(&command, ctx),
        Command::MazeSlam(options) => maze_slam::run(&options, ctx),
        Command::Dataset(args) => whisker::dataset::run(&args),
        Command::Slam(options) => whisker::dataset::slam(&options, ctx),
        Command::Assets {
            command: AssetsCommand::Generate { out },
        } => assets_cmd::generate_all(&out),
        Command::Urdf { command } => match command {
            UrdfCommand::Info {
                urdf,
                package_paths,
            } => urdf_cmd::info(&urdf, &package_paths),
            UrdfCommand::Fk {
                urdf,
                joints,
                base,
                link,
                json,
                package_paths,
            } => urdf_cmd::fk(
                &urdf,
                &package_paths,
                &joints,
                base.as_deref(),
                link.as_deref(),
                json,
            ),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code() as u8)
        }
    }
}
