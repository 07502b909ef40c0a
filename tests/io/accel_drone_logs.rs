//! The accelerometers of drone and robot logs as accelerometer axes: PX4's `sensor_accel`,
//! ArduPilot's `IMU` `AccX`/`AccY`/`AccZ` and ROS's `linear_acceleration`, made axes of the
//! log beside its gyro (`log::accel_axes::take`), each sample the value the independent readers
//! (pyulog, pymavlink, rosbags, Foxglove's mcap) wrote of the same real files: float32 values
//! bit for bit, float64 values bit for bit.
//!
//! The samples are not in the repository (several are GPL): the tests read them from
//! `../shared/data/formats/`. Without them a test fails when `CI` is set and otherwise says it
//! skips.

use crate::common::drone::{DATAFLASH, ULOG, data_dir};
use driftlab::log::AxisKind;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::ingest::ReadOptions;
use driftlab::log::read::{self, FormatChoice, TempFrom};
use std::path::Path;

const BAG: &str = "ros1_bag/sparkfun_razor.bag";
const MCAP: &str = "ros2_mcap/sparkfun_razor_ros2.mcap";

/// The rows of a reference CSV whose `filter_col` is `value`, as (header, cells).
fn reference(
    dir: &Path,
    rel: &str,
    filter_col: &str,
    value: &str,
) -> (Vec<String>, Vec<Vec<String>>) {
    let stem = rel.rsplit_once('.').unwrap().0;
    let text = std::fs::read_to_string(dir.join(format!("{stem}.accel.csv"))).unwrap();
    let mut lines = text.lines().filter(|l| !l.is_empty());
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let k = header.iter().position(|h| h == filter_col).unwrap();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect::<Vec<_>>())
        .filter(|r| r[k] == value)
        .collect();
    (header, rows)
}

/// Instance `gyro` of the log at `rel` read with its accelerometer made axes, against the
/// reference rows: the axes' names and kind, and every sample as stored.
fn check(dir: &Path, rel: &str, gyro: usize, (filter_col, value): (&str, &str), f32_file: bool) {
    let choice = FormatChoice {
        gyro: Some(gyro),
        temp_from: (!f32_file).then_some(TempFrom::None),
        ..FormatChoice::default()
    };
    let mut log = read::read_any(&dir.join(rel), &ReadOptions::default(), &choice)
        .unwrap_or_else(|e| panic!("{rel}: {e}"))
        .log;
    let names = accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    assert_eq!(names, ["accel_x", "accel_y", "accel_z"], "{rel}");
    assert_eq!(log.axes_of(AxisKind::Gyro), ["gyro_x", "gyro_y", "gyro_z"]);
    assert!(log.extra.is_empty(), "{rel}: the channels became the axes");
    let (header, rows) = reference(dir, rel, filter_col, value);
    assert_eq!(rows.len(), log.len(), "{rel} {gyro}");
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let c = header
            .iter()
            .position(|h| *h == format!("accel_{axis}_m_s2"))
            .unwrap();
        let values = log.axis_rate(&names[k]).unwrap();
        assert_eq!(
            log.find_axis(&format!("accel_{axis}_m_s2")),
            Some(names[k].clone())
        );
        for (i, r) in rows.iter().enumerate() {
            let stored = if f32_file {
                f64::from(r[c].parse::<f32>().unwrap())
            } else {
                r[c].parse::<f64>().unwrap()
            };
            assert_eq!(
                values[i].to_bits(),
                stored.to_bits(),
                "{rel} instance {gyro} accel_{axis} sample {i}: {} read, {} stored",
                values[i],
                r[c]
            );
        }
    }
}

#[test]
fn drone_and_robot_accelerometers_become_axes_with_the_stored_values() {
    let Some(dir) = data_dir() else { return };
    for k in 0..3 {
        check(&dir, ULOG, k, ("multi_id", &k.to_string()), true);
    }
    for k in 0..2 {
        check(&dir, DATAFLASH, k, ("instance", &k.to_string()), true);
    }
    for rel in [BAG, MCAP] {
        check(&dir, rel, 0, ("topic", "/imu/data_raw"), false);
    }
}

#[test]
fn a_real_ulogs_z_accelerometer_reads_gravity_in_m_s2() {
    // The CubeOrange lies level, z down: z reads -9.7 m/s², and every accelerometer is in
    // m/s² already (no unit to tell, nothing converted).
    let Some(dir) = data_dir() else { return };
    let mut log = read::read_any(
        &dir.join(ULOG),
        &ReadOptions::default(),
        &FormatChoice::default(),
    )
    .unwrap()
    .log;
    accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    let z = log.axis_rate("accel_z").unwrap();
    let mean = z.iter().sum::<f64>() / z.len() as f64;
    assert!((mean + 9.7).abs() < 0.1, "{mean}");
}

#[test]
fn an_accelerometer_whose_clock_steps_back_is_matched_across_no_step_and_said() {
    // 1 Hz, 400 s; the accelerometer's clock steps back 150 s at its 201st message, and its
    // readings say which second they were read at (x = that second, in mm/s²).
    let n = 400;
    let time_s: Vec<f64> = (0..n).map(|k| 1.0 + k as f64).collect();
    let accel_time_s: Vec<f64> = (0..n)
        .map(|k| {
            if k < 200 {
                time_s[k]
            } else {
                time_s[k] - 150.0
            }
        })
        .collect();
    let gyro = vec![[0.0f32; 3]; n];
    let accel: Vec<[f32; 3]> = (0..n).map(|k| [k as f32 * 1e-3, 0.0, 9.81]).collect();
    let temp: Vec<f32> = (0..n).map(|k| 20.0 + k as f32 * 0.05).collect();
    let bytes = crate::common::drone::ulog_imu_stamped(
        &time_s,
        &accel_time_s,
        &gyro,
        &accel,
        &temp,
        2424842,
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("step.ulg");
    std::fs::write(&path, bytes).unwrap();
    let any = read::read_any(&path, &ReadOptions::default(), &FormatChoice::default()).unwrap();
    let mut log = any.log;
    let said: Vec<&str> = any
        .drone
        .iter()
        .flat_map(|d| d.problems.iter().map(|p| p.message.as_str()))
        .chain(log.info.problems.iter().map(|p| p.message.as_str()))
        .collect();
    assert!(
        said.iter()
            .any(|m| m
                .contains("sensor_accel[0]: its clock steps back (first at message 201); the 200")),
        "{said:?}"
    );
    accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    log.select_axis("accel_x");
    // Every gyro sample's accelerometer was read at its own second, or is NaN: none from
    // 150 s away.
    for (k, v) in log.omega_dph.iter().enumerate() {
        let second = log.time_s[k] - log.time_s[0];
        assert!(
            v.is_nan() || (*v * 1e3 - second).abs() < 0.5,
            "at {second} s: {v}"
        );
    }
    assert!(log.omega_dph.iter().any(|v| v.is_nan()));
}
