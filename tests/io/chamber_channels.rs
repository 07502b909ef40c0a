//! A chamber's channels beside the gyro's rate are kept as channels, never taken for gyro
//! axes: a name holding the English word `rate` (`coolant_flow_rate_lpm`, `rate_limit`) or
//! ending in the watts of a power (`heater_power_w`) names no gyro's rate. What names one
//! stays an axis: gyro, omega and angular-rate words, axis letters with a rate's unit, `rate`
//! alone or with notes. The truth is the header the test writes: which of its columns are a
//! gyro's, and the values written in each.

use crate::common::ingest::{close, opts, role_of};
use crate::common::run::sample;
use driftlab::Log;
use driftlab::log::ColumnRole;
use driftlab::log::ingest::read_bytes;

const N: usize = 120;

/// Column `k`'s value at row `i`: distinct per column, so a column read into the wrong slot
/// shows.
fn value(k: usize, i: usize) -> f64 {
    (k as f64 + 1.0) * 0.5 + 0.001 * ((i * (k + 3)) % 97) as f64
}

/// A log of `time_s`, then `names` (each column `k` holding `value(k, i)`).
fn log_text(names: &[&str]) -> String {
    let mut text = format!("time_s,{}\n", names.join(","));
    for i in 0..N {
        let cells: Vec<String> = (0..names.len())
            .map(|k| format!("{}", value(k, i)))
            .collect();
        text.push_str(&format!("{i},{}\n", cells.join(",")));
    }
    text
}

fn read(names: &[&str]) -> Log {
    let text = log_text(names);
    read_bytes("t.csv", text.as_bytes(), &opts())
        .unwrap_or_else(|e| panic!("{names:?}: read failed: {e}"))
}

fn written(k: usize) -> Vec<f64> {
    (0..N).map(|i| value(k, i)).collect()
}

#[test]
fn a_chambers_channels_are_no_gyro_axes() {
    // The log of the report: one gyro and three channels of the chamber.
    let names = [
        "omega_dph",
        "temp_c",
        "heater_power_w",
        "coolant_flow_rate_lpm",
        "ramp_rate_c_min",
    ];
    let log = read(&names);
    assert_eq!(log.axis_names(), ["omega"]);
    close(&log.omega_dph, &written(0));
    for (k, name) in names.iter().enumerate().skip(2) {
        assert_eq!(role_of(&log, name), ColumnRole::Extra, "{name}");
        close(&log.channel(name).expect("kept").values, &written(k));
    }
}

#[test]
fn names_holding_rate_or_watts_stay_channels() {
    for name in [
        "power_w",
        "heater_w",
        "setpoint_rate",
        "rate_limit",
        "table_rate",
        "fan_rpm",
        "humidity_pct",
        "vibration_rms",
        "ramp_rate [°C/min]",
    ] {
        let log = read(&["omega_dph", "temp_c", name]);
        assert_eq!(log.axis_names(), ["omega"], "{name}");
        assert_eq!(role_of(&log, name), ColumnRole::Extra, "{name}");
        close(&log.channel(name).expect("kept").values, &written(2));
    }
}

#[test]
fn what_names_a_gyro_rate_is_still_an_axis() {
    // deg/h in one unit, from the units' definitions.
    let dps = 3600.0;
    let rad_s = 180.0 / std::f64::consts::PI * 3600.0;
    // (columns, the axes they read as, deg/h in the first one's unit)
    for (names, axes, to_dph) in [
        (
            &["gx_dps", "gy_dps", "gz_dps", "temp_c"][..],
            &["gx", "gy", "gz"][..],
            dps,
        ),
        (
            &["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s", "temp_c"],
            &["gyro_x", "gyro_y", "gyro_z"],
            rad_s,
        ),
        (&["wx_dps", "wy_dps", "temp_c"], &["wx", "wy"], dps),
        (
            &["w_rad_s_x", "w_rad_s_y", "temp_c"],
            &["w_x", "w_y"],
            rad_s,
        ),
        (&["rate_x", "rate_y", "temp_c"], &["rate_x", "rate_y"], 1.0),
        (&["rate", "temp_c"], &["rate"], 1.0),
        (&["Rate (deg/s)", "temp_c"], &["rate"], dps),
        (&["rate_dps_mean", "temp_c"], &["rate_mean"], dps),
        (
            &["omega_x_dph", "omega_y_dph", "temp_c"],
            &["omega_x", "omega_y"],
            1.0,
        ),
        (
            &["angular_velocity_x", "temp_c"],
            &["angular_velocity_x"],
            1.0,
        ),
    ] {
        let log = read(names);
        assert_eq!(log.axis_names(), axes, "{names:?}");
        let want: Vec<f64> = written(0).iter().map(|v| v * to_dph).collect();
        close(&log.omega_dph, &want);
    }
}

#[test]
fn the_bundled_imu_logs_still_read_their_three_axes() {
    for name in ["imu3-calibration.csv", "imu3-validation.csv"] {
        let path = sample(name);
        let log = driftlab::read_path(std::path::Path::new(&path), &opts()).unwrap();
        assert_eq!(log.axis_names(), ["gx", "gy", "gz"], "{name}");
        // The header the file was written with: its gyro columns are those three, in deg/s.
        let header = std::fs::read_to_string(&path).unwrap();
        let header = header.lines().find(|l| !l.starts_with('#')).unwrap();
        let rates: Vec<&str> = header.split(';').filter(|c| c.ends_with("_dps")).collect();
        assert_eq!(rates, ["gx_dps", "gy_dps", "gz_dps"], "{name}");
        for c in &log.info.columns {
            let axis = matches!(c.role, ColumnRole::Rate | ColumnRole::OtherAxis);
            assert_eq!(axis, rates.contains(&c.name.as_str()), "{name}: {c:?}");
        }
    }
}

#[test]
fn a_log_whose_only_rate_is_a_chambers_asks_for_the_gyros_column() {
    let text = log_text(&["rate_limit", "temp_c"]);
    let e = read_bytes("t.csv", text.as_bytes(), &opts()).unwrap_err();
    assert_eq!(e.line, 1, "{e}");
    assert!(
        e.message.contains("no gyro rate column") && e.message.contains("rate_col"),
        "{e}"
    );
}
