//! ROS 1 bags (format 2.0): `sensor_msgs/Imu` and `sensor_msgs/Temperature` topics, from
//! uncompressed, bz2 or lz4 chunks.
//!
//! The format (wiki.ros.org/Bags/Format/2.0): `#ROSBAG V2.0\n`, then records of
//! `u32 header length, header fields (u32 length, name=value), u32 data length, data`. The
//! field `op` says what a record is: bag header, chunk (holding connection and message
//! records, compressed), index data, connection, chunk info. The bag is read front to back,
//! without its index, so a bag whose recording was cut (no index written) reads too, and a
//! cut in the last chunk keeps the chunks before it.
//!
//! Why not a crate: `rosbag` 0.6.3 panics on a bag cut short (it slices the file to the index
//! position its header names: 188 of 200 cuts of the sample), and loops on a mutated sample.

use super::bytes::{Bytes, each_record_of_chunk};
use super::decompress::{Budget, Codec, decompress};
use super::error::{Broken, quoted};
use super::recording::Problem;
use super::ros_msgs::{self, Kind};
use super::ros_topics::{Slot, Topics};
use std::collections::HashMap;

/// The first 13 bytes of a bag of format 2.0.
pub(crate) const MAGIC: &[u8; 13] = b"#ROSBAG V2.0\n";

const OP_MESSAGE: u8 = 0x02;
const OP_CHUNK: u8 = 0x05;
const OP_CONNECTION: u8 = 0x07;

/// A record's header fields and data.
struct Record<'a> {
    at: u64,
    fields: Vec<(&'a [u8], &'a [u8])>,
    data: &'a [u8],
    data_at: u64,
}

impl<'a> Record<'a> {
    fn field(&self, name: &str) -> Option<&'a [u8]> {
        self.fields
            .iter()
            .find(|(n, _)| *n == name.as_bytes())
            .map(|(_, v)| *v)
    }

    fn op(&self) -> Result<u8, Broken> {
        match self.field("op") {
            Some([op]) => Ok(*op),
            _ => Err(Broken::at(self.at, "a record has no one-byte op field")),
        }
    }

    fn u32_field(&self, name: &str) -> Result<u32, Broken> {
        match self.field(name) {
            Some(v) if v.len() == 4 => Ok(u32::from_le_bytes([v[0], v[1], v[2], v[3]])),
            _ => Err(Broken::at(
                self.at,
                format!("a record has no 4-byte {name} field"),
            )),
        }
    }
}

/// The next record of `b`; `Ok(None)` when the record runs past the end of `b`.
fn record<'a>(b: &mut Bytes<'a>) -> Result<Option<Record<'a>>, Broken> {
    let at = b.offset();
    let Ok(hlen) = b.len_u32("a record header") else {
        return Ok(None);
    };
    let header_at = b.offset();
    let header = b.take(hlen, "a record header")?;
    let Ok(dlen) = b.len_u32("a record's data") else {
        return Ok(None);
    };
    let data_at = b.offset();
    let data = b.take(dlen, "a record's data")?;
    let mut fields = Vec::new();
    let mut h = Bytes::new(header, header_at);
    while !h.is_empty() {
        let fat = h.offset();
        let n = h
            .len_u32("a header field")
            .map_err(|e| Broken::at(e.offset, e.message))?;
        let f = h.take(n, "a header field")?;
        let Some(eq) = f.iter().position(|&c| c == b'=') else {
            return Err(Broken::at(fat, "a record header field has no '='"));
        };
        fields.push((&f[..eq], &f[eq + 1..]));
    }
    Ok(Some(Record {
        at,
        fields,
        data,
        data_at,
    }))
}

/// A connection: its topic and what it carries.
struct Connection<'a> {
    topic: std::borrow::Cow<'a, str>,
    kind: Option<Kind>,
}

fn connection<'a>(r: &Record<'a>) -> Result<(u32, Connection<'a>), Broken> {
    let id = r.u32_field("conn")?;
    let topic = String::from_utf8_lossy(r.field("topic").unwrap_or_default());
    // The type is in the connection header, the record's data.
    let mut d = Bytes::new(r.data, r.data_at);
    let mut ty = None;
    while !d.is_empty() {
        let n = d.len_u32("a connection header field")?;
        let f = d.take(n, "a connection header field")?;
        if let Some(v) = f.strip_prefix(b"type=") {
            ty = Some(String::from_utf8_lossy(v));
        }
    }
    Ok((
        id,
        Connection {
            topic,
            kind: ty.as_deref().and_then(Kind::of),
        },
    ))
}

/// What a bag gives.
pub(crate) struct Read {
    pub topics: Topics,
    pub problems: Vec<Problem>,
}

/// Reads a bag held in memory.
pub(crate) fn read(data: &[u8]) -> Result<Read, Broken> {
    if data.len() < MAGIC.len() || &data[..MAGIC.len()] != MAGIC {
        return Err(Broken::at(0, "the bag does not start with #ROSBAG V2.0"));
    }
    let mut b = Bytes::new(&data[MAGIC.len()..], MAGIC.len() as u64);
    let mut state = State {
        connections: HashMap::new(),
        topics: Topics::for_file(data.len()),
        orphans: 0,
        budget: Budget::for_file(data.len()),
    };
    let mut problems = Vec::new();
    while !b.is_empty() {
        let at = b.offset();
        let Some(r) = record(&mut b)? else {
            problems.push(Problem::at(
                at,
                "a record here claims more bytes than the file has left: a cut (or corrupt) \
                 bag; every whole record before it was read",
            ));
            break;
        };
        match r.op()? {
            OP_CHUNK => {
                let codec = match r.field("compression") {
                    Some(b"none") => Codec::None,
                    Some(b"bz2") => Codec::Bz2,
                    Some(b"lz4") => Codec::Lz4,
                    other => {
                        return Err(Broken::at(
                            r.at,
                            match other {
                                Some(c) => format!(
                                    "a chunk has compression \"{}\", not none, bz2 or lz4",
                                    quoted(&String::from_utf8_lossy(c))
                                ),
                                None => "a chunk has no compression field".to_string(),
                            },
                        ));
                    }
                };
                let size = r.u32_field("size")?;
                let inner = decompress(codec, r.data, u64::from(size), &mut state.budget)
                    .map_err(|e| Broken::at(r.at, e.to_string()))?;
                state.chunk(&inner, r.at)?;
            }
            OP_CONNECTION => state.connection(&r)?,
            OP_MESSAGE => state.message(&r)?,
            // Bag header, index data, chunk info: the index, not needed front to back.
            _ => {}
        }
    }
    if state.orphans > 0 {
        problems.push(Problem::note(format!(
            "{} message(s) name a connection the bag never defines; skipped",
            state.orphans
        )));
    }
    Ok(Read {
        topics: state.topics,
        problems,
    })
}

struct State {
    /// Connection id → the slot of its topic, `None` for a type not read.
    connections: HashMap<u32, Option<Slot>>,
    topics: Topics,
    orphans: usize,
    budget: Budget,
}

impl State {
    fn connection(&mut self, r: &Record<'_>) -> Result<(), Broken> {
        let (id, c) = connection(r)?;
        let slot = c.kind.map(|k| self.topics.slot(k, &c.topic));
        self.connections.insert(id, slot);
        Ok(())
    }

    /// The records of a decompressed chunk; offsets are reported as the chunk's own.
    fn chunk(&mut self, inner: &[u8], chunk_at: u64) -> Result<(), Broken> {
        each_record_of_chunk(inner, chunk_at, |b, at| {
            let r =
                record(b)?.ok_or_else(|| Broken::at(at, "a record runs past the chunk's end"))?;
            match r.op()? {
                OP_CONNECTION => self.connection(&r),
                OP_MESSAGE => self.message(&r),
                _ => Ok(()),
            }
        })
    }

    fn message(&mut self, r: &Record<'_>) -> Result<(), Broken> {
        let id = r.u32_field("conn")?;
        let Some(&c) = self.connections.get(&id) else {
            self.orphans += 1;
            return Ok(());
        };
        let Some(slot) = c else {
            return Ok(());
        };
        // The message's place on its topic, for errors: its count from 1 in file order.
        let n = self.topics.count(slot) + 1;
        let time = match r.field("time") {
            Some(v) if v.len() == 8 => {
                let sec = u32::from_le_bytes([v[0], v[1], v[2], v[3]]);
                let nsec = u32::from_le_bytes([v[4], v[5], v[6], v[7]]);
                if nsec >= ros_msgs::NANOS_PER_SECOND {
                    return Err(Broken::at(
                        r.at,
                        format!(
                            "message {n} on {} (counted from 1 in file order): its record's \
                             time has {nsec} nanoseconds (with {sec} s), not below \
                             1000000000: not a time",
                            quoted(self.topics.name(slot))
                        ),
                    ));
                }
                u64::from(sec) * 1_000_000_000 + u64::from(nsec)
            }
            _ => {
                return Err(Broken::at(
                    r.at,
                    "a message record has no 8-byte time field",
                ));
            }
        };
        let topics = &mut self.topics;
        let bad = |m: ros_msgs::MessageError, topics: &Topics| {
            Broken::at(
                r.data_at,
                format!(
                    "message {n} on {} (counted from 1 in file order): {m}",
                    quoted(topics.name(slot))
                ),
            )
        };
        match slot.kind() {
            Kind::Imu => {
                let m = ros_msgs::imu_ros1(r.data).map_err(|e| bad(e, topics))?;
                topics
                    .push_imu(slot, time, &m)
                    .map_err(|e| Broken::too_large(r.at, e))?;
            }
            Kind::Temperature => {
                let m = ros_msgs::temperature_ros1(r.data).map_err(|e| bad(e, topics))?;
                topics
                    .push_temperature(slot, time, &m)
                    .map_err(|e| Broken::too_large(r.at, e))?;
            }
        }
        Ok(())
    }
}
