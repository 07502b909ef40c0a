//! Errors the engine reports to its faces (CLI, GUI), each naming what and where.

use std::path::PathBuf;

/// An error from reading, fitting or writing.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A log could not be read; says file, line and column.
    #[error(transparent)]
    Ingest(#[from] crate::ingest::IngestError),
    /// A calibration or recipe file is malformed or of an unknown version.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong, with line and column where known.
        message: String,
    },
    /// The recipe asks for something that cannot be done on this log.
    #[error("{0}")]
    Recipe(String),
    /// The data cannot support the fit that was asked for.
    #[error("{0}")]
    Fit(String),
    /// The engineer stopped a long fit before it finished.
    #[error("cancelled")]
    Cancelled,
    /// An operating-system error while reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
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
