//! The unit a temperature column's header states. The same run written in °C and in another
//! temperature unit reads as the same temperatures: each value is written here from the
//! unit's definition (a tenth, a hundredth, a thousandth of a degree Celsius; kelvin; degrees
//! Fahrenheit), not from what driftlab makes of it. A header stating a unit of another
//! quantity (`%`, `V`, `kOhm`, `°C/min`, counts) or a count of degrees (`0.1 °C`) is refused at
//! the header's line and the column's number, naming the column, the unit and what to do; a
//! lone word where a unit goes is read in °C and warned of, as for a rate or a time.

use crate::common::ingest::{close, opts, unit_of};
use crate::common::run::driftlab;
use driftlab::Log;
use driftlab::log::ingest::{IngestError, read_bytes};
use driftlab::log::{ColumnRole, ProblemKind};

const N: usize = 200;

/// The gyro's temperature at row `i`, °C: −15 … 45 °C.
fn temp_c(i: usize) -> f64 {
    15.0 + 30.0 * (i as f64 / 30.0).sin()
}

/// A log whose temperature column `name` holds the run's temperature as `write(°C)`, a sample a
/// minute.
fn log_text(name: &str, write: impl Fn(f64) -> f64) -> String {
    let quoted = if name.contains(',') {
        format!("\"{name}\"")
    } else {
        name.to_string()
    };
    let mut text = format!("time_s,omega_dph,{quoted}\n");
    for i in 0..N {
        text.push_str(&format!(
            "{},{},{}\n",
            60 * i,
            0.3 + 0.01 * temp_c(i),
            write(temp_c(i))
        ));
    }
    text
}

fn read(text: &str) -> Result<Log, IngestError> {
    read_bytes("t.csv", text.as_bytes(), &opts())
}

fn read_ok(text: &str) -> Log {
    read(text).unwrap_or_else(|e| panic!("read failed: {e}"))
}

#[test]
fn scaled_celsius_reads_as_the_same_run_in_degrees_celsius() {
    for (name, per_degree, unit) in [
        ("temp [d°C]", 10.0, "d°C"),
        ("temp [ddegC]", 10.0, "d°C"),
        ("temp [decidegrees]", 10.0, "d°C"),
        ("temp [decidegrees C]", 10.0, "d°C"),
        ("temp [cdegC]", 100.0, "c°C"),
        ("temp [c°C]", 100.0, "c°C"),
        ("temp [centidegrees]", 100.0, "c°C"),
        ("temp [m°C]", 1000.0, "m°C"),
        ("temp [mdegC]", 1000.0, "m°C"),
        ("temp [millidegrees Celsius]", 1000.0, "m°C"),
        ("temp_mdegc", 1000.0, "m°C"),
        ("temp [1 °C]", 1.0, "°C"),
    ] {
        // The run as a stand writes it in whole counts of the unit, and the same run in °C.
        let counts = |t: f64| (t * per_degree).round();
        let plain = read_ok(&log_text("temp_c", |t| counts(t) / per_degree));
        let log = read_ok(&log_text(name, counts));
        close(&log.temp_c, &plain.temp_c);
        assert_eq!(unit_of(&log, ColumnRole::Temperature), unit, "{name}");
        assert!(
            log.info.problems.is_empty(),
            "{name}: {:?}",
            log.info.problems
        );
    }
}

#[test]
fn kelvin_and_fahrenheit_still_read_as_the_same_run() {
    let plain = read_ok(&log_text("temp_c", |t| t));
    let kelvin = read_ok(&log_text("temp [K]", |t| t + 273.15));
    close(&kelvin.temp_c, &plain.temp_c);
    let fahrenheit = read_ok(&log_text("temp [°F]", |t| t * 9.0 / 5.0 + 32.0));
    close(&fahrenheit.temp_c, &plain.temp_c);
}

/// The read of `text` is refused at line 1, column 3 (the temperature's), with a message that
/// names the column, the unit it states, the option that chooses another column and `more`.
fn refused(name: &str, unit: &str, more: &[&str]) -> Result<(), String> {
    let e = match read(&log_text(name, |t| t)) {
        Ok(log) => {
            return Err(format!(
                "{name}: read in {} without refusing; problems {:?}",
                unit_of(&log, ColumnRole::Temperature),
                log.info.problems
            ));
        }
        Err(e) => e,
    };
    if (e.line, e.column) != (1, 3) {
        return Err(format!(
            "{name}: refused at {}:{}, not 1:3: {e}",
            e.line, e.column
        ));
    }
    if !e.to_string().starts_with("t.csv:1:3: ") {
        return Err(format!(
            "{name}: the message does not lead with t.csv:1:3: {e}"
        ));
    }
    for want in [&format!("\"{name}\""), unit, "temperature", "temp_col"]
        .into_iter()
        .chain(more.iter().copied())
    {
        if !e.message.contains(want) {
            return Err(format!("{name}: {want:?} not in: {e}"));
        }
    }
    Ok(())
}

#[test]
fn a_temperature_in_a_unit_of_another_quantity_is_refused() {
    let failures: Vec<String> = [
        ("temp [%]", "%", &["a ratio"][..]),
        ("temp [V]", "V", &["voltage"]),
        ("temp [mV]", "mV", &["voltage"]),
        ("temp [kOhm]", "kOhm", &["resistance"]),
        ("temp [°C/min]", "°C/min", &["rate of change"]),
        ("temp [K/s]", "K/s", &["rate of change"]),
        ("temp [LSB]", "LSB", &["counts"]),
        ("temp [counts]", "counts", &["counts"]),
        ("temp [s]", "s", &["a time unit"]),
        // A prefix on a scale the reader has no factor for.
        ("temp [mK]", "mK", &["does not read"]),
        ("temp [m°F]", "m°F", &["does not read"]),
        ("temp [deg/s]", "deg/s", &["a rate unit"]),
        // A count of degrees: the message names the unit that reads such counts.
        ("temp [0.1 °C]", "0.1 °C", &["d°C", "factor of 10"]),
        ("temp [0.01 degC]", "0.01 degC", &["c°C", "factor of 100"]),
        ("temp [0,001 °C]", "0,001 °C", &["m°C"]),
        ("temp [0.5 °C]", "0.5 °C", &["factor of 2"]),
    ]
    .into_iter()
    .filter_map(|(name, unit, more)| refused(name, unit, more).err())
    .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_lone_word_where_a_temperature_unit_goes_is_read_in_celsius_and_warned_of() {
    let plain = read_ok(&log_text("temp_c", |t| t));
    let log = read_ok(&log_text("temp [arb]", |t| t));
    close(&log.temp_c, &plain.temp_c);
    let p = &log.info.problems;
    assert!(
        p.iter().any(|p| p.kind == ProblemKind::UnitMismatch
            && p.column == Some(3)
            && p.message.contains("\"temp [arb]\"")
            && p.message.contains("temp_col")),
        "{p:?}"
    );
    // Notes are no unit: neither refused nor warned of.
    for name in [
        "temp (filtered)",
        "temp (imu1)",
        "temp [deg]",
        "temp [°C, board]",
    ] {
        let log = read_ok(&log_text(name, |t| t));
        close(&log.temp_c, &plain.temp_c);
        assert!(
            log.info.problems.is_empty(),
            "{name}: {:?}",
            log.info.problems
        );
    }
}

#[test]
fn an_extra_temperature_in_another_quantity_keeps_its_own_unit() {
    let mut text =
        String::from("time_s,omega_dph,temp_c,temp_sensor_supply [V],temp_board [m°C]\n");
    for i in 0..N {
        text.push_str(&format!(
            "{},0.3,{},3.3,{}\n",
            60 * i,
            temp_c(i),
            (temp_c(i) * 1000.0).round()
        ));
    }
    let log = read_ok(&text);
    let supply = log.channel("temp_sensor_supply [V]").expect("kept");
    assert_eq!(supply.unit, "V");
    assert!(supply.values.iter().all(|&v| v == 3.3));
    let board = log.channel("temp_board [m°C]").expect("kept");
    assert_eq!(board.unit, "°C");
    let thousandths: Vec<f64> = (0..N)
        .map(|i| (temp_c(i) * 1000.0).round() / 1000.0)
        .collect();
    close(&board.values, &thousandths);
}

#[test]
fn a_rate_in_percent_is_warned_of_as_in_ppm_or_volts() {
    for unit in ["%", "ppm", "V"] {
        let name = format!("omega [{unit}]");
        let mut text = format!("time_s,{name},temp_c\n");
        for i in 0..N {
            text.push_str(&format!(
                "{},{},{}\n",
                60 * i,
                0.3 + 0.01 * temp_c(i),
                temp_c(i)
            ));
        }
        let log = read_ok(&text);
        let truth: Vec<f64> = (0..N).map(|i| 0.3 + 0.01 * temp_c(i)).collect();
        close(&log.omega_dph, &truth);
        let p = &log.info.problems;
        assert!(
            p.iter().any(|p| p.kind == ProblemKind::UnitMismatch
                && p.column == Some(2)
                && p.message.contains(&format!("\"{name}\""))
                && p.message.contains(&format!("\"{unit}\""))
                && p.message.contains("rate_unit")),
            "{name}: {p:?}"
        );
    }
}

#[test]
fn the_command_line_names_the_file_line_column_and_option() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("volts.csv");
    std::fs::write(&path, log_text("temp [V]", |t| t)).unwrap();
    let out = driftlab(&["inspect", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("volts.csv:1:3: ")
            && err.contains("\"temp [V]\"")
            && err.contains("--temp-col")
            && !err.contains("temp_col"),
        "{err}"
    );
}
