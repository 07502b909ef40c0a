//! Readings no sensor gives (a float register's 1e38) among hours of good ones: a glitch,
//! dropped as a blank cell is (a gyro's rate: its row or sample) or kept as NaN (an
//! accelerometer's, whose axis keeps its samples where the gyro has them), and told with its
//! line or sample; never a calibration refused after its fit, or an accelerometer's unit
//! blamed. A column most of whose readings are beyond is not glitching: it is left to the
//! plausibility check, which doubts its unit.

use crate::common::drone::ulog_imu;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::ingest::{ReadOptions, read_bytes};
use driftlab::log::read::{self, FormatChoice};

/// A three-axis stand log of `n` rows at 1 s (°/h), gravity on z in m/s², with `cell` put in
/// column `col` of data row `row` (0-based).
fn stand_log(n: usize, row: usize, col: usize, cell: &str) -> String {
    let mut s = String::from(
        "time_s,temp_c,omega_x_dph,omega_y_dph,omega_z_dph,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n",
    );
    for i in 0..n {
        let t = i as f64;
        let temp = 20.0 + 30.0 * (t / n as f64);
        let mut cells: Vec<String> = [
            t,
            temp,
            0.1 * temp,
            -0.2,
            0.3,
            0.01,
            -0.02,
            9.81 + 1e-4 * temp,
        ]
        .iter()
        .map(|v| v.to_string())
        .collect();
        if i == row {
            cells[col] = cell.to_string();
        }
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}

#[test]
fn a_gyro_reading_of_1e38_drops_its_row_and_says_which_line() {
    let text = stand_log(2000, 999, 4, "1e38");
    let log = read_bytes("stand.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    // The header is line 1: data row 999 is line 1001.
    assert_eq!(log.len(), 1999);
    assert!(log.time_s.iter().all(|&t| t != 999.0));
    let told: Vec<&str> = log
        .info
        .problems
        .iter()
        .filter(|p| p.message.contains("no gyro gives"))
        .map(|p| p.message.as_str())
        .collect();
    assert_eq!(told.len(), 1, "{:?}", log.info.problems);
    assert!(
        told[0].contains("\"omega_z_dph\"") && told[0].contains("1e38 at line 1001"),
        "{}",
        told[0]
    );
    for (name, axis) in log.axis_names().iter().zip(0..) {
        let values = log.axis_rate(name).unwrap();
        assert!(
            values.iter().all(|v| v.abs() < 1e3),
            "axis {axis} {name} keeps a glitch"
        );
    }
}

#[test]
fn a_column_beyond_throughout_is_no_glitch_and_keeps_its_rows() {
    // Every rate 1e9 °/h (a register's counts read as °/h): the unit is in doubt, not a few
    // readings, and no row goes.
    let text = stand_log(500, usize::MAX, 0, "");
    let text: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                format!("{l}\n")
            } else {
                let mut c: Vec<&str> = l.split(',').collect();
                c[2] = "1e9";
                format!("{}\n", c.join(","))
            }
        })
        .collect();
    let log = read_bytes("counts.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), 500);
    assert!(
        log.info
            .problems
            .iter()
            .all(|p| !p.message.contains("no gyro gives")),
        "{:?}",
        log.info.problems
    );
}

#[test]
fn an_accelerometer_reading_of_1e38_is_kept_as_nan_and_gravity_is_still_read() {
    let text = stand_log(2000, 1500, 7, "-3.4e38");
    let mut log = read_bytes("imu.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    let names = accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    assert_eq!(names, ["acc_x", "acc_y", "acc_z"]);
    let z = log.axis_rate("acc_z").unwrap();
    assert_eq!(z.len(), 2000);
    assert!(z[1500].is_nan());
    assert_eq!(z.iter().filter(|v| v.is_nan()).count(), 1);
    let told: Vec<&str> = log
        .info
        .problems
        .iter()
        .map(|p| p.message.as_str())
        .filter(|m| m.contains("no accelerometer gives"))
        .collect();
    assert_eq!(told.len(), 1, "{:?}", log.info.problems);
    assert!(told[0].contains("-3.4e38 at sample 1501"), "{}", told[0]);
}

#[test]
fn a_ulog_gyro_sample_of_1e38_is_dropped_with_its_sample_number() {
    let n = 2000;
    let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut gyro: Vec<[f32; 3]> = vec![[1e-5, -2e-5, 3e-5]; n];
    gyro[700][1] = 1e38;
    let accel = vec![[0.0f32, 0.0, -9.81]; n];
    let temp: Vec<f32> = (0..n).map(|i| 20.0 + 0.01 * i as f32).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("imu.ulg");
    std::fs::write(&path, ulog_imu(&time, &gyro, &accel, &temp, 2424842)).unwrap();
    let read = read::read_any(&path, &ReadOptions::default(), &FormatChoice::default()).unwrap();
    let log = read.log;
    assert_eq!(log.len(), n - 1);
    assert!(log.time_s.iter().all(|&t| t != 700.0));
    let told: Vec<String> = log
        .info
        .problems
        .iter()
        .map(|p| p.message.clone())
        .chain(
            read.drone
                .iter()
                .flat_map(|d| d.problems.iter().map(|p| p.to_string())),
        )
        .filter(|m| m.contains("no gyro gives"))
        .collect();
    assert_eq!(told.len(), 1, "{told:?}");
    assert!(
        told[0].contains("\"gyro_y_rad_s\"") && told[0].contains("1e38 at sample 701"),
        "{}",
        told[0]
    );
}
