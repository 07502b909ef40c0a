//! What keeps a figure from being made: an axis over numbers no figure can show, a failure of
//! the plotting library or of the PNG encoder, a file that cannot be written. Apart because
//! every figure fails the same ways, and the report carries these into `driftlab::Error`.

use crate::number::readable;
use std::path::PathBuf;

/// A figure that could not be drawn or written, naming its file.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// The picture could not be drawn.
    #[error("{path}: drawing the figure: {source}")]
    Drawing {
        /// The file it was to be drawn into.
        path: PathBuf,
        /// Why it could not be drawn.
        source: DrawError,
    },
    /// The PNG encoder refused the picture.
    #[error("{path}: drawing the figure: {source}")]
    Png {
        /// The PNG file.
        path: PathBuf,
        /// The encoder's error.
        source: png::EncodingError,
    },
    /// An operating-system error while writing the file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// Why a picture could not be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DrawError {
    /// An axis would reach numbers no gyro gives; drawing it would not end (the plotting
    /// library's search for tick spacings runs without end on an infinite span).
    #[error(
        "the {axis} axis would reach {}, beyond the {} a figure can show: the data hold \
         numbers no gyro gives (check the calibration and the log)",
        readable(*.value),
        if *.log { "1e-100 .. 1e100" } else { "±1e100" }
    )]
    AxisBeyond {
        /// The axis, as the figure names it (`K0`, `temperature`).
        axis: String,
        /// The bound beyond the limit.
        value: f64,
        /// Whether the axis is logarithmic.
        log: bool,
    },
    /// An axis whose bounds are equal, reversed or not numbers.
    #[error("the {axis} axis has no span ({} .. {})", readable(*.lo), readable(*.hi))]
    AxisWithoutSpan {
        /// The axis, as the figure names it.
        axis: String,
        /// Its lower bound.
        lo: f64,
        /// Its upper bound.
        hi: f64,
    },
    /// The plotting library's own error, in its words (its error type is generic over the
    /// drawing backend, so only its text is kept).
    #[error("{0}")]
    Plotting(String),
    /// The plotting library panicked; the report catches it rather than end the process.
    #[error("the plotting library panicked")]
    Panicked,
}
