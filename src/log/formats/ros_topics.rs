//! Gyro instances from the decoded messages of a ROS 1 bag or an MCAP file: one instance per
//! `sensor_msgs/Imu` topic (per frame of it, when its `frame_id` changes: each frame's
//! samples a gyro of their own, by the rule of `device_change`, as a PX4 gyro whose
//! `device_id` changes), its temperature from a `sensor_msgs/Temperature` topic of the same
//! frame.
//!
//! Bounded by construction: a topic is found by its name in a hash map once, when the
//! connection or channel naming it is read (a bag of 100 000 topics, or an MCAP redefining a
//! channel before each of 200 000 messages, costs one lookup each, not a walk over every
//! topic), and a message is filed by the slot its connection holds. A `frame_id` is not kept
//! per message: a topic keeps its first in log-time order and the first that differs from it,
//! and the first few distinct ones ([`FRAMES_AT_MOST`]), which an Imu message names by number
//! in bytes its stamp leaves as padding.
//!
//! The messages kept are bounded too: a compressed chunk may expand a thousand-fold, so a
//! small file can hold tens of millions of messages (a 18 MB bag of lz4 chunks holds 11
//! million Imu messages). Every topic is kept (`inspect` lists each one), so the bound is on
//! all of them together: [`KEPT_BYTES_AT_MOST`] of messages as stored, their vectors grown
//! within it, and a log holding more is refused ([`TooLarge`], which the public error tells
//! apart from a malformed file) with what each topic held when it ran out.

use super::device_change;
use super::error::{LIST_AT_MOST, TooLarge, listed, quoted};
use super::recording::{
    Axes, DeviceId, GyroInstance, Problem, RosTime, Timestamps, Values, median_step, nearest_within,
};
use super::ros_msgs::{Imu, Kind, Temperature};
use std::collections::HashMap;

/// The memory the messages of a small ROS log may take as kept while reading: 256 MiB, about
/// 3.7 million Imu messages (72 bytes each) over all topics, e.g. an hour of one IMU at 1 kHz.
/// A larger file may keep [`KEPT_PER_FILE_BYTE`] times its size ([`Topics::for_file`]).
/// Turning them into instances takes about as much again; with one decompressed chunk
/// (at most 256 MiB) a read of a small file stays within about 1 GiB.
pub(crate) const KEPT_BYTES_AT_MOST: usize = 256 << 20;

/// How many bytes of messages a log may keep per byte of its file, past
/// [`KEPT_BYTES_AT_MOST`]: an honest bag or MCAP of a 10-hour 1 kHz IMU, lz4- or
/// zstd-compressed, keeps a few times its size; a small file of chunks that expand a
/// hundred-fold into messages of a topic nobody asked for is refused instead of held.
pub(crate) const KEPT_PER_FILE_BYTE: usize = 8;

/// `bytes` as a message gives a size: in MiB or KiB with one decimal, or in bytes below one
/// KiB.
fn size(bytes: usize) -> String {
    if bytes >= 1 << 20 {
        format!("{:.1} MiB", bytes as f64 / f64::from(1u32 << 20))
    } else if bytes >= 1 << 10 {
        format!("{:.1} KiB", bytes as f64 / 1024.0)
    } else {
        format!("{bytes} bytes")
    }
}

/// An Imu message as kept: all of it but its `frame_id`, which is kept as its place among
/// its topic's frames ([`Topic::frame_names`]). The stamp is held apart from a [`RosTime`] so
/// that the frame's number takes the bytes a `RosTime` leaves as padding: a message takes 64
/// bytes, as before the frame was kept.
struct ImuSample {
    sec: i64,
    nsec: u32,
    frame: u16,
    angular_velocity: [f64; 3],
    linear_acceleration: [f64; 3],
}

impl ImuSample {
    fn stamp(&self) -> RosTime {
        RosTime {
            sec: self.sec,
            nsec: self.nsec,
        }
    }
}

/// The most `frame_id`s a topic tells apart: a topic of two IMUs is two gyros, one of a new
/// frame on every message (a crafted log) not a gyro each.
const FRAMES_AT_MOST: usize = LIST_AT_MOST;

/// The frame number of a message on none of the first [`FRAMES_AT_MOST`] frames of its topic.
const ANOTHER_FRAME: u16 = u16::MAX;

/// A Temperature message as kept.
struct TempSample {
    stamp: RosTime,
    celsius: f64,
}

/// A message's place in its topic's log-time order: log time, then arrival (the order a
/// stable sort by log time gives).
type Key = (u64, usize);

/// The `frame_id`s of a topic's messages as far as they are used: the first in log-time
/// order, and the first after it (in that order) that differs from it. Kept as messages
/// arrive, whatever their order.
#[derive(Default)]
struct Frames {
    first: Option<(Key, String)>,
    other: Option<(Key, String)>,
}

/// The most bytes of a `frame_id` kept as they are: real ones are a few words (`imu_link`).
const FRAME_ID_KEPT_BYTES: usize = 256;

/// A `frame_id` as a topic keeps it: as it is when short, else its first bytes with its
/// length and a hash of the whole, so that two topics' frames still compare equal when they
/// are, and a crafted log's 250-MB `frame_id` costs a topic a few hundred bytes, not a copy.
fn kept_frame(frame: &str) -> std::borrow::Cow<'_, str> {
    if frame.len() <= FRAME_ID_KEPT_BYTES {
        return std::borrow::Cow::Borrowed(frame);
    }
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    frame.hash(&mut h);
    let mut cut = 24;
    while !frame.is_char_boundary(cut) {
        cut -= 1;
    }
    std::borrow::Cow::Owned(format!(
        "{}… ({} bytes, {:016x})",
        &frame[..cut],
        frame.len(),
        h.finish()
    ))
}

impl Frames {
    /// Notes the frame of message `key`, `frame` as kept ([`kept_frame`]).
    fn see(&mut self, key: Key, frame: &str) {
        match &self.first {
            None => self.first = Some((key, frame.to_string())),
            Some((k, _)) if key < *k => {
                // The new message comes first; the first different from it is the old first
                // (earlier than every other old message) when its frame differs, else the
                // old "other" still.
                let old = self.first.replace((key, frame.to_string()));
                if let Some(old) = old
                    && old.1 != frame
                {
                    self.other = Some(old);
                }
            }
            Some((_, f)) => {
                if f != frame && self.other.as_ref().is_none_or(|(k, _)| key < *k) {
                    self.other = Some((key, frame.to_string()));
                }
            }
        }
    }

    fn first(&self) -> &str {
        self.first.as_ref().map_or("", |(_, f)| f)
    }
}

/// True when a topic of two messages or more stamps every one alike (`header.stamp` left 0
/// by a driver that does not fill it, or set once): its samples have no time of their own,
/// and read by it every one but the first would repeat the first's stamp.
fn stuck<T>(msgs: &[(u64, T)], stamp: impl Fn(&T) -> RosTime) -> bool {
    match msgs {
        [(_, first), _, ..] => msgs.iter().all(|(_, m)| stamp(m) == stamp(first)),
        _ => false,
    }
}

/// True when the log times (ns) are not all one: a clock that can time the samples.
fn advances(log_times: &[u64]) -> bool {
    log_times.iter().any(|&t| t != log_times[0])
}

/// A log time (ns since the epoch) as a ROS time stamp.
fn log_stamp(ns: u64) -> RosTime {
    RosTime {
        sec: (ns / 1_000_000_000) as i64,
        nsec: (ns % 1_000_000_000) as u32,
    }
}

/// The messages of one topic, with their log (bag) time in ns.
struct Topic<T> {
    name: String,
    msgs: Vec<(u64, T)>,
    frames: Frames,
    /// The topic's distinct `frame_id`s as kept ([`kept_frame`]), in order of arrival, the
    /// first [`FRAMES_AT_MOST`]: what an Imu message's frame number names.
    frame_names: Vec<String>,
}

impl<T> Topic<T> {
    fn new(name: &str) -> Topic<T> {
        Topic {
            name: name.to_string(),
            msgs: Vec::new(),
            frames: Frames::default(),
            frame_names: Vec::new(),
        }
    }

    /// The number of `frame` (as kept) among the topic's frames, given it on first sight;
    /// [`ANOTHER_FRAME`] past the first [`FRAMES_AT_MOST`].
    fn frame_number(&mut self, frame: &str) -> u16 {
        if let Some(k) = self.frame_names.iter().position(|f| f == frame) {
            return k as u16;
        }
        if self.frame_names.len() < FRAMES_AT_MOST {
            self.frame_names.push(frame.to_string());
            return (self.frame_names.len() - 1) as u16;
        }
        ANOTHER_FRAME
    }

    /// Keeps `m`, of frame `frame` (as kept, [`kept_frame`]), its vector grown (doubling)
    /// only within what `kept` (bytes allocated for every topic's messages) leaves of
    /// `limit`; `false` when full.
    fn push(&mut self, t: u64, frame: &str, m: T, kept: &mut usize, limit: usize) -> bool {
        if self.msgs.len() == self.msgs.capacity() {
            let each = std::mem::size_of::<(u64, T)>();
            let left = limit.saturating_sub(*kept) / each;
            let grow = self.msgs.capacity().max(16).min(left);
            if grow == 0 {
                return false;
            }
            let before = self.msgs.capacity();
            self.msgs.reserve_exact(grow);
            *kept += (self.msgs.capacity() - before) * each;
        }
        self.frames.see((t, self.msgs.len()), frame);
        self.msgs.push((t, m));
        true
    }
}

/// Where a connection's (channel's) messages are filed: its topic's slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Slot {
    kind: Kind,
    index: usize,
}

impl Slot {
    /// The message type filed there.
    pub(crate) fn kind(self) -> Kind {
        self.kind
    }
}

/// The messages of a log, topic by topic.
#[derive(Default)]
pub(crate) struct Topics {
    imu: Vec<Topic<ImuSample>>,
    temperature: Vec<Topic<TempSample>>,
    imu_by_name: HashMap<String, usize>,
    temperature_by_name: HashMap<String, usize>,
    /// Slots of `imu` and `temperature` in order of their first message: the instances'
    /// order.
    imu_order: Vec<usize>,
    temperature_order: Vec<usize>,
    /// What the messages of every topic take, and may take.
    room: Room,
}

/// The room the messages of every topic take together, and the most they may take.
#[derive(Default)]
struct Room {
    /// Bytes allocated for the messages of every topic.
    bytes: usize,
    /// Messages kept in every topic.
    messages: usize,
    /// The most bytes of messages kept ([`Topics::for_file`]).
    limit: usize,
}

impl Room {
    /// Files message `m` of log time `t` in `topics[index]`, noting the topic's first message
    /// in `order`; `false` when it does not fit.
    fn file<T>(
        &mut self,
        topics: &mut [Topic<T>],
        order: &mut Vec<usize>,
        index: usize,
        t: u64,
        frame: &str,
        m: T,
    ) -> bool {
        let topic = &mut topics[index];
        if topic.msgs.is_empty() {
            order.push(index);
        }
        let filed = topic.push(t, frame, m, &mut self.bytes, self.limit);
        self.messages += usize::from(filed);
        filed
    }
}

impl Topics {
    /// The topics of a file of `file_len` bytes: the messages kept may take
    /// [`KEPT_BYTES_AT_MOST`], or [`KEPT_PER_FILE_BYTE`] times the file's size if that is more.
    pub(crate) fn for_file(file_len: usize) -> Topics {
        Topics {
            room: Room {
                limit: KEPT_BYTES_AT_MOST.max(file_len.saturating_mul(KEPT_PER_FILE_BYTE)),
                ..Room::default()
            },
            ..Topics::default()
        }
    }

    /// The slot of `topic` for messages of `kind`, made on first sight.
    pub(crate) fn slot(&mut self, kind: Kind, topic: &str) -> Slot {
        let (by_name, len) = match kind {
            Kind::Imu => (&mut self.imu_by_name, self.imu.len()),
            Kind::Temperature => (&mut self.temperature_by_name, self.temperature.len()),
        };
        if let Some(&index) = by_name.get(topic) {
            return Slot { kind, index };
        }
        by_name.insert(topic.to_string(), len);
        match kind {
            Kind::Imu => self.imu.push(Topic::new(topic)),
            Kind::Temperature => self.temperature.push(Topic::new(topic)),
        }
        Slot { kind, index: len }
    }

    /// The topic of `slot`.
    pub(crate) fn name(&self, slot: Slot) -> &str {
        match slot.kind {
            Kind::Imu => &self.imu[slot.index].name,
            Kind::Temperature => &self.temperature[slot.index].name,
        }
    }

    /// How many messages of `slot`'s topic are kept: the next one's place among them, in
    /// file order, from 0.
    pub(crate) fn count(&self, slot: Slot) -> usize {
        match slot.kind {
            Kind::Imu => self.imu[slot.index].msgs.len(),
            Kind::Temperature => self.temperature[slot.index].msgs.len(),
        }
    }

    /// The error for a message on `slot` that does not fit: what every topic holds, the
    /// largest (in bytes allocated for it, which is what the limit counts) first.
    fn full(&self, slot: Slot) -> TooLarge {
        fn held<T>(t: &Topic<T>) -> (&str, usize, usize) {
            let bytes = t.msgs.capacity() * std::mem::size_of::<(u64, T)>();
            (&t.name, t.msgs.len(), bytes)
        }
        let mut kept: Vec<(&str, usize, usize)> = self
            .imu
            .iter()
            .map(held)
            .chain(self.temperature.iter().map(held))
            .filter(|&(_, n, _)| n > 0)
            .collect();
        kept.sort_by_key(|&(_, _, bytes)| std::cmp::Reverse(bytes));
        let topics = kept.len();
        let each = kept.into_iter().map(|(name, n, bytes)| {
            let s = if n == 1 { "" } else { "s" };
            format!("{} ({n} message{s}, {})", quoted(name), size(bytes))
        });
        TooLarge {
            limit_mib: self.room.limit >> 20,
            topic: quoted(self.name(slot)).into_owned(),
            kept: format!(
                "{} messages on {topics} topic{}: {}",
                self.room.messages,
                if topics == 1 { "" } else { "s" },
                listed(each, ", ")
            ),
        }
    }

    /// Files an Imu message under `slot` (of kind Imu).
    ///
    /// # Errors
    /// The messages kept would pass their limit ([`Topics::for_file`]).
    pub(crate) fn push_imu(
        &mut self,
        slot: Slot,
        log_time_ns: u64,
        m: &Imu<'_>,
    ) -> Result<(), TooLarge> {
        debug_assert_eq!(slot.kind, Kind::Imu);
        let kept = kept_frame(&m.frame_id);
        let frame = self.imu[slot.index].frame_number(&kept);
        let sample = ImuSample {
            sec: m.stamp.sec,
            nsec: m.stamp.nsec,
            frame,
            angular_velocity: m.angular_velocity,
            linear_acceleration: m.linear_acceleration,
        };
        let (topics, order) = (&mut self.imu, &mut self.imu_order);
        let filed = self
            .room
            .file(topics, order, slot.index, log_time_ns, &kept, sample);
        filed.then_some(()).ok_or_else(|| self.full(slot))
    }

    /// Files a Temperature message under `slot` (of kind Temperature).
    ///
    /// # Errors
    /// As [`Topics::push_imu`].
    pub(crate) fn push_temperature(
        &mut self,
        slot: Slot,
        log_time_ns: u64,
        m: &Temperature<'_>,
    ) -> Result<(), TooLarge> {
        debug_assert_eq!(slot.kind, Kind::Temperature);
        let sample = TempSample {
            stamp: m.stamp,
            celsius: m.celsius,
        };
        let (topics, order) = (&mut self.temperature, &mut self.temperature_order);
        let filed = self.room.file(
            topics,
            order,
            slot.index,
            log_time_ns,
            &kept_frame(&m.frame_id),
            sample,
        );
        filed.then_some(()).ok_or_else(|| self.full(slot))
    }

    /// One instance per Imu topic, in order of its first message, messages in log-time
    /// order (as rosbags and the mcap reader give them); and the Temperature topics taken as
    /// no gyro's temperature, each as `name (frame_id "f")`, for the message refusing a gyro
    /// without one.
    ///
    /// A gyro's temperature is the first Temperature topic (by first message) on its
    /// frame_id, else the log's only one when the log has one Imu topic. When that leaves a
    /// choice unmade (several topics on the frame) or undone (several topics, none on the
    /// frame), a problem names every candidate: no setting picks a Temperature topic.
    ///
    /// A topic whose `header.stamp` never advances ([`stuck`]: a driver that leaves it 0)
    /// is timed by `clock` (the log time each message was recorded at, as the format names
    /// it: "the bag's record time") instead, with a note saying so, and its temperature
    /// paired by that clock too; so is a gyro's pairing with a Temperature topic whose stamps
    /// never advance.
    pub(crate) fn into_instances(
        mut self,
        problems: &mut Vec<Problem>,
        clock: &str,
    ) -> (Vec<GyroInstance>, Vec<String>) {
        for t in &mut self.imu {
            t.msgs.sort_by_key(|(t, _)| *t);
        }
        for t in &mut self.temperature {
            t.msgs.sort_by_key(|(t, _)| *t);
        }
        let temps: Vec<&Topic<TempSample>> = self
            .temperature_order
            .iter()
            .map(|&k| &self.temperature[k])
            .collect();
        // Each Imu topic's gyros: its messages parted by frame_id, each frame's a gyro of its
        // own (one part when the frame never changes); messages of a frame past those a topic
        // tells apart ([`FRAMES_AT_MOST`]) are left out, counted.
        let gyros: Vec<(usize, Vec<device_change::Part<u16>>, usize)> = self
            .imu_order
            .iter()
            .map(|&slot| {
                let frames: Vec<u16> = self.imu[slot].msgs.iter().map(|(_, m)| m.frame).collect();
                let (mut parts, mut left_out) = device_change::parts(&frames);
                parts.retain(|p| {
                    let known = p.device != ANOTHER_FRAME;
                    if !known {
                        left_out += p.rows.len();
                    }
                    known
                });
                (slot, parts, left_out)
            })
            .collect();
        let single = gyros.iter().map(|g| g.1.len()).sum::<usize>() == 1 && temps.len() == 1;
        // The Temperature topics of each frame in order of their first message: the first is
        // the frame's, as a walk in order would find it.
        let mut by_frame: HashMap<&str, Vec<usize>> = HashMap::new();
        for (k, t) in temps.iter().enumerate() {
            by_frame.entry(t.frames.first()).or_default().push(k);
        }
        let named = |k: &usize| {
            let t = temps[*k];
            format!(
                "{} (frame_id \"{}\")",
                quoted(&t.name),
                quoted(t.frames.first())
            )
        };
        let mut used = vec![false; temps.len()];
        // Imu topics left without a temperature although the log has Temperature topics.
        let mut without: Vec<String> = Vec::new();
        // The frames of every gyro.
        let mut imu_frames: std::collections::HashSet<&str> = std::collections::HashSet::new();
        let mut out = Vec::new();
        for (slot, parts, left_out) in &gyros {
            let Topic {
                name: topic,
                msgs,
                frame_names,
                ..
            } = &self.imu[*slot];
            let log_times: Vec<u64> = msgs.iter().map(|(t, _)| *t).collect();
            let by_clock = stuck(msgs, ImuSample::stamp) && advances(&log_times);
            if by_clock {
                problems.push(Problem::note(format!(
                    "{}: header.stamp never advances (all {} messages are stamped {} s, as a \
                     driver that does not fill it leaves them): its samples are timed by {clock} \
                     instead, and its temperature paired by it, which lags each sample by the \
                     transport's delay and jitter; to time them by the sensor, have the driver \
                     fill header.stamp",
                    quoted(topic),
                    msgs.len(),
                    msgs[0].1.stamp().seconds()
                )));
            }
            let stamp_of = |i: usize| {
                if by_clock {
                    log_stamp(log_times[i])
                } else {
                    msgs[i].1.stamp()
                }
            };
            let frame_of =
                |p: &device_change::Part<u16>| frame_names[usize::from(p.device)].as_str();
            let label = |k: usize| {
                if parts.len() == 1 {
                    topic.clone()
                } else {
                    format!("{topic} frame {} of {}", k + 1, parts.len())
                }
            };
            if parts.len() > 1 {
                let at = parts[1].rows[0];
                let first = parts[0].rows.iter().take_while(|&&i| i < at).count();
                let each = parts.iter().enumerate().map(|(k, p)| {
                    let n = p.rows.len();
                    format!(
                        "{} (frame_id \"{}\", {n} sample{})",
                        quoted(&label(k)),
                        quoted(frame_of(p)),
                        if n == 1 { "" } else { "s" }
                    )
                });
                let mut message = format!(
                    "{}; each frame's samples are a gyro of their own, never one calibration \
                     over two sensors: {}",
                    device_change::changes(
                        &quoted(topic),
                        "frame_id",
                        (
                            &format!("\"{}\"", quoted(frame_of(&parts[0]))),
                            &format!("\"{}\"", quoted(frame_of(&parts[1])))
                        ),
                        "topic",
                        first + 1,
                        stamp_of(at).seconds()
                    ),
                    listed(each, ", ")
                );
                if *left_out > 0 {
                    message.push_str(&format!(
                        "; {left_out} samples of further frames left out (a gyro of each of \
                         the first {FRAMES_AT_MOST} only)"
                    ));
                }
                problems.push(Problem::note(message));
            }
            for (k, part) in parts.iter().enumerate() {
                let frame = frame_of(part).to_string();
                imu_frames.insert(frame_of(part));
                let rows = &part.rows;
                let stamps: Vec<RosTime> = rows.iter().map(|&i| stamp_of(i)).collect();
                let part_log_times: Vec<u64> = rows.iter().map(|&i| log_times[i]).collect();
                let column = |f: &dyn Fn(&ImuSample) -> f64| {
                    Values::F64(rows.iter().map(|&i| f(&msgs[i].1)).collect())
                };
                let gyro = Axes {
                    xyz: [
                        column(&|m| m.angular_velocity[0]),
                        column(&|m| m.angular_velocity[1]),
                        column(&|m| m.angular_velocity[2]),
                    ],
                };
                let accel = Axes {
                    xyz: [
                        column(&|m| m.linear_acceleration[0]),
                        column(&|m| m.linear_acceleration[1]),
                        column(&|m| m.linear_acceleration[2]),
                    ],
                };
                let label = label(k);
                // Its temperature: a Temperature topic on the same frame, else the only one of
                // a log with one gyro and one temperature.
                let on_frame = by_frame.get(frame.as_str());
                if let Some(ks) = on_frame.filter(|ks| ks.len() > 1) {
                    problems.push(Problem::note(format!(
                        "{}: {} Temperature topics are on its frame_id \"{}\": {}; its \
                         temperature is the first in the file, {} (temp_from own), and no \
                         setting picks another: to use another, cut the others out of the log \
                         (e.g. rosbag filter or mcap filter)",
                        quoted(&label),
                        ks.len(),
                        quoted(&frame),
                        listed(
                            ks.iter().map(|k| quoted(&temps[*k].name).into_owned()),
                            ", "
                        ),
                        quoted(&temps[ks[0]].name)
                    )));
                }
                let matched = on_frame.map(|ks| ks[0]).or(single.then_some(0));
                if matched.is_none() && !temps.is_empty() {
                    without.push(format!(
                        "{} (frame_id \"{}\")",
                        quoted(&label),
                        quoted(&frame)
                    ));
                }
                let temp_c = match matched {
                    Some(k) => {
                        used[k] = true;
                        let t = temps[k];
                        let tf = t.frames.first();
                        if tf != frame {
                            problems.push(Problem::note(format!(
                                "{}: temperature taken from {}, the log's only Temperature \
                                 topic, although its frame_id \"{}\" is not the IMU's \"{}\"",
                                quoted(&label),
                                quoted(&t.name),
                                quoted(tf),
                                quoted(&frame)
                            )));
                        }
                        // Both by the log's clock when either's stamps never advance: the
                        // stamps of one beside the log times of the other would be two clocks.
                        let temp_stuck = stuck(&t.msgs, |m| m.stamp);
                        let log_times_of = |t: &Topic<TempSample>| -> Vec<u64> {
                            t.msgs.iter().map(|(lt, _)| *lt).collect()
                        };
                        if temp_stuck && advances(&log_times_of(t)) && !by_clock {
                            problems.push(Problem::note(format!(
                                "{}: header.stamp never advances (all {} messages are stamped \
                                 {} s, as a driver that does not fill it leaves them): its \
                                 readings are paired with {}'s samples by {clock} instead",
                                quoted(&t.name),
                                t.msgs.len(),
                                t.msgs[0].1.stamp.seconds(),
                                quoted(&label)
                            )));
                        }
                        let (g, tk): (Vec<i128>, Vec<i128>) = if by_clock || temp_stuck {
                            (
                                part_log_times.iter().map(|&x| i128::from(x)).collect(),
                                log_times_of(t).into_iter().map(i128::from).collect(),
                            )
                        } else {
                            (
                                stamps.iter().map(|s| s.nanos()).collect(),
                                t.msgs.iter().map(|(_, m)| m.stamp.nanos()).collect(),
                            )
                        };
                        let tol = median_step(&tk)
                            .unwrap_or(0)
                            .max(median_step(&g).unwrap_or(0));
                        let pick = nearest_within(&g, &tk, tol);
                        Values::F64(
                            pick.iter()
                                .map(|p| p.map_or(f64::NAN, |i| t.msgs[i].1.celsius))
                                .collect(),
                        )
                    }
                    None => Values::F64(vec![f64::NAN; rows.len()]),
                };
                out.push(GyroInstance {
                    index: out.len(),
                    label,
                    device: Some(DeviceId::Ros {
                        topic: topic.clone(),
                        frame_id: frame,
                    }),
                    time: Timestamps::Ros(stamps),
                    time_sample_us: None,
                    log_time_ns: Some(part_log_times),
                    gyro,
                    temp_c,
                    accel: Some(accel),
                    alt_temps: Vec::new(),
                });
            }
        }
        let unused: Vec<usize> = (0..temps.len()).filter(|&k| !used[k]).collect();
        if !without.is_empty() {
            // Every Temperature topic could have been theirs, had it been the only one or on
            // their frame.
            let many = without.len() > 1;
            problems.push(Problem::note(format!(
                "Imu topic{} {} ha{} no Temperature topic on {} frame_id, and the log's {} \
                 Temperature topic{} on other frames: {}; none is taken as {} temperature \
                 (a log's only Temperature topic stands in for its only Imu topic), and no \
                 setting picks one (temp_from takes own, accel, imu-status or none): to use \
                 one, cut the log to the gyro's topic and that Temperature topic (e.g. rosbag \
                 filter or mcap filter)",
                if many { "s" } else { "" },
                listed(without.into_iter(), ", "),
                if many { "ve" } else { "s" },
                if many { "their" } else { "its" },
                temps.len(),
                if temps.len() == 1 { " is" } else { "s are" },
                listed((0..temps.len()).map(|k| named(&k)), ", "),
                if many { "their" } else { "its" },
            )));
        } else {
            // Those on a frame of no Imu topic (the others, a frame's second or third, are in
            // the note on that frame's gyro).
            let alone: Vec<&usize> = unused
                .iter()
                .filter(|k| !imu_frames.contains(temps[**k].frames.first()))
                .collect();
            for k in alone.iter().take(LIST_AT_MOST) {
                problems.push(Problem::note(format!(
                    "Temperature topic {} matches no Imu topic's frame; not used",
                    named(k)
                )));
            }
            if alone.len() > LIST_AT_MOST {
                problems.push(Problem::note(format!(
                    "and {} more Temperature topics match no Imu topic's frame; not used",
                    alone.len() - LIST_AT_MOST
                )));
            }
        }
        let untied = unused.iter().map(named).collect();
        (out, untied)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn imu(sec: i64, frame: &str, w: f64) -> Imu<'_> {
        Imu {
            stamp: RosTime { sec, nsec: 0 },
            frame_id: frame.into(),
            angular_velocity: [w, 0.0, 0.0],
            linear_acceleration: [0.0, 0.0, 9.8],
        }
    }

    fn temp(sec: i64, frame: &str, c: f64) -> Temperature<'_> {
        Temperature {
            stamp: RosTime { sec, nsec: 0 },
            frame_id: frame.into(),
            celsius: c,
        }
    }

    #[test]
    fn an_imu_message_keeps_its_frame_in_no_more_room_than_without() {
        // KEPT_BYTES_AT_MOST's count of messages, and the limits the attack tests check,
        // take 72 bytes an Imu message with its log time.
        assert_eq!(std::mem::size_of::<(u64, ImuSample)>(), 72);
    }

    #[test]
    fn a_temperature_topic_of_the_same_frame_is_the_gyros_own() {
        let mut t = Topics::for_file(0);
        // Slots made in another order than the first messages: the instances follow the
        // messages.
        let other = t.slot(Kind::Imu, "/other/imu");
        let data = t.slot(Kind::Imu, "/imu/data");
        let board = t.slot(Kind::Temperature, "/board/temperature");
        let own = t.slot(Kind::Temperature, "/imu/temperature");
        for s in 0..6 {
            t.push_imu(data, s as u64, &imu(s, "imu_link", s as f64))
                .unwrap();
            t.push_imu(other, s as u64, &imu(s, "other", 0.0)).unwrap();
        }
        // Half as often as the gyro, on its frame; another frame's topic is not used.
        for s in [0, 2, 4] {
            t.push_temperature(own, s as u64, &temp(s, "imu_link", 30.0 + s as f64))
                .unwrap();
            t.push_temperature(board, s as u64, &temp(s, "board", 99.0))
                .unwrap();
        }
        let mut problems = Vec::new();
        let (inst, _) = t.into_instances(&mut problems, "the log time");
        assert_eq!(inst.len(), 2);
        assert_eq!(inst[0].label, "/imu/data");
        // The nearest temperature beside each gyro sample (ties go to the earlier one).
        assert_eq!(
            inst[0].temp_c,
            Values::F64(vec![30.0, 30.0, 32.0, 32.0, 34.0, 34.0])
        );
        assert!(!inst[1].temp_c.has_numbers());
        assert!(
            problems
                .iter()
                .any(|p| p.message.contains("/board/temperature")),
            "{problems:?}"
        );
    }

    #[test]
    fn a_full_log_lists_its_largest_topics_first_and_counts_the_rest() {
        let mut t = Topics::for_file(0);
        // Room for 200 Temperature messages (32 bytes each) in all.
        t.room.limit = 200 * 32;
        let small: Vec<Slot> = (0..9)
            .map(|k| t.slot(Kind::Temperature, &format!("/t{k}")))
            .collect();
        for &s in &small {
            t.push_temperature(s, 0, &temp(0, "f", 1.0)).unwrap();
        }
        let big = t.slot(Kind::Temperature, &"/big/".repeat(40));
        // Nine topics of one message hold 16 each (144 messages' room): 56 left.
        let mut n = 0;
        let e = loop {
            match t.push_temperature(big, n, &temp(0, "f", 1.0)) {
                Ok(()) => n += 1,
                Err(e) => break e,
            }
        };
        assert_eq!(n, 56);
        assert_eq!(e.limit_mib, 0);
        assert_eq!(e.topic, quoted(&"/big/".repeat(40)));
        assert_eq!(
            e.kept,
            format!(
                "65 messages on 10 topics: {} (56 messages, 1.8 KiB), /t0 (1 message, 512 \
                 bytes), /t1 (1 message, 512 bytes), /t2 (1 message, 512 bytes), /t3 (1 \
                 message, 512 bytes), /t4 (1 message, 512 bytes), /t5 (1 message, 512 bytes), \
                 /t6 (1 message, 512 bytes), and 2 more",
                quoted(&"/big/".repeat(40))
            )
        );
    }

    /// The frames a sort by log time, then a walk, would find: the first message's, and the
    /// first after it that differs.
    fn by_sorting(msgs: &[(u64, &str)]) -> (String, Option<String>) {
        let mut v: Vec<(u64, &str)> = msgs.to_vec();
        v.sort_by_key(|m| m.0);
        let first = v[0].1.to_string();
        let other = v.iter().find(|m| m.1 != first).map(|m| m.1.to_string());
        (first, other)
    }

    #[test]
    fn the_frames_kept_are_those_a_sort_then_a_walk_would_find() {
        let names = ["a", "b", "c"];
        // Every sequence of 5 messages over 3 log times and 3 frames.
        for code in 0..9usize.pow(5) {
            let mut c = code;
            let msgs: Vec<(u64, &str)> = (0..5)
                .map(|_| {
                    let m = ((c % 3) as u64, names[(c / 3) % 3]);
                    c /= 9;
                    m
                })
                .collect();
            let mut f = Frames::default();
            for (i, (t, name)) in msgs.iter().enumerate() {
                f.see((*t, i), name);
            }
            let got = (
                f.first().to_string(),
                f.other.as_ref().map(|(_, s)| s.clone()),
            );
            assert_eq!(got, by_sorting(&msgs), "{msgs:?}");
        }
    }
}
