//! The binary readers (PX4 ULog, ROS 1 bag, MCAP) on the crafted files of issue 21: sizes that
//! allocate a terabyte or wrap, formats nested 16 deep, padding on every sample, chunks that
//! expand a thousand-fold, 100 000 topics, megabyte frame_ids. Each file is built here; each
//! run must stay within a memory limit sized to what the command keeps plus a fixed
//! allowance, end without a signal, and say what it should in a readable message.

use super::limits::{crafted, driftlab_within};

/// The address space every run gets: the binary, its threads and allocator arenas, one
/// decompressed chunk at most (256 MiB), the file and what is kept of it.
pub(super) const LIMIT_MIB: u64 = 768;

// ---------------------------------------------------------------- PX4 ULog

fn ulog_message(ty: u8, body: &[u8]) -> Vec<u8> {
    let mut m = u16::try_from(body.len()).unwrap().to_le_bytes().to_vec();
    m.push(ty);
    m.extend_from_slice(body);
    m
}

/// A ULog with the formats `formats` (the first is `sensor_gyro`'s), `sensor_gyro`
/// subscribed as msg_id 0, and `samples` samples of timestamp, x, y, z, temperature.
fn ulog(formats: &[&str], samples: usize) -> Vec<u8> {
    let mut b = b"ULog\x01\x12\x35\x01".to_vec();
    b.extend_from_slice(&0u64.to_le_bytes());
    for f in formats {
        b.extend(ulog_message(b'F', f.as_bytes()));
    }
    b.extend(ulog_message(b'A', b"\x00\x00\x00sensor_gyro"));
    for k in 0..samples {
        let mut d = vec![0u8, 0];
        d.extend_from_slice(&(1000 * k as u64).to_le_bytes());
        for v in [0.01f32, -0.02, 0.03, 30.0 + k as f32 * 1e-3] {
            d.extend_from_slice(&v.to_le_bytes());
        }
        b.extend(ulog_message(b'D', &d));
    }
    b
}

const GYRO_FIELDS: &str = "uint64_t timestamp;float x;float y;float z;float temperature;";

#[test]
fn a_ulog_declaring_a_terabyte_of_padding_is_refused_without_allocating_it() {
    let dir = tempfile::tempdir().unwrap();
    let f = format!("sensor_gyro:{GYRO_FIELDS}uint8_t[1099511627776] _padding0;");
    let log = crafted(dir.path(), "terabyte.ulg", &ulog(&[&f], 3));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        "malformed at byte 125: type sensor_gyro is larger than a message can be",
        300,
    );
}

#[test]
fn a_ulog_field_count_that_wraps_the_row_offset_is_refused_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    // 2^64 - 1 bytes, then the fields: their offsets wrap round to small numbers.
    let f = format!("sensor_gyro:uint8_t[18446744073709551615] skip;{GYRO_FIELDS}");
    let log = crafted(dir.path(), "wrap.ulg", &ulog(&[&f], 3));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with("type sensor_gyro is larger than a message can be", 300);
}

#[test]
fn sixteen_levels_of_nested_formats_are_read_at_once() {
    // n0 .. n15, each four fields of the next, n15 empty: 4^16 walks of the format tree
    // without remembering sizes.
    let mut formats = vec![format!("sensor_gyro:{GYRO_FIELDS}n0 nest;")];
    for k in 0..16 {
        if k == 15 {
            formats.push(format!("n{k}:"));
        } else {
            let j = k + 1;
            formats.push(format!("n{k}:n{j} a;n{j} b;n{j} c;n{j} d;"));
        }
    }
    let formats: Vec<&str> = formats.iter().map(String::as_str).collect();
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "nested.ulg", &ulog(&formats, 10));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.succeeds();
    assert!(ran.stdout.contains("10 samples"), "{}", ran.stdout);
}

#[test]
fn ulog_padding_is_not_kept_for_every_sample() {
    // 20 000 samples of 24 bytes, each declared with 65 000 bytes of trailing padding (left
    // out of the file, as PX4 does): 1.3 GB if padding were stored, 0.5 MB as it is not.
    let f = format!("sensor_gyro:{GYRO_FIELDS}uint8_t[65000] _padding0;");
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "padding.ulg", &ulog(&[&f], 20_000));
    let ran = driftlab_within(dir.path(), 256, &["inspect", &log]);
    ran.succeeds();
    assert!(ran.stdout.contains("20000 samples"), "{}", ran.stdout);
}

#[test]
fn ulog_padding_past_a_message_is_refused() {
    // 340 bytes that asked for 2.9 GB: padding larger than any message.
    let f = format!("sensor_gyro:{GYRO_FIELDS}uint8_t[290000000] _padding0;");
    let dir = tempfile::tempdir().unwrap();
    let bytes = ulog(&[&f], 7);
    let log = crafted(dir.path(), "padding340.ulg", &bytes);
    let ran = driftlab_within(dir.path(), 256, &["inspect", &log]);
    ran.fails_with("type sensor_gyro is larger than a message can be", 300);
}

// ---------------------------------------------------------------- ROS messages

/// `sensor_msgs/Imu` in the ROS 1 serialization.
pub(super) fn imu_ros1(sec: u32, frame: &[u8], w: f64) -> Vec<u8> {
    let mut b = 0u32.to_le_bytes().to_vec();
    b.extend_from_slice(&sec.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes());
    b.extend_from_slice(&u32::try_from(frame.len()).unwrap().to_le_bytes());
    b.extend_from_slice(frame);
    for k in 0..37 {
        let v = if k == 13 { w } else { 0.0 };
        b.extend_from_slice(&v.to_le_bytes());
    }
    b
}

/// `sensor_msgs/msg/Imu` in little-endian CDR.
pub(super) fn imu_cdr(sec: i32, frame: &[u8], w: f64) -> Vec<u8> {
    let mut b = vec![0, 1, 0, 0];
    b.extend_from_slice(&sec.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes());
    b.extend_from_slice(&u32::try_from(frame.len() + 1).unwrap().to_le_bytes());
    b.extend_from_slice(frame);
    b.push(0);
    while (b.len() - 4) % 8 != 0 {
        b.push(0);
    }
    for k in 0..37 {
        let v = if k == 13 { w } else { 0.0 };
        b.extend_from_slice(&v.to_le_bytes());
    }
    b
}

// ---------------------------------------------------------------- ROS 1 bag

pub(super) fn bag_field(name: &str, value: &[u8]) -> Vec<u8> {
    let mut f = u32::try_from(name.len() + 1 + value.len())
        .unwrap()
        .to_le_bytes()
        .to_vec();
    f.extend_from_slice(name.as_bytes());
    f.push(b'=');
    f.extend_from_slice(value);
    f
}

pub(super) fn bag_record(fields: &[Vec<u8>], data: &[u8]) -> Vec<u8> {
    let header: Vec<u8> = fields.concat();
    let mut r = u32::try_from(header.len()).unwrap().to_le_bytes().to_vec();
    r.extend(header);
    r.extend_from_slice(&u32::try_from(data.len()).unwrap().to_le_bytes());
    r.extend_from_slice(data);
    r
}

pub(super) fn bag_connection(conn: u32, topic: &str) -> Vec<u8> {
    bag_record(
        &[
            bag_field("op", &[0x07]),
            bag_field("conn", &conn.to_le_bytes()),
            bag_field("topic", topic.as_bytes()),
        ],
        &bag_field("type", b"sensor_msgs/Imu"),
    )
}

pub(super) fn bag_message(conn: u32, sec: u32, data: &[u8]) -> Vec<u8> {
    let mut time = sec.to_le_bytes().to_vec();
    time.extend_from_slice(&0u32.to_le_bytes());
    bag_record(
        &[
            bag_field("op", &[0x02]),
            bag_field("conn", &conn.to_le_bytes()),
            bag_field("time", &time),
        ],
        data,
    )
}

pub(super) fn bag(records: &[u8]) -> Vec<u8> {
    let mut b = b"#ROSBAG V2.0\n".to_vec();
    b.extend_from_slice(records);
    b
}

#[test]
fn a_bag_of_100k_topics_reads_in_one_pass_and_its_error_names_a_few() {
    let mut records = Vec::new();
    for k in 0..100_000u32 {
        records.extend(bag_connection(k, &format!("/imu/{k}")));
        records.extend(bag_message(k, 1, &imu_ros1(1, b"imu", 0.5)));
    }
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "topics.bag", &bag(&records));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    // No temperature anywhere: refused, the first few gyros named, the rest counted.
    ran.fails_with("and 99992 more", 2000);
    assert!(
        ran.stdout.contains("100000 gyro instance(s)"),
        "{}",
        &ran.stdout[..200]
    );
}

/// A bzip2 stream of `blocks` copies of one block of 45 000 000 zero bytes (a 3 KB stream
/// for 3.9 GB), made by compressing the block once and repeating its bits, with the stream's
/// combined CRC worked out as bzip2 does.
fn bz2_bomb(blocks: usize) -> Vec<u8> {
    use std::io::Write;
    let mut e = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::best());
    e.write_all(&vec![0u8; 45_000_000]).unwrap();
    let one = e.finish().unwrap();
    let bits: Vec<bool> = one
        .iter()
        .flat_map(|&b| (0..8).rev().map(move |i| b >> i & 1 == 1))
        .collect();
    let value = |at: usize, n: usize| -> u64 {
        bits[at..at + n]
            .iter()
            .fold(0u64, |v, &b| (v << 1) | u64::from(b))
    };
    assert_eq!(value(32, 48), 0x3141_5926_5359, "one block after BZh9");
    let eos = (0..8)
        .map(|pad| bits.len() - pad - 80)
        .find(|&at| value(at, 48) == 0x1772_4538_5090)
        .expect("the end-of-stream magic");
    let block_crc = value(80, 32) as u32;
    let mut out: Vec<bool> = bits[..32].to_vec();
    let mut combined = 0u32;
    for _ in 0..blocks {
        out.extend_from_slice(&bits[32..eos]);
        combined = combined.rotate_left(1) ^ block_crc;
    }
    out.extend((0..48).rev().map(|i| 0x1772_4538_5090u64 >> i & 1 == 1));
    out.extend((0..32).rev().map(|i| combined >> i & 1 == 1));
    out.chunks(8)
        .map(|c| {
            c.iter()
                .enumerate()
                .fold(0u8, |v, (i, &b)| v | (u8::from(b) << (7 - i)))
        })
        .collect()
}

#[test]
fn a_bz2_chunk_expanding_to_4_gb_is_refused_by_its_size() {
    let stream = bz2_bomb(87);
    assert!(stream.len() < 8000, "{} bytes", stream.len());
    let size = 87u32 * 45_000_000;
    let chunk = bag_record(
        &[
            bag_field("op", &[0x05]),
            bag_field("compression", b"bz2"),
            bag_field("size", &size.to_le_bytes()),
        ],
        &stream,
    );
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "bz2bomb.bag", &bag(&chunk));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        "bz2bomb.bag: ROS 1 bag log malformed at byte 13: the bz2 chunk declares 3915000000 \
         bytes",
        400,
    );
}

/// An lz4 chunk record (frame format, as `roslz4` writes it) holding `records`.
pub(super) fn bag_lz4_chunk(records: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = lz4_flex::frame::FrameEncoder::new(Vec::new());
    e.write_all(records).unwrap();
    let z = e.finish().unwrap();
    let size = u32::try_from(records.len()).unwrap();
    bag_record(
        &[
            bag_field("op", &[0x05]),
            bag_field("compression", b"lz4"),
            bag_field("size", &size.to_le_bytes()),
        ],
        &z,
    )
}

#[test]
fn lz4_chunks_of_millions_of_messages_on_a_second_topic_are_refused_within_the_limit() {
    // A gyro of 50 samples, then ten 150 MB chunks of one Imu message repeated on /other
    // (4.2 million in all, each chunk under the per-chunk cap, the whole about 200 times the
    // file, under the bomb limit): every sample of /other used to be kept, 1.7 GB.
    let mut records = bag_connection(0, "/imu/data");
    for k in 0..50 {
        records.extend(bag_message(0, k + 1, &imu_ros1(k + 1, b"imu", 0.01)));
    }
    let one = bag_message(5, 1, &imu_ros1(1, b"o", 0.0));
    let mut inner = bag_connection(5, "/other");
    while inner.len() + one.len() <= 150_000_000 {
        inner.extend_from_slice(&one);
    }
    let per_chunk = (inner.len() - bag_connection(5, "/other").len()) / one.len();
    let chunk = bag_lz4_chunk(&inner);
    for _ in 0..10 {
        records.extend_from_slice(&chunk);
    }
    assert!(per_chunk * 10 > 4_000_000, "{per_chunk} a chunk");
    let file = bag(&records);
    assert!(file.len() < 10_000_000, "{} bytes", file.len());
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "lz4_repeat.bag", &file);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        "lz4_repeat.bag: ROS 1 bag log not malformed, but larger than driftlab keeps: its Imu \
         and Temperature messages reach 256 MiB at byte ",
        1000,
    );
    ran.fails_with(", at a message on /other (the most kept is 256 MiB", 1000);
    // Its first chunk alone (1 million messages) reads, each topic whole.
    let first = bag(&records[..records.len() - 9 * chunk.len()]);
    let log = crafted(dir.path(), "lz4_one.bag", &first);
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    assert!(
        ran.stdout
            .contains(&format!("/other  frame_id o  {per_chunk} samples")),
        "{}\n{}",
        ran.stdout,
        ran.stderr
    );
    assert!(
        ran.stdout.contains("/imu/data  frame_id imu  50 samples"),
        "{}",
        ran.stdout
    );
}

// ---------------------------------------------------------------- MCAP

pub(super) fn mcap_record(op: u8, content: &[u8]) -> Vec<u8> {
    let mut r = vec![op];
    r.extend_from_slice(&(content.len() as u64).to_le_bytes());
    r.extend_from_slice(content);
    r
}

pub(super) fn mcap_string(s: &[u8]) -> Vec<u8> {
    let mut b = u32::try_from(s.len()).unwrap().to_le_bytes().to_vec();
    b.extend_from_slice(s);
    b
}

pub(super) fn mcap_schema(id: u16, name: &str) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(mcap_string(name.as_bytes()));
    c.extend(mcap_string(b"ros2msg"));
    c.extend(mcap_string(b""));
    mcap_record(0x03, &c)
}

pub(super) fn mcap_channel(id: u16, schema: u16, topic: &str) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend_from_slice(&schema.to_le_bytes());
    c.extend(mcap_string(topic.as_bytes()));
    c.extend(mcap_string(b"cdr"));
    c.extend_from_slice(&0u32.to_le_bytes());
    mcap_record(0x04, &c)
}

pub(super) fn mcap_message(channel: u16, log_time: u64, data: &[u8]) -> Vec<u8> {
    let mut c = channel.to_le_bytes().to_vec();
    c.extend_from_slice(&0u32.to_le_bytes());
    c.extend_from_slice(&log_time.to_le_bytes());
    c.extend_from_slice(&log_time.to_le_bytes());
    c.extend_from_slice(data);
    mcap_record(0x05, &c)
}

pub(super) fn mcap_chunk(compression: &str, size: u64, records: &[u8]) -> Vec<u8> {
    let mut c = 0u64.to_le_bytes().to_vec();
    c.extend_from_slice(&0u64.to_le_bytes());
    c.extend_from_slice(&size.to_le_bytes());
    c.extend_from_slice(&0u32.to_le_bytes());
    c.extend(mcap_string(compression.as_bytes()));
    c.extend_from_slice(&(records.len() as u64).to_le_bytes());
    c.extend_from_slice(records);
    mcap_record(0x06, &c)
}

pub(super) fn mcap(records: &[u8]) -> Vec<u8> {
    let mut b = b"\x89MCAP0\r\n".to_vec();
    b.extend_from_slice(records);
    b.extend(mcap_record(0x0F, &0u32.to_le_bytes()));
    b
}

#[test]
fn an_mcap_redefining_its_channel_before_each_of_200k_messages_reads_in_one_pass() {
    let mut records = mcap_schema(1, "sensor_msgs/msg/Imu");
    let data = imu_cdr(1, b"imu", 0.5);
    for k in 0..200_000u64 {
        records.extend(mcap_channel(1, 1, &format!("/imu/{k}")));
        records.extend(mcap_message(1, k, &data));
    }
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "channels.mcap", &mcap(&records));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with("and 199992 more", 2000);
}

/// A zstd frame of `blocks` RLE blocks of 128 KiB of zeros: 4 bytes for each 128 KiB.
fn zstd_bomb(blocks: usize) -> Vec<u8> {
    let mut f = vec![0x28, 0xB5, 0x2F, 0xFD, 0x00, 0x38];
    for k in 0..blocks {
        let last = u32::from(k + 1 == blocks);
        let header = (131_072u32 << 3) | (1 << 1) | last;
        f.extend_from_slice(&header.to_le_bytes()[..3]);
        f.push(0);
    }
    f
}

#[test]
fn a_zstd_chunk_expanding_to_3_gb_is_refused_by_its_size() {
    let blocks = 22_126;
    let size = blocks as u64 * 131_072;
    let frame = zstd_bomb(blocks);
    assert!(frame.len() < 92 * 1024);
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(
        dir.path(),
        "zstdbomb.mcap",
        &mcap(&mcap_chunk("zstd", size, &frame)),
    );
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["inspect", &log]);
    ran.fails_with(
        "zstdbomb.mcap: MCAP log malformed at byte 8: the zstd chunk declares 2900099072 bytes",
        400,
    );
}

#[test]
fn a_zstd_chunk_giving_more_than_it_declares_stops_there() {
    let frame = zstd_bomb(22_126);
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(
        dir.path(),
        "zstdliar.mcap",
        &mcap(&mcap_chunk("zstd", 1000, &frame)),
    );
    let ran = driftlab_within(dir.path(), 256, &["inspect", &log]);
    ran.fails_with("decompresses to 1001+ bytes but declares 1000", 400);
}

#[test]
fn megabyte_frame_ids_are_neither_kept_per_message_nor_quoted_whole() {
    // 48 zstd chunks of 16 Imu messages, each with a frame_id of 1 MiB: 768 MiB of frame_ids
    // if every message kept its own.
    let frame = vec![b'f'; 1 << 20];
    let mut inner = mcap_schema(1, "sensor_msgs/msg/Imu");
    inner.extend(mcap_channel(1, 1, "/imu"));
    for k in 0..16 {
        inner.extend(mcap_message(1, k, &imu_cdr(k as i32, &frame, 0.5)));
    }
    let chunk = mcap_chunk(
        "zstd",
        inner.len() as u64,
        &zstd::bulk::compress(&inner, 1).unwrap(),
    );
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "frames.mcap", &mcap(&chunk.repeat(48)));
    let ran = driftlab_within(dir.path(), 512, &["inspect", &log]);
    // No temperature: refused, the frame_id quoted by its start and length.
    ran.fails_with("(1048576 bytes", 1000);
}

#[test]
fn huge_frame_ids_on_several_topics_are_kept_short() {
    // Four topics, each one Imu message in a zstd chunk of its own with a 96-MiB frame_id: a
    // topic kept its frame whole, 384 MiB for the four beside the chunk being read (a 1.9-KB
    // bag of bz2 chunks took 1.96 GB this way and aborted under a limit).
    let frame = vec![b'f'; 96 << 20];
    let mut file = Vec::new();
    for k in 0..4u16 {
        let mut inner = mcap_schema(1, "sensor_msgs/msg/Imu");
        inner.extend(mcap_channel(k + 1, 1, &format!("/imu{k}")));
        inner.extend(mcap_message(k + 1, u64::from(k), &imu_cdr(1, &frame, 0.5)));
        file.extend(mcap_chunk(
            "zstd",
            inner.len() as u64,
            &zstd::bulk::compress(&inner, 1).unwrap(),
        ));
    }
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "bigframes.mcap", &mcap(&file));
    let ran = driftlab_within(dir.path(), 448, &["inspect", &log]);
    // No temperature: refused, the frame_id named by its start, length and hash.
    ran.fails_with("(100663296 bytes", 1000);
}

// ---------------------------------------------------------------- DataFlash

/// A DataFlash message `A3 95 type payload`.
fn df_message(ty: u8, payload: &[u8]) -> Vec<u8> {
    let mut m = vec![0xA3, 0x95, ty];
    m.extend_from_slice(payload);
    m
}

/// The FMT of type `ty`: its length, name, format and labels in their fixed widths.
fn df_fmt(ty: u8, length: u8, name: &str, format: &str, labels: &str) -> Vec<u8> {
    let fixed = |s: &str, n: usize| {
        let mut v = s.as_bytes().to_vec();
        v.resize(n, 0);
        v
    };
    let mut p = vec![ty, length];
    p.extend(fixed(name, 4));
    p.extend(fixed(format, 16));
    p.extend(fixed(labels, 64));
    df_message(0x80, &p)
}

/// A DataFlash log of 50 IMU messages (54 bytes each) whose FMT gives `imu_length`.
fn dataflash(imu_length: u8) -> Vec<u8> {
    let mut b = df_fmt(0x80, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
    b.extend(df_fmt(
        163,
        imu_length,
        "IMU",
        "QBffffffIIfBBHH",
        "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz",
    ));
    for k in 0..50u64 {
        let mut p = (1_000_000 * (k + 1)).to_le_bytes().to_vec();
        p.push(0);
        for v in [0.01f32, 0.0, 0.0, 0.0, 0.0, -9.8] {
            p.extend_from_slice(&v.to_le_bytes());
        }
        p.extend_from_slice(&[0; 8]);
        p.extend_from_slice(&(20.0 + 0.05 * k as f32).to_le_bytes());
        p.extend_from_slice(&[1, 1, 0xE8, 0x03, 0xE8, 0x03]);
        b.extend(df_message(163, &p));
    }
    b
}

#[test]
fn a_dataflash_fmt_longer_than_its_format_is_malformed_not_a_fifth_of_the_samples() {
    let dir = tempfile::tempdir().unwrap();
    // The same log with the right length converts whole: 50 rows and a header.
    let log = crafted(dir.path(), "imu_len_right.bin", &dataflash(54));
    let csv = dir.path().join("right.csv").display().to_string();
    driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &csv]).succeeds();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(
        text.lines().filter(|l| !l.starts_with('#')).count(),
        51,
        "{text}"
    );
    // 255 bytes for a 54-byte message: each would swallow the next four.
    let log = crafted(dir.path(), "imu_len_big.bin", &dataflash(255));
    let csv = dir.path().join("big.csv").display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &csv]);
    ran.fails_with(
        "imu_len_big.bin: ArduPilot DataFlash log malformed at byte 89: the FMT of message \
         type IMU (163) gives a length of 255 bytes, but its format \"QBffffffIIfBBHH\" \
         makes 54",
        400,
    );
    // And shorter than its format: refused the same way.
    let log = crafted(dir.path(), "imu_len_small.bin", &dataflash(40));
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &csv]);
    ran.fails_with("gives a length of 40 bytes, but its format", 400);
}
