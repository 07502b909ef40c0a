//! Units a header states. Every unit the reader reads gives back the drift the test wrote into
//! the log: a rate of 0.3 + 0.01·T deg/h and a time in seconds, each written in the column's own
//! unit with the factors worked out here from the units' definitions (not taken from driftlab).
//! A unit the reader does not read is never taken for the default (deg/h, s): the read
//! refuses, naming the column, the unit it saw and the setting that gives the unit (`rate_unit`,
//! `time_unit`; `--rate-unit`, `--time-unit` on the command line), or, where the name only may
//! state a unit, it reads and warns with the same words.

use crate::common::ingest::opts;
use driftlab::log::ingest::{IngestError, RateUnit, ReadOptions, TimeUnit, read_bytes};
use driftlab::log::{ColumnRole, Log, ProblemKind};
use std::f64::consts::PI;
use std::process::Command;

mod scales;

const N: usize = 240;

/// The gyro's temperature at row `i`, °C: 0 … 40 °C.
fn temp_c(i: usize) -> f64 {
    20.0 + 20.0 * (i as f64 / 40.0).sin()
}

/// The true drift at row `i`, deg/h.
fn drift_dph(i: usize) -> f64 {
    0.3 + 0.01 * temp_c(i)
}

/// The true time of row `i`, s: a sample a minute.
fn time_s(i: usize) -> f64 {
    60.0 * i as f64
}

// deg/h in one unit of each rate unit, and s in one unit of each time unit, from definitions.
const DPH: f64 = 1.0;
const DEG_PER_S: f64 = 3600.0;
const DEG_PER_MIN: f64 = 60.0;
const MDEG_PER_S: f64 = 3600.0 / 1000.0;
/// An arc second is 1/3600 deg; per second, 3600 of them an hour: 1 deg/h.
const ARCSEC_PER_S: f64 = 1.0 / 3600.0 * 3600.0;
fn rad_per_s() -> f64 {
    180.0 / PI * 3600.0
}
fn mrad_per_s() -> f64 {
    rad_per_s() / 1000.0
}
fn urad_per_s() -> f64 {
    rad_per_s() / 1e6
}
const SECOND: f64 = 1.0;
const MILLISECOND: f64 = 1e-3;
const MICROSECOND: f64 = 1e-6;
const CENTISECOND: f64 = 0.01;
const DECISECOND: f64 = 0.1;
const MINUTE: f64 = 60.0;
const DAY: f64 = 86_400.0;

/// A log whose time column `time` holds the true time in units of `s_per_unit` seconds and
/// whose rate column `rate` holds the true drift in units of `dph_per_unit` deg/h.
fn log_text(time: &str, s_per_unit: f64, rate: &str, dph_per_unit: f64) -> String {
    let quote = |n: &str| {
        if n.contains(',') {
            format!("\"{n}\"")
        } else {
            n.to_string()
        }
    };
    let mut text = format!("{},{},temp_c\n", quote(time), quote(rate));
    for i in 0..N {
        text.push_str(&format!(
            "{},{},{}\n",
            time_s(i) / s_per_unit,
            drift_dph(i) / dph_per_unit,
            temp_c(i)
        ));
    }
    text
}

/// Where `got` and `want` differ by more than 1e-9 (relative): the first such row.
fn mismatch(got: &[f64], want: &[f64]) -> Option<String> {
    if got.len() != want.len() {
        return Some(format!("{} rows read, {} written", got.len(), want.len()));
    }
    let i = (0..got.len()).find(|&i| (got[i] - want[i]).abs() > 1e-9 * (1.0 + want[i].abs()))?;
    Some(format!(
        "row {i}: read {}, truth {} (read/truth = {})",
        got[i],
        want[i],
        got[i] / want[i]
    ))
}

fn close(got: &[f64], want: &[f64]) {
    if let Some(m) = mismatch(got, want) {
        panic!("{m}");
    }
}

fn try_read(text: &str, o: &ReadOptions) -> Result<Log, IngestError> {
    read_bytes("t.csv", text.as_bytes(), o)
}

fn read_ok(text: &str, o: &ReadOptions) -> Log {
    try_read(text, o).unwrap_or_else(|e| panic!("read failed: {e}\n{}", first_line(text)))
}

fn first_line(text: &str) -> &str {
    text.lines().next().unwrap_or("")
}

fn truth_rate() -> Vec<f64> {
    (0..N).map(drift_dph).collect()
}

fn truth_time() -> Vec<f64> {
    (0..N).map(time_s).collect()
}

/// The log reads back the truth, with no problem to report, or what is wrong.
fn truth_of(text: &str, o: &ReadOptions) -> Result<Log, String> {
    let header = first_line(text);
    let log = try_read(text, o).map_err(|e| format!("{header}: refused: {e}"))?;
    let wrong = [
        mismatch(&log.omega_dph, &truth_rate()).map(|m| format!("rate, deg/h: {m}")),
        mismatch(&log.time_s, &truth_time()).map(|m| format!("time, s: {m}")),
        (!log.info.problems.is_empty()).then(|| format!("problems: {:?}", log.info.problems)),
    ];
    let wrong: Vec<String> = wrong.into_iter().flatten().collect();
    if wrong.is_empty() {
        Ok(log)
    } else {
        Err(format!("{header}: {}", wrong.join("; ")))
    }
}

fn reads_truth(text: &str, o: &ReadOptions) -> Log {
    truth_of(text, o).unwrap_or_else(|e| panic!("{e}"))
}

/// Panics listing every entry of `failures`.
fn none_failed(failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "{} failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

fn unit_of(log: &Log, role: ColumnRole) -> String {
    let c = log.info.columns.iter().find(|c| c.role == role);
    c.map(|c| c.unit.clone()).unwrap_or_default()
}

// ---------------------------------------------------------------------------------------------
// Units read

#[test]
fn rate_units_a_header_states_give_the_true_drift() {
    let cases: Vec<(&str, f64, &str)> = vec![
        // Plain spellings that already read.
        ("omega_dph", DPH, "deg/h"),
        ("Rate [°/h]", DPH, "deg/h"),
        ("Rate (deg/s)", DEG_PER_S, "deg/s"),
        ("gyro_x_rad_s", rad_per_s(), "rad/s"),
        ("gx_mdps", MDEG_PER_S, "mdeg/s"),
        ("gx_raw_dps", DEG_PER_S, "deg/s"),
        // Milliradians and microradians per second.
        ("Rate [mrad/s]", mrad_per_s(), "mrad/s"),
        ("Rate (mrad/s)", mrad_per_s(), "mrad/s"),
        ("gyro_z [mrad/sec]", mrad_per_s(), "mrad/s"),
        ("omega_mrad_s", mrad_per_s(), "mrad/s"),
        ("Rate [µrad/s]", urad_per_s(), "urad/s"),
        ("Rate [urad/s]", urad_per_s(), "urad/s"),
        // Degrees per minute, written so that "min" cannot be a minimum.
        ("Rate [deg/min]", DEG_PER_MIN, "deg/min"),
        ("Rate [°/min]", DEG_PER_MIN, "deg/min"),
        ("omega [degrees per minute]", DEG_PER_MIN, "deg/min"),
        ("omega_deg_per_min", DEG_PER_MIN, "deg/min"),
        // Arc seconds per second (one of them is one deg/h).
        ("Rate [arcsec/s]", ARCSEC_PER_S, "arcsec/s"),
        // A unit followed by a qualifier, or before the axis letter.
        ("omega_dps_raw", DEG_PER_S, "deg/s"),
        ("omega_dps_filtered", DEG_PER_S, "deg/s"),
        ("gyro_x_dps_avg", DEG_PER_S, "deg/s"),
        ("rate_dps_mean", DEG_PER_S, "deg/s"),
        ("w_rad_s_x", rad_per_s(), "rad/s"),
        ("gyro_rad_s_z", rad_per_s(), "rad/s"),
        ("Rate (deg/s, filtered)", DEG_PER_S, "deg/s"),
        // An angle glued to `p` and a time, as in `dps`; one word with `per` inside it.
        ("gyro_x_radps", rad_per_s(), "rad/s"),
        ("omega_degps", DEG_PER_S, "deg/s"),
        ("omega_mradps", mrad_per_s(), "mrad/s"),
        ("omega_degph", DPH, "deg/h"),
        ("omega_dpm", DEG_PER_MIN, "deg/min"),
        ("Rate [radps]", rad_per_s(), "rad/s"),
        ("gyro_radianspersecond", rad_per_s(), "rad/s"),
        ("omega_degpermin", DEG_PER_MIN, "deg/min"),
        // A second to the power minus one, whose one is the unit's exponent, not a scale.
        ("omega [deg s-1]", DEG_PER_S, "deg/s"),
        ("omega [deg.s-1]", DEG_PER_S, "deg/s"),
        ("omega [deg·s⁻¹]", DEG_PER_S, "deg/s"),
        ("omega [m°/s]", MDEG_PER_S, "mdeg/s"),
        ("omega [millideg/s]", MDEG_PER_S, "mdeg/s"),
    ];
    let mut failures = Vec::new();
    for (name, factor, unit) in cases {
        match truth_of(&log_text("time_s", SECOND, name, factor), &opts()) {
            Ok(log) if unit_of(&log, ColumnRole::Rate) != unit => failures.push(format!(
                "{name}: read in {}, not {unit}",
                unit_of(&log, ColumnRole::Rate)
            )),
            Ok(_) => {}
            Err(e) => failures.push(e),
        }
    }
    none_failed(failures);
}

#[test]
fn time_units_a_header_states_give_the_true_time() {
    let cases: Vec<(&str, f64, &str)> = vec![
        ("time_s", SECOND, "s"),
        ("Time [ms]", MILLISECOND, "ms"),
        ("t [min]", MINUTE, "min"),
        ("time_us", MICROSECOND, "us"),
        ("time [days]", DAY, "d"),
        ("time [d]", DAY, "d"),
        ("Time, d", DAY, "d"),
        ("time_days", DAY, "d"),
        ("elapsed_days", DAY, "d"),
        ("time_cs", CENTISECOND, "cs"),
        ("time [cs]", CENTISECOND, "cs"),
        ("time [ds]", DECISECOND, "ds"),
        ("time [deciseconds]", DECISECOND, "ds"),
        // A unit before a qualifier.
        ("time_ms_since_boot", MILLISECOND, "ms"),
        ("time in ms since boot", MILLISECOND, "ms"),
        // One of a unit is that unit.
        ("time [1 s]", SECOND, "s"),
    ];
    let mut failures = Vec::new();
    for (name, factor, unit) in cases {
        match truth_of(&log_text(name, factor, "omega_dph", DPH), &opts()) {
            Ok(log) if unit_of(&log, ColumnRole::Time) != unit => failures.push(format!(
                "{name}: read in {}, not {unit}",
                unit_of(&log, ColumnRole::Time)
            )),
            Ok(_) => {}
            Err(e) => failures.push(e),
        }
    }
    none_failed(failures);
}

#[test]
fn the_new_time_units_are_options_too() {
    for (s, u, factor) in [
        ("d", TimeUnit::Days, DAY),
        ("days", TimeUnit::Days, DAY),
        ("cs", TimeUnit::Centis, CENTISECOND),
        ("ds", TimeUnit::Decis, DECISECOND),
    ] {
        assert_eq!(s.parse::<TimeUnit>(), Ok(u), "{s}");
        assert_eq!(u.to_string().parse::<TimeUnit>(), Ok(u));
        assert_eq!(u.to_s_factor(), Some(factor));
        let o = ReadOptions {
            time_unit: Some(u),
            ..opts()
        };
        reads_truth(&log_text("time", factor, "omega_dph", DPH), &o);
    }
}

#[test]
fn a_unit_away_from_the_end_leaves_the_axis_its_own_words() {
    for (name, axis) in [
        ("w_rad_s_x", "w_x"),
        ("gyro_x_dps_avg", "gyro_x_avg"),
        ("omega_dps_raw", "omega_raw"),
        ("Rate [mrad/s]", "rate"),
        ("gx_dps", "gx"),
    ] {
        let log = read_ok(&log_text("time_s", SECOND, name, DEG_PER_S), &opts());
        assert_eq!(log.axis_names(), [axis], "{name}");
    }
}

// ---------------------------------------------------------------------------------------------
// Units not read: refused

/// The read of `text` fails at the header, naming `column`, `unit` and `setting`; returns its
/// message, or what is wrong.
fn refusal(text: &str, column: &str, unit: &str, setting: &str) -> Result<String, String> {
    let header = first_line(text);
    let e = match try_read(text, &opts()) {
        Ok(log) => {
            return Err(format!(
                "{header}: read as {} / {} without refusing; problems: {:?}",
                unit_of(&log, ColumnRole::Time),
                unit_of(&log, ColumnRole::Rate),
                log.info.problems
            ));
        }
        Err(e) => e,
    };
    if e.line != 1 {
        return Err(format!("{header}: refused, but not at the header: {e}"));
    }
    for want in [&format!("\"{column}\""), unit, setting] {
        if !e.message.contains(want) {
            return Err(format!("{header}: {want:?} not in: {e}"));
        }
    }
    Ok(e.message)
}

#[test]
fn unknown_units_in_a_unit_slot_are_refused() {
    let gy = "time_s,gx_dph,gy [mdeg/fortnight],temp_c\n0,1,1,20\n1,1,1,20\n".to_string();
    // (log, column, unit, setting, more words the message must hold)
    let cases: Vec<(String, &str, &str, &str, &[&str])> = vec![
        // Ticks of a fixed length: the message says how to read them (a sample rate).
        (
            log_text("time [10 ms]", 10.0 * MILLISECOND, "omega_dph", DPH),
            "time [10 ms]",
            "10 ms",
            "time_unit",
            &["time_unit samples", "sample_rate_hz 100"],
        ),
        (
            log_text("time [0.1 s]", 0.1, "omega_dph", DPH),
            "time [0.1 s]",
            "0.1 s",
            "time_unit",
            &["sample_rate_hz 10"],
        ),
        (
            log_text("time_100us", 100.0 * MICROSECOND, "omega_dph", DPH),
            "time_100us",
            "100us",
            "time_unit",
            &["sample_rate_hz 10000"],
        ),
        (
            log_text("time [ticks/2]", 0.5, "omega_dph", DPH),
            "time [ticks/2]",
            "ticks/2",
            "time_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "Rate [furlongs/fortnight]", 1.0),
            "Rate [furlongs/fortnight]",
            "furlongs/fortnight",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "Rate [LSB]", 1.0),
            "Rate [LSB]",
            "LSB",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "Rate [°C]", 1.0),
            "Rate [°C]",
            "°C",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "Rate [10 deg/h]", 10.0),
            "Rate [10 deg/h]",
            "10 deg/h",
            "rate_unit",
            &[],
        ),
        // A second axis in an unknown unit is refused as the first is.
        (
            gy,
            "gy [mdeg/fortnight]",
            "mdeg/fortnight",
            "rate_unit",
            &[],
        ),
        // Counts of a register or a clock: no factor.
        (
            log_text("time_s", SECOND, "gx_lsb", 1.0),
            "gx_lsb",
            "lsb",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_ticks", SECOND, "omega_dph", DPH),
            "time_ticks",
            "ticks",
            "time_unit",
            &["samples"],
        ),
        (
            log_text("time [ticks]", SECOND, "omega_dph", DPH),
            "time [ticks]",
            "ticks",
            "time_unit",
            &[],
        ),
        // Names that may state either of two units: "ds" deciseconds or "downsampled", "d"
        // days or a delta, "deg_min" deg/min or a minimum in degrees; two units in one name.
        (
            log_text("time_ds", DECISECOND, "omega_dph", DPH),
            "time_ds",
            "ds",
            "time_unit",
            &[],
        ),
        (
            log_text("time_d", DAY, "omega_dph", DPH),
            "time_d",
            "d",
            "time_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "omega_deg_min", DEG_PER_MIN),
            "omega_deg_min",
            "deg_min",
            "rate_unit",
            &[],
        ),
        // An angle the reader has no factor for glued to `p` and a time, as a word of the
        // name or alone: revolutions per minute, micro-degrees per second.
        (
            log_text("time_s", SECOND, "omega_rpm", 1.0),
            "omega_rpm",
            "rpm",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "Rate [rpm]", 1.0),
            "Rate [rpm]",
            "rpm",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "omega_udps", 1.0),
            "omega_udps",
            "udps",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "gyro_revps_x", 1.0),
            "gyro_revps_x",
            "revps",
            "rate_unit",
            &[],
        ),
        (
            log_text("time_s", SECOND, "gyro_dps_x_rad_s_filtered", DEG_PER_S),
            "gyro_dps_x_rad_s_filtered",
            "dps",
            "rate_unit",
            &["rad_s"],
        ),
    ];
    let mut failures = Vec::new();
    for (text, column, unit, setting, more) in cases {
        match refusal(&text, column, unit, setting) {
            Ok(m) => {
                for w in more {
                    if !m.contains(w) {
                        failures.push(format!("{column}: {w:?} not in: {m}"));
                    }
                }
            }
            Err(e) => failures.push(e),
        }
    }
    none_failed(failures);
}

#[test]
fn an_explicit_unit_still_wins() {
    // Ticks of 10 ms read as samples at 100 Hz.
    let o = ReadOptions {
        time_unit: Some(TimeUnit::Samples),
        sample_rate_hz: Some(100.0),
        ..opts()
    };
    reads_truth(
        &log_text("time [10 ms]", 10.0 * MILLISECOND, "omega_dph", DPH),
        &o,
    );
    let o = ReadOptions {
        time_unit: Some(TimeUnit::Samples),
        sample_rate_hz: Some(10_000.0),
        ..opts()
    };
    reads_truth(
        &log_text("time_100us", 100.0 * MICROSECOND, "omega_dph", DPH),
        &o,
    );
    let o = ReadOptions {
        time_unit: Some(TimeUnit::Seconds),
        ..opts()
    };
    reads_truth(&log_text("time_ds", SECOND, "omega_dph", DPH), &o);
    let o = ReadOptions {
        rate_unit: Some(RateUnit::DegPerSec),
        ..opts()
    };
    let log = read_ok(
        &log_text("time_s", SECOND, "Rate [furlongs/fortnight]", DEG_PER_S),
        &o,
    );
    close(&log.omega_dph, &truth_rate());
    assert_eq!(unit_of(&log, ColumnRole::Rate), "deg/s");
    // A unit the name states and the option contradicts: taken as asked, and said.
    let o = ReadOptions {
        rate_unit: Some(RateUnit::RadPerSec),
        ..opts()
    };
    let log = read_ok(
        &log_text("time_s", SECOND, "Rate [mrad/s]", rad_per_s()),
        &o,
    );
    close(&log.omega_dph, &truth_rate());
    let p = &log.info.problems;
    assert!(
        p.iter().any(|p| p.kind == ProblemKind::UnitMismatch
            && p.message.contains("mrad/s")
            && p.message.contains("1000")),
        "{p:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// A word where a unit goes: read, and warned

#[test]
fn a_word_where_a_unit_goes_is_warned_of() {
    for (time, rate, column, word, setting) in [
        ("time_s", "Rate [arb]", "Rate [arb]", "arb", "rate_unit"),
        // A short word of a rate's name shaped as a unit, as `dps` is.
        ("time_s", "omega_kph", "omega_kph", "kph", "rate_unit"),
        (
            "time [fortnights]",
            "omega_dph",
            "time [fortnights]",
            "fortnights",
            "time_unit",
        ),
    ] {
        let log = read_ok(&log_text(time, SECOND, rate, DPH), &opts());
        close(&log.omega_dph, &truth_rate());
        let p = &log.info.problems;
        assert!(
            p.iter().any(|p| p.kind == ProblemKind::UnitMismatch
                && p.message.contains(&format!("\"{column}\""))
                && p.message.contains(word)
                && p.message.contains(setting)),
            "{column}: {p:?}"
        );
    }
}

#[test]
fn notes_in_brackets_are_no_units() {
    for (time, rate) in [
        ("time (UTC)", "omega_dph"),
        ("Time [s]", "Rate (x)"),
        ("time_s", "omega_dph (filtered)"),
        ("time_s", "Rate [deg/h] (gyro 2)"),
        ("time_s", "omega (imu1)"),
    ] {
        let log = reads_truth(&log_text(time, SECOND, rate, DPH), &opts());
        assert_eq!(unit_of(&log, ColumnRole::Rate), "deg/h");
        assert_eq!(unit_of(&log, ColumnRole::Time), "s");
    }
}

// ---------------------------------------------------------------------------------------------
// Through the front door and the command line

#[test]
fn the_front_door_and_the_command_line_say_the_same() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("mrad.csv");
    std::fs::write(
        &path,
        log_text("time [days]", DAY, "Rate [mrad/s]", mrad_per_s()),
    )
    .unwrap();
    let log = driftlab::read_path(&path, &opts()).unwrap();
    close(&log.omega_dph, &truth_rate());
    close(&log.time_s, &truth_time());

    let run = |args: &[&str], path: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_driftlab"))
            .args(args)
            .arg(path)
            .output()
            .unwrap()
    };
    let bad = tmp.path().join("furlongs.csv");
    std::fs::write(
        &bad,
        log_text("time_s", SECOND, "Rate [furlongs/fortnight]", 1.0),
    )
    .unwrap();
    let out = run(&["inspect"], &bad);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("\"Rate [furlongs/fortnight]\"")
            && err.contains("--rate-unit")
            && !err.contains("rate_unit"),
        "{err}"
    );

    let odd = tmp.path().join("arb.csv");
    std::fs::write(&odd, log_text("time_s", SECOND, "Rate [arb]", DPH)).unwrap();
    let out = run(&["inspect"], &odd);
    assert!(out.status.success());
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(
        text.contains("arb") && text.contains("--rate-unit") && !text.contains("problems: none"),
        "{text}"
    );
    let out = run(&["inspect", "--json"], &odd);
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let problems = json["info"]["problems"].as_array().expect("problems");
    assert!(
        problems.iter().any(|p| {
            let m = p["message"].as_str().unwrap_or("");
            m.contains("\"Rate [arb]\"") && m.contains("--rate-unit")
        }),
        "{problems:?}"
    );
}
