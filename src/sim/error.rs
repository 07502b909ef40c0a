//! Why a run could not be simulated or written, and the error of a choice the simulator does
//! not know: apart from the physics so that the faces can match on them without reading it.

use std::path::PathBuf;

use crate::error::Invalid;

/// Why a run could not be simulated or written.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A profile or an option that cannot be simulated, naming it.
    #[error(transparent)]
    Invalid(#[from] Invalid),
    /// The log could not be written.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file being written.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
}

/// A word of a choice (`--dialect`, `--rate-names`, `--separator`, `--decimal-mark`) that the
/// simulator does not know, with the words it does.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} {given:?}: use {known}")]
pub struct UnknownChoice {
    /// What the word was to name (`dialect`, `separator`).
    pub what: &'static str,
    /// The word given.
    pub given: String,
    /// The words known, as a sentence.
    pub known: &'static str,
}
