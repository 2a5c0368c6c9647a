//! The error of the `whisker` library: bad input, or a failure while doing valid work.
//!
//! Bad input (scenario, mesh, URDF, dataset, settings) is an [`Error::Input`] naming the
//! file, the field or line and what was expected; an output that cannot be written (no
//! space, an I/O error, a permission: the machine's failure, not the work's) is an
//! [`Error::Output`]; anything else that goes wrong is an [`Error::Failure`]. The command
//! line decides what each means to the shell (exit codes 2, 1 and 1); a batch stops on an
//! `Output` error instead of recording the trial as failed (issue #68).

use std::fmt;
use std::path::Path;

/// An error of the library.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Error {
    /// The user's input is wrong.
    Input(String),
    /// Something failed while doing valid work.
    Failure(String),
    /// An output could not be written: the machine failed, not the work.
    Output(String),
    /// A signal asked the process to stop ([`crate::stop`]): exit code 128 + `signal`.
    Interrupted { signal: i32, message: String },
}

impl Error {
    /// An input error about `field` of `file`.
    pub fn field(file: &Path, field: &str, message: impl fmt::Display) -> Self {
        Self::Input(format!("{}: field `{field}`: {message}", file.display()))
    }

    /// Stopped by `signal` (SIGTERM 15, SIGINT 2).
    pub fn interrupted(signal: i32) -> Self {
        Self::Interrupted {
            signal,
            message: format!("stopped by {}", signal_name(signal)),
        }
    }

    /// `path` could not be written (or its directory made): `e`.
    pub fn output(path: &Path, e: impl fmt::Display) -> Self {
        Self::Output(format!("cannot write {}: {e}", path.display()))
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Input(m) | Self::Failure(m) | Self::Output(m) => f.write_str(m),
            Self::Interrupted { message, .. } => f.write_str(message),
        }
    }
}

impl std::error::Error for Error {}

impl From<whisker_sim::kinematics::UrdfError> for Error {
    fn from(e: whisker_sim::kinematics::UrdfError) -> Self {
        Self::Input(e.to_string())
    }
}

/// A signal's name: SIGINT, SIGTERM, else "signal N".
pub fn signal_name(signal: i32) -> String {
    match signal {
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        s => format!("signal {s}"),
    }
}

/// A result of the library (by default of nothing).
pub type Result<T = (), E = Error> = std::result::Result<T, E>;
