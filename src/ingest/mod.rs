//! Reading test-stand logs (in progress).

/// A log that could not be read, with file, line and column.
#[derive(Debug, thiserror::Error)]
#[error("{file}:{line}:{column}: {message}")]
pub struct IngestError {
    /// File name.
    pub file: String,
    /// 1-based line, 0 when not about a line.
    pub line: usize,
    /// 1-based column, 0 when not about a column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}
