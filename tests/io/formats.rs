//! Drone and robot logs against independent readers: every sample in
//! `../shared/data/formats/` (real PX4, ArduPilot and ROS recordings) read by driftlab and
//! compared, sample for sample, with the CSVs pyulog 1.3.0, pymavlink 2.4.50, rosbags 0.11.9
//! and Foxglove's mcap wrote of the same file: integer time stamps exactly, float32 values
//! bit for bit, float64 values bit for bit, NaN as NaN.
//!
//! The samples are not copied into the repository (several are GPL): the tests read them by
//! path. Without them a test fails when `CI` is set and otherwise says it skips.

use crate::common::drone::{DATAFLASH, ULOG, data_dir};
use driftlab::log::formats::{
    self, DeviceId, Format, FormatError, GyroInstance, ImuRecording, TempFrom, Timestamps, Values,
};
use std::collections::HashMap;
use std::path::Path;

const BAG: &str = "ros1_bag/sparkfun_razor.bag";
const MCAP: &str = "ros2_mcap/sparkfun_razor_ros2.mcap";

/// A reference CSV as rows of named cells.
struct Table {
    rows: Vec<HashMap<String, String>>,
}

impl Table {
    fn read(path: &Path) -> Table {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .unwrap()
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .filter(|l| !l.is_empty())
            .map(|l| {
                header
                    .iter()
                    .cloned()
                    .zip(l.split(',').map(str::to_string))
                    .collect()
            })
            .collect();
        Table { rows }
    }

    fn filter(&self, col: &str, value: &str) -> Vec<&HashMap<String, String>> {
        self.rows.iter().filter(|r| r[col] == value).collect()
    }
}

fn f32_of(s: &str) -> f32 {
    if s == "nan" {
        f32::NAN
    } else {
        s.parse().unwrap()
    }
}

fn f64_of(s: &str) -> f64 {
    if s == "nan" {
        f64::NAN
    } else {
        s.parse().unwrap()
    }
}

/// Same number or both NaN, bit for bit otherwise.
fn same_f32(a: f32, b: f32) -> bool {
    (a.is_nan() && b.is_nan()) || a.to_bits() == b.to_bits()
}

fn same_f64(a: f64, b: f64) -> bool {
    (a.is_nan() && b.is_nan()) || a.to_bits() == b.to_bits()
}

/// Compares one channel with a reference column in the channel's own precision.
fn check_values(what: &str, v: &Values, rows: &[&HashMap<String, String>], col: &str) {
    assert_eq!(v.len(), rows.len(), "{what}: sample count");
    for (i, r) in rows.iter().enumerate() {
        match v {
            Values::F32(x) => assert!(
                same_f32(x[i], f32_of(&r[col])),
                "{what} sample {i}: {} read, {} in the reference",
                x[i],
                r[col]
            ),
            Values::F64(x) => assert!(
                same_f64(x[i], f64_of(&r[col])),
                "{what} sample {i}: {} read, {} in the reference",
                x[i],
                r[col]
            ),
        }
    }
}

fn check_micros(what: &str, inst: &GyroInstance, rows: &[&HashMap<String, String>], col: &str) {
    let Timestamps::Micros(t) = &inst.time else {
        panic!("{what}: expected microsecond stamps");
    };
    assert_eq!(t.len(), rows.len(), "{what}: sample count");
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(t[i], r[col].parse::<u64>().unwrap(), "{what}: stamp {i}");
        assert!(
            same_f64(inst.time.seconds(i), f64_of(&r["time_s"])),
            "{what}: time_s {i}"
        );
    }
}

fn read(dir: &Path, rel: &str) -> ImuRecording {
    formats::read_path(&dir.join(rel)).unwrap_or_else(|e| panic!("{e}"))
}

fn reference(dir: &Path, rel: &str, kind: &str) -> Table {
    let stem = rel.rsplit_once('.').unwrap().0;
    Table::read(&dir.join(format!("{stem}.{kind}.csv")))
}

#[test]
fn ulog_matches_pyulog() {
    let Some(dir) = data_dir() else { return };
    let rec = read(&dir, ULOG);
    assert_eq!(rec.format, Format::Ulog);
    let gyro = reference(&dir, ULOG, "gyro");
    let accel = reference(&dir, ULOG, "accel");
    // Three sensor_gyro instances, then sensor_combined.
    assert_eq!(rec.instances.len(), 4, "{:?}", rec.summaries());
    let ids = [2424842u32, 3670050, 2621474];
    for (m, &id) in ids.iter().enumerate() {
        let inst = &rec.instances[m];
        let what = format!("sensor_gyro multi_id {m}");
        assert_eq!(inst.device, Some(DeviceId::Ulog { device_id: id }));
        let rows = gyro.filter("multi_id", &m.to_string());
        assert_eq!(rows.len(), 6);
        check_micros(&what, inst, &rows, "timestamp_us");
        let sample = inst.time_sample_us.as_ref().unwrap();
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(sample[i], r["timestamp_sample_us"].parse::<u64>().unwrap());
            assert_eq!(r["device_id"], id.to_string());
        }
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            check_values(
                &what,
                &inst.gyro.xyz[k],
                &rows,
                &format!("gyro_{axis}_rad_s"),
            );
        }
        check_values(&what, &inst.temp_c, &rows, "temp_c");
        // The accelerometer of the same device, one sample beside each gyro sample.
        let arows = accel.filter("multi_id", &m.to_string());
        let a = inst.accel.as_ref().unwrap();
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            check_values(&what, &a.xyz[k], &arows, &format!("accel_{axis}_m_s2"));
        }
        let at = inst.alt_temp(TempFrom::Accel).unwrap();
        check_values(&what, &at.values, &arows, "temp_c");
        // This firmware's vehicle_imu_status has no temperature fields.
        assert!(inst.alt_temp(TempFrom::ImuStatus).is_none());
    }
    // The fused primary IMU at 200 Hz, no temperature.
    let comb = reference(&dir, ULOG, "sensor_combined");
    let rows: Vec<_> = comb.rows.iter().collect();
    let inst = &rec.instances[3];
    assert_eq!(rows.len(), 1298);
    check_micros("sensor_combined", inst, &rows, "timestamp");
    for k in 0..3 {
        check_values(
            "sensor_combined",
            &inst.gyro.xyz[k],
            &rows,
            &format!("gyro_rad[{k}]"),
        );
        check_values(
            "sensor_combined",
            &inst.accel.as_ref().unwrap().xyz[k],
            &rows,
            &format!("accelerometer_m_s2[{k}]"),
        );
    }
    assert!(!inst.temp_c.has_numbers());
    // Summaries: rates, counts and temperature ranges as the data README gives them.
    let s = rec.summaries();
    assert_eq!(s[0].samples, 6);
    let r = s[0].temp_range_c.unwrap();
    assert!(
        (r.0 - 40.03).abs() < 0.01 && (r.1 - 40.36).abs() < 0.01,
        "{r:?}"
    );
    assert!((s[0].rate_hz.unwrap() - 1.0).abs() < 0.01);
    assert!((s[3].rate_hz.unwrap() - 1.0 / 0.004888).abs() < 1.0);
    assert_eq!(s[3].temp_range_c, None);
    let line = s[0].line();
    for part in [
        "gyro 0  sensor_gyro multi_id 0  device_id 2424842 (0x25000A)",
        "6 samples at 1.000 Hz",
        "temperature 40.03 .. 40.36 degC",
        "temp_from accel: sensor_accel[0].temperature",
    ] {
        assert!(line.contains(part), "{line}");
    }
    assert!(s[3].line().contains("temperature n/a"), "{}", s[3].line());
    // The 30 ms dropout is reported.
    assert!(
        rec.problems.iter().any(|p| p.message.contains("30 ms")),
        "{:?}",
        rec.problems
    );
}

#[test]
fn dataflash_matches_pymavlink_and_reports_the_cut() {
    let Some(dir) = data_dir() else { return };
    let rec = read(&dir, DATAFLASH);
    assert_eq!(rec.format, Format::DataFlash);
    let gyro = reference(&dir, DATAFLASH, "gyro");
    let accel = reference(&dir, DATAFLASH, "accel");
    assert_eq!(rec.instances.len(), 2);
    for (n, inst) in rec.instances.iter().enumerate() {
        let what = format!("IMU I={n}");
        assert_eq!(inst.label, "IMU");
        assert_eq!(inst.device, Some(DeviceId::DataFlash { instance: n as u8 }));
        let rows = gyro.filter("instance", &n.to_string());
        assert_eq!(rows.len(), 10);
        check_micros(&what, inst, &rows, "time_us");
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            check_values(
                &what,
                &inst.gyro.xyz[k],
                &rows,
                &format!("gyro_{axis}_rad_s"),
            );
        }
        check_values(&what, &inst.temp_c, &rows, "temp_c");
        let arows = accel.filter("instance", &n.to_string());
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            check_values(
                &what,
                &inst.accel.as_ref().unwrap().xyz[k],
                &arows,
                &format!("accel_{axis}_m_s2"),
            );
        }
    }
    assert_eq!(rec.instances[1].temp_c.range(), Some((28.5, 28.5)));
    // The last two bytes (a3 95) start a message the file cuts.
    let len = std::fs::metadata(dir.join(DATAFLASH)).unwrap().len();
    let cut: Vec<_> = rec
        .problems
        .iter()
        .filter(|p| p.message.contains("cut"))
        .collect();
    assert_eq!(cut.len(), 1, "{:?}", rec.problems);
    assert_eq!(cut[0].offset, Some(len - 2));
    assert_eq!(rec.problems.len(), 1, "{:?}", rec.problems);
}

fn check_ros(dir: &Path, rec: &ImuRecording, rel: &str, log_col: &str) {
    let gyro = reference(dir, rel, "gyro");
    let accel = reference(dir, rel, "accel");
    assert_eq!(rec.instances.len(), 1, "{:?}", rec.summaries());
    let inst = &rec.instances[0];
    assert_eq!(
        inst.device,
        Some(DeviceId::Ros {
            topic: "/imu/data_raw".into(),
            frame_id: "/imu".into()
        })
    );
    let rows: Vec<_> = gyro.rows.iter().collect();
    assert_eq!(inst.len(), 2144);
    assert_eq!(rows.len(), 2144);
    let log = inst.log_time_ns.as_ref().unwrap();
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(
            inst.time.nanos(i),
            r["header_stamp_ns"].parse::<i128>().unwrap(),
            "stamp {i}"
        );
        assert_eq!(log[i], r[log_col].parse::<u64>().unwrap(), "log time {i}");
        assert!(
            same_f64(inst.time.seconds(i), f64_of(&r["time_s"])),
            "time_s {i}"
        );
        assert_eq!(r["topic"], "/imu/data_raw");
        assert_eq!(r["frame_id"], "/imu");
    }
    let arows: Vec<_> = accel.rows.iter().collect();
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        assert!(matches!(inst.gyro.xyz[k], Values::F64(_)));
        check_values(rel, &inst.gyro.xyz[k], &rows, &format!("gyro_{axis}_rad_s"));
        check_values(
            rel,
            &inst.accel.as_ref().unwrap().xyz[k],
            &arows,
            &format!("accel_{axis}_m_s2"),
        );
    }
    assert!(!inst.temp_c.has_numbers());
    let rate = inst.rate_hz().unwrap();
    assert!((60.0..80.0).contains(&rate), "{rate}");
}

#[test]
fn ros1_bag_matches_rosbags() {
    let Some(dir) = data_dir() else { return };
    let rec = read(&dir, BAG);
    assert_eq!(rec.format, Format::RosBag);
    check_ros(&dir, &rec, BAG, "bag_time_ns");
    assert!(rec.problems.is_empty(), "{:?}", rec.problems);
}

#[test]
fn mcap_matches_foxglove_mcap() {
    let Some(dir) = data_dir() else { return };
    let rec = read(&dir, MCAP);
    assert_eq!(rec.format, Format::Mcap);
    check_ros(&dir, &rec, MCAP, "log_time_ns");
    assert!(rec.problems.is_empty(), "{:?}", rec.problems);
}

/// The bag's bz2 chunks rewritten as lz4 (frame format, as roslz4 writes) or uncompressed;
/// the index is left stale, which a front-to-back reader does not use.
fn recompress_bag(bytes: &[u8], to: &str) -> Vec<u8> {
    use std::io::Read;
    let u32_at = |b: &[u8], i: usize| u32::from_le_bytes(b[i..i + 4].try_into().unwrap()) as usize;
    let mut out = bytes[..13].to_vec();
    let mut pos = 13;
    let mut chunks = 0;
    while pos < bytes.len() {
        let hlen = u32_at(bytes, pos);
        let header = &bytes[pos + 4..pos + 4 + hlen];
        let dpos = pos + 4 + hlen;
        let dlen = u32_at(bytes, dpos);
        let data = &bytes[dpos + 4..dpos + 4 + dlen];
        pos = dpos + 4 + dlen;
        // Header fields, rewritten where they say the compression.
        let mut fields = Vec::new();
        let mut h = 0;
        let mut is_chunk = false;
        while h < header.len() {
            let n = u32_at(header, h);
            let f = header[h + 4..h + 4 + n].to_vec();
            if f == b"op=\x05" {
                is_chunk = true;
            }
            fields.push(f);
            h += 4 + n;
        }
        let mut data = data.to_vec();
        if is_chunk {
            chunks += 1;
            let mut plain = Vec::new();
            bzip2::read::BzDecoder::new(&data[..])
                .read_to_end(&mut plain)
                .unwrap();
            data = match to {
                "lz4" => {
                    let mut e = lz4_flex::frame::FrameEncoder::new(Vec::new());
                    std::io::Write::write_all(&mut e, &plain).unwrap();
                    e.finish().unwrap()
                }
                _ => plain,
            };
            for f in &mut fields {
                if f.starts_with(b"compression=") {
                    *f = format!("compression={to}").into_bytes();
                }
            }
        }
        let header: Vec<u8> = fields
            .iter()
            .flat_map(|f| {
                let mut v = (f.len() as u32).to_le_bytes().to_vec();
                v.extend_from_slice(f);
                v
            })
            .collect();
        out.extend_from_slice(&(header.len() as u32).to_le_bytes());
        out.extend_from_slice(&header);
        out.extend_from_slice(&(data.len() as u32).to_le_bytes());
        out.extend_from_slice(&data);
    }
    assert_eq!(chunks, 2);
    out
}

#[test]
fn ros1_bag_reads_lz4_and_uncompressed_chunks() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join(BAG)).unwrap();
    for to in ["lz4", "none"] {
        let b = recompress_bag(&bytes, to);
        assert_ne!(b, bytes);
        let rec = formats::read_bytes(&format!("sparkfun_razor.{to}.bag"), &b)
            .unwrap_or_else(|e| panic!("{to}: {e}"));
        check_ros(&dir, &rec, BAG, "bag_time_ns");
    }
}

#[test]
fn formats_are_sniffed_by_their_bytes_not_their_names() {
    let Some(dir) = data_dir() else { return };
    let tmp = tempfile::tempdir().unwrap();
    for (rel, format) in [
        (ULOG, Format::Ulog),
        (DATAFLASH, Format::DataFlash),
        (BAG, Format::RosBag),
        (MCAP, Format::Mcap),
    ] {
        let renamed = tmp.path().join("recording.dat");
        std::fs::copy(dir.join(rel), &renamed).unwrap();
        assert_eq!(formats::sniff_path(&renamed).unwrap(), Some(format));
        let rec = formats::read_path(&renamed).unwrap();
        assert_eq!(rec.format, format);
        assert!(!rec.instances.is_empty());
    }
    // A CSV is none of them, and says so.
    let csv = tmp.path().join("log.ulg");
    std::fs::write(&csv, "time_s,omega_dph,temp_c\n0,1,2\n").unwrap();
    assert_eq!(formats::sniff_path(&csv).unwrap(), None);
    let e = formats::read_path(&csv).unwrap_err();
    assert!(matches!(e, FormatError::Unrecognised { .. }), "{e}");
    assert!(e.to_string().contains("log.ulg"), "{e}");
}

/// Reads `bytes` and checks that the outcome is a recording or a located error, never a
/// panic (a panic fails the test by itself).
fn must_not_panic(name: &str, bytes: &[u8]) -> Result<ImuRecording, FormatError> {
    let r = formats::read_bytes(name, bytes);
    if let Err(e) = &r {
        assert!(e.to_string().contains(name), "{e}");
        if let Some(o) = e.offset() {
            assert!(o <= bytes.len() as u64, "{e}: offset past the end");
        }
        match e {
            FormatError::Malformed { .. }
            | FormatError::TooLargeToKeep { .. }
            | FormatError::NoGyro { .. }
            | FormatError::Unrecognised { .. } => {}
            FormatError::Io { .. } => panic!("{e}"),
        }
    }
    r
}

#[test]
fn cut_and_mutated_samples_give_located_errors_or_problems_never_a_panic() {
    let Some(dir) = data_dir() else { return };
    let iters: usize = std::env::var("DRIFTLAB_FUZZ_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(150);
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for rel in [ULOG, DATAFLASH, BAG, MCAP] {
        let bytes = std::fs::read(dir.join(rel)).unwrap();
        let name = rel.rsplit('/').next().unwrap();
        let mut outcomes = [0usize; 2];
        // Cut anywhere: the whole messages before the cut are kept or the error is located.
        for k in 0..iters {
            let cut = bytes.len() * k / iters;
            outcomes[must_not_panic(name, &bytes[..cut]).is_ok() as usize] += 1;
        }
        // A few bytes changed anywhere, lengths and headers included.
        for _ in 0..iters {
            let mut b = bytes.clone();
            for _ in 0..1 + rnd() % 4 {
                let i = (rnd() % b.len() as u64) as usize;
                b[i] = rnd() as u8;
            }
            outcomes[must_not_panic(name, &b).is_ok() as usize] += 1;
        }
        eprintln!(
            "{name}: {} read, {} refused with a located error",
            outcomes[1], outcomes[0]
        );
    }
}

#[test]
fn a_cut_ulog_keeps_its_whole_messages_and_says_where() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join(ULOG)).unwrap();
    let whole = formats::read_bytes("whole.ulg", &bytes).unwrap();
    let cut = bytes.len() - 1;
    let rec = formats::read_bytes("cut.ulg", &bytes[..cut]).unwrap();
    let p = rec
        .problems
        .iter()
        .find(|p| p.message.contains("cut"))
        .expect("the cut is reported");
    assert!(p.offset.unwrap() < cut as u64);
    // The last message was not a gyro sample: nothing is lost (compared as text, where a
    // NaN equals itself).
    assert_eq!(
        format!("{:?}", rec.instances),
        format!("{:?}", whole.instances)
    );
    // A cut inside the definitions is an error at an offset.
    let e = formats::read_bytes("head.ulg", &bytes[..10]).unwrap_err();
    assert_eq!(e.offset(), Some(7), "{e}");
}

#[test]
fn selection_defaults_to_the_first_gyro_with_a_temperature_and_names_alternatives() {
    let Some(dir) = data_dir() else { return };
    let rec = read(&dir, ULOG);
    let s = formats::select(&rec, None, None).unwrap();
    assert_eq!(s.instance.index, 0);
    assert_eq!(s.temp_from, TempFrom::Own);
    assert!(
        s.note.contains("gyro 0") && s.note.contains("first"),
        "{}",
        s.note
    );
    // sensor_combined has no temperature: refused, with the alternatives named.
    let e = formats::select(&rec, Some(3), None).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("no temperature of its own"), "{text}");
    assert!(text.contains("temp_from none"), "{text}");
    // The accelerometer's temperature only when asked.
    let s = formats::select(&rec, Some(1), Some(TempFrom::Accel)).unwrap();
    assert_eq!(
        s.temp_c,
        s.instance.alt_temp(TempFrom::Accel).unwrap().values
    );
    assert!(s.note.contains("sensor_accel[1].temperature"), "{}", s.note);
    let e = formats::select(&rec, Some(0), Some(TempFrom::ImuStatus)).unwrap_err();
    assert!(e.to_string().contains("temp_from accel"), "{e}");
    let e = formats::select(&rec, Some(9), None).unwrap_err();
    assert!(e.to_string().contains("no gyro 9"), "{e}");
    // A ROS log without a Temperature topic: refused unless none is asked for.
    let bag = read(&dir, BAG);
    let e = formats::select(&bag, None, None).unwrap_err();
    assert!(e.to_string().contains("no gyro in the log"), "{e}");
    let s = formats::select(&bag, None, Some(TempFrom::None)).unwrap();
    let c = s.columns();
    assert_eq!(c.time_s.len(), 2144);
    assert!(c.temp_c.iter().all(|t| t.is_nan()));
    assert!(c.accel_m_s2.is_some());
}

/// Parses the converted CSV: header and rows of cells.
fn parse_csv(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

#[test]
fn converted_csvs_hold_the_stored_values_exactly() {
    let Some(dir) = data_dir() else { return };
    for (rel, gyro_col, stamp_col, filter) in [
        (ULOG, "multi_id", "timestamp_us", "0"),
        (DATAFLASH, "instance", "time_us", "0"),
        (BAG, "topic", "header_stamp_ns", "/imu/data_raw"),
        (MCAP, "topic", "header_stamp_ns", "/imu/data_raw"),
    ] {
        let rec = read(&dir, rel);
        let temp =
            (rec.format == Format::RosBag || rec.format == Format::Mcap).then_some(TempFrom::None);
        let s = formats::select(&rec, None, temp).unwrap();
        let mut out = Vec::new();
        // Every stored sample, in the order stored: the writer against the reference.
        let every: Vec<usize> = (0..s.instance.len()).collect();
        formats::write_csv(&s, &every, &mut out).unwrap();
        let (header, rows) = parse_csv(std::str::from_utf8(&out).unwrap());
        assert_eq!(
            header.join(","),
            "time_s,gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s,temp_c,\
             accel_x_m_s2,accel_y_m_s2,accel_z_m_s2"
        );
        let g = reference(&dir, rel, "gyro");
        let a = reference(&dir, rel, "accel");
        let grows = g.filter(gyro_col, filter);
        let arows = a.filter(gyro_col, filter);
        assert_eq!(rows.len(), grows.len(), "{rel}");
        let f32_file = matches!(rec.format, Format::Ulog | Format::DataFlash);
        for (i, row) in rows.iter().enumerate() {
            assert!(
                same_f64(f64_of(&row[0]), f64_of(&grows[i]["time_s"])),
                "{rel} {i}"
            );
            let _ = stamp_col;
            let cells = [
                (&row[1], grows[i]["gyro_x_rad_s"].as_str()),
                (&row[2], grows[i]["gyro_y_rad_s"].as_str()),
                (&row[3], grows[i]["gyro_z_rad_s"].as_str()),
                (&row[5], arows[i]["accel_x_m_s2"].as_str()),
                (&row[6], arows[i]["accel_y_m_s2"].as_str()),
                (&row[7], arows[i]["accel_z_m_s2"].as_str()),
            ];
            for (mine, theirs) in cells {
                if f32_file {
                    assert!(
                        same_f32(f32_of(mine), f32_of(theirs)),
                        "{rel} {i}: {mine} {theirs}"
                    );
                } else {
                    assert!(
                        same_f64(f64_of(mine), f64_of(theirs)),
                        "{rel} {i}: {mine} {theirs}"
                    );
                }
            }
            if f32_file {
                assert!(same_f32(f32_of(&row[4]), f32_of(&grows[i]["temp_c"])));
            } else {
                assert_eq!(row[4], "nan");
            }
        }
    }
}

#[test]
fn convert_writes_a_csv_driftlab_reads_back_with_no_options() {
    let Some(dir) = data_dir() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let exe = env!("CARGO_BIN_EXE_driftlab");
    for (rel, args, rows) in [
        (ULOG, vec![], 6usize),
        (ULOG, vec!["--gyro", "2"], 6),
        (DATAFLASH, vec!["--gyro", "1"], 10),
    ] {
        let out = tmp.path().join("converted.csv");
        let o = std::process::Command::new(exe)
            .arg("convert")
            .arg(dir.join(rel))
            .arg("--out")
            .arg(&out)
            .args(&args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{rel} {args:?}: {stderr}");
        assert!(stderr.contains("chosen"), "{stderr}");
        let log = driftlab::log::ingest::read_path(&out, &Default::default())
            .unwrap_or_else(|e| panic!("{rel}: {e}"));
        assert_eq!(log.len(), rows, "{rel}");
        // Gyro read in rad/s (converted to deg/h by the reader), temperature in degC.
        let rec = read(&dir, rel);
        let n: usize = args.get(1).map_or(0, |s| s.parse().unwrap());
        let inst = &rec.instances[n];
        for i in 0..rows {
            let want = inst.gyro.xyz[0].get(i).to_degrees() * 3600.0;
            // Read in rad/s: the shortest float32 text is within float32 precision.
            assert!(
                (log.omega_dph[i] - want).abs() <= 1e-7 * want.abs(),
                "{rel} {i}: {} deg/h read, {want} stored",
                log.omega_dph[i]
            );
            // The float32 text read as float64 narrows back to the stored float32.
            assert_eq!(log.temp_c[i] as f32, inst.temp_c.get(i) as f32);
            assert_eq!(log.time_s[i], inst.time.seconds(i));
        }
    }
    // A gyro without a temperature is refused with the alternatives, and nothing is written.
    let out = tmp.path().join("refused.csv");
    let o = std::process::Command::new(exe)
        .arg("convert")
        .arg(dir.join(ULOG))
        .arg("--out")
        .arg(&out)
        .args(["--gyro", "3"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--temp-from"));
    assert!(!out.exists());
}

/// The MCAP's zstd chunks rewritten as lz4 (frame format) or uncompressed, each given the CRC
/// of its decompressed records (the sample's writer leaves it 0, "not computed"); the
/// summary's offsets go stale, which a front-to-back reader does not use.
fn recompress_mcap(bytes: &[u8], to: &str) -> Vec<u8> {
    use std::io::Write;
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap()) as usize;
    let mut out = bytes[..8].to_vec();
    let mut pos = 8;
    let mut chunks = 0;
    while pos + 9 <= bytes.len() {
        let op = bytes[pos];
        let len = u64_at(pos + 1);
        let content = &bytes[pos + 9..pos + 9 + len];
        pos += 9 + len;
        if op != 0x06 {
            out.push(op);
            out.extend_from_slice(&(len as u64).to_le_bytes());
            out.extend_from_slice(content);
            continue;
        }
        chunks += 1;
        let fixed = &content[..28]; // start, end, uncompressed size, crc
        let clen = u32::from_le_bytes(content[28..32].try_into().unwrap()) as usize;
        assert_eq!(&content[32..32 + clen], b"zstd");
        let at = 32 + clen;
        let rlen = u64::from_le_bytes(content[at..at + 8].try_into().unwrap()) as usize;
        let plain = zstd::decode_all(&content[at + 8..at + 8 + rlen]).unwrap();
        let crc = crc32fast::hash(&plain);
        let (name, records): (&[u8], Vec<u8>) = match to {
            "lz4" => {
                let mut e = lz4_flex::frame::FrameEncoder::new(Vec::new());
                e.write_all(&plain).unwrap();
                (b"lz4", e.finish().unwrap())
            }
            _ => (b"", plain),
        };
        let mut c = fixed.to_vec();
        c[24..28].copy_from_slice(&crc.to_le_bytes());
        c.extend_from_slice(&(name.len() as u32).to_le_bytes());
        c.extend_from_slice(name);
        c.extend_from_slice(&(records.len() as u64).to_le_bytes());
        c.extend_from_slice(&records);
        out.push(op);
        out.extend_from_slice(&(c.len() as u64).to_le_bytes());
        out.extend_from_slice(&c);
    }
    out.extend_from_slice(&bytes[pos..]);
    assert_eq!(chunks, 2);
    out
}

#[test]
fn mcap_reads_lz4_and_uncompressed_chunks_and_checks_their_crc() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join(MCAP)).unwrap();
    for to in ["lz4", "none"] {
        let b = recompress_mcap(&bytes, to);
        let rec = formats::read_bytes(&format!("razor.{to}.mcap"), &b)
            .unwrap_or_else(|e| panic!("{to}: {e}"));
        check_ros(&dir, &rec, MCAP, "log_time_ns");
        // A flipped bit inside an uncompressed chunk's records is caught by its CRC.
        if to == "none" {
            let mut bad = b.clone();
            let i = bad.len() / 4;
            bad[i] ^= 0x10;
            let e = formats::read_bytes("flipped.mcap", &bad).unwrap_err();
            assert!(e.to_string().contains("CRC"), "{e}");
            assert!(e.offset().unwrap() < i as u64, "{e}");
        }
    }
}

#[test]
fn garbage_inside_a_dataflash_log_is_skipped_and_reported() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join(DATAFLASH)).unwrap();
    let whole = formats::read_bytes("whole.bin", &bytes).unwrap();
    // 37 bytes of noise between two messages, just before the first IMU message.
    let first_imu = (0..bytes.len() - 3)
        .find(|&i| {
            bytes[i] == 0xA3
                && bytes[i + 1] == 0x95
                && formats::read_bytes("x.bin", &bytes[..i])
                    .map(|r| r.instances.is_empty())
                    .unwrap_or(true)
                && formats::read_bytes("y.bin", &bytes[..i + 200])
                    .is_ok_and(|r| !r.instances.is_empty())
        })
        .unwrap();
    let mut b = bytes[..first_imu].to_vec();
    b.extend((0..37u8).map(|k| k.wrapping_mul(7)));
    b.extend_from_slice(&bytes[first_imu..]);
    let rec = formats::read_bytes("noisy.bin", &b).unwrap();
    assert_eq!(
        format!("{:?}", rec.instances),
        format!("{:?}", whole.instances)
    );
    let p = rec
        .problems
        .iter()
        .find(|p| p.message.contains("skipped"))
        .expect("the skipped bytes are reported");
    assert_eq!(p.offset, Some(first_imu as u64));
    assert!(p.message.starts_with("37 byte(s)"), "{}", p.message);
}

/// An ArduPilot DataFlash log whose IMU messages give an instance over 255 (a two-byte `I`
/// field): those messages name no IMU and are skipped and told, never folded onto instance 0.
#[test]
fn a_dataflash_instance_over_a_byte_is_skipped_and_told() {
    fn fmt(ty: u8, length: u8, name: &str, form: &str, labels: &str) -> Vec<u8> {
        let mut b = vec![0xA3, 0x95, 0x80, ty, length];
        let field = |s: &str, n: usize| {
            let mut v = s.as_bytes().to_vec();
            v.resize(n, 0);
            v
        };
        b.extend(field(name, 4));
        b.extend(field(form, 16));
        b.extend(field(labels, 64));
        b
    }
    let mut b = fmt(0x80, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
    b.extend(fmt(
        0x82,
        3 + 8 + 2 + 4 * 7,
        "IMU",
        "QHfffffff",
        "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,T",
    ));
    for k in 0..400u64 {
        for (inst, w) in [(0u16, 0.001f32), (256, 0.5)] {
            b.extend([0xA3, 0x95, 0x82]);
            b.extend((100_000_000 + k * 1_000_000).to_le_bytes());
            b.extend(inst.to_le_bytes());
            for v in [w, w, w, 0.0, 0.0, 9.8, 25.0] {
                b.extend(v.to_le_bytes());
            }
        }
    }
    let rec = formats::read_bytes("wide.bin", &b).unwrap();
    assert_eq!(rec.instances.len(), 1, "{:?}", rec.instances);
    let p = rec
        .problems
        .iter()
        .find(|p| p.message.contains("instance number over 255"))
        .expect("the skipped messages are told");
    assert!(p.message.starts_with("400 IMU messages"), "{}", p.message);
}
