//! Errors of the `whisker` binary and their exit codes.
//!
//! Bad input (scenario, URDF, CLI arguments) is a [`CliError::Input`] and exits with
//! code 2, naming the file, the field or element, and what was expected. Anything else
//! that goes wrong (an output directory that cannot be written…) exits with code 1.

use std::fmt;
use std::path::Path;

/// An error of the command line tool.
#[derive(Debug)]
pub enum CliError {
    /// The user's input is wrong: exit code 2.
    Input(String),
    /// Something failed while doing valid work: exit code 1.
    Failure(String),
}

impl CliError {
    /// An input error about `field` of `file`.
    pub fn field(file: &Path, field: &str, message: impl fmt::Display) -> Self {
        Self::Input(format!("{}: field `{field}`: {message}", file.display()))
    }

    /// The process exit code for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            Self::Input(_) => 2,
            Self::Failure(_) => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Input(m) | Self::Failure(m) => f.write_str(m),
        }
    }
}

impl From<whisker_sim::kinematics::UrdfError> for CliError {
    fn from(e: whisker_sim::kinematics::UrdfError) -> Self {
        Self::Input(e.to_string())
    }
}

/// Result of a command.
pub type CliResult<T = ()> = Result<T, CliError>;
