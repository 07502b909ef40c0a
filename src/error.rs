//! Errors the engine reports to its faces (CLI, GUI), each naming what and where.

use std::path::PathBuf;

/// An error from reading, fitting or writing.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A log could not be read; says file, line and column.
    #[error(transparent)]
    Ingest(#[from] crate::log::ingest::IngestError),
    /// A calibration or recipe file is malformed or of an unknown version.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong, with line and column where known.
        message: String,
    },
    /// A setting, a field of a file or a spec holds a value driftlab cannot use.
    #[error(transparent)]
    Invalid(#[from] Invalid),
    /// The data cannot support the fit that was asked for, or a model cannot be applied.
    #[error(transparent)]
    Fit(#[from] crate::models::FitError),
    /// A model's setting written as text that does not parse.
    #[error(transparent)]
    Parse(#[from] crate::models::ParseError),
    /// A stage the engine needed was not there: a defect of driftlab, named so it can be
    /// reported.
    #[error("internal: {0} (please report this)")]
    Internal(&'static str),
    /// The engineer stopped a long fit before it finished.
    #[error("cancelled")]
    Cancelled,
    /// A figure of the report could not be drawn or written; names its file.
    #[error(transparent)]
    Figure(#[from] crate::export::report::figures::FigureError),
    /// An operating-system error while reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// A setting or a field with a value driftlab cannot use: which one (as a recipe or file
/// names it, `k1_plus.knots`, `resolved.dt_s`), and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {reason}")]
pub struct Invalid {
    /// The setting or field, as a recipe or file names it.
    pub field: String,
    /// What is wrong with its value.
    pub reason: String,
}

impl Invalid {
    /// `field` cannot be used, for `reason`.
    pub fn new(field: impl Into<String>, reason: impl Into<String>) -> Invalid {
        Invalid {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

/// For the faces, whose messages are text: `?` turns an [`Invalid`] into its message.
impl From<Invalid> for String {
    fn from(e: Invalid) -> String {
        e.to_string()
    }
}

/// Shorthand for the engine's results.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Error {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
