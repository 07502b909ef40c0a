//! PX4 ULog: `sensor_gyro` instances with their temperature, the `sensor_accel` of the same
//! device, `vehicle_imu_status` temperatures, and the fused `sensor_combined`.
//!
//! The format (docs.px4.io, "ULog File Format"): a 16-byte header (`ULog` 01 12 35, version,
//! start time), then messages of `u16 size, u8 type, payload`. Format messages (`F`) describe
//! each topic's packed layout; `A` subscribes a `msg_id` to a topic instance (`multi_id`); `D`
//! carries one sample. Only the fields driftlab needs are decoded, straight from the bytes at
//! offsets computed once per subscription, so a 100 MB log is one pass over memory.
//!
//! Why not a crate: `px4-ulog` 0.6.1 panics on a parameter message whose key length runs past
//! the message (found by mutating the sample), and neither it nor `yule_log` 0.4.0 (which
//! prints a debug line per format to standard output) reports byte offsets.
//!
//! This module holds the entry point, `read`, which walks the sections of a file; the format
//! language, the subscriptions, the message walk and the assembly of gyro instances are each in
//! a module of their own.

mod format;
mod instances;
mod messages;
mod subscription;
#[cfg(test)]
mod tests;

use super::bytes::Bytes;
use super::error::Broken;
use super::recording::{GyroInstance, Problem};
use instances::assemble;
use messages::{State, Stop};

/// The first 7 bytes of every ULog file.
pub(crate) const MAGIC: [u8; 7] = [b'U', b'L', b'o', b'g', 0x01, 0x12, 0x35];

/// The topics read, each kept per subscription.
const WANTED: [&str; 4] = [
    "sensor_gyro",
    "sensor_accel",
    "vehicle_imu_status",
    "sensor_combined",
];

/// What a ULog gives: gyro instances and the problems seen.
pub(crate) struct Read {
    pub instances: Vec<GyroInstance>,
    pub problems: Vec<Problem>,
}

/// Reads a ULog held in memory.
pub(crate) fn read(data: &[u8]) -> Result<Read, Broken> {
    let mut head = Bytes::new(data, 0);
    let magic = head.take(7, "the ULog header")?;
    if magic != MAGIC {
        return Err(Broken::at(0, "the ULog magic bytes are wrong"));
    }
    head.skip(9, "the ULog header")?;
    let mut state = State::new(data.len());
    let mut problems = Vec::new();
    // Segments: the main data, then each appended-data section the flag bits point to.
    let mut pos = 16usize;
    let mut end = data.len();
    let mut segments_left: Vec<usize> = Vec::new();
    let mut first = true;
    loop {
        match state.messages(data, pos, end, first, &mut problems)? {
            Stop::End => {}
            Stop::Flags(offsets) => {
                // Flag bits came first: the main section ends where the first appended one
                // starts; go on reading from where the flag bits ended.
                let mut offs: Vec<usize> = offsets
                    .iter()
                    .filter(|&&o| o > 0)
                    .map(|&o| usize::try_from(o).unwrap_or(usize::MAX))
                    .collect();
                offs.sort_unstable();
                if let Some(&o) = offs.iter().find(|&&o| o > data.len()) {
                    problems.push(Problem::note(format!(
                        "the flag bits point to appended data at byte {o}, past the end of \
                         the file ({} bytes); it is missing",
                        data.len()
                    )));
                }
                offs.retain(|&o| o <= data.len());
                if let Some(&o) = offs.first() {
                    end = o;
                }
                segments_left = offs;
                pos = state.resume_at;
                first = false;
                continue;
            }
        }
        if segments_left.is_empty() {
            break;
        }
        pos = segments_left.remove(0);
        end = segments_left.first().copied().unwrap_or(data.len());
        first = false;
    }
    if state.dropouts > 0 {
        problems.push(Problem::at(
            state.first_dropout_at,
            format!(
                "{} dropout(s) recorded by the logger, {} ms in all: samples are missing there",
                state.dropouts, state.dropout_ms
            ),
        ));
    }
    if state.unknown_ids > 0 {
        problems.push(Problem::at(
            state.first_unknown_id_at,
            format!(
                "{} data message(s) with a msg_id no subscription names were skipped",
                state.unknown_ids
            ),
        ));
    }
    let instances = assemble(state.subs, &mut problems);
    Ok(Read {
        instances,
        problems,
    })
}
