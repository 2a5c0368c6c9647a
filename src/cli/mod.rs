//! The command line: one module per command, each clap's arguments → the library's
//! settings → the report printed. Everything else is in the `whisker` library.

pub mod bench;
pub mod characterize;
pub mod console;
pub mod dataset;
pub mod export;
pub mod fidelity;
pub mod maze_slam;
pub mod object_slam;
pub mod radial;
pub mod run;
pub mod signals;
pub mod soak;
pub mod tools;
pub mod trials;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use serde::Serialize;
use std::path::PathBuf;
use whisker_experiments::record::Target;
use whisker_scenario::choice::Choice;

/// `--rrd FILE` / `--no-rrd`: where a command writes its recording.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RrdArgs {
    /// Write the Rerun recording to FILE [default: run.rrd in the output directory].
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
    /// Write no Rerun recording.
    #[arg(long, conflicts_with = "rrd")]
    pub no_rrd: bool,
}

impl RrdArgs {
    /// The recording's target.
    pub fn target(&self) -> Target {
        Target {
            rrd: self.rrd.clone(),
            no_rrd: self.no_rrd,
            id: None,
        }
    }
}

/// Parses a [`Choice`] by its name, its values and their meanings in the help.
pub fn choice<T: Choice + Clone>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|(_, name, help)| PossibleValue::new(name).help(help)),
    )
    .map(|name| T::named(&name).expect("clap accepts only the names"))
}

/// Prints `value` as JSON, its objects' keys sorted.
pub fn print_json(value: &impl Serialize, pretty: bool) {
    let v = serde_json::to_value(value).expect("plain data");
    if pretty {
        println!("{}", serde_json::to_string_pretty(&v).expect("plain JSON"));
    } else {
        println!("{v}");
    }
}
