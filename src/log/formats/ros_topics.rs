//! Gyro instances from the decoded messages of a ROS 1 bag or an MCAP file: one instance per
//! `sensor_msgs/Imu` topic (per frame of it, when its `frame_id` changes: each frame's
//! samples a gyro of their own, by the rule of `device_change`, as a PX4 gyro whose
//! `device_id` changes), its temperature from a `sensor_msgs/Temperature` topic of the same
//! frame (the readings of that frame, when the topic's `frame_id` changes too), paired by the
//! clock `ros_clocks` chooses.
//!
//! Bounded by construction: a topic is found by its name in a hash map once, when the
//! connection or channel naming it is read (a bag of 100 000 topics, or an MCAP redefining a
//! channel before each of 200 000 messages, costs one lookup each, not a walk over every
//! topic), and a message is filed by the slot its connection holds. A `frame_id` is not kept
//! per message: a topic keeps the first few distinct ones (`ros_frames`), which a message
//! names by number in bytes its stamp leaves as padding.
//!
//! The messages kept are bounded too: a compressed chunk may expand a thousand-fold, so a
//! small file can hold tens of millions of messages (a 18 MB bag of lz4 chunks holds 11
//! million Imu messages). Every topic is kept (`inspect` lists each one), so the bound is on
//! all of them together: [`KEPT_BYTES_AT_MOST`] of messages as stored, their vectors grown
//! within it, and a log holding more is refused ([`TooLarge`], which the public error tells
//! apart from a malformed file) with what each topic held when it ran out.

use super::error::{TooLarge, listed, quoted};
use super::recording::RosTime;
use super::ros_frames::{FrameNames, kept_frame};
use super::ros_msgs::{Imu, Kind, Temperature};
use std::collections::HashMap;

mod instances;

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

/// An Imu message as kept: all of it but its `frame_id`, which is kept as its number among
/// its topic's frames ([`Topic::frame_names`]). The stamp is held apart from a [`RosTime`] so
/// that the frame's number, and whether the message has an acceleration, take the bytes a
/// `RosTime` leaves as padding: a message takes 64 bytes, as before either was kept.
struct ImuSample {
    sec: i64,
    nsec: u32,
    frame: u16,
    /// `linear_acceleration` is no reading (`Imu::no_acceleration`).
    no_acceleration: bool,
    angular_velocity: [f64; 3],
    linear_acceleration: [f64; 3],
}

/// A Temperature message as kept, its frame by number as an Imu message's: 24 bytes.
struct TempSample {
    sec: i64,
    nsec: u32,
    frame: u16,
    celsius: f64,
}

/// A kept message's `header.stamp` and frame number.
trait Stamped {
    fn stamp(&self) -> RosTime;
    fn frame(&self) -> u16;
}

/// [`Stamped`] of the kept messages, which hold their stamp and frame number alike.
macro_rules! stamped {
    ($($kind:ty),*) => {$(
        impl Stamped for $kind {
            fn stamp(&self) -> RosTime {
                RosTime {
                    sec: self.sec,
                    nsec: self.nsec,
                }
            }

            fn frame(&self) -> u16 {
                self.frame
            }
        }
    )*};
}

stamped!(ImuSample, TempSample);

/// The messages of one topic, with their log (bag) time in ns.
struct Topic<T> {
    name: String,
    msgs: Vec<(u64, T)>,
    /// The topic's distinct `frame_id`s, the first few: what a message's frame number names.
    frame_names: FrameNames,
}

impl<T: Stamped> Topic<T> {
    fn new(name: &str) -> Topic<T> {
        Topic {
            name: name.to_string(),
            msgs: Vec::new(),
            frame_names: FrameNames::default(),
        }
    }

    /// Keeps `m`, its vector grown (doubling) only within what `kept` (bytes allocated for
    /// every topic's messages) leaves of `limit`; `false` when full.
    fn push(&mut self, t: u64, m: T, kept: &mut usize, limit: usize) -> bool {
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
    fn file<T: Stamped>(
        &mut self,
        topics: &mut [Topic<T>],
        order: &mut Vec<usize>,
        index: usize,
        t: u64,
        m: T,
    ) -> bool {
        let topic = &mut topics[index];
        if topic.msgs.is_empty() {
            order.push(index);
        }
        let filed = topic.push(t, m, &mut self.bytes, self.limit);
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
        let frame = self.imu[slot.index]
            .frame_names
            .number(&kept_frame(&m.frame_id));
        let sample = ImuSample {
            sec: m.stamp.sec,
            nsec: m.stamp.nsec,
            frame,
            no_acceleration: m.no_acceleration,
            angular_velocity: m.angular_velocity,
            linear_acceleration: m.linear_acceleration,
        };
        let (topics, order) = (&mut self.imu, &mut self.imu_order);
        let filed = self
            .room
            .file(topics, order, slot.index, log_time_ns, sample);
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
        let frame = self.temperature[slot.index]
            .frame_names
            .number(&kept_frame(&m.frame_id));
        let sample = TempSample {
            sec: m.stamp.sec,
            nsec: m.stamp.nsec,
            frame,
            celsius: m.celsius,
        };
        let (topics, order) = (&mut self.temperature, &mut self.temperature_order);
        let filed = self
            .room
            .file(topics, order, slot.index, log_time_ns, sample);
        filed.then_some(()).ok_or_else(|| self.full(slot))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(super) fn imu(sec: i64, frame: &str, w: f64) -> Imu<'_> {
        Imu {
            stamp: RosTime { sec, nsec: 0 },
            frame_id: frame.into(),
            angular_velocity: [w, 0.0, 0.0],
            linear_acceleration: [0.0, 0.0, 9.8],
            no_acceleration: false,
        }
    }

    pub(super) fn temp(sec: i64, frame: &str, c: f64) -> Temperature<'_> {
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
        // And a Temperature message 32, as the test of a full log counts them.
        assert_eq!(std::mem::size_of::<(u64, TempSample)>(), 32);
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
}
