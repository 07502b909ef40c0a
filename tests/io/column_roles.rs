//! Which role a column's name gives it when the name holds a role's word but states another
//! quantity: a temperature's rate of change (`temp_rate_c_min`, `temp_k_min`) is never the
//! temperature; a gyro's status, setting or statistic (`gyro_rate_hz`, `gyro_error_count`,
//! `gyro_x_bias`) and a reference or command rate (`omega_ref`, `wx_cmd`, `table_rate_dps`)
//! are never gyro axes, and never make the log unreadable; a temperature unit written with a
//! multiplier, a prefix the reader has no factor for or the degree sign after its letter reads
//! consistently. The truth is the same log read with the right columns chosen by the options
//! (`temp_col`, `rate_col`, `axis_cols`), and the values the test writes.

use crate::common::ingest::{close, opts, role_of, unit_of};
use driftlab::Log;
use driftlab::log::ingest::{ColumnRef, IngestError, ReadOptions, read_bytes};
use driftlab::log::{ColumnRole, ProblemKind};

const N: usize = 150;

/// Column `k`'s value at row `i`: distinct per column, so a column read into the wrong slot
/// shows. Column 0 is a gyro's rate; the others between -40 and 70, as a temperature may be.
fn value(k: usize, i: usize) -> f64 {
    let wave = (i as f64 / 20.0 + k as f64).sin();
    match k {
        0 => 0.2 + 0.01 * wave,
        _ => 10.0 * k as f64 + 30.0 * wave,
    }
}

/// A log of `time_s`, then `names` (each column `k` holding `value(k, i)`), a sample a minute.
fn log_text(names: &[&str]) -> String {
    let quoted: Vec<String> = names
        .iter()
        .map(|n| {
            if n.contains(',') {
                format!("\"{n}\"")
            } else {
                n.to_string()
            }
        })
        .collect();
    let mut text = format!("time_s,{}\n", quoted.join(","));
    for i in 0..N {
        let cells: Vec<String> = (0..names.len())
            .map(|k| format!("{}", value(k, i)))
            .collect();
        text.push_str(&format!("{},{}\n", 60 * i, cells.join(",")));
    }
    text
}

fn read_as(names: &[&str], o: &ReadOptions) -> Result<Log, IngestError> {
    read_bytes("t.csv", log_text(names).as_bytes(), o)
}

fn read(names: &[&str]) -> Log {
    read_as(names, &opts()).unwrap_or_else(|e| panic!("{names:?}: read failed: {e}"))
}

fn written(k: usize) -> Vec<f64> {
    (0..N).map(|i| value(k, i)).collect()
}

fn name(s: &str) -> ColumnRef {
    ColumnRef::Name(s.to_string())
}

#[test]
fn a_rate_of_change_of_temperature_is_never_the_temperature() {
    for rate in [
        "temp_rate_c_min",
        "temp_c_per_min",
        "temperature_rate_degC_min",
        "temp_deriv_c",
        "temp_k_min",
        "temp_rate_k_min",
        "temp_ramp_c_min",
        "t_rate_c_min",
        "temp_slope",
        "temp_degc_s",
        "temp_rate [°C/min]",
    ] {
        // The rate before the temperature, as the chamber's log writes them.
        let names = ["omega_dph", rate, "temp_c"];
        let log = read(&names);
        let chosen = ReadOptions {
            temp_col: Some(name("temp_c")),
            ..opts()
        };
        let truth = read_as(&names, &chosen).unwrap_or_else(|e| panic!("{rate}: {e}"));
        close(&log.temp_c, &truth.temp_c);
        close(&log.temp_c, &written(2));
        assert_eq!(role_of(&log, "temp_c"), ColumnRole::Temperature, "{rate}");
        assert_eq!(unit_of(&log, ColumnRole::Temperature), "°C", "{rate}");
        assert_eq!(role_of(&log, rate), ColumnRole::Extra, "{rate}");
        close(&log.channel(rate).expect("kept").values, &written(1));
    }
}

/// A temperature named a command, reference, demand, statistic or model's value, written
/// before the gyro's own: the gyro's is the temperature, the other a channel; alone, it is
/// still read as the temperature.
#[test]
fn a_commanded_or_statistical_temperature_gives_way_to_the_gyros() {
    for other in [
        "temp_cmd_c",
        "temp_command_c",
        "temp_commanded_c",
        "temp_demand_c",
        "temp_desired_c",
        "temp_ref_c",
        "temp_reference_c",
        "temp_control_c",
        "temp_std_c",
        "temp_max_c",
        "temp_mean_c",
        "temp_model_c",
        "temp_pred_c",
        "temp_sim_c",
        "temp_nominal_c",
    ] {
        let names = ["omega_dph", other, "temp_c"];
        let log = read(&names);
        close(&log.temp_c, &written(2));
        assert_eq!(role_of(&log, "temp_c"), ColumnRole::Temperature, "{other}");
        assert_eq!(role_of(&log, other), ColumnRole::Extra, "{other}");
        close(&log.channel(other).expect("kept").values, &written(1));
        let alone = read(&["omega_dph", other]);
        assert_eq!(role_of(&alone, other), ColumnRole::Temperature, "{other}");
        close(&alone.temp_c, &written(1));
    }
}

#[test]
fn a_rate_of_change_of_temperature_mapped_as_the_temperature_is_refused() {
    for rate in ["temp_rate_c_min", "temp_k_min", "ramp_rate_c_min"] {
        let names = ["omega_dph", rate, "temp_c"];
        let o = ReadOptions {
            temp_col: Some(name(rate)),
            ..opts()
        };
        let e = read_as(&names, &o).expect_err(rate);
        assert_eq!((e.line, e.column), (1, 3), "{rate}: {e}");
        assert!(e.to_string().starts_with("t.csv:1:3: "), "{e}");
        assert!(
            e.message.contains(&format!("\"{rate}\""))
                && e.message.contains("rate of change of temperature")
                && e.message.contains("temp_col"),
            "{rate}: {e}"
        );
    }
}

#[test]
fn a_gyros_status_setting_or_statistic_is_a_channel() {
    let dps = 3600.0;
    for other in [
        "gyro_rate_hz",
        "gyro_device_id",
        "gyro_dt",
        "gyro_x_bias",
        "gyro_x_std",
        "gyro_error_count",
        "gyro_clip_count",
        "gyro_clipping",
        "gyro_status",
        "gyro_odr_hz",
        "gyro_range_dps",
        "gyro_x_integral",
    ] {
        let names = ["gyro_x_dps", "gyro_y_dps", "temp_c", other];
        let log = read(&names);
        // The truth: the two axes chosen by hand.
        let chosen = ReadOptions {
            rate_col: Some(name("gyro_x_dps")),
            axis_cols: vec![name("gyro_y_dps")],
            temp_col: Some(name("temp_c")),
            ..opts()
        };
        let truth = read_as(&names, &chosen).unwrap_or_else(|e| panic!("{other}: {e}"));
        assert_eq!(log.axis_names(), truth.axis_names(), "{other}");
        assert_eq!(log.axis_names(), ["gyro_x", "gyro_y"], "{other}");
        close(&log.omega_dph, &truth.omega_dph);
        let want: Vec<f64> = written(0).iter().map(|v| v * dps).collect();
        close(&log.omega_dph, &want);
        assert_eq!(role_of(&log, other), ColumnRole::Extra, "{other}");
        close(&log.channel(other).expect("kept").values, &written(3));
    }
}

#[test]
fn a_gyro_name_that_states_an_angular_rate_is_still_an_axis() {
    let rad_s = 180.0 / std::f64::consts::PI * 3600.0;
    for (names, axes, to_dph) in [
        (
            &["gyro_x", "gyro_y", "temp_c"][..],
            &["gyro_x", "gyro_y"][..],
            1.0,
        ),
        (&["gyro", "temp_c"], &["gyro"], 1.0),
        (&["gyro_x_rad_s", "temp_c"], &["gyro_x"], rad_s),
        (&["gyro_z_dps", "temp_c"], &["gyro_z"], 3600.0),
        (
            &["gyro_x_dps_filtered", "temp_c"],
            &["gyro_x_filtered"],
            3600.0,
        ),
    ] {
        let log = read(names);
        assert_eq!(log.axis_names(), axes, "{names:?}");
        let want: Vec<f64> = written(0).iter().map(|v| v * to_dph).collect();
        close(&log.omega_dph, &want);
    }
}

#[test]
fn a_reference_or_command_rate_is_a_channel() {
    for other in [
        "omega_ref",
        "omega_cmd",
        "omega_setpoint",
        "omega_target",
        "wx_cmd",
        "gyro_x_cmd",
        "turntable_rate_dps",
        "rate_table_dps",
        "table_rate_dps",
        "table_rate",
        "rate_setpoint",
        "table [deg/s]",
    ] {
        let names = ["omega_dph", "temp_c", other];
        let log = read(&names);
        let chosen = ReadOptions {
            rate_col: Some(name("omega_dph")),
            temp_col: Some(name("temp_c")),
            ..opts()
        };
        let truth = read_as(&names, &chosen).unwrap_or_else(|e| panic!("{other}: {e}"));
        assert_eq!(log.axis_names(), ["omega"], "{other}");
        close(&log.omega_dph, &truth.omega_dph);
        close(&log.omega_dph, &written(0));
        assert_eq!(role_of(&log, other), ColumnRole::Extra, "{other}");
        close(&log.channel(other).expect("kept").values, &written(2));
    }
}

/// The log `time_s,omega_dph,NAME` with the temperature column `NAME`, read.
fn read_temp(temp: &str) -> Result<Log, IngestError> {
    read_as(&["omega_dph", temp], &opts())
}

#[test]
fn a_temperature_unit_with_a_multiplier_is_refused_alike() {
    for (unit, per_degree) in [
        ("degC*100", "100"),
        ("deg C x100", "100"),
        ("degC(x100)", "100"),
        ("°C*10", "10"),
        ("°C x 100", "100"),
        ("°C × 1000", "1000"),
    ] {
        let temp = format!("temp [{unit}]");
        let e = read_temp(&temp).expect_err(&temp);
        assert_eq!((e.line, e.column), (1, 3), "{temp}: {e}");
        assert!(e.to_string().starts_with("t.csv:1:3: "), "{e}");
        assert!(
            e.message.contains(&format!("\"{temp}\""))
                && e.message.contains(&format!("factor of {per_degree}"))
                && e.message.contains("temp_col"),
            "{temp}: {e}"
        );
    }
}

#[test]
fn a_prefix_without_a_factor_is_refused_and_c_degree_reads_as_celsius() {
    // Mega, micro, hecto: no factor driftlab reads; refused alike.
    for unit in ["MdegC", "Mdeg C", "M°C", "udegC", "µ°C", "µdegC", "hdegC"] {
        let temp = format!("temp [{unit}]");
        let e = read_temp(&temp).expect_err(&temp);
        assert_eq!((e.line, e.column), (1, 3), "{temp}: {e}");
        assert!(
            e.message.contains(&format!("\"{unit}\"")) && e.message.contains("temp_col"),
            "{temp}: {e}"
        );
    }
    // `C°` is °C written the other way round: the same run as `temp_c`.
    let plain = read_temp("temp_c").unwrap();
    for temp in ["temp [C°]", "temp [c°]"] {
        let log = read_temp(temp).unwrap_or_else(|e| panic!("{temp}: {e}"));
        close(&log.temp_c, &plain.temp_c);
        assert_eq!(unit_of(&log, ColumnRole::Temperature), "°C", "{temp}");
    }
    // Millidegrees written with a small m are still read.
    let milli = read_temp("temp [mdegC]").unwrap();
    let thousandths: Vec<f64> = plain.temp_c.iter().map(|t| t / 1000.0).collect();
    close(&milli.temp_c, &thousandths);
}

#[test]
fn a_word_that_may_be_a_temperature_unit_is_read_in_celsius_and_warned_of() {
    let plain = read_temp("temp_c").unwrap();
    for (temp, word) in [("temp_dF", "df"), ("temp_mk", "mk"), ("temp [raw]", "raw")] {
        let log = read_temp(temp).unwrap_or_else(|e| panic!("{temp}: {e}"));
        close(&log.temp_c, &plain.temp_c);
        let p = &log.info.problems;
        assert!(
            p.iter().any(|p| p.kind == ProblemKind::UnitMismatch
                && p.column == Some(3)
                && p.message.contains(&format!("\"{temp}\""))
                && p.message.contains(&format!("\"{word}\""))
                && p.message.contains("temp_col")),
            "{temp}: {p:?}"
        );
    }
}
