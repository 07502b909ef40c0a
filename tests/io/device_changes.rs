//! A PX4 `sensor_gyro` subscription whose `device_id` changes partway (the chip swapped or
//! re-enumerated): each device's samples are a gyro of their own, told with the sample and
//! time where the id changes, never one gyro filed under the first chip's id. Each log is
//! built here from known samples.

use crate::common;
use common::drone::ulog_of_devices;
use common::run::{driftlab, p};
use driftlab::log::formats::{self, DeviceId, Timestamps, Values};

/// A log of `ids.len()` samples at 1 Hz from t = 1 s, sample k with device `ids[k]`, a rate
/// of its device's id times 1e-6 rad/s (so a sample filed under another device shows), and a
/// temperature of 20 + k/10 °C.
fn log_of(ids: &[u32]) -> Vec<u8> {
    let time_s: Vec<f64> = (0..ids.len()).map(|k| 1.0 + k as f64).collect();
    let gyro: Vec<[f32; 3]> = ids.iter().map(|&d| [d as f32 * 1e-6; 3]).collect();
    let temp: Vec<f32> = (0..ids.len()).map(|k| 20.0 + k as f32 / 10.0).collect();
    ulog_of_devices(&time_s, &gyro, &temp, ids)
}

#[test]
fn a_chip_swapped_partway_is_two_gyros_and_the_change_is_told() {
    // 30 samples of device 7, then 25 of device 9.
    let ids: Vec<u32> = [vec![7; 30], vec![9; 25]].concat();
    let rec = formats::read_bytes("swapped.ulg", &log_of(&ids)).unwrap();
    assert_eq!(rec.instances.len(), 2);
    for (inst, (device, first, n)) in rec
        .instances
        .iter()
        .zip([(7u32, 0usize, 30usize), (9, 30, 25)])
    {
        assert_eq!(inst.device, Some(DeviceId::Ulog { device_id: device }));
        // Its own samples only: their stamps, and a rate and temperature of its device.
        let micros: Vec<u64> = (first..first + n)
            .map(|k| (1 + k as u64) * 1_000_000)
            .collect();
        assert_eq!(inst.time, Timestamps::Micros(micros));
        assert_eq!(inst.gyro.xyz[0], Values::F32(vec![device as f32 * 1e-6; n]));
        let temp: Vec<f32> = (first..first + n).map(|k| 20.0 + k as f32 / 10.0).collect();
        assert_eq!(inst.temp_c, Values::F32(temp));
    }
    assert_eq!(
        rec.instances[0].label,
        "sensor_gyro multi_id 0 device 1 of 2"
    );
    assert_eq!(
        rec.instances[1].label,
        "sensor_gyro multi_id 0 device 2 of 2"
    );
    let notes: Vec<String> = rec.problems.iter().map(ToString::to_string).collect();
    assert_eq!(
        notes,
        [
            "sensor_gyro multi_id 0: device_id changes from 7 (0x7) to 9 (0x9) within the \
             subscription at sample 31 (31 s); each device's samples are a gyro of their own, \
             never one calibration over two chips: sensor_gyro multi_id 0 device 1 of 2 \
             (device_id 7 (0x7), 30 samples), sensor_gyro multi_id 0 device 2 of 2 \
             (device_id 9 (0x9), 25 samples)"
        ]
    );
}

#[test]
fn a_chip_that_comes_back_is_one_gyro_of_both_its_stretches() {
    // Device 7 re-enumerated as 9 for ten samples, then 7 again.
    let ids: Vec<u32> = [vec![7; 10], vec![9; 10], vec![7; 10]].concat();
    let rec = formats::read_bytes("back.ulg", &log_of(&ids)).unwrap();
    assert_eq!(rec.instances.len(), 2);
    let secs = |i: usize| rec.instances[i].time.all_seconds();
    let want: Vec<f64> = (1..=10).chain(21..=30).map(f64::from).collect();
    assert_eq!(secs(0), want);
    assert_eq!(secs(1), (11..=20).map(f64::from).collect::<Vec<_>>());
    assert!(
        rec.problems[0].message.contains("at sample 11 (11 s)"),
        "{:?}",
        rec.problems
    );
}

#[test]
fn a_device_id_that_never_changes_keeps_one_gyro_and_its_label() {
    let rec = formats::read_bytes("one.ulg", &log_of(&[7; 12])).unwrap();
    assert_eq!(rec.instances.len(), 1);
    assert_eq!(rec.instances[0].label, "sensor_gyro multi_id 0");
    assert_eq!(rec.instances[0].len(), 12);
    assert!(rec.problems.is_empty(), "{:?}", rec.problems);
}

#[test]
fn a_new_device_id_on_every_sample_is_not_a_gyro_each() {
    // A crafted log: 100 ids. The first eight are gyros, the rest counted as left out.
    let ids: Vec<u32> = (1..=100).collect();
    let rec = formats::read_bytes("every.ulg", &log_of(&ids)).unwrap();
    assert_eq!(rec.instances.len(), 8);
    let note = rec.problems[0].to_string();
    assert!(
        note.contains("device 2 of 8 (device_id 2 (0x2), 1 sample), "),
        "{note}"
    );
}

#[test]
fn convert_writes_the_chosen_chips_samples_only() {
    let ids: Vec<u32> = [vec![7; 30], vec![9; 25]].concat();
    let dir = tempfile::tempdir().unwrap();
    let log = p(dir.path(), "swapped.ulg");
    std::fs::write(&log, log_of(&ids)).unwrap();
    for (gyro, rows, device) in [("0", 30, 7), ("1", 25, 9)] {
        let out = p(dir.path(), &format!("gyro{gyro}.csv"));
        let ran = driftlab(&["convert", &log, "-o", &out, "--gyro", gyro]);
        let stderr = String::from_utf8_lossy(&ran.stderr);
        assert!(ran.status.success(), "{stderr}");
        assert!(
            stderr.contains("device_id changes from 7 (0x7) to 9 (0x9) within the subscription"),
            "{stderr}"
        );
        let csv = std::fs::read_to_string(&out).unwrap();
        // float32 as written, in its shortest decimals.
        let rates: Vec<f32> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(rates.len(), rows);
        let want = device as f32 * 1e-6;
        assert!(rates.iter().all(|&r| r == want), "{rates:?}");
    }
}
