//! MCAP with ROS 2 messages: `sensor_msgs/msg/Imu` and `sensor_msgs/msg/Temperature` in CDR,
//! from uncompressed, zstd or lz4 chunks.
//!
//! The format (mcap.dev/spec): the magic `89 M C A P 0 \r \n`, then records of `u8 opcode,
//! u64 length, content`: schemas, channels, messages, chunks (holding schemas, channels and
//! messages, compressed, with a CRC of the decompressed bytes) and, after `DataEnd`, a
//! summary that repeats what came before. The data section is read front to back, so a file
//! without its summary (a recording cut short) reads too.
//!
//! Why not a crate: `mcap` 0.26.0 aborts the whole process ("memory allocation of
//! 6173593962729701385 bytes failed") on a sample with four mutated bytes: it allocates
//! what a corrupt length field says before checking it against the file.

use super::bytes::{Bytes, each_record_of_chunk};
use super::decompress::{Budget, Codec, decompress};
use super::error::{Broken, LIST_AT_MOST, quoted};
use super::recording::Problem;
use super::ros_msgs::{self, Kind};
use super::ros_topics::{Slot, Topics};
use std::collections::{HashMap, HashSet};

/// The first (and last) 8 bytes of an MCAP file.
pub(crate) const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

const OP_SCHEMA: u8 = 0x03;
const OP_CHANNEL: u8 = 0x04;
const OP_MESSAGE: u8 = 0x05;
const OP_CHUNK: u8 = 0x06;
const OP_FOOTER: u8 = 0x02;
const OP_DATA_END: u8 = 0x0F;

/// What an MCAP file gives.
pub(crate) struct Read {
    pub topics: Topics,
    pub problems: Vec<Problem>,
}

fn string(b: &mut Bytes<'_>, what: &str) -> Result<String, Broken> {
    let n = b.len_u32(what)?;
    Ok(String::from_utf8_lossy(b.take(n, what)?).into_owned())
}

struct State {
    /// Schema id → message type, for the types read.
    schemas: HashMap<u16, Option<Kind>>,
    /// Channel id → the slot of its topic, `None` for a type not read.
    channels: HashMap<u16, Option<Slot>>,
    topics: Topics,
    orphans: usize,
    /// Topics of Imu or Temperature channels in another encoding than CDR, each once, in
    /// order of first sight (a channel redefined 200 000 times is one topic).
    not_cdr: Vec<String>,
    not_cdr_seen: HashSet<String>,
    budget: Budget,
}

/// Reads an MCAP file held in memory.
pub(crate) fn read(data: &[u8]) -> Result<Read, Broken> {
    if data.len() < MAGIC.len() || &data[..MAGIC.len()] != MAGIC {
        return Err(Broken::at(0, "the file does not start with the MCAP magic"));
    }
    let mut b = Bytes::new(&data[MAGIC.len()..], MAGIC.len() as u64);
    let mut state = State {
        schemas: HashMap::new(),
        channels: HashMap::new(),
        topics: Topics::for_file(data.len()),
        orphans: 0,
        not_cdr: Vec::new(),
        not_cdr_seen: HashSet::new(),
        budget: Budget::for_file(data.len()),
    };
    let mut problems = Vec::new();
    let mut ended = false;
    while !b.is_empty() {
        let at = b.offset();
        if b.remaining() < 9 {
            problems.push(Problem::at(
                at,
                "the file ends inside a record header: a cut file; every whole record before \
                 it was read",
            ));
            break;
        }
        let op = b.u8("a record opcode")?;
        let Ok(len) = b.len_u64("a record") else {
            problems.push(Problem::at(
                at,
                "a record here claims more bytes than the file has left: a cut (or corrupt) \
                 file; every whole record before it was read",
            ));
            break;
        };
        let content = Bytes::new(b.take(len, "a record")?, b.offset() - len as u64);
        if op == OP_DATA_END || op == OP_FOOTER {
            ended = true;
            break;
        }
        state.record(op, content, at)?;
    }
    if !ended {
        problems.push(Problem::note(
            "the file has no DataEnd record or footer: its recording was cut short",
        ));
    }
    if state.orphans > 0 {
        problems.push(Problem::note(format!(
            "{} message(s) name a channel the file never defines; skipped",
            state.orphans
        )));
    }
    for t in state.not_cdr.iter().take(LIST_AT_MOST) {
        problems.push(Problem::note(format!(
            "channel {} carries Imu or Temperature messages in an encoding other than cdr; \
             skipped",
            quoted(t)
        )));
    }
    if state.not_cdr.len() > LIST_AT_MOST {
        problems.push(Problem::note(format!(
            "and {} more channels carry Imu or Temperature messages in an encoding other than \
             cdr; skipped",
            state.not_cdr.len() - LIST_AT_MOST
        )));
    }
    Ok(Read {
        topics: state.topics,
        problems,
    })
}

impl State {
    fn record(&mut self, op: u8, mut c: Bytes<'_>, at: u64) -> Result<(), Broken> {
        match op {
            OP_SCHEMA => {
                let id = c.u16("a schema id")?;
                let name = string(&mut c, "a schema name")?;
                self.schemas.insert(id, Kind::of(&name));
            }
            OP_CHANNEL => {
                let id = c.u16("a channel id")?;
                let schema = c.u16("a channel's schema id")?;
                let topic = string(&mut c, "a channel topic")?;
                let encoding = string(&mut c, "a channel's message encoding")?;
                let kind = self.schemas.get(&schema).copied().flatten();
                let kind = if kind.is_some() && encoding != "cdr" {
                    if !self.not_cdr_seen.contains(&topic) {
                        self.not_cdr_seen.insert(topic.clone());
                        self.not_cdr.push(topic.clone());
                    }
                    None
                } else {
                    kind
                };
                let slot = kind.map(|k| self.topics.slot(k, &topic));
                self.channels.insert(id, slot);
            }
            OP_MESSAGE => {
                let ch = c.u16("a message's channel id")?;
                c.skip(4, "a message's sequence")?;
                let log_time = c.u64("a message's log time")?;
                c.skip(8, "a message's publish time")?;
                // Where the message's own bytes start: the place its errors count from.
                let data_at = c.offset();
                let payload = c.take(c.remaining(), "")?;
                let Some(&channel) = self.channels.get(&ch) else {
                    self.orphans += 1;
                    return Ok(());
                };
                let Some(slot) = channel else {
                    return Ok(());
                };
                // The message's place on its topic, for errors: its count from 1 in file
                // order.
                let n = self.topics.count(slot) + 1;
                let topics = &mut self.topics;
                let bad = |m: ros_msgs::MessageError, topics: &Topics| {
                    Broken::at(
                        data_at,
                        format!(
                            "message {n} on {} (counted from 1 in file order): {m}",
                            quoted(topics.name(slot))
                        ),
                    )
                };
                match slot.kind() {
                    Kind::Imu => {
                        let m = ros_msgs::imu_cdr(payload).map_err(|e| bad(e, topics))?;
                        topics
                            .push_imu(slot, log_time, &m)
                            .map_err(|e| Broken::too_large(at, e))?;
                    }
                    Kind::Temperature => {
                        let m = ros_msgs::temperature_cdr(payload).map_err(|e| bad(e, topics))?;
                        topics
                            .push_temperature(slot, log_time, &m)
                            .map_err(|e| Broken::too_large(at, e))?;
                    }
                }
            }
            OP_CHUNK => {
                c.skip(16, "a chunk's time range")?;
                let size = c.u64("a chunk's uncompressed size")?;
                let crc = c.u32("a chunk's CRC")?;
                let compression = string(&mut c, "a chunk's compression")?;
                let n = c.len_u64("a chunk's records")?;
                let compressed = c.take(n, "a chunk's records")?;
                let codec = match compression.as_str() {
                    "" => Codec::None,
                    "zstd" => Codec::Zstd,
                    "lz4" => Codec::Lz4,
                    other => {
                        return Err(Broken::at(
                            at,
                            format!(
                                "a chunk is compressed with \"{}\", not zstd or lz4",
                                quoted(other)
                            ),
                        ));
                    }
                };
                let inner = decompress(codec, compressed, size, &mut self.budget)
                    .map_err(|e| Broken::at(at, e.to_string()))?;
                if crc != 0 && crc32fast::hash(&inner) != crc {
                    return Err(Broken::at(
                        at,
                        "a chunk's records do not match its CRC: the chunk is corrupt",
                    ));
                }
                self.chunk(&inner, at)?;
            }
            // Attachments, metadata, indexes, statistics: nothing driftlab reads.
            _ => {}
        }
        Ok(())
    }

    /// The records of a decompressed chunk; errors are placed at the chunk.
    fn chunk(&mut self, inner: &[u8], chunk_at: u64) -> Result<(), Broken> {
        each_record_of_chunk(inner, chunk_at, |b, at| {
            let op = b.u8("a record opcode")?;
            let len = b.len_u64("a record")?;
            let content = Bytes::new(b.take(len, "a record")?, at + 9);
            match op {
                OP_SCHEMA | OP_CHANNEL | OP_MESSAGE => self.record(op, content, at),
                _ => Ok(()),
            }
        })
    }
}
