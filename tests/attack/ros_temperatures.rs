//! The temperature a ROS gyro is paired with, and the accelerometer it has: a Temperature
//! topic stamped by another clock than the Imu topic (paired by the bag's record time, told,
//! not with readings taken long before), a Temperature topic holding two frames (each frame's
//! readings its own gyro's), and an Imu whose messages say they have no acceleration (a gyro
//! without an accelerometer, as a CSV log without one). Each bag is built here with its
//! clocks, frames and temperatures known.

use super::limits::{crafted, driftlab_within};
use super::readers::{LIMIT_MIB, bag, bag_connection, bag_message, imu_ros1};
use super::ros_limits::{bag_connection_of, bag_message_at, temperature_ros1};
use driftlab::log::formats::{self, Values};

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

/// A bag of `/imu/data` and `/imu/temperature` on its frame, message `k` of each recorded at
/// [`recorded`]`(k)`, the Imu stamped by the record time and the Temperature `temp_stamp(k)`.
fn bag_with_temperature_stamped(temp_stamp: impl Fn(u32) -> u32) -> Vec<u8> {
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
            &imu_ros1(recorded(k), b"imu", 0.01),
        ));
        let t = temperature_ros1(temp_stamp(k), b"imu", celsius(k));
        r.extend(bag_message(1, recorded(k), &t));
    }
    bag(&r)
}

fn ramp() -> Values {
    Values::F64((1..=N).map(celsius).collect())
}

#[test]
fn a_temperature_topic_an_hour_ahead_is_paired_by_record_time_and_told() {
    // The temperature driver's clock runs 3600 s ahead; paired by stamp, each sample would
    // have the reading stamped with it, taken an hour before (none in this bag).
    let file = bag_with_temperature_stamped(|k| recorded(k) + 3600);
    let rec = formats::read_bytes("tempoff.bag", &file).unwrap();
    assert_eq!(rec.instances[0].temp_c, ramp());
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    assert_eq!(notes.len(), 1, "{notes:?}");
    for part in [
        "/imu/temperature: header.stamp stands 3600 s from the bag's record time",
        "/imu/data's 0 s",
        "clocks 3600 s apart, more than 10 s",
        "paired with /imu/data's samples by the bag's record time instead",
    ] {
        assert!(notes[0].contains(part), "{part:?} not in {notes:?}");
    }
}

#[test]
fn a_temperature_topic_stamped_from_boot_is_paired_by_record_time() {
    // Stamps 100 s .. from the node's boot, the gyro's by the wall clock.
    let file = bag_with_temperature_stamped(|k| 100 + k);
    let rec = formats::read_bytes("tempboot.bag", &file).unwrap();
    assert_eq!(rec.instances[0].temp_c, ramp());
    let offset = 100 - i64::from(recorded(0));
    assert!(
        rec.problems[0].message.contains(&format!(
            "/imu/temperature: header.stamp stands {offset} s from the bag's record time"
        )),
        "{:?}",
        rec.problems
    );
    // The command line writes every sample with the reading recorded beside it.
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "tempboot.bag", &file);
    let csv = dir.path().join("out.csv");
    let out = csv.display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["convert", &log, "-o", &out]);
    ran.succeeds();
    let temps: Vec<f64> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    assert_eq!(temps, (1..=N).map(celsius).collect::<Vec<f64>>());
}

#[test]
fn a_temperature_topic_a_few_steps_behind_is_paired_by_stamp() {
    // Stamped 5 s (5 steps, under the 10 s that make another clock) behind its record time:
    // one clock, the reading stamped with each sample is recorded 5 messages later; of the
    // last 5 samples, the first is a step (the pairing's tolerance) from the last reading,
    // the others have none.
    let file = bag_with_temperature_stamped(|k| recorded(k) - 5);
    let rec = formats::read_bytes("late.bag", &file).unwrap();
    let want: Vec<f64> = (1..=N)
        .map(|k| match k + 5 {
            j if j <= N => celsius(j),
            j if j == N + 1 => celsius(N),
            _ => f64::NAN,
        })
        .collect();
    let Values::F64(got) = &rec.instances[0].temp_c else {
        panic!("{:?}", rec.instances[0].temp_c)
    };
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        assert!(
            g == w || (g.is_nan() && w.is_nan()),
            "{got:?} against {want:?}"
        );
    }
    // The samples without a reading are told as such, with the reason, not left to read
    // as NaN temperatures in the log.
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    assert_eq!(
        notes,
        [
            "/imu/data: 4 of 40 samples have no reading of /imu/temperature within 1 s of their \
          stamps (first at sample 37): their temp_c is NaN"
        ],
    );
}

/// `message` with its header stamp's nanoseconds set to `nsec` (after the ROS 1 `seq` and
/// seconds).
fn stamp_nanos(mut message: Vec<u8>, nsec: u32) -> Vec<u8> {
    message[8..12].copy_from_slice(&nsec.to_le_bytes());
    message
}

#[test]
fn a_temperature_topic_of_two_frames_is_parted_by_frame() {
    // Two IMUs on /imu/data, both sampling at each whole second; one Temperature topic of
    // both frames, a's reading published 200 ms before each sample, b's 50 ms after (so the
    // reading nearest a's sample, and the next after it, is b's), b running 30 degC hotter.
    let hot = 30.0;
    let mut r = bag_connection(0, "/imu/data");
    r.extend(bag_connection_of(
        1,
        "/imu/temperature",
        "sensor_msgs/Temperature",
    ));
    for k in 1..=N {
        let s = recorded(k);
        for (f, w) in [(b"imu_a", 0.01), (b"imu_b", 0.02)] {
            r.extend(bag_message(0, s, &imu_ros1(s, f, w)));
        }
        let a = stamp_nanos(temperature_ros1(s - 1, b"imu_a", celsius(k)), 800_000_000);
        r.extend(bag_message_at(1, s - 1, 800_000_000, &a));
        let b = stamp_nanos(temperature_ros1(s, b"imu_b", celsius(k) + hot), 50_000_000);
        r.extend(bag_message_at(1, s, 50_000_000, &b));
    }
    let rec = formats::read_bytes("two.bag", &bag(&r)).unwrap();
    assert_eq!(rec.instances.len(), 2);
    assert_eq!(
        rec.instances[0].gyro.xyz[0],
        Values::F64(vec![0.01; N as usize])
    );
    // Each gyro's temperature is the line between its own frame's readings around its
    // sample (a's 0.2 of the way from the reading 200 ms before to the next, b's 0.95 from
    // the reading 950 ms before), never b's for a; past a frame's last reading (before its
    // first), the reading within a step.
    let line = |ca: f64, cb: f64, w: f64| ca + (cb - ca) * w;
    let a: Vec<f64> = (1..=N)
        .map(|k| match k {
            N => celsius(N),
            _ => line(celsius(k), celsius(k + 1), 0.2),
        })
        .collect();
    let b: Vec<f64> = (1..=N)
        .map(|k| match k {
            1 => celsius(1) + hot,
            _ => line(celsius(k - 1) + hot, celsius(k) + hot, 0.95),
        })
        .collect();
    for (inst, want) in rec.instances.iter().zip([a, b]) {
        let Values::F64(got) = &inst.temp_c else {
            panic!("{:?}", inst.temp_c)
        };
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-12, "{got:?} against {want:?}");
        }
    }
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    // The second reading, b's after the first sample, is where the frame changes.
    let told = notes
        .iter()
        .find(|n| n.starts_with("/imu/temperature: "))
        .expect("a note on the Temperature topic");
    assert!(
        told.starts_with(
            "/imu/temperature: frame_id changes from \"imu_a\" to \"imu_b\" within the topic \
             at sample 2 ("
        ),
        "{told}"
    );
    assert!(
        told.ends_with(&format!(
            "s); each frame's readings are the temperature of that frame's gyro: \
             /imu/temperature frame 1 of 2 (frame_id \"imu_a\", {N} readings), \
             /imu/temperature frame 2 of 2 (frame_id \"imu_b\", {N} readings)"
        )),
        "{told}"
    );
    // No Temperature topic is taken from another frame.
    assert!(
        !notes.iter().any(|n| n.contains("temperature taken from")),
        "{notes:?}"
    );
}

/// `sensor_msgs/Imu` (ROS 1) of a gyro alone: `linear_acceleration` 0 and
/// `linear_acceleration_covariance[0]` -1, the message's mark for "no such data".
fn gyro_only_imu(sec: u32, w: [f64; 3]) -> Vec<u8> {
    let mut b = imu_ros1(sec, b"imu", 0.0);
    // The header (seq, stamp, a 3-byte frame_id) takes 19 bytes; the rate is the 14th to
    // 16th float64 (after orientation 4 and its covariance 9), the covariance the 29th (after
    // the rate's 9, acceleration 3).
    let f64_at = |n: usize| 19 + n * 8;
    for (a, v) in w.iter().enumerate() {
        b[f64_at(13 + a)..f64_at(14 + a)].copy_from_slice(&v.to_le_bytes());
    }
    b[f64_at(28)..f64_at(29)].copy_from_slice(&(-1.0f64).to_le_bytes());
    b
}

#[test]
fn an_imu_without_acceleration_has_no_accelerometer_and_gets_a_kalibr_file() {
    // 3000 s at 1 Hz of a rate of white noise and a random walk (a fixed pseudo-random
    // sequence), enough for both Allan regions Kalibr needs, at 25 degC.
    let mut r = bag_connection(0, "/imu/data");
    r.extend(bag_connection_of(
        1,
        "/imu/temperature",
        "sensor_msgs/Temperature",
    ));
    let mut x: u64 = 12345;
    let mut walk = [0.0; 3];
    for k in 1..=3000 {
        let mut noise = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut w = [0.0; 3];
        for a in 0..3 {
            walk[a] += 7e-7 * noise();
            w[a] = walk[a] + 1e-5 * noise();
        }
        r.extend(bag_message(0, recorded(k), &gyro_only_imu(recorded(k), w)));
        r.extend(bag_message(
            1,
            recorded(k),
            &temperature_ros1(recorded(k), b"imu", 25.0),
        ));
    }
    let file = bag(&r);
    let rec = formats::read_bytes("gyro_only.bag", &file).unwrap();
    assert!(rec.instances[0].accel.is_none());
    assert!(rec.problems.is_empty(), "{:?}", rec.problems);
    let dir = tempfile::tempdir().unwrap();
    let log = crafted(dir.path(), "gyro_only.bag", &file);
    let yaml = dir.path().join("k.yaml");
    let out = yaml.display().to_string();
    let ran = driftlab_within(dir.path(), LIMIT_MIB, &["allan", &log, "--kalibr", &out]);
    ran.succeeds();
    let text = std::fs::read_to_string(&yaml).unwrap();
    assert!(text.contains("# the log has no accelerometer"), "{text}");
    assert!(text.contains("gyroscope_noise_density"), "{text}");
}

#[test]
fn messages_without_acceleration_among_others_read_nan_there() {
    // Every other message says it has no acceleration.
    let mut r = bag_connection(0, "/imu/data");
    for k in 1..=6 {
        let m = if k % 2 == 0 {
            gyro_only_imu(recorded(k), [0.01, 0.0, 0.0])
        } else {
            imu_ros1(recorded(k), b"imu", 0.01)
        };
        r.extend(bag_message(0, recorded(k), &m));
    }
    let rec = formats::read_bytes("mixed.bag", &bag(&r)).unwrap();
    let accel = rec.instances[0].accel.as_ref().unwrap();
    let Values::F64(x) = &accel.xyz[0] else {
        panic!("{:?}", accel.xyz[0])
    };
    let nan: Vec<bool> = x.iter().map(|v| v.is_nan()).collect();
    assert_eq!(nan, (1..=6).map(|k| k % 2 == 0).collect::<Vec<bool>>());
    assert!(
        rec.problems[0]
            .message
            .contains("3 of 6 messages have no acceleration"),
        "{:?}",
        rec.problems
    );
}
