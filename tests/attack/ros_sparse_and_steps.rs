//! A ROS gyro's time and temperature where its Imu stamps step mid-bag (back or forward, or
//! away for a block and back) and where its Temperature topic is sparse. Every message of both
//! topics is recorded the second it was taken, one record clock throughout, and the true
//! temperature is known: 20 + 20 sin(t/800) °C, a chamber swinging 40 °C over 80 minutes.
//!
//! A gyro whose stamps change clock is timed by the record time: every sample kept, one second
//! apart, each with the temperature of its second. A sparse Temperature topic is read as the
//! straight line between the readings around each sample, and one too sparse for that (a
//! reading every 2000 s) is told, its samples far from a reading left without a temperature
//! rather than given a held one that reads as a plateau.

use super::limits::{crafted, driftlab_within};
use super::readers::{
    LIMIT_MIB, bag, bag_connection, bag_message, imu_cdr, imu_ros1, mcap, mcap_channel,
    mcap_message, mcap_schema,
};
use super::ros_clock_changes::{notes, says};
use super::ros_limits::temperature_cdr;
use driftlab::log::formats::{self, ImuRecording, Values};

/// The record time of second `k` (from 0), s.
fn recorded(k: u32) -> u32 {
    1_700_000_000 + k
}

/// The true temperature at second `k`, °C. Its slope is at most 0.025 °C/s and its curvature
/// at most 20/800² = 3.1e-5 °C/s².
fn true_c(k: u32) -> f64 {
    20.0 + 20.0 * (f64::from(k) / 800.0).sin()
}

/// The most a straight line between readings `h` s apart leaves the true temperature:
/// h²/8 times its largest curvature (the error of linear interpolation), with 1e-9 °C for
/// rounding.
fn line_within(h: u32) -> f64 {
    f64::from(h).powi(2) / 8.0 * 20.0 / 800.0_f64.powi(2) + 1e-9
}

/// A bag of `/imu/data` (one message a second, `n` of them, sample `k` stamped `imu_stamp(k)`)
/// and `/imu/temperature` on its frame (a reading at the seconds `every(k)` takes, stamped
/// with its record time), each message recorded at [`recorded`]`(k)`.
fn bag_of(n: u32, every: impl Fn(u32) -> bool, imu_stamp: impl Fn(u32) -> u32) -> Vec<u8> {
    super::ros_clock_changes::bag_with(n, every, imu_stamp, recorded, true_c)
}

/// Converts `file` (named `name`) with the command line: each row's time (s after the first
/// record time) and temperature, and what it printed on stderr.
fn written(name: &str, file: &[u8]) -> (Vec<(f64, f64)>, String) {
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), name, file);
    let csv = dir.path().join("out.csv");
    let out = csv.display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &out]);
    ran.succeeds();
    let rows = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let t: f64 = f[0].parse().unwrap();
            (t - f64::from(recorded(0)), f[4].parse().unwrap())
        })
        .collect();
    (rows, ran.stderr)
}

/// Asserts that rows `rows` are taken one second apart from 0 (every sample, in its true
/// order and spacing) and each within `within` °C of the true temperature of its second.
fn every_second_true(rows: &[(f64, f64)], n: u32, within: f64, stderr: &str) {
    assert_eq!(rows.len(), n as usize, "{stderr}");
    for (k, &(t, c)) in rows.iter().enumerate() {
        assert_eq!(t, k as f64, "row {k}: {stderr}");
        let want = true_c(k as u32);
        assert!(
            (c - want).abs() <= within,
            "row {k}: temp_c {c}, true {want}; {stderr}"
        );
    }
}

/// The temperatures read of `rec`'s first gyro.
fn temps(rec: &ImuRecording) -> &[f64] {
    let Values::F64(got) = &rec.instances[0].temp_c else {
        panic!("{:?}", rec.instances[0].temp_c)
    };
    got
}

// ---------------------------------------------------------------- Imu stamps that step

/// Imu stamps that step by `by` s from sample `from` on.
fn stepped(from: u32, by: i64) -> impl Fn(u32) -> u32 {
    move |k| {
        let s = i64::from(recorded(k)) + if k >= from { by } else { 0 };
        u32::try_from(s).unwrap()
    }
}

#[test]
fn an_imu_clock_stepping_back_keeps_every_sample_on_the_record_time() {
    // Back an hour (the stamps run again over the first half's) and back 1000 s (they would
    // splice the second half on 1000 s early), and forward an hour (a gap that never was).
    let n = 2000;
    for by in [-3600, -1000, 3600] {
        let file = bag_of(n, |_| true, stepped(1000, by));
        let (rows, stderr) = written("imujump.bag", &file);
        every_second_true(&rows, n, 0.0, &stderr);
        for part in [
            "/imu/data: header.stamp changes clock at message 1001",
            &format!("a step of {}{by} s", if by > 0 { "+" } else { "" }),
            "/imu/data's samples are timed by the bag's record time instead, one clock \
             throughout",
            "/imu/temperature's readings are paired with /imu/data's samples by the bag's \
             record time instead",
        ] {
            assert!(stderr.contains(part), "{by}: {part:?} not in {stderr}");
        }
        for drop in ["samples dropped", "sample dropped", "gap in time", "°C/s"] {
            assert!(!stderr.contains(drop), "{by}: {drop:?} in {stderr}");
        }
    }
}

#[test]
fn an_imu_clock_away_for_a_block_and_back_keeps_every_sample_on_the_record_time() {
    // 100 messages an hour ahead, and 500 messages 30 s ahead, then back to the first clock.
    let n = 2000;
    for (by, len) in [(3600, 100), (30, 500)] {
        let away = move |k: u32| (600..600 + len).contains(&k);
        let file = bag_of(
            n,
            |_| true,
            move |k| recorded(k) + if away(k) { by } else { 0 },
        );
        let rec = formats::read_bytes("imublock.bag", &file).unwrap();
        let time = &rec.instances[0].time;
        for k in 0..n as usize {
            assert_eq!(time.seconds(k), f64::from(recorded(k as u32)), "{by}: {k}");
        }
        assert_eq!(temps(&rec), (0..n).map(true_c).collect::<Vec<_>>());
        says(
            &notes(&rec)[0],
            &[
                "/imu/data: header.stamp changes clock at message 601",
                "the messages alternate between 2 clocks, changing 2 times",
                "timed by the bag's record time instead",
            ],
        );
        let (rows, stderr) = written("imublock.bag", &file);
        every_second_true(&rows, n, 0.0, &stderr);
    }
}

#[test]
fn an_imu_clock_stepping_back_in_an_mcap_is_timed_by_log_time() {
    let mut r = mcap_schema(1, "sensor_msgs/msg/Imu");
    r.extend(mcap_schema(2, "sensor_msgs/msg/Temperature"));
    r.extend(mcap_channel(1, 1, "/imu"));
    r.extend(mcap_channel(2, 2, "/imu/temperature"));
    let n = 1000;
    for k in 0..n {
        let t = u64::from(recorded(k)) * 1_000_000_000;
        let stamp = recorded(k) as i32 - if k >= 500 { 3600 } else { 0 };
        r.extend(mcap_message(1, t, &imu_cdr(stamp, b"imu", 0.01)));
        r.extend(mcap_message(
            2,
            t,
            &temperature_cdr(recorded(k) as i32, 0, b"imu", true_c(k)),
        ));
    }
    let (rows, stderr) = written("imujump.mcap", &mcap(&r));
    every_second_true(&rows, n, 0.0, &stderr);
    assert!(
        stderr.contains("/imu's samples are timed by the MCAP log time instead"),
        "{stderr}"
    );
}

#[test]
fn an_imu_clock_stepping_back_without_a_temperature_topic_is_timed_by_record_time() {
    // No Temperature topic: the gyro's clock is checked all the same (allan reads it).
    let mut r = bag_connection(0, "/imu/data");
    for k in 0..1000 {
        r.extend(bag_message(
            0,
            recorded(k),
            &imu_ros1(stepped(500, -3600)(k), b"imu", 0.01),
        ));
    }
    let rec = formats::read_bytes("imujump.bag", &bag(&r)).unwrap();
    let time = &rec.instances[0].time;
    for k in 0..1000 {
        assert_eq!(time.seconds(k), f64::from(recorded(k as u32)), "{k}");
    }
    let notes = notes(&rec);
    assert_eq!(notes.len(), 1, "{notes:?}");
    says(
        &notes[0],
        &[
            "/imu/data: header.stamp changes clock at message 501",
            "a step of -3600 s",
            "/imu/data's samples are timed by the bag's record time instead",
            "have the driver keep one clock",
        ],
    );
}

// ---------------------------------------------------------------- a sparse Temperature topic

#[test]
fn a_reading_a_minute_is_interpolated_not_held() {
    // Held, the nearest reading is up to 30 s (0.75 °C) off; the line between two readings a
    // minute apart is within 60²/8 × 3.1e-5 = 0.014 °C. The last sample is taken with a
    // reading, so none is held past the last.
    let n = 3001;
    let file = bag_of(n, |k| k % 60 == 0, recorded);
    let (rows, stderr) = written("every60.bag", &file);
    every_second_true(&rows, n, line_within(60), &stderr);
    assert!(!stderr.contains("too sparse"), "{stderr}");
    // Taken with a reading, a sample keeps its value bit for bit.
    for k in (0..n).step_by(60) {
        assert_eq!(rows[k as usize].1, true_c(k), "{k}");
    }
}

#[test]
fn a_chamber_reading_every_100_s_is_interpolated_past_its_ends_held_at_most_10_s() {
    // Readings at 0, 100, .., 2900 s; samples to 2919 s: the last 19 past the last reading,
    // held 10 s (0.25 °C at most), the 9 beyond that without a reading, told and dropped.
    let n = 2920;
    let file = bag_of(n, |k| k % 100 == 0, recorded);
    let (rows, stderr) = written("every100.bag", &file);
    every_second_true(&rows, 2911, line_within(100).max(10.0 * 0.025), &stderr);
    for part in [
        "/imu/data: 9 of 2920 samples have no reading of /imu/temperature within 10 s of \
         their stamps (first at sample 2912)",
        "9 samples dropped: no reading of its Temperature topic paired with the sample",
    ] {
        assert!(stderr.contains(part), "{part:?} not in {stderr}");
    }
    // Within the line's reach, within its bound.
    for (k, &(_, c)) in rows.iter().enumerate().take(2901) {
        assert!((c - true_c(k as u32)).abs() <= line_within(100), "{k}: {c}");
    }
}

#[test]
fn a_gap_of_90_s_in_a_1_hz_topic_is_bridged_and_one_of_600_s_is_told() {
    // 90 s: within the two minutes a line is trusted (90²/8 × 3.1e-5 = 0.032 °C).
    let n = 2000;
    let file = bag_of(n, |k| !(1000..1089).contains(&k), recorded);
    let (rows, stderr) = written("gap90.bag", &file);
    every_second_true(&rows, n, line_within(90), &stderr);
    // 600 s: beyond it; the samples more than a step (1 s, the pairing's tolerance) from the
    // readings at its ends are left without a temperature, told with the gap, not a reading
    // held over 600 s.
    let file = bag_of(n, |k| !(1000..1599).contains(&k), recorded);
    let rec = formats::read_bytes("gap600.bag", &file).unwrap();
    let got = temps(&rec);
    for (k, c) in got.iter().enumerate() {
        let gap = (1001..=1597).contains(&k);
        assert_eq!(c.is_nan(), gap, "{k}: {c}");
        if !gap {
            assert!((c - true_c(k as u32)).abs() <= 0.025, "{k}: {c}");
        }
    }
    let notes = notes(&rec);
    assert_eq!(notes.len(), 1, "{notes:?}");
    says(
        &notes[0],
        &[
            "/imu/data: 597 of 2000 samples fall between two readings of /imu/temperature \
             more than 120 s apart (first at sample 1002, the widest gap 600 s)",
            "their temp_c is NaN",
        ],
    );
}

#[test]
fn a_reading_every_2000_s_is_told_too_sparse_and_makes_no_plateau() {
    // Held, the nearest reading stood for 2000 s at a time: two "plateaus" at 31.97 and
    // 0.82 °C that the true temperature only passed through. Here a reading is kept only
    // within 10 s of a sample (0.25 °C), and the rest is told and dropped.
    let n = 4001;
    let file = bag_of(n, |k| k % 2000 == 0, recorded);
    let (rows, stderr) = written("every2000.bag", &file);
    assert_eq!(rows.len(), 11 + 21 + 11, "{stderr}");
    for &(t, c) in &rows {
        let k = t as u32;
        assert!(k % 2000 <= 10 || k % 2000 >= 1990, "{t}: {stderr}");
        assert!((c - true_c(k)).abs() <= 10.0 * 0.025, "{t}: {c}");
    }
    for part in [
        "/imu/temperature has one reading every 2000 s: too sparse to pair with a 1 Hz gyro \
         (/imu/data); 3958 of 4001 samples fall between two readings more than 120 s apart",
        "a held reading reads as a plateau the temperature never held",
        "record the temperature at least every 120 s",
        "3958 samples dropped: no reading of its Temperature topic paired with the sample",
    ] {
        assert!(stderr.contains(part), "{part:?} not in {stderr}");
    }
}
