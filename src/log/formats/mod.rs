//! Drone and robot logs: PX4 ULog, ArduPilot DataFlash `.bin`, ROS 1 bags and MCAP (ROS 2),
//! read into the gyro instances they hold.
//!
//! Flight controllers and robots record their IMUs in their own binary formats. This module
//! recognises each by its magic bytes ([`sniff`], whatever the file is called), reads it
//! whole ([`read_path`]) into an [`ImuRecording`]: every gyro instance with its device id,
//! time stamps, axes, temperature and accelerometer, values kept exactly as stored. Then
//! [`select`] picks the instance a command works on (`--gyro N`, `--temp-from`), and
//! [`Selected::columns`] or [`write_csv`] turn it into what the rest of driftlab reads.
//!
//! ```text
//! read_path(&Path) -> ImuRecording            (sniffs, reads, reports problems)
//!   ImuRecording::summaries()                 (what inspect lists)
//!   select(&rec, gyro, temp_from) -> Selected (the instance, its temperature, a note)
//!     Selected::columns() -> Columns          (time_s, gyro rad/s, temp_c, accel as f64)
//!     write_csv(&Selected, rows, writer)      (driftlab convert, the rows kept_samples keeps)
//! ```
//!
//! What is read, format by format:
//!
//! | format | gyro instances | temperature | accelerometer |
//! |---|---|---|---|
//! | ULog | `sensor_gyro` by `multi_id`, then `sensor_combined` | `temperature`; alternatives `sensor_accel`, `vehicle_imu_status` | `sensor_accel` of the same device |
//! | DataFlash | `IMU` by `I` (`IMU2`, `IMU3` in old logs) | `T` | `AccX..Z` |
//! | ROS 1 bag, MCAP | each `sensor_msgs/Imu` topic | a `sensor_msgs/Temperature` topic of the same frame | `linear_acceleration` |
//!
//! Bad input never panics: a malformed file is a [`FormatError`] naming the file and the
//! byte offset; a file cut inside its last message keeps every whole message and says so in
//! [`ImuRecording::problems`]; a ROS log holding more messages than are kept is
//! [`FormatError::TooLargeToKeep`], not malformed, with what each topic held.
//!
//! Crafted input is bounded by construction: every size and offset read from a file is
//! checked arithmetic against the bytes that exist, nothing is allocated for a declared size
//! before its bytes exist, ULog formats are walked once each (at most 16 deep, at most a
//! message large) and their padding is not stored, chunks decompress as a stream within a
//! per-chunk cap and a per-file budget (`decompress.rs`), the messages a ROS log keeps stay
//! within 256 MiB (or 8 times the file's size) over all its topics (`ros_topics.rs`:
//! decompressed chunks can hold far more than the file), topics and channels are found in hash maps, a ROS message's `frame_id` is
//! not kept per message, a DataFlash FMT whose length is not its format's is refused (it would
//! frame every message of its type wrongly), and names and lists in messages
//! are cut to a readable length (`error::quoted`, `error::listed`, [`PROBLEMS_AT_MOST`]).
//! `tests/attack/readers.rs` holds a file for each way this once failed.
//!
//! Each format has its own reader here, not a crate's: every crate tried failed on the
//! samples' mutated or cut copies (see each reader's documentation).

mod bytes;
mod csv;
mod dataflash;
mod decompress;
mod device_change;
mod error;
mod mcap;
mod recording;
mod ros_clock_changes;
mod ros_clocks;
mod ros_frames;
mod ros_msgs;
mod ros_readings;
mod ros_topics;
mod rosbag;
mod select;
mod ulog;

pub use csv::{csv_header, write_csv};
pub use error::{FormatError, SelectionError};
pub use recording::{
    AltTemperature, AltTemperatureSummary, Axes, DeviceId, GyroInstance, ImuRecording,
    InstanceSummary, Problem, RosTime, TempFrom, Timestamps, UnknownTempFrom, Values,
};
pub use select::{Columns, Selected, select};

use error::Broken;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The log formats driftlab reads besides its CSV dialects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Format {
    /// PX4 ULog (`.ulg`).
    Ulog,
    /// ArduPilot DataFlash (`.bin`).
    DataFlash,
    /// ROS 1 bag, format 2.0 (`.bag`).
    RosBag,
    /// MCAP (`.mcap`), ROS 2 messages in CDR.
    Mcap,
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Format::Ulog => "PX4 ULog",
            Format::DataFlash => "ArduPilot DataFlash",
            Format::RosBag => "ROS 1 bag",
            Format::Mcap => "MCAP",
        })
    }
}

/// The most problems a recording lists: a crafted file can have a bad format message every
/// 89 bytes, and a list of a million is read by nobody.
pub const PROBLEMS_AT_MOST: usize = 50;

/// The longest magic: the bytes [`sniff`] needs to decide.
pub const SNIFF_BYTES: usize = 13;

/// The format whose magic bytes `head` (the first [`SNIFF_BYTES`] bytes of a file, or all
/// of it) starts with; `None` for anything else, a CSV included.
pub fn sniff(head: &[u8]) -> Option<Format> {
    if head.starts_with(&ulog::MAGIC) {
        Some(Format::Ulog)
    } else if head.starts_with(&dataflash::MAGIC) {
        Some(Format::DataFlash)
    } else if head.starts_with(rosbag::MAGIC) {
        Some(Format::RosBag)
    } else if head.starts_with(mcap::MAGIC) {
        Some(Format::Mcap)
    } else {
        None
    }
}

/// The format of the file at `path` from its first bytes, without reading the rest; `None`
/// when it is none of them (a CSV, say).
///
/// # Errors
/// The file cannot be opened or read.
pub fn sniff_path(path: &Path) -> Result<Option<Format>, FormatError> {
    use std::io::Read;
    let io = |source| FormatError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut head = Vec::with_capacity(SNIFF_BYTES);
    std::fs::File::open(path)
        .map_err(io)?
        .take(SNIFF_BYTES as u64)
        .read_to_end(&mut head)
        .map_err(io)?;
    Ok(sniff(&head))
}

/// Reads a drone or robot log, recognised by its magic bytes.
///
/// # Errors
/// The file cannot be read, is none of the formats, is malformed (with the byte offset) or
/// holds no gyro data.
pub fn read_path(path: &Path) -> Result<ImuRecording, FormatError> {
    let bytes = std::fs::read(path).map_err(|source| FormatError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_bytes(&path.display().to_string(), &bytes)
}

/// Reads a log held in memory; `source` names it in messages and errors.
///
/// # Errors
/// As [`read_path`].
pub fn read_bytes(source: &str, bytes: &[u8]) -> Result<ImuRecording, FormatError> {
    let path = PathBuf::from(source);
    let Some(format) = sniff(bytes) else {
        return Err(FormatError::Unrecognised {
            path,
            head: bytes::hex_head(bytes),
        });
    };
    let malformed = |b: Broken| b.into_error(PathBuf::from(source), format);
    let (instances, mut problems, untied_temps, wanted) = match format {
        Format::Ulog => {
            let r = ulog::read(bytes).map_err(malformed)?;
            (
                r.instances,
                r.problems,
                Vec::new(),
                "sensor_gyro or sensor_combined topic",
            )
        }
        Format::DataFlash => {
            let r = dataflash::read(bytes).map_err(malformed)?;
            (r.instances, r.problems, Vec::new(), "IMU messages")
        }
        Format::RosBag => {
            let mut r = rosbag::read(bytes).map_err(malformed)?;
            let (i, untied) = r
                .topics
                .into_instances(&mut r.problems, "the bag's record time");
            (i, r.problems, untied, "sensor_msgs/Imu topic")
        }
        Format::Mcap => {
            let mut r = mcap::read(bytes).map_err(malformed)?;
            let (i, untied) = r
                .topics
                .into_instances(&mut r.problems, "the MCAP log time");
            (i, r.problems, untied, "sensor_msgs/msg/Imu channel in CDR")
        }
    };
    if instances.iter().all(GyroInstance::is_empty) {
        let mut message = format!("it has no {wanted}");
        if let Some(p) = problems.first() {
            message.push_str(&format!(" ({p})"));
        }
        return Err(FormatError::NoGyro {
            path,
            format,
            message,
        });
    }
    let before = instances.len();
    let mut instances: Vec<GyroInstance> =
        instances.into_iter().filter(|i| !i.is_empty()).collect();
    if instances.len() < before {
        problems.push(Problem::note(format!(
            "{} gyro instance(s) without a sample left out",
            before - instances.len()
        )));
    }
    for (k, inst) in instances.iter_mut().enumerate() {
        inst.index = k;
    }
    if problems.len() > PROBLEMS_AT_MOST {
        let more = problems.len() - PROBLEMS_AT_MOST;
        problems.truncate(PROBLEMS_AT_MOST);
        problems.push(Problem::note(format!(
            "and {more} more problems not listed"
        )));
    }
    Ok(ImuRecording {
        format,
        source: source.to_string(),
        instances,
        problems,
        untied_temps,
    })
}
