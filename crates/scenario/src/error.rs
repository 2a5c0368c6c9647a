//! The error of the `whisker` library: bad input, or a failure while doing valid work.
//!
//! Bad input (scenario, mesh, URDF, dataset, settings) is an [`Error::Input`] naming the
//! file, the field or line and what was expected; anything else that goes wrong (an
//! output directory that cannot be written…) is an [`Error::Failure`]. The command line
//! decides what each means to the shell (exit codes 2 and 1).

use std::fmt;
use std::path::Path;

/// An error of the library.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Error {
    /// The user's input is wrong.
    Input(String),
    /// Something failed while doing valid work.
    Failure(String),
}

impl Error {
    /// An input error about `field` of `file`.
    pub fn field(file: &Path, field: &str, message: impl fmt::Display) -> Self {
        Self::Input(format!("{}: field `{field}`: {message}", file.display()))
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Input(m) | Self::Failure(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Error {}

impl From<whisker_sim::kinematics::UrdfError> for Error {
    fn from(e: whisker_sim::kinematics::UrdfError) -> Self {
        Self::Input(e.to_string())
    }
}

/// A result of the library (by default of nothing).
pub type Result<T = (), E = Error> = std::result::Result<T, E>;
