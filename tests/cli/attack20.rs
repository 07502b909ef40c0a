//! The twentieth attack's findings about the gyro a calibration records (`source.instance`):
//! `evaluate`, `apply` and `report` read gyro 0 of a DataFlash log for a calibration fitted on
//! IMU I=1 and called it "in-sample: the calibration log"; now they read the recorded gyro
//! unless `--gyro` says otherwise, say so, and call another gyro held out.

use crate::common::drone::{DataFlashImu, dataflash};
use crate::common::run::{driftlab, fails, ok, p};

/// One rad/s in °/h.
const DPH_PER_RAD_S: f64 = 180.0 / std::f64::consts::PI * 3600.0;

/// Gyro x drift slope of IMU `instance` in the crafted log, rad/s per °C.
fn slope_x(instance: u8) -> f64 {
    match instance {
        0 => 5.0e-4,
        _ => 1.0e-4,
    }
}

/// Temperature offset of IMU `instance` from the chamber, °C (IMU 1 a degree warmer).
fn warmer(instance: u8) -> f64 {
    f64::from(instance)
}

/// Three hours at 1 Hz of a DataFlash log of IMUs `instances`, warmed from 10 to 60 °C and
/// cooled again, each gyro axis drifting `0.01 + slope·(T − 35)` rad/s, y and z at twice and
/// three times x's slope.
fn imus(instances: &[u8]) -> Vec<u8> {
    let mut messages = Vec::new();
    for k in 0..3 * 3600u64 {
        let t = 35.0 - 25.0 * (2.0 * std::f64::consts::PI * k as f64 / 10_800.0).cos();
        for &instance in instances {
            let temp = t + warmer(instance);
            let s = slope_x(instance);
            messages.push(DataFlashImu {
                time_us: 100_000_000 + k * 1_000_000 + u64::from(instance),
                instance,
                gyro: [1.0, 2.0, 3.0].map(|m| (0.01 + m * s * (temp - 35.0)) as f32),
                temp_c: temp as f32,
            });
        }
    }
    dataflash(&messages)
}

/// The raw peak-to-peak of gyro x's filtered drift IMU `instance` has in [`imus`], °/h: its
/// slope over the 50 °C it spans (the 100-s filter barely touches a 3-hour swing).
fn p2p_truth(instance: u8) -> f64 {
    slope_x(instance) * 50.0 * DPH_PER_RAD_S
}

/// `evaluate --json`'s first axis.
fn evaluated(args: &[&str]) -> (serde_json::Value, String) {
    let out = driftlab(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (j["axes"][0].clone(), String::from_utf8(out.stderr).unwrap())
}

/// A unit calibration of IMU I=1 of a two-IMU log, evaluated on that log with no `--gyro`,
/// is judged on IMU I=1 (its raw drift is I=1's, a fifth of I=0's) and called in-sample, with
/// a note saying the gyro was chosen from the calibration; with `--gyro 0` it is judged on
/// I=0, called held out, and the note names the gyro calibrated. `report` does the same, and
/// `apply` corrects I=1's samples (its raw column is I=1's drift at I=1's temperature).
#[test]
fn commands_read_the_gyro_a_calibration_was_fitted_on() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = p(d, "two_imus.bin");
    std::fs::write(&log, imus(&[0, 1])).unwrap();
    let cal = p(d, "cal1.json");
    ok(&[
        "calibrate",
        &log,
        "--gyro",
        "1",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);

    // evaluate, no --gyro: IMU I=1, in-sample.
    let (axis, err) = evaluated(&["evaluate", &cal, &log, "--json"]);
    let raw = axis["evaluation"]["comparison"]["raw"]["p2p_dph"]
        .as_f64()
        .unwrap();
    assert!(
        (raw / p2p_truth(1) - 1.0).abs() < 0.03,
        "raw p2p {raw} for IMU 1's {} (IMU 0's {})",
        p2p_truth(1),
        p2p_truth(0)
    );
    assert_eq!(axis["in_sample"], true, "{axis}");
    assert!(
        err.contains("gyro 1 (IMU, I=1) chosen (the gyro the calibration was fitted on"),
        "{err}"
    );
    assert!(err.contains("--gyro N chooses another"), "{err}");

    // evaluate --gyro 0: IMU I=0 as asked, held out, the difference said.
    let (axis, err) = evaluated(&["evaluate", &cal, &log, "--gyro", "0", "--json"]);
    let raw = axis["evaluation"]["comparison"]["raw"]["p2p_dph"]
        .as_f64()
        .unwrap();
    assert!(
        (raw / p2p_truth(0) - 1.0).abs() < 0.03,
        "raw p2p {raw} for IMU 0's {}",
        p2p_truth(0)
    );
    assert_eq!(axis["in_sample"], false, "{axis}");
    assert!(
        err.contains(
            "but the calibration was fitted on gyro 1 (DataFlash IMU I=1), gyro 1 of this log"
        ),
        "{err}"
    );

    // evaluate --gyro 1: as asked, and no word about a difference.
    let (axis, err) = evaluated(&["evaluate", &cal, &log, "--gyro", "1", "--json"]);
    assert_eq!(axis["in_sample"], true, "{axis}");
    assert!(!err.contains("fitted on"), "{err}");

    // report: the same rule.
    let out = ok(&["report", &cal, &log, "--out", &p(d, "rep")]);
    assert!(out.contains("two_imus.bin (in-sample)"), "{out}");
    let out = ok(&["report", &cal, &log, "--gyro", "0", "--out", &p(d, "rep0")]);
    assert!(out.contains("two_imus.bin (held out)"), "{out}");

    // apply: IMU I=1's samples, by their drift at their temperature.
    let csv = p(d, "applied.csv");
    ok(&["apply", &cal, &log, "-o", &csv]);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (raw_x, temp) = (col("gyro_x_raw_dph"), col("temp_c"));
    let mut rows = 0;
    for line in lines.step_by(500) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let truth = (0.01 + slope_x(1) * (v[temp] - 35.0)) * DPH_PER_RAD_S;
        assert!(
            (v[raw_x] - truth).abs() < 1e-3 * truth.abs().max(1.0),
            "raw {} for IMU 1's {truth}",
            v[raw_x]
        );
        // Where the slopes tell the IMUs apart.
        if (v[temp] - 35.0).abs() > 5.0 {
            rows += 1;
        }
    }
    assert!(rows > 10, "{rows} rows checked");
}

/// A log without the gyro the calibration was fitted on (IMU I=1) is refused when no gyro is
/// asked for, naming the record and `--gyro N`; `--gyro 0` reads its one gyro, held out, and
/// says the calibrated one is not in the log.
#[test]
fn a_log_without_the_calibrated_gyro_is_refused_unless_one_is_chosen() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let both = p(d, "two_imus.bin");
    std::fs::write(&both, imus(&[0, 1])).unwrap();
    let only0 = p(d, "imu0.bin");
    std::fs::write(&only0, imus(&[0])).unwrap();
    let cal = p(d, "cal1.json");
    ok(&[
        "calibrate",
        &both,
        "--gyro",
        "1",
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);

    let err = fails(&["evaluate", &cal, &only0]);
    assert!(
        err.contains("fitted on gyro 1 (DataFlash IMU I=1) (its source.instance)"),
        "{err}"
    );
    assert!(err.contains("gyro 0 (DataFlash IMU I=0)"), "{err}");
    assert!(err.contains("--gyro N"), "{err}");
    let err = fails(&["apply", &cal, &only0, "-o", &p(d, "a.csv")]);
    assert!(err.contains("its source.instance"), "{err}");
    assert!(!std::path::Path::new(&p(d, "a.csv")).exists());

    let (axis, err) = evaluated(&["evaluate", &cal, &only0, "--gyro", "0", "--json"]);
    assert_eq!(axis["in_sample"], false, "{axis}");
    let raw = axis["evaluation"]["comparison"]["raw"]["p2p_dph"]
        .as_f64()
        .unwrap();
    assert!((raw / p2p_truth(0) - 1.0).abs() < 0.03, "{raw}");
    assert!(err.contains("which this log does not have"), "{err}");
}
