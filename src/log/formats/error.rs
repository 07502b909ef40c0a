//! What can go wrong reading a drone or robot log, and choosing a gyro in it: each error
//! names the file and, for a malformed file, the byte offset where the reader stopped.

use super::Format;
use super::ros_topics::{KEPT_BYTES_AT_MOST, KEPT_PER_FILE_BYTE};
use std::path::PathBuf;

/// A log that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// The operating system could not read the file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The first bytes are none of the formats' magic bytes.
    #[error(
        "{path}: not a PX4 ULog, ArduPilot DataFlash, ROS 1 bag or MCAP file \
         (it starts with {head})"
    )]
    Unrecognised {
        /// The file.
        path: PathBuf,
        /// The first bytes, in hex.
        head: String,
    },
    /// The file is of a known format but broken at `offset`.
    #[error("{path}: {format} log malformed at byte {offset}: {message}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What the magic bytes said it is.
        format: Format,
        /// Byte offset in the file where the broken part starts.
        offset: u64,
        /// What is wrong there.
        message: String,
    },
    /// A ROS 1 bag or MCAP file that is not broken but holds more Imu and Temperature
    /// messages than the reader keeps (`ros_topics.rs`): told apart from [`Malformed`]
    /// so that an honest long recording is not called corrupt.
    ///
    /// [`Malformed`]: FormatError::Malformed
    #[error(
        "{path}: {format} log not malformed, but larger than driftlab keeps: its Imu and \
         Temperature messages reach {limit_mib} MiB at byte {offset}, at a message on {topic} \
         (the most kept is {floor_mib} MiB, or {per_byte} times the file's size when that is \
         more); kept by then: {kept}; every Imu and Temperature topic is kept while reading \
         (gyro N chooses among them only afterwards), so no setting reads less: cut the log to \
         the topics or the time span needed (e.g. {}) and read that",
        cutting_tool(*.format),
        floor_mib = KEPT_BYTES_AT_MOST >> 20,
        per_byte = KEPT_PER_FILE_BYTE
    )]
    TooLargeToKeep {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: Format,
        /// Byte offset of the record (or the chunk holding it) where the messages ran out of
        /// room.
        offset: u64,
        /// The most the file's messages may take, MiB.
        limit_mib: usize,
        /// The topic of the message that did not fit, quoted.
        topic: String,
        /// What was kept, topic by topic, largest first: name, messages, bytes.
        kept: String,
    },
    /// The file is whole but holds no gyro data driftlab can use.
    #[error("{path}: {format} log without gyro data: {message}")]
    NoGyro {
        /// The file.
        path: PathBuf,
        /// Its format.
        format: Format,
        /// What was looked for and what was found instead.
        message: String,
    },
}

impl FormatError {
    /// The byte offset of a malformed file's broken part, if that is the error.
    pub fn offset(&self) -> Option<u64> {
        match self {
            FormatError::Malformed { offset, .. } => Some(*offset),
            _ => None,
        }
    }
}

/// The tool that cuts a log of `format` to some of its topics or a time span: what a user
/// can do about a log too large to keep, as no setting reads fewer topics (`gyro` chooses
/// among them once every one is read).
fn cutting_tool(format: Format) -> &'static str {
    match format {
        Format::RosBag => "rosbag filter",
        Format::Mcap => "mcap filter",
        Format::Ulog | Format::DataFlash => "the format's own tools",
    }
}

/// A gyro instance (or its temperature) that cannot be used as asked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SelectionError {
    /// `--gyro N` past the last instance.
    #[error("{source_name}: there is no gyro {asked}; the log has {count}: {listing}")]
    NoSuchInstance {
        /// The log.
        source_name: String,
        /// The index asked for.
        asked: usize,
        /// How many instances there are.
        count: usize,
        /// The instances, one `N: label` each.
        listing: String,
    },
    /// The chosen gyro has no temperature of its own (or no instance has one) and no
    /// replacement was asked for.
    #[error("{source_name}: {what}; {alternatives}")]
    NoTemperature {
        /// The log.
        source_name: String,
        /// Which gyro lacks a temperature (or that none has one).
        what: String,
        /// The temperatures that could stand in, with the option that picks each, or a
        /// sentence saying there are none.
        alternatives: String,
    },
}

/// Where in its bytes a reader stopped and why; the public error adds file and format.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Broken {
    /// Byte offset in the file.
    pub offset: u64,
    /// What is wrong.
    pub message: String,
    /// Set when nothing is wrong with the file but it holds more messages than are kept
    /// ([`FormatError::TooLargeToKeep`]); `message` then says the same for a reader of this
    /// struct alone.
    pub too_large: Option<Box<TooLarge>>,
}

/// What a ROS log had kept when its messages reached the most the reader keeps.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct TooLarge {
    /// The most the messages may take, MiB.
    pub limit_mib: usize,
    /// The topic of the message that did not fit, quoted.
    pub topic: String,
    /// The topics kept, largest first, as [`listed`] gives them: `name (N messages, size)`.
    pub kept: String,
}

impl Broken {
    pub(crate) fn at(offset: u64, message: impl Into<String>) -> Broken {
        Broken {
            offset,
            message: message.into(),
            too_large: None,
        }
    }

    /// A stop at `offset` because the messages kept reached their limit.
    pub(crate) fn too_large(offset: u64, t: TooLarge) -> Broken {
        Broken {
            offset,
            message: format!(
                "the messages kept reach {} MiB at a message on {}",
                t.limit_mib, t.topic
            ),
            too_large: Some(Box::new(t)),
        }
    }

    /// An error found inside a compressed chunk (ROS bag, MCAP), whose offsets count its
    /// decompressed bytes, placed at the chunk's own offset in the file (the only offset an
    /// engineer can find in the file) with the offset inside it in the message.
    pub(crate) fn inside_chunk(self, chunk_at: u64) -> Broken {
        Broken {
            too_large: self.too_large,
            ..Broken::at(
                chunk_at,
                format!(
                    "in the chunk starting here, at byte {} of its decompressed records: {}",
                    self.offset, self.message
                ),
            )
        }
    }

    /// The public error for this stop in `path`, a file of `format`.
    pub(crate) fn into_error(self, path: PathBuf, format: Format) -> FormatError {
        match self.too_large {
            Some(t) => FormatError::TooLargeToKeep {
                path,
                format,
                offset: self.offset,
                limit_mib: t.limit_mib,
                topic: t.topic,
                kept: t.kept,
            },
            None => FormatError::Malformed {
                path,
                format,
                offset: self.offset,
                message: self.message,
            },
        }
    }
}

/// The most characters of a name read from a file (topic, frame_id, format, field) a message
/// quotes: enough to recognise it, too few to flood a terminal with a crafted megabyte.
pub(crate) const QUOTE_AT_MOST: usize = 80;

/// `name` as a message quotes it: whole up to [`QUOTE_AT_MOST`] characters, else its start,
/// `...` and its length in bytes.
pub(crate) fn quoted(name: &str) -> std::borrow::Cow<'_, str> {
    match name.char_indices().nth(QUOTE_AT_MOST) {
        None => std::borrow::Cow::Borrowed(name),
        Some((cut, _)) => {
            std::borrow::Cow::Owned(format!("{}... ({} bytes)", &name[..cut], name.len()))
        }
    }
}

/// The most items a message lists before it says how many more there are.
pub(crate) const LIST_AT_MOST: usize = 8;

/// The first [`LIST_AT_MOST`] of `items` joined by `sep`, then `and N more` when there are
/// more: a message about a log of 20 000 topics stays one readable line.
pub(crate) fn listed(items: impl ExactSizeIterator<Item = String>, sep: &str) -> String {
    let total = items.len();
    let mut s: Vec<String> = items.take(LIST_AT_MOST).collect();
    if total > LIST_AT_MOST {
        s.push(format!("and {} more", total - LIST_AT_MOST));
    }
    s.join(sep)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_name_is_quoted_by_its_start_and_length() {
        assert_eq!(quoted("/imu"), "/imu");
        let long = "é".repeat(1000);
        let q = quoted(&long);
        assert!(q.starts_with(&"é".repeat(QUOTE_AT_MOST)), "{q}");
        assert!(q.ends_with("... (2000 bytes)"), "{q}");
        assert_eq!(q.chars().count(), QUOTE_AT_MOST + "... (2000 bytes)".len());
    }

    #[test]
    fn a_long_list_names_its_first_items_and_counts_the_rest() {
        let few = listed((0..3).map(|i| i.to_string()), ", ");
        assert_eq!(few, "0, 1, 2");
        let many = listed((0..20_000).map(|i| i.to_string()), ", ");
        assert_eq!(many, "0, 1, 2, 3, 4, 5, 6, 7, and 19992 more");
    }
}
