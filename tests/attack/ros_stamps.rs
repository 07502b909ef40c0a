//! ROS 1 bags and MCAP files whose messages' `header.stamp` never advances (a driver that
//! leaves it 0): their samples are timed by the log's own clock (the bag's record time,
//! MCAP's log time) with a note saying so, and their temperature paired by that clock, not
//! every sample with the first reading. Each file is built here with its record times and
//! temperatures known.

use super::limits::{crafted, driftlab_within};
use super::readers::{
    LIMIT_MIB, bag, bag_connection, bag_message, imu_cdr, imu_ros1, mcap, mcap_channel,
    mcap_message, mcap_schema,
};
use super::ros_limits::{bag_connection_of, temperature_cdr, temperature_ros1};
use driftlab::log::formats::{self, RosTime, Timestamps, Values};

/// Messages per topic.
const N: u32 = 40;

/// The record time of message `k` (from 1), s: a clean 1 Hz series.
fn recorded(k: u32) -> u32 {
    1_700_000_000 + k
}

/// The temperature recorded with message `k`: a ramp, so a reading paired with the wrong
/// sample shows.
fn celsius(k: u32) -> f64 {
    20.0 + 0.5 * f64::from(k)
}

/// A bag of an Imu topic and a Temperature topic on its frame, message `k` of each recorded
/// at [`recorded`]`(k)`, their header stamps `imu_stamp(k)` and `temp_stamp(k)` s.
fn bag_stamped(imu_stamp: impl Fn(u32) -> u32, temp_stamp: impl Fn(u32) -> u32) -> Vec<u8> {
    let mut r = bag_connection(0, "/imu/data");
    r.extend(bag_connection_of(
        1,
        "/imu/temperature",
        "sensor_msgs/Temperature",
    ));
    for k in 1..=N {
        r.extend(bag_message(
            0,
            recorded(k),
            &imu_ros1(imu_stamp(k), b"imu", 0.01),
        ));
        let t = temperature_ros1(temp_stamp(k), b"imu", celsius(k));
        r.extend(bag_message(1, recorded(k), &t));
    }
    bag(&r)
}

fn record_times() -> Timestamps {
    Timestamps::Ros(
        (1..=N)
            .map(|k| RosTime {
                sec: i64::from(recorded(k)),
                nsec: 0,
            })
            .collect(),
    )
}

fn ramp() -> Values {
    Values::F64((1..=N).map(celsius).collect())
}

#[test]
fn a_bag_whose_stamps_are_never_filled_is_timed_by_its_record_time() {
    let file = bag_stamped(|_| 0, |_| 0);
    let rec = formats::read_bytes("zero_stamp.bag", &file).unwrap();
    let inst = &rec.instances[0];
    assert_eq!(inst.time, record_times());
    // Each sample with the temperature recorded beside it, not all with the first.
    assert_eq!(inst.temp_c, ramp());
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    assert_eq!(
        notes,
        [format!(
            "/imu/data: header.stamp never advances (all {N} messages are stamped 0 s, as a \
             driver that does not fill it leaves them): its samples are timed by the bag's \
             record time instead, and its temperature paired by it, which lags each sample by \
             the transport's delay and jitter; to time them by the sensor, have the driver \
             fill header.stamp"
        )]
    );
    // The command line writes every sample, timed and warmed as recorded, and says why.
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "zero_stamp.bag", &file);
    let csv = dir.path().join("out.csv");
    let out = csv.display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &out]);
    ran.succeeds();
    assert!(
        ran.stderr
            .contains("timed by the bag's record time instead"),
        "{}",
        ran.stderr
    );
    let rows: Vec<(f64, f64)> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (c[0], c[4])
        })
        .collect();
    let want: Vec<(f64, f64)> = (1..=N)
        .map(|k| (f64::from(recorded(k)), celsius(k)))
        .collect();
    assert_eq!(rows, want);
}

#[test]
fn a_temperature_topic_whose_stamps_are_never_filled_is_paired_by_record_time() {
    // The gyro's stamps are the sensor's clock (from boot), the temperature's are 0.
    let file = bag_stamped(|k| k, |_| 0);
    let rec = formats::read_bytes("zero_temp_stamp.bag", &file).unwrap();
    let inst = &rec.instances[0];
    // The gyro keeps its own stamps; each reading is the one recorded beside its sample.
    let own: Vec<RosTime> = (1..=N)
        .map(|k| RosTime {
            sec: i64::from(k),
            nsec: 0,
        })
        .collect();
    assert_eq!(inst.time, Timestamps::Ros(own));
    assert_eq!(inst.temp_c, ramp());
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    assert_eq!(
        notes,
        [format!(
            "/imu/temperature: header.stamp never advances (all {N} messages are stamped 0 s, \
             as a driver that does not fill it leaves them): its readings are paired with \
             /imu/data's samples by the bag's record time instead"
        )]
    );
}

#[test]
fn stamps_that_advance_are_read_as_stamped() {
    // The sensor's clock, offset from the record time: kept as it is, without a note.
    let file = bag_stamped(|k| 100 + k, |k| 100 + k);
    let rec = formats::read_bytes("stamped.bag", &file).unwrap();
    assert_eq!(rec.instances[0].time.seconds(0), 101.0);
    assert_eq!(rec.instances[0].temp_c, ramp());
    assert!(rec.problems.is_empty(), "{:?}", rec.problems);
}

#[test]
fn an_mcap_whose_stamps_are_never_filled_is_timed_by_its_log_time() {
    let mut r = mcap_schema(1, "sensor_msgs/msg/Imu");
    r.extend(mcap_schema(2, "sensor_msgs/msg/Temperature"));
    r.extend(mcap_channel(1, 1, "/imu"));
    r.extend(mcap_channel(2, 2, "/imu/temperature"));
    for k in 1..=N {
        let t = u64::from(recorded(k)) * 1_000_000_000;
        r.extend(mcap_message(1, t, &imu_cdr(0, b"imu", 0.01)));
        r.extend(mcap_message(
            2,
            t,
            &temperature_cdr(0, 0, b"imu", celsius(k)),
        ));
    }
    let rec = formats::read_bytes("zero_stamp.mcap", &mcap(&r)).unwrap();
    assert_eq!(rec.instances[0].time, record_times());
    assert_eq!(rec.instances[0].temp_c, ramp());
    assert_eq!(rec.problems.len(), 1, "{:?}", rec.problems);
    assert!(
        rec.problems[0]
            .message
            .contains("its samples are timed by the MCAP log time instead"),
        "{:?}",
        rec.problems
    );
}
