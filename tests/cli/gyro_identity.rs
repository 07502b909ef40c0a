//! A calibration of a PX4 log's gyro records the chip's `device_id` beside driftlab's number
//! of it, and another log of the same drone is read at that chip, whatever number it has
//! there: the number shifts when a chip of an earlier `multi_id` is re-enumerated in one log
//! (listed as two gyros) and not in the other. A log without the chip is refused naming it;
//! `--gyro N` still chooses; a file written before the chip was recorded is read by number,
//! and the note says so; a hand-edited record is refused naming its field.
//!
//! The logs are built here: each chip's drift is a known line in temperature, so the gyro a
//! calibration is judged on is told by the corrected mean (near 0 on the chip it was fitted
//! on, tens of °/h off on another).

use crate::common::drone::ulog_of_subscriptions;
use crate::common::run::{driftlab, fails, ok, p};
use std::path::Path;

/// Chips by `device_id`: `EARLY` and `LATE` are one `multi_id` re-enumerated; `FITTED` is the
/// chip calibrated; `OTHER` a third.
const EARLY: u32 = 0x25000A;
const LATE: u32 = 0x2A000A;
const FITTED: u32 = 0x380022;
const OTHER: u32 = 0x280022;

/// The drift of a chip, °/h, at `temp_c`: a line of its own.
fn drift_dph(device_id: u32, temp_c: f64) -> f64 {
    let dt = temp_c - 20.0;
    match device_id {
        FITTED => 10.0 + 0.8 * dt,
        OTHER => -30.0 - 0.5 * dt,
        _ => 2.0 + 0.1 * dt,
    }
}

/// A ULog of `subs` (one `multi_id` each: its `device_id` before and after sample `n / 2`),
/// `n` samples at 1 Hz from 1 s, the temperature ramping from 20 °C by `rate` °C a sample.
fn log(dir: &Path, name: &str, subs: &[(u32, u32)], n: usize, rate: f64) -> String {
    let time_s: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
    let temp: Vec<f64> = (0..n).map(|i| 20.0 + rate * i as f64).collect();
    let built: Vec<(Vec<u32>, Vec<[f32; 3]>)> = subs
        .iter()
        .map(|&(before, after)| {
            let ids: Vec<u32> = (0..n)
                .map(|i| if i < n / 2 { before } else { after })
                .collect();
            let gyro = (0..n)
                .map(|i| {
                    // A small wobble, so that no rate reads as frozen.
                    let w = drift_dph(ids[i], temp[i]) + 0.05 * (i as f64 * 0.7).sin();
                    let r = (w.to_radians() / 3600.0) as f32;
                    [r, r, r]
                })
                .collect();
            (ids, gyro)
        })
        .collect();
    let subs: Vec<(&[u32], &[[f32; 3]])> = built
        .iter()
        .map(|(ids, g)| (ids.as_slice(), g.as_slice()))
        .collect();
    let temp: Vec<f32> = temp.iter().map(|&t| t as f32).collect();
    let path = p(dir, name);
    std::fs::write(&path, ulog_of_subscriptions(&time_s, &temp, &subs)).unwrap();
    path
}

/// The corrected mean of each axis, °/h, of `evaluate ARGS --json`.
fn corrected_means(args: &[&str]) -> Vec<f64> {
    let mut all = args.to_vec();
    all.push("--json");
    let v: serde_json::Value = serde_json::from_str(&ok(&all)).unwrap();
    v["axes"]
        .as_array()
        .expect("axes")
        .iter()
        .map(|a| {
            a["evaluation"]["comparison"]["corrected"]["mean_dph"]
                .as_f64()
                .unwrap()
        })
        .collect()
}

/// What `driftlab ARGS` writes to its error stream (it succeeds).
fn notes(args: &[&str]) -> String {
    let out = driftlab(args);
    assert!(out.status.success(), "{args:?}: {out:?}");
    String::from_utf8(out.stderr).unwrap()
}

/// `cal` with its `source.instance` replaced by `instance`, written as `name`.
fn with_instance(dir: &Path, cal: &str, name: &str, instance: serde_json::Value) -> String {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cal).unwrap()).unwrap();
    let mut replaced = 0;
    replace_instances(&mut v, &instance, &mut replaced);
    assert!(replaced > 0, "no source.instance in {cal}");
    let path = p(dir, name);
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    path
}

fn replace_instances(v: &mut serde_json::Value, instance: &serde_json::Value, n: &mut usize) {
    match v {
        serde_json::Value::Object(map) => {
            for (k, child) in map.iter_mut() {
                if k == "source" && child.get("instance").is_some() {
                    child["instance"] = instance.clone();
                    *n += 1;
                } else {
                    replace_instances(child, instance, n);
                }
            }
        }
        serde_json::Value::Array(items) => {
            for child in items {
                replace_instances(child, instance, n);
            }
        }
        _ => {}
    }
}

#[test]
fn another_log_is_read_at_the_chip_the_calibration_was_fitted_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Log A: multi_id 0 re-enumerated half way, so FITTED is gyro 2 and OTHER gyro 3.
    let a = log(
        d,
        "a.ulg",
        &[(EARLY, LATE), (FITTED, FITTED), (OTHER, OTHER)],
        4000,
        0.01,
    );
    // Log B: the same chips, none re-enumerated: FITTED is gyro 1, OTHER gyro 2.
    let b = log(
        d,
        "b.ulg",
        &[(EARLY, EARLY), (FITTED, FITTED), (OTHER, OTHER)],
        3000,
        0.012,
    );
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &a,
        "--gyro",
        "2",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let text = v.to_string();
    assert!(
        text.contains(&format!("\"px4_device_id\":{FITTED}")),
        "the chip is recorded: {text}"
    );

    // Without --gyro, B's gyro 1 (the fitted chip) is read, and named.
    let said = notes(&["evaluate", &cal, &b]);
    assert!(
        said.contains("gyro 1 (sensor_gyro multi_id 1")
            && said.contains("the gyro the calibration was fitted on"),
        "{said}"
    );
    let means = corrected_means(&["evaluate", &cal, &b]);
    assert_eq!(means.len(), 3);
    for m in &means {
        assert!(
            m.abs() < 1.0,
            "the fitted chip corrected to near 0: {means:?}"
        );
    }
    // B's gyro 2 is the other chip: the correction misses it by its bias and slope's gap.
    let mid_temp = 20.0 + 0.012 * 1500.0;
    let gap = drift_dph(OTHER, mid_temp) - drift_dph(FITTED, mid_temp);
    let other = corrected_means(&["evaluate", &cal, &b, "--gyro", "2"]);
    for m in &other {
        assert!((m - gap).abs() < 2.0, "{other:?} against {gap}");
    }

    // A log without the chip is refused, naming it, the gyros the log has, and --gyro N.
    let c = log(d, "c.ulg", &[(EARLY, EARLY), (OTHER, OTHER)], 3000, 0.012);
    let e = fails(&["evaluate", &cal, &c]);
    for words in [
        "device_id 3670050 (0x380022)",
        "gyro 0 (device_id 2424842 (0x25000A))",
        "gyro 1 (device_id 2621474 (0x280022))",
        "--gyro N",
    ] {
        assert!(e.contains(words), "{words:?}: {e}");
    }
    // --gyro N still chooses, and the note says it is another chip.
    let said = notes(&["evaluate", &cal, &c, "--gyro", "1"]);
    assert!(
        said.contains("another gyro than the one calibrated") && said.contains("0x380022"),
        "{said}"
    );
}

#[test]
fn a_calibration_without_the_chip_recorded_is_read_by_number_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = log(d, "a.ulg", &[(EARLY, EARLY), (FITTED, FITTED)], 3000, 0.01);
    let b = log(d, "b.ulg", &[(FITTED, FITTED), (OTHER, OTHER)], 3000, 0.01);
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &a,
        "--gyro",
        "1",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);
    // As a file written before the chip was recorded: gyro 1 of B is taken (the other chip,
    // which the number alone cannot tell), and the note says it was found by number.
    let old = with_instance(d, &cal, "old.json", serde_json::json!({"index": 1}));
    let said = notes(&["evaluate", &old, &b]);
    assert!(
        said.contains("gyro 1 (sensor_gyro multi_id 1") && said.contains("by its number alone"),
        "{said}"
    );
    // The file as written finds the chip at B's gyro 0.
    let said = notes(&["evaluate", &cal, &b]);
    assert!(
        said.contains("gyro 0 (sensor_gyro multi_id 0") && !said.contains("number alone"),
        "{said}"
    );
}

#[test]
fn a_hand_edited_gyro_identity_is_refused_naming_its_field() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = log(d, "a.ulg", &[(FITTED, FITTED)], 3000, 0.01);
    let cal = p(d, "cal.json");
    ok(&["calibrate", &a, "--model", "poly-t", "-o", &cal]);
    use serde_json::json;
    for (k, (record, field, why)) in [
        (
            json!({"index": 0, "px4_device_id": "3670050"}),
            "source.instance.px4_device_id",
            "is text, not a whole number from 0",
        ),
        (
            json!({"index": 0, "px4_device_id": 1u64 << 32}),
            "source.instance.px4_device_id",
            "is 4294967296, more than 4294967295",
        ),
        (
            json!({"index": 0, "ros_topic": "/imu"}),
            "source.instance.ros_frame_id",
            "is missing",
        ),
        (
            json!({"index": 0, "ros_topic": "/imu", "ros_frame_id": 3}),
            "source.instance.ros_frame_id",
            "is a number, not text",
        ),
        (
            json!({"index": 0, "px4_device_id": 5, "ros_topic": "/imu", "ros_frame_id": ""}),
            "source.instance.ros_topic",
            "is given with px4_device_id",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let edited = with_instance(d, &cal, &format!("e{k}.json"), record.clone());
        let e = fails(&["evaluate", &edited, &a]);
        assert!(
            e.contains(&format!("{field}: {why}")),
            "{record}: {field}: {why}: {e}"
        );
    }
    // What the readers write loads: a ROS record, and a PX4 one.
    for record in [
        json!({"index": 0, "ros_topic": "/imu", "ros_frame_id": ""}),
        json!({"index": 0, "px4_device_id": FITTED}),
    ] {
        let edited = with_instance(d, &cal, "fine.json", record.clone());
        let out = driftlab(&["evaluate", &edited, &a]);
        assert!(out.status.success(), "{record}: {out:?}");
    }
}

/// Two gyros of a log reporting the chip a calibration records (a driver that gives two
/// sensors one `device_id`): which one it was fitted on cannot be told, and the first was
/// read as "the gyro the calibration was fitted on" (the twenty-third attack: the other chip,
/// corrected to −40 °/h). It is refused naming both; `--gyro N` chooses.
#[test]
fn two_gyros_reporting_the_recorded_chip_are_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = log(d, "a.ulg", &[(EARLY, EARLY), (FITTED, FITTED)], 3000, 0.01);
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &a,
        "--gyro",
        "1",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);
    let twice = log(
        d,
        "twice.ulg",
        &[(EARLY, EARLY), (FITTED, FITTED), (FITTED, FITTED)],
        3000,
        0.012,
    );
    let e = fails(&["evaluate", &cal, &twice]);
    for words in [
        "gyros 1 and 2 of this log all report device_id 3670050 (0x380022)",
        "cannot be told",
        "--gyro N",
    ] {
        assert!(e.contains(words), "{words:?}: {e}");
    }
    let means = corrected_means(&["evaluate", &cal, &twice, "--gyro", "2"]);
    assert!(means.iter().all(|m| m.abs() < 1.0), "{means:?}");
}

/// A key given twice in the record of the gyro (two `px4_device_id` lines left by a merge)
/// was read as the last, which chose another chip without a word; a calibration file now
/// refuses a key given twice in any of its objects, naming the key, its line and column.
#[test]
fn a_key_given_twice_in_the_record_of_the_gyro_is_refused_with_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = log(d, "a.ulg", &[(FITTED, FITTED), (OTHER, OTHER)], 3000, 0.01);
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &a,
        "--gyro",
        "0",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);
    let text = std::fs::read_to_string(&cal).unwrap();
    let key = format!("\"px4_device_id\": {FITTED}");
    assert!(text.contains(&key), "{text}");
    let twice = text.replacen(&key, &format!("{key}, \"px4_device_id\": {OTHER}"), 1);
    let line = twice
        .lines()
        .position(|l| l.contains("\"px4_device_id\": ") && l.contains(&OTHER.to_string()))
        .unwrap()
        + 1;
    let edited = p(d, "twice.json");
    std::fs::write(&edited, twice).unwrap();
    let e = fails(&["evaluate", &edited, &a]);
    assert!(
        e.contains("the field `px4_device_id` is given twice")
            && e.contains(&format!("at line {line} column")),
        "{e}"
    );
}
