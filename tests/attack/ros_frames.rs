//! A ROS Imu topic whose `frame_id` changes partway (two IMUs publishing on one topic, or a
//! sensor swapped): each frame's samples are a gyro of their own, with the Temperature topic
//! of its frame, told with the sample and time where the frame first changes; the same rule
//! as a PX4 gyro whose `device_id` changes (`tests/io/device_changes.rs`). Each file is built
//! here with its frames, rates and temperatures known.

use super::limits::{crafted, driftlab_within};
use super::readers::{LIMIT_MIB, bag, bag_connection, bag_message, imu_ros1};
use super::ros_limits::{bag_connection_of, temperature_ros1};
use driftlab::log::formats::{self, DeviceId, Values};

/// The record time of message `k` (from 1), s.
fn recorded(k: u32) -> u32 {
    1_000 + k
}

#[test]
fn two_imus_on_one_topic_are_two_gyros_each_with_its_frames_temperature() {
    // Messages 1..=10 on frame "a" only, then "a" and "b" alternating to 30; the rate names
    // the frame (a: 0.01, b: 0.02 rad/s), and each frame has its Temperature topic.
    let frame = |k: u32| {
        if k <= 10 || k.is_multiple_of(2) {
            "a"
        } else {
            "b"
        }
    };
    let mut r = bag_connection(0, "/imu/data");
    r.extend(bag_connection_of(1, "/a/temp", "sensor_msgs/Temperature"));
    r.extend(bag_connection_of(2, "/b/temp", "sensor_msgs/Temperature"));
    for k in 1..=30 {
        let f = frame(k);
        let w = if f == "a" { 0.01 } else { 0.02 };
        r.extend(bag_message(0, recorded(k), &imu_ros1(k, f.as_bytes(), w)));
        r.extend(bag_message(
            1,
            recorded(k),
            &temperature_ros1(k, b"a", 30.0),
        ));
        r.extend(bag_message(
            2,
            recorded(k),
            &temperature_ros1(k, b"b", 45.0),
        ));
    }
    let file = bag(&r);
    let rec = formats::read_bytes("two_imus.bag", &file).unwrap();
    assert_eq!(rec.instances.len(), 2);
    let a: Vec<u32> = (1..=30).filter(|&k| frame(k) == "a").collect();
    let b: Vec<u32> = (1..=30).filter(|&k| frame(k) == "b").collect();
    for (inst, (name, ks, w, c)) in rec
        .instances
        .iter()
        .zip([("a", &a, 0.01, 30.0), ("b", &b, 0.02, 45.0)])
    {
        assert_eq!(
            inst.device,
            Some(DeviceId::Ros {
                topic: "/imu/data".into(),
                frame_id: name.into()
            })
        );
        let secs: Vec<f64> = ks.iter().map(|&k| f64::from(k)).collect();
        assert_eq!(inst.time.all_seconds(), secs);
        assert_eq!(inst.gyro.xyz[0], Values::F64(vec![w; ks.len()]));
        assert_eq!(inst.temp_c, Values::F64(vec![c; ks.len()]));
    }
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    assert_eq!(
        notes,
        [
            "/imu/data: frame_id changes from \"a\" to \"b\" within the topic at sample 11 (11 \
             s); each frame's samples are a gyro of their own, never one calibration over two \
             sensors: /imu/data frame 1 of 2 (frame_id \"a\", 20 samples), /imu/data frame 2 \
             of 2 (frame_id \"b\", 10 samples)"
        ]
    );
    // The command line: gyro 1 is frame b's, its samples and temperature alone.
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "two_imus.bag", &file);
    let csv = dir.path().join("b.csv");
    let out = csv.display().to_string();
    let ran = driftlab_within(
        dir.path(),
        LIMIT_MIB,
        &["convert", &log, "-o", &out, "--gyro", "1"],
    );
    ran.succeeds();
    let rows: Vec<Vec<f64>> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), b.len());
    assert!(
        rows.iter().all(|r| r[1] == 0.02 && r[4] == 45.0),
        "{rows:?}"
    );
}

#[test]
fn a_topic_of_one_frame_is_one_gyro_under_its_name() {
    let mut r = bag_connection(0, "/imu/data");
    for k in 1..=5 {
        r.extend(bag_message(0, recorded(k), &imu_ros1(k, b"imu", 0.01)));
    }
    let rec = formats::read_bytes("one_frame.bag", &bag(&r)).unwrap();
    assert_eq!(rec.instances.len(), 1);
    assert_eq!(rec.instances[0].label, "/imu/data");
    assert_eq!(rec.instances[0].len(), 5);
}

#[test]
fn a_new_frame_on_every_message_is_not_a_gyro_each() {
    let mut r = bag_connection(0, "/imu/data");
    for k in 1..=100 {
        let f = format!("f{k}");
        r.extend(bag_message(
            0,
            recorded(k),
            &imu_ros1(k, f.as_bytes(), 0.01),
        ));
    }
    let rec = formats::read_bytes("frames.bag", &bag(&r)).unwrap();
    assert_eq!(rec.instances.len(), 8);
    let note = rec.problems[0].to_string();
    assert!(
        note.ends_with(
            "; 92 samples of further frames left out (a gyro of each of the first 8 only)"
        ),
        "{note}"
    );
}
