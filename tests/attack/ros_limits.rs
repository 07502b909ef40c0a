//! ROS 1 bags and MCAP files the readers refuse or warn about for what they hold, not for a
//! broken byte: more messages than are kept (an honest long log, told apart from a malformed
//! one), stamps whose nanoseconds are a second or more (no time, not turned into one), and
//! several Temperature topics that could be a gyro's (every candidate named). Each file is
//! built here.

use super::limits::{crafted, driftlab_within};
use super::readers::{
    LIMIT_MIB, bag, bag_connection, bag_field, bag_lz4_chunk, bag_message, bag_record, imu_cdr,
    imu_ros1, mcap, mcap_channel, mcap_chunk, mcap_message, mcap_schema,
};
use driftlab::log::formats::{self, FormatError, Values};

/// A bag connection of message type `ty`.
pub(super) fn bag_connection_of(conn: u32, topic: &str, ty: &str) -> Vec<u8> {
    bag_record(
        &[
            bag_field("op", &[0x07]),
            bag_field("conn", &conn.to_le_bytes()),
            bag_field("topic", topic.as_bytes()),
        ],
        &bag_field("type", ty.as_bytes()),
    )
}

/// A bag message record whose time field is `sec`, `nsec`.
pub(super) fn bag_message_at(conn: u32, sec: u32, nsec: u32, data: &[u8]) -> Vec<u8> {
    let mut time = sec.to_le_bytes().to_vec();
    time.extend_from_slice(&nsec.to_le_bytes());
    bag_record(
        &[
            bag_field("op", &[0x02]),
            bag_field("conn", &conn.to_le_bytes()),
            bag_field("time", &time),
        ],
        data,
    )
}

/// `sensor_msgs/Temperature` in the ROS 1 serialization.
pub(super) fn temperature_ros1(sec: u32, frame: &[u8], celsius: f64) -> Vec<u8> {
    let mut b = 0u32.to_le_bytes().to_vec();
    b.extend_from_slice(&sec.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes());
    b.extend_from_slice(&u32::try_from(frame.len()).unwrap().to_le_bytes());
    b.extend_from_slice(frame);
    b.extend_from_slice(&celsius.to_le_bytes());
    b.extend_from_slice(&0.0f64.to_le_bytes());
    b
}

/// `sensor_msgs/msg/Temperature` in little-endian CDR.
pub(super) fn temperature_cdr(sec: i32, nsec: u32, frame: &[u8], celsius: f64) -> Vec<u8> {
    let mut b = vec![0, 1, 0, 0];
    b.extend_from_slice(&sec.to_le_bytes());
    b.extend_from_slice(&nsec.to_le_bytes());
    b.extend_from_slice(&u32::try_from(frame.len() + 1).unwrap().to_le_bytes());
    b.extend_from_slice(frame);
    b.push(0);
    while (b.len() - 4) % 8 != 0 {
        b.push(0);
    }
    b.extend_from_slice(&celsius.to_le_bytes());
    b.extend_from_slice(&0.0f64.to_le_bytes());
    b
}

/// The byte of a ROS message (either serialization) where its header stamp's nanoseconds
/// are: after the ROS 1 `seq` and seconds, or after the CDR encapsulation and seconds.
const NSEC_AT: usize = 8;

/// `message` with its header stamp's nanoseconds set to `nsec`.
fn with_stamp_nanos(mut message: Vec<u8>, nsec: u32) -> Vec<u8> {
    message[NSEC_AT..NSEC_AT + 4].copy_from_slice(&nsec.to_le_bytes());
    message
}

// ---------------------------------------------------------------- more than is kept

#[test]
fn a_bag_past_the_kept_messages_is_too_large_not_malformed_and_says_what_it_held() {
    // Eleven small Imu topics, then lz4 chunks of one Temperature message repeated: the
    // Temperature topic grows until every topic together holds the 256 MiB the reader keeps
    // of a file this small (3 MB). Nothing in the file is broken.
    let mut records = bag_connection(0, "/imu/data");
    for k in 0..50 {
        records.extend(bag_message(0, k + 1, &imu_ros1(k + 1, b"imu", 0.01)));
    }
    for s in 0..10u32 {
        let conn = 1 + s;
        records.extend(bag_connection(conn, &format!("/imu/s{s}")));
        for k in 0..20 {
            records.extend(bag_message(conn, k + 1, &imu_ros1(k + 1, b"s", 0.0)));
        }
    }
    let one = bag_message(20, 1, &temperature_ros1(1, b"board", 35.0));
    let mut inner = bag_connection_of(20, "/board/temperature", "sensor_msgs/Temperature");
    while inner.len() + one.len() <= 200_000_000 {
        inner.extend_from_slice(&one);
    }
    let chunk = bag_lz4_chunk(&inner);
    let first_chunk_at = 13 + records.len();
    for _ in 0..4 {
        records.extend_from_slice(&chunk);
    }
    let file = bag(&records);
    assert!(file.len() * 8 < 256 << 20, "{} bytes", file.len());

    // What the reader keeps, by its documented rule: each topic's vector doubles from 16
    // within 256 MiB in all, the last growth taking what is left. The small topics hold 64
    // Imu messages' room (/imu/data, 50) and 32 each (/imu/s*, 20), 72 bytes a message; the
    // Temperature topic, 32 bytes a message, gets the rest.
    let (imu_bytes, temp_bytes) = (72usize, 32usize);
    let small = 64 * imu_bytes + 10 * 32 * imu_bytes;
    let temps = ((256 << 20) - small) / temp_bytes;
    assert!(
        4 * (inner.len() / one.len()) > temps,
        "the chunks hold enough"
    );
    let kept = temps + 50 + 10 * 20;

    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "too_large.bag", &file);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    // Not malformed: refused as too large, the limit, where, and what each topic held, the
    // largest first, eight named and the rest counted.
    ran.fails_with(
        "too_large.bag: ROS 1 bag log not malformed, but larger than driftlab keeps: its Imu \
         and Temperature messages reach 256 MiB at byte ",
        1000,
    );
    ran.fails_with(
        &format!(
            ", at a message on /board/temperature (the most kept is 256 MiB, or 8 times the \
             file's size when that is more); kept by then: {kept} messages on 12 topics: \
             /board/temperature ({temps} messages, 256.0 MiB), /imu/data (50 messages, 4.5 \
             KiB), /imu/s0 (20 messages, 2.2 KiB), /imu/s1 (20 messages, 2.2 KiB), /imu/s2 \
             (20 messages, 2.2 KiB), /imu/s3 (20 messages, 2.2 KiB), /imu/s4 (20 messages, 2.2 \
             KiB), /imu/s5 (20 messages, 2.2 KiB), and 4 more; "
        ),
        1000,
    );
    // What to do, in the command line's words: no option reads fewer topics.
    ran.fails_with(
        "every Imu and Temperature topic is kept while reading (--gyro N chooses among them \
         only afterwards), so no setting reads less: cut the log to the topics or the time \
         span needed (e.g. rosbag filter) and read that",
        1000,
    );
    assert!(!ran.stderr.contains("malformed at"), "{}", ran.stderr);
    // The messages ran out inside a chunk: the error is placed at one of the chunks.
    let at: usize = ran
        .stderr
        .split("256 MiB at byte ")
        .nth(1)
        .and_then(|r| r.split(',').next())
        .and_then(|n| n.parse().ok())
        .expect("an offset");
    assert!(
        (0..4).any(|k| at == first_chunk_at + k * chunk.len()),
        "{at} is no chunk's offset"
    );
}

// ---------------------------------------------------------------- nanoseconds of a second

#[test]
fn a_bag_record_time_of_a_second_of_nanoseconds_is_refused_not_a_time() {
    let conn = bag_connection(0, "/imu/data");
    let good: Vec<Vec<u8>> = (1..=2)
        .map(|k| bag_message(0, k, &imu_ros1(k, b"imu", 0.01)))
        .collect();
    let bad = bag_message_at(0, 3, 1_000_000_000, &imu_ros1(3, b"imu", 0.01));
    let at = 13 + conn.len() + good.concat().len();
    let file = bag(&[conn, good.concat(), bad].concat());
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "record_nsec.bag", &file);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        &format!(
            "record_nsec.bag: ROS 1 bag log malformed at byte {at}: message 3 on /imu/data \
             (counted from 1 in file order): its record's time has 1000000000 nanoseconds \
             (with 3 s), not below 1000000000: not a time"
        ),
        400,
    );
}

#[test]
fn a_bag_header_stamp_of_a_second_of_nanoseconds_is_refused_not_a_time() {
    let conn = bag_connection(0, "/imu/data");
    let first = bag_message(0, 1, &imu_ros1(1, b"imu", 0.01));
    let data = with_stamp_nanos(imu_ros1(2, b"imu", 0.01), 2_000_000_000);
    let second = bag_message(0, 2, &data);
    // The message's data starts after the record's header and the data's length.
    let data_at = 13 + conn.len() + first.len() + second.len() - data.len();
    let file = bag(&[conn, first, second].concat());
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "stamp_nsec.bag", &file);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        &format!(
            "stamp_nsec.bag: ROS 1 bag log malformed at byte {data_at}: message 2 on \
             /imu/data (counted from 1 in file order): its header.stamp has 2000000000 \
             nanoseconds (at byte {NSEC_AT} of the message, with 2 s), not below 1000000000: \
             not a time"
        ),
        400,
    );
}

/// An MCAP of one zstd chunk holding an Imu channel and a Temperature channel on its frame,
/// six messages each, the fourth Temperature message stamped with `nsec` nanoseconds; and
/// the offset of that message's bytes among the chunk's decompressed records.
fn mcap_with_stamp_nanos(nsec: u32) -> (Vec<u8>, usize) {
    let mut inner = mcap_schema(1, "sensor_msgs/msg/Imu");
    inner.extend(mcap_schema(2, "sensor_msgs/msg/Temperature"));
    inner.extend(mcap_channel(1, 1, "/imu"));
    inner.extend(mcap_channel(2, 2, "/imu/temperature"));
    let mut fourth_at = 0;
    for k in 0..6u32 {
        inner.extend(mcap_message(
            1,
            u64::from(k),
            &imu_cdr(k as i32, b"imu", 0.5),
        ));
        let t = temperature_cdr(k as i32, 0, b"imu", 30.0);
        if k == 3 {
            // After the record's opcode and length (9 bytes), its channel, sequence and two
            // times (22).
            fourth_at = inner.len() + 9 + 22;
            inner.extend(mcap_message(2, u64::from(k), &with_stamp_nanos(t, nsec)));
        } else {
            inner.extend(mcap_message(2, u64::from(k), &t));
        }
    }
    let chunk = mcap_chunk(
        "zstd",
        inner.len() as u64,
        &zstd::bulk::compress(&inner, 1).unwrap(),
    );
    (mcap(&chunk), fourth_at)
}

#[test]
fn an_mcap_header_stamp_of_a_second_of_nanoseconds_is_refused_not_a_time() {
    let (file, fourth_at) = mcap_with_stamp_nanos(u32::MAX);
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "stamp_nsec.mcap", &file);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    // The chunk starts after the 8 bytes of the magic.
    ran.fails_with(
        &format!(
            "stamp_nsec.mcap: MCAP log malformed at byte 8: in the chunk starting here, at \
             byte {fourth_at} of its decompressed records: message 4 on /imu/temperature \
             (counted from 1 in file order): its header.stamp has 4294967295 nanoseconds (at \
             byte {NSEC_AT} of the message, with 3 s), not below 1000000000: not a time"
        ),
        500,
    );
    // A nanosecond less than a second is a time: the same file reads, the stamp as stored.
    let (file, _) = mcap_with_stamp_nanos(999_999_999);
    let rec = formats::read_bytes("stamp_nsec_ok.mcap", &file).unwrap();
    assert_eq!(rec.instances[0].temp_c, Values::F64(vec![30.0; 6]));
    let (file, _) = mcap_with_stamp_nanos(1_000_000_000);
    let e = formats::read_bytes("stamp_nsec_1s.mcap", &file).unwrap_err();
    assert!(matches!(e, FormatError::Malformed { offset: 8, .. }), "{e}");
    assert!(e.to_string().contains("has 1000000000 nanoseconds"), "{e}");
}

// ---------------------------------------------------------------- several temperatures

/// An MCAP of one Imu channel on frame `imu` (6 messages a second apart) and Temperature
/// channels `temps` (topic, frame, °C), each with a message every second.
fn mcap_with_temperatures(temps: &[(&str, &str, f64)]) -> Vec<u8> {
    let mut r = mcap_schema(1, "sensor_msgs/msg/Imu");
    r.extend(mcap_schema(2, "sensor_msgs/msg/Temperature"));
    r.extend(mcap_channel(1, 1, "/imu"));
    for (k, (topic, _, _)) in temps.iter().enumerate() {
        r.extend(mcap_channel(2 + k as u16, 2, topic));
    }
    for s in 0..6i32 {
        let t = 1_000_000_000 * s as u64;
        r.extend(mcap_message(1, t, &imu_cdr(s, b"imu", 0.01)));
        for (k, (_, frame, c)) in temps.iter().enumerate() {
            let m = temperature_cdr(s, 0, frame.as_bytes(), *c);
            r.extend(mcap_message(2 + k as u16, t, &m));
        }
    }
    mcap(&r)
}

#[test]
fn two_temperature_topics_on_the_gyros_frame_are_both_named_with_the_choice_made() {
    let file = mcap_with_temperatures(&[
        ("/imu/temp_die", "imu", 41.0),
        ("/imu/temp_case", "imu", 29.0),
    ]);
    // The engine: the first in the file is the gyro's, both named, the setting by its name.
    let rec = formats::read_bytes("two_temps.mcap", &file).unwrap();
    assert_eq!(rec.instances.len(), 1);
    assert_eq!(rec.instances[0].temp_c, Values::F64(vec![41.0; 6]));
    let notes: Vec<String> = rec.problems.iter().map(|p| p.to_string()).collect();
    assert_eq!(
        notes,
        [
            "/imu: 2 Temperature topics are on its frame_id \"imu\": /imu/temp_die, \
             /imu/temp_case; its temperature is the first in the file, /imu/temp_die \
             (temp_from own), and no setting picks another: to use another, cut the others \
             out of the log (e.g. rosbag filter or mcap filter)"
        ],
        "the second is not said to match no frame"
    );
    assert_eq!(rec.untied_temps, ["/imu/temp_case (frame_id \"imu\")"]);
    // The command line: the same warning, the setting as its flag.
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "two_temps.mcap", &file);
    let csv = dir.path().join("out.csv").display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &csv]);
    ran.succeeds();
    assert!(
        ran.stderr.contains(
            "/imu: 2 Temperature topics are on its frame_id \"imu\": /imu/temp_die, \
             /imu/temp_case; its temperature is the first in the file, /imu/temp_die \
             (--temp-from own)"
        ),
        "{}",
        ran.stderr
    );
}

#[test]
fn temperature_topics_off_the_gyros_frame_are_named_when_the_gyro_is_refused() {
    let file = mcap_with_temperatures(&[("/a/temp", "a", 40.0), ("/b/temp", "b", 20.0)]);
    // The engine: a note naming every candidate; the refusal names them too instead of
    // saying the gyro has no other temperature and stopping there.
    let rec = formats::read_bytes("off_frame.mcap", &file).unwrap();
    assert!(!rec.instances[0].temp_c.has_numbers());
    let notes: Vec<String> = rec.problems.iter().map(|p| p.to_string()).collect();
    assert_eq!(
        notes,
        [
            "Imu topic /imu (frame_id \"imu\") has no Temperature topic on its frame_id, and \
             the log's 2 Temperature topics are on other frames: /a/temp (frame_id \"a\"), \
             /b/temp (frame_id \"b\"); none is taken as its temperature (a log's only \
             Temperature topic stands in for its only Imu topic), and no setting picks one \
             (temp_from takes own, accel, imu-status or none): to use one, cut the log to the \
             gyro's topic and that Temperature topic (e.g. rosbag filter or mcap filter)"
        ]
    );
    let e = formats::select(&rec, None, None).unwrap_err().to_string();
    assert!(
        e.contains(
            "the log's Temperature topics /a/temp (frame_id \"a\"), /b/temp (frame_id \"b\") \
             are taken as no gyro's temperature (a ROS gyro's own is the Temperature topic on \
             its frame_id, or a log's only one beside its only Imu topic), and no setting \
             picks one"
        ),
        "{e}"
    );
    // The command line: refused with both named and the settings as flags.
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "off_frame.mcap", &file);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        "off_frame.mcap: no gyro in the log has a temperature of its own; gyro 0 (/imu, ",
        1000,
    );
    ran.fails_with(
        "the log's Temperature topics /a/temp (frame_id \"a\"), /b/temp (frame_id \"b\") are \
         taken as no gyro's temperature",
        1000,
    );
    ran.fails_with("; --temp-from none writes temp_c as NaN", 1000);
    // One of them alone beside the gyro is taken, with a note that its frame differs.
    let one = mcap_with_temperatures(&[("/a/temp", "a", 40.0)]);
    let rec = formats::read_bytes("one_off_frame.mcap", &one).unwrap();
    assert_eq!(rec.instances[0].temp_c, Values::F64(vec![40.0; 6]));
    assert!(rec.untied_temps.is_empty());
}
