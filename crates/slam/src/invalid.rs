//! What is wrong with a value an algorithm or a model was given: the field at fault
//! (dotted, relative to what was checked; empty when the message says it all) and what
//! was expected. Every `validate` of a parameter set returns it; the scenario crate adds
//! the file and the section it sits in.

use std::fmt;

/// A value outside what was expected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Invalid {
    /// The field at fault, relative to what was checked (`sigma_t`, `pose_cells.cells`);
    /// empty when the message names it.
    pub field: String,
    /// What is wrong and what was expected.
    pub message: String,
}

impl Invalid {
    /// The value is wrong, as `message` says.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            field: String::new(),
            message: message.into(),
        }
    }

    /// Its `field` is wrong, as `message` says.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for Invalid {
    /// `field: message`, or the message alone.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            f.write_str(&self.message)
        } else {
            write!(f, "{}: {}", self.field, self.message)
        }
    }
}

impl std::error::Error for Invalid {}

impl From<String> for Invalid {
    fn from(message: String) -> Self {
        Self::new(message)
    }
}

impl<F: Into<String>> From<(F, String)> for Invalid {
    /// (field, message).
    fn from((field, message): (F, String)) -> Self {
        Self::field(field, message)
    }
}

impl From<&str> for Invalid {
    fn from(message: &str) -> Self {
        Self::new(message)
    }
}
