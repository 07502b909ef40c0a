//! Drone and robot logs wherever driftlab reads a log: `log::read::read_any` turns one gyro of
//! a PX4 ULog or ArduPilot DataFlash log into a `Log` (checked against the reference CSVs
//! pyulog and pymavlink wrote of the same real files, and against driftlab's own converted
//! CSV read back), and every command reads the samples, with `--gyro` and `--temp-from`
//! honoured or refused by name.
//!
//! The samples are not in the repository (several are GPL): the tests read them from
//! `../shared/data/formats/`. Without them a test fails when `CI` is set and otherwise says
//! it skips.

use crate::common;
use common::drone::{DATAFLASH, ULOG, data_dir};

use common::run::{driftlab, fails, ok};
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::log::read::{self, FormatChoice, ReadError, TempFrom};
use std::path::{Path, PathBuf};

fn path(dir: &Path, rel: &str) -> String {
    dir.join(rel).display().to_string()
}

/// The rows of a reference CSV as (header, cells).
fn table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.is_empty());
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

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap()
}

const DPH_PER_RAD_S: f64 = 180.0 / std::f64::consts::PI * 3600.0;

/// The log of one instance against the reference rows of that instance: time from the
/// integer stamp, each axis the stored float32 in °/h, temperature and accelerometer as
/// stored.
fn check_against_reference(
    log: &driftlab::Log,
    gyro: &(Vec<String>, Vec<Vec<String>>),
    accel: &(Vec<String>, Vec<Vec<String>>),
    instance_col: &str,
    instance: &str,
    stamp_col: &str,
) {
    let (gh, grows) = gyro;
    let (ah, arows) = accel;
    let pick = |h: &[String], rows: &[Vec<String>]| -> Vec<Vec<String>> {
        let k = col(h, instance_col);
        rows.iter().filter(|r| r[k] == instance).cloned().collect()
    };
    let g = pick(gh, grows);
    let a = pick(ah, arows);
    assert_eq!(log.len(), g.len(), "{}", log.source);
    assert_eq!(log.axis, "gyro_x");
    let names: Vec<&str> = log.other_axes.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["gyro_y", "gyro_z"]);
    for (i, r) in g.iter().enumerate() {
        let us: u64 = r[col(gh, stamp_col)].parse().unwrap();
        assert_eq!(log.time_s[i], us as f64 / 1e6);
        let f = |name: &str| f64::from(r[col(gh, name)].parse::<f32>().unwrap());
        assert_eq!(log.omega_dph[i], f("gyro_x_rad_s") * DPH_PER_RAD_S);
        assert_eq!(
            log.other_axes[0].omega_dph[i],
            f("gyro_y_rad_s") * DPH_PER_RAD_S
        );
        assert_eq!(
            log.other_axes[1].omega_dph[i],
            f("gyro_z_rad_s") * DPH_PER_RAD_S
        );
        assert_eq!(log.temp_c[i], f("temp_c"));
    }
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let c = &log.extra[k];
        assert_eq!(c.name, format!("accel_{axis}_m_s2"));
        assert_eq!(c.unit, "m/s^2");
        let name = format!("accel_{axis}_m_s2");
        for (i, r) in a.iter().enumerate() {
            assert_eq!(
                c.values[i],
                f64::from(r[col(ah, &name)].parse::<f32>().unwrap())
            );
        }
    }
}

#[test]
fn ulog_and_dataflash_gyros_become_logs_with_the_stored_values() {
    let Some(dir) = data_dir() else { return };
    let opts = ReadOptions::default();
    let refs = |rel: &str, kind: &str| {
        let stem = rel.rsplit_once('.').unwrap().0;
        table(&dir.join(format!("{stem}.{kind}.csv")))
    };
    // Every sensor_gyro instance of the ULog, by multi_id.
    let (gyro, accel) = (refs(ULOG, "gyro"), refs(ULOG, "accel"));
    for k in 0..3 {
        let any = read::read_any(
            &dir.join(ULOG),
            &opts,
            &FormatChoice {
                gyro: Some(k),
                temp_from: None,
                ..FormatChoice::default()
            },
        )
        .unwrap();
        let drone = any.drone.as_ref().unwrap();
        assert_eq!(drone.chosen, k);
        assert_eq!(drone.instances.len(), 4);
        assert!(drone.note.contains("as asked"), "{}", drone.note);
        check_against_reference(
            &any.log,
            &gyro,
            &accel,
            "multi_id",
            &k.to_string(),
            "timestamp_us",
        );
    }
    // Both IMU instances of the DataFlash log, by I.
    let (gyro, accel) = (refs(DATAFLASH, "gyro"), refs(DATAFLASH, "accel"));
    for k in 0..2 {
        let any = read::read_any(
            &dir.join(DATAFLASH),
            &opts,
            &FormatChoice {
                gyro: Some(k),
                temp_from: None,
                ..FormatChoice::default()
            },
        )
        .unwrap();
        check_against_reference(
            &any.log,
            &gyro,
            &accel,
            "instance",
            &k.to_string(),
            "time_us",
        );
        // The cut last message is reported with its byte offset.
        let p = &any.drone.as_ref().unwrap().problems;
        assert!(p.iter().any(|p| p.offset == Some(81918)), "{p:?}");
    }
}

#[test]
fn a_drone_log_reads_as_its_converted_csv_does() {
    let Some(dir) = data_dir() else { return };
    let tmp = tempfile::tempdir().unwrap();
    for rel in [ULOG, DATAFLASH] {
        let csv = tmp.path().join("gyro.csv");
        ok(&[
            "convert",
            &path(&dir, rel),
            "--out",
            &csv.display().to_string(),
        ]);
        let from_csv = ingest::read_path(&csv, &ReadOptions::default()).unwrap();
        let any = read::read_any(
            &dir.join(rel),
            &ReadOptions::default(),
            &FormatChoice::default(),
        )
        .unwrap();
        let log = any.log;
        assert_eq!(log.len(), from_csv.len());
        // The CSV holds each float32 in its shortest text, which parses to the nearest
        // float64 rather than the float32 widened: equal to float32 precision.
        let close = |a: &[f64], b: &[f64], what: &str| {
            for (x, y) in a.iter().zip(b) {
                assert!(
                    (x - y).abs() <= 1e-7 * x.abs().max(1e-3),
                    "{rel} {what}: {x} {y}"
                );
            }
        };
        close(&log.time_s, &from_csv.time_s, "time");
        close(&log.omega_dph, &from_csv.omega_dph, "rate");
        close(&log.temp_c, &from_csv.temp_c, "temperature");
        // The accelerometer channels carry the CSV's names.
        for c in &log.extra {
            let other = from_csv.channel(&c.name).unwrap();
            close(&c.values, &other.values, &c.name);
        }
        // The other gyro axes are the CSV's other rate columns, both in °/h.
        assert_eq!(log.other_axes.len(), 2, "{rel}");
        assert_eq!(from_csv.other_axes.len(), 2, "{rel}");
        for (a, b) in log.other_axes.iter().zip(&from_csv.other_axes) {
            close(&a.omega_dph, &b.omega_dph, &b.name);
        }
    }
}

#[test]
fn choices_that_do_not_fit_are_refused_with_the_alternatives_named() {
    let Some(dir) = data_dir() else { return };
    let ulog = dir.join(ULOG);
    // sensor_combined has no temperature: refused, naming what could stand in.
    let e = read::read_any(
        &ulog,
        &ReadOptions::default(),
        &FormatChoice {
            gyro: Some(3),
            temp_from: None,
            ..FormatChoice::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, ReadError::Selection(_)), "{e}");
    assert!(e.to_string().contains("temp_from none"), "{e}");
    // Past the last instance: the instances are listed.
    let e = read::read_any(
        &ulog,
        &ReadOptions::default(),
        &FormatChoice {
            gyro: Some(7),
            temp_from: None,
            ..FormatChoice::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("device_id 2424842"), "{e}");
    // The accelerometer's temperature when asked.
    let any = read::read_any(
        &ulog,
        &ReadOptions::default(),
        &FormatChoice {
            gyro: Some(1),
            temp_from: Some(TempFrom::Accel),
            ..FormatChoice::default()
        },
    )
    .unwrap();
    assert!(any.drone.unwrap().note.contains("may lag"));
    // CSV options on a drone log, and a gyro choice on a CSV, by name.
    let e = read::read_any(
        &ulog,
        &ReadOptions {
            rate_col: Some("2".parse().unwrap()),
            ..ReadOptions::default()
        },
        &FormatChoice::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("rate_col"), "{e}");
    let csv = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let e = read::read_any(
        &csv,
        &ReadOptions::default(),
        &FormatChoice {
            gyro: Some(0),
            temp_from: None,
            ..FormatChoice::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("none of them"), "{e}");
    // skip_extras leaves the accelerometer out.
    let any = read::read_any(
        &ulog,
        &ReadOptions {
            skip_extras: true,
            ..ReadOptions::default()
        },
        &FormatChoice::default(),
    )
    .unwrap();
    assert!(any.log.extra.is_empty());
}

/// A poly-t calibration fitted on a simulated chamber run (the samples are far too short to
/// fit one), to apply to the samples.
fn simulated_calibration(dir: &Path) -> String {
    let log = dir.join("sim.csv").display().to_string();
    ok(&["simulate", "--out", &log, "--seed", "3"]);
    let cal = dir.join("cal.json").display().to_string();
    ok(&["calibrate", &log, "--model", "poly-t", "--out", &cal]);
    cal
}

#[test]
fn every_command_reads_the_ulog_and_dataflash_samples() {
    let Some(dir) = data_dir() else { return };
    let tmp = tempfile::tempdir().unwrap();
    let cal = simulated_calibration(tmp.path());
    for (rel, samples, note) in [
        (ULOG, 6, "gyro 0 (sensor_gyro multi_id 0, device_id 2424842"),
        (DATAFLASH, 10, "gyro 0 (IMU, I=0) chosen"),
    ] {
        let log = path(&dir, rel);
        // inspect lists the instances with their device ids, rates and temperatures.
        let out = ok(&["inspect", &log]);
        assert!(out.contains("gyro 1"), "{out}");
        assert!(out.contains("temperature"), "{out}");
        let json: serde_json::Value =
            serde_json::from_str(&ok(&["inspect", &log, "--json"])).unwrap();
        assert_eq!(json["samples"], samples);
        assert_eq!(json["axis"], "gyro_x");
        assert!(json["instances"].as_array().unwrap().len() >= 2);
        // calibrate reads it and gets to the checks before a fit, which refuse a 6-s log its
        // 100-s filter (and, were the filter shorter, the few hundredths of a degree the
        // sample spans).
        let out = driftlab(&[
            "calibrate",
            &log,
            "--model",
            "poly-t",
            "--out",
            &tmp.path().join("x.json").display().to_string(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(note), "{err}");
        assert!(
            err.contains("filter_s: 100 s is longer than the log"),
            "{err}"
        );
        // apply, evaluate, compare and report run on it (evaluate, compare and report with a
        // filter that fits in its few seconds; the default 100 s is refused by name).
        let applied = tmp.path().join("applied.csv");
        ok(&["apply", &cal, &log, "--out", &applied.display().to_string()]);
        let rows = std::fs::read_to_string(&applied).unwrap().lines().count();
        assert_eq!(rows, samples + 1, "{rel}");
        let e = fails(&["evaluate", &cal, &log]);
        assert!(e.contains("filter_s (--filter)"), "{e}");
        ok(&["evaluate", &cal, &log, "--filter", "0.1"]);
        let sim = tmp.path().join("sim.csv").display().to_string();
        ok(&[
            "compare", "--train", &sim, "--test", &log, "--models", "poly-t", "--filter", "0.1",
        ]);
        ok(&[
            "report",
            &cal,
            &log,
            "--filter",
            "0.1",
            "--out",
            &tmp.path().join("report").display().to_string(),
        ]);
        // allan reads it too, and --gyro picks another instance.
        let out = driftlab(&["allan", &log, "--gyro", "1", "--json"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(json["samples"], samples);
    }
}

#[test]
fn the_command_line_refuses_what_does_not_fit_by_name() {
    let Some(dir) = data_dir() else { return };
    let ulog = path(&dir, ULOG);
    let e = fails(&["inspect", &ulog, "--time-col", "1"]);
    assert!(e.contains("--time-col"), "{e}");
    let csv = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs/calibration.csv")
        .display()
        .to_string();
    let e = fails(&["inspect", &csv, "--gyro", "1"]);
    assert!(e.contains("--gyro"), "{e}");
    let e = fails(&["inspect", &ulog, "--gyro", "9"]);
    assert!(e.contains("no gyro 9"), "{e}");
    let e = fails(&["calibrate", &ulog, "--out", "x.json", "--temp-from", "none"]);
    assert!(e.contains("--temp-from none"), "{e}");
    // sensor_combined without a temperature: listed by inspect, refused with the reason.
    let out = driftlab(&["inspect", &ulog, "--gyro", "3"]);
    assert!(!out.status.success());
    let listing = String::from_utf8_lossy(&out.stdout);
    assert!(listing.contains("gyro 3  sensor_combined"), "{listing}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("has no temperature of its own"), "{err}");
    // allan reads it without a temperature when told so, on its longest stretch without a
    // gap (the logger's dropout leaves one near the start of the 1298 samples).
    let out = driftlab(&[
        "allan",
        &ulog,
        "--gyro",
        "3",
        "--temp-from",
        "none",
        "--json",
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("only its longest stretch is used, 1297 samples"),
        "{err}"
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["samples"], 1297);
}

#[test]
fn the_librarys_front_door_reads_every_format() {
    let Some(dir) = data_dir() else { return };
    // `driftlab::read_path` is the reader of any log, as the faces read one by default: the
    // ULog and the DataFlash log as `read_any` reads them with the default choice, checked
    // against the independent readers' tables through it.
    for rel in [ULOG, DATAFLASH] {
        let front = driftlab::read_path(&dir.join(rel), &ReadOptions::default())
            .unwrap_or_else(|e| panic!("{rel}: {e}"));
        let any =
            read::read_any(&dir.join(rel), &ReadOptions::default(), &Default::default()).unwrap();
        assert_eq!(front.time_s, any.log.time_s, "{rel}");
        assert_eq!(front.omega_dph, any.log.omega_dph, "{rel}");
        assert_eq!(front.temp_c, any.log.temp_c, "{rel}");
        assert!(!front.is_empty(), "{rel}: no sample");
    }
    // A CSV reads as the CSV reader reads it.
    let csv = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let front = driftlab::read_path(&csv, &ReadOptions::default()).unwrap();
    let plain = ingest::read_path(&csv, &ReadOptions::default()).unwrap();
    assert_eq!(front.omega_dph, plain.omega_dph);
    assert_eq!(front.time_s, plain.time_s);
}
