//! A gyro's temperature when a ROS topic's stamps leave the gyro's clock in ways a median
//! offset does not see: a slow Temperature topic (one reading every 100 s) on a clock minutes
//! ahead, a topic whose clock steps an hour mid-bag (the Temperature's or the Imu's), and a
//! Temperature topic whose messages alternate between two clocks. Every message of both
//! topics is recorded the second it was taken, so the bag's record time pairs each sample
//! with the true temperature; each bag is built here with that temperature known, and each
//! test checks the temperatures written against it and the note naming the clocks.

use super::limits::{crafted, driftlab_within};
use super::readers::{
    LIMIT_MIB, bag, bag_connection, bag_message, imu_cdr, imu_ros1, mcap, mcap_channel,
    mcap_message, mcap_schema,
};
use super::ros_limits::{bag_connection_of, temperature_cdr, temperature_ros1};
use driftlab::log::formats::{self, ImuRecording, Values};

/// The record time of second `k` (from 0), s.
fn recorded(k: u32) -> u32 {
    1_700_000_000 + k
}

/// The true temperature at second `k`: a ramp of 0.5 °C a minute, so that a reading taken
/// 300 s away is 2.5 °C off, and one 50 s away (half a slow topic's step) 0.42 °C.
fn true_c(k: u32) -> f64 {
    20.0 + f64::from(k) / 120.0
}

/// A bag of `/imu/data` (one message a second, `n` of them, stamped `imu_stamp(k)`) and
/// `/imu/temperature` on its frame (a message at the seconds `every(k)` takes, stamped `temp_stamp(k)`),
/// each message recorded at [`recorded`]`(k)` with the true temperature of that second.
fn bag_of(
    n: u32,
    every: impl Fn(u32) -> bool,
    imu_stamp: impl Fn(u32) -> u32,
    temp_stamp: impl Fn(u32) -> u32,
) -> Vec<u8> {
    bag_with(n, every, imu_stamp, temp_stamp, true_c)
}

/// [`bag_of`] with the true temperature of second `k` given by `true_c`.
pub(super) fn bag_with(
    n: u32,
    every: impl Fn(u32) -> bool,
    imu_stamp: impl Fn(u32) -> u32,
    temp_stamp: impl Fn(u32) -> u32,
    true_c: impl Fn(u32) -> f64,
) -> Vec<u8> {
    let mut r = bag_connection(0, "/imu/data");
    r.extend(bag_connection_of(
        1,
        "/imu/temperature",
        "sensor_msgs/Temperature",
    ));
    for k in 0..n {
        r.extend(bag_message(
            0,
            recorded(k),
            &imu_ros1(imu_stamp(k), b"imu", 0.01),
        ));
        if every(k) {
            let t = temperature_ros1(temp_stamp(k), b"imu", true_c(k));
            r.extend(bag_message(1, recorded(k), &t));
        }
    }
    bag(&r)
}

/// The notes of a recording, as printed.
pub(super) fn notes(rec: &ImuRecording) -> Vec<String> {
    rec.problems.iter().map(ToString::to_string).collect()
}

/// Asserts that gyro sample `k` of `rec` (recorded at second `k`) has a temperature within
/// `within` °C of the true one, for every sample.
fn temperatures_true(rec: &ImuRecording, within: f64) {
    temperatures_true_at(rec, |k| k, within);
}

/// Asserts that gyro sample `k` of `rec` has a temperature within `within` °C of the true one
/// at second `taken(k)`: the reading it should be paired with, for every sample.
fn temperatures_true_at(rec: &ImuRecording, taken: impl Fn(u32) -> u32, within: f64) {
    let Values::F64(got) = &rec.instances[0].temp_c else {
        panic!("{:?}", rec.instances[0].temp_c)
    };
    for (k, c) in got.iter().enumerate() {
        let want = true_c(taken(k as u32));
        assert!(
            (c - want).abs() <= within,
            "sample {k}: temp_c {c}, true {want}; notes {:?}",
            notes(rec)
        );
    }
}

/// Converts `file` (named `name`) with the command line; the temperatures written (the CSV's
/// fifth column) in row order, and what it printed on stderr.
fn converted(name: &str, file: &[u8]) -> (Vec<f64>, String) {
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), name, file);
    let csv = dir.path().join("out.csv");
    let out = csv.display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &out]);
    ran.succeeds();
    let temps = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    (temps, ran.stderr)
}

/// Asserts that `note` holds every one of `parts`.
pub(super) fn says(note: &str, parts: &[&str]) {
    for part in parts {
        assert!(note.contains(part), "{part:?} not in {note:?}");
    }
}

// ---------------------------------------------------------------- a slow topic on another clock

#[test]
fn a_temperature_topic_every_100_s_on_a_clock_900_s_ahead_is_paired_by_record_time() {
    // Ten steps of the slow topic are 1000 s: a limit that grows with the step would take
    // 900 s (and 500 s) for a transport's delay and give each sample a reading 900 s old.
    for ahead in [500, 900] {
        let file = bag_of(2001, |k| k % 100 == 0, recorded, |k| recorded(k) + ahead);
        let rec = formats::read_bytes("slow.bag", &file).unwrap();
        // Each sample has the line between the readings recorded around it, the true ramp,
        // as a topic this slow on the gyro's own clock would give it: paired by stamp, the
        // readings taken `ahead` s before (4.2 or 7.5 °C off).
        temperatures_true(&rec, 1e-9);
        let notes = notes(&rec);
        assert_eq!(notes.len(), 1, "{notes:?}");
        says(
            &notes[0],
            &[
                &format!("/imu/temperature: header.stamp stands {ahead} s from the bag's record"),
                &format!("clocks {ahead} s apart, more than 10 s"),
                "at most 10 s, whatever the rate",
                "paired with /imu/data's samples by the bag's record time instead",
            ],
        );
    }
}

// ---------------------------------------------------------------- a clock that steps mid-bag

#[test]
fn a_temperature_clock_stepping_an_hour_mid_bag_is_named_and_paired_by_record_time() {
    let n = 400;
    let file = bag_of(
        n,
        |_| true,
        recorded,
        |k| recorded(k) + if k >= 200 { 3600 } else { 0 },
    );
    let rec = formats::read_bytes("tempjump.bag", &file).unwrap();
    temperatures_true(&rec, 0.0);
    let notes = notes(&rec);
    assert_eq!(notes.len(), 1, "{notes:?}");
    says(
        &notes[0],
        &[
            "/imu/temperature: header.stamp changes clock at message 201",
            "it stands 3600 s from the bag's record time there, against 0 s at message 200",
            "a step of +3600 s",
            "the messages from there on (200 of 400) stay on that clock",
            "/imu/temperature's readings are paired with /imu/data's samples by the bag's \
             record time instead",
        ],
    );
    // The command line writes every sample, with its true temperature: none dropped as a NaN.
    let (temps, stderr) = converted("tempjump.bag", &file);
    assert_eq!(temps.len(), n as usize, "{stderr}");
    for (k, c) in temps.iter().enumerate() {
        assert!(
            (c - true_c(k as u32)).abs() <= 0.05,
            "row {k}: {c}; {stderr}"
        );
    }
    assert!(!stderr.contains("NaN or infinite"), "{stderr}");
}

#[test]
fn an_imu_clock_stepping_an_hour_mid_bag_is_named_and_its_temperature_paired_by_record_time() {
    let file = bag_of(
        400,
        |_| true,
        |k| recorded(k) + if k >= 200 { 3600 } else { 0 },
        recorded,
    );
    let rec = formats::read_bytes("imujump.bag", &file).unwrap();
    // The gyro's samples are timed by the record time, one clock throughout (no gap of an
    // hour that never was); each has the reading recorded with it.
    let time = &rec.instances[0].time;
    for k in 0..400 {
        assert_eq!(time.seconds(k), f64::from(recorded(k as u32)), "{k}");
    }
    temperatures_true(&rec, 0.0);
    let notes = notes(&rec);
    assert_eq!(notes.len(), 1, "{notes:?}");
    says(
        &notes[0],
        &[
            "/imu/data: header.stamp changes clock at message 201",
            "a step of +3600 s",
            "/imu/data's samples are timed by the bag's record time instead",
            "paired with /imu/data's samples by the bag's record time instead",
        ],
    );
}

#[test]
fn an_mcap_whose_temperature_clock_steps_mid_log_is_paired_by_log_time() {
    // The same pairing serves MCAP: its log_time is the record time.
    let mut r = mcap_schema(1, "sensor_msgs/msg/Imu");
    r.extend(mcap_schema(2, "sensor_msgs/msg/Temperature"));
    r.extend(mcap_channel(1, 1, "/imu"));
    r.extend(mcap_channel(2, 2, "/imu/temperature"));
    for k in 0..400u32 {
        let t = u64::from(recorded(k)) * 1_000_000_000;
        let stamp = recorded(k) as i32;
        r.extend(mcap_message(1, t, &imu_cdr(stamp, b"imu", 0.01)));
        let temp_stamp = stamp + if k >= 300 { 3600 } else { 0 };
        r.extend(mcap_message(
            2,
            t,
            &temperature_cdr(temp_stamp, 0, b"imu", true_c(k)),
        ));
    }
    let rec = formats::read_bytes("tempjump.mcap", &mcap(&r)).unwrap();
    temperatures_true(&rec, 0.0);
    let notes = notes(&rec);
    assert_eq!(notes.len(), 1, "{notes:?}");
    says(
        &notes[0],
        &[
            "/imu/temperature: header.stamp changes clock at message 301",
            "a step of +3600 s",
            "by the MCAP log time instead",
        ],
    );
}

// ---------------------------------------------------------------- two clocks in turn

#[test]
fn a_temperature_topic_alternating_between_two_clocks_is_told_and_paired_by_record_time() {
    for ahead in [300, 900] {
        let file = bag_of(
            400,
            |_| true,
            recorded,
            |k| recorded(k) + if k % 2 == 1 { ahead } else { 0 },
        );
        let rec = formats::read_bytes("tempalt.bag", &file).unwrap();
        temperatures_true(&rec, 0.0);
        let notes = notes(&rec);
        assert_eq!(notes.len(), 1, "{notes:?}");
        says(
            &notes[0],
            &[
                "/imu/temperature: header.stamp changes clock at message 2",
                &format!("a step of +{ahead} s"),
                "the messages alternate between 2 clocks, changing 399 times (200 of 400 away",
                "by the bag's record time instead",
            ],
        );
    }
}

#[test]
fn a_temperature_topic_alternating_by_a_second_and_a_half_stays_paired_by_stamp() {
    // 1.5 s is within a transport's delay at 1 Hz: one clock, paired by stamp, and every
    // sample's reading is at most 1.5 s (0.0125 °C) from its own.
    let file = bag_of(
        400,
        |_| true,
        recorded,
        |k| recorded(k) + u32::from(k % 2 == 1),
    );
    let rec = formats::read_bytes("close.bag", &file).unwrap();
    temperatures_true(&rec, 0.05);
    assert!(rec.problems.is_empty(), "{:?}", notes(&rec));
}

// ---------------------------------------------------------------- samples without a reading

#[test]
fn samples_without_a_reading_are_dropped_for_that_reason_not_as_nan() {
    // The temperature node stops after 300 s: the last 100 samples have no reading within a
    // step, and the warning says so (not "NaN or infinite temp_c", which the bag has none of).
    let file = bag_of(400, |k| k < 300, recorded, recorded);
    let (temps, stderr) = converted("stopped.bag", &file);
    assert_eq!(temps.len(), 301, "{stderr}");
    for part in [
        "/imu/data: 99 of 400 samples have no reading of /imu/temperature within 1 s of their \
         stamps (first at sample 302): their temp_c is NaN",
        "99 samples dropped: no reading of its Temperature topic paired with the sample",
    ] {
        assert!(stderr.contains(part), "{part:?} not in {stderr}");
    }
    assert!(!stderr.contains("NaN or infinite temp_c"), "{stderr}");
}
