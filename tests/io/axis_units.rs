//! The axes of one gyro share a unit. A rate column whose name states no unit beside axes whose
//! names state one (`gx_dps, gy_dps, gz`) is refused at the header, naming the column, its
//! siblings' unit and `rate_unit` (`--rate-unit`), instead of being read in the default deg/h
//! 3600 times off; `rate_unit` settles every axis, and axes that all state no unit (or
//! deg/h, the default), or each state their own, read as before.

use crate::common::ingest::{close, fail, read, read_with};
use driftlab::log::ingest::{RateUnit, ReadOptions};
use std::process::Command;

const N: usize = 60;

/// A log of `N` rows whose rate columns (every column between time and temperature) hold
/// distinct known values: row `i` of rate column `k` is `(k + 1) + i / 100`.
fn log_text(header: &str) -> String {
    let rates = header.split(',').count() - 2;
    let mut text = format!("{header}\n");
    for i in 0..N {
        let cells: Vec<String> = (0..rates)
            .map(|k| format!("{}", (k + 1) as f64 + i as f64 / 100.0))
            .collect();
        text.push_str(&format!(
            "{i},{},{}\n",
            cells.join(","),
            20.0 + i as f64 * 0.1
        ));
    }
    text
}

/// What `log_text` wrote in rate column `k`, times `to_dph` (the deg/h in one of its unit).
fn column(k: usize, to_dph: f64) -> Vec<f64> {
    (0..N)
        .map(|i| ((k + 1) as f64 + i as f64 / 100.0) * to_dph)
        .collect()
}

/// The rate of the axis named `name`, deg/h.
fn rate(log: &driftlab::Log, name: &str) -> Vec<f64> {
    log.axis_rate(name)
        .unwrap_or_else(|| panic!("no axis {name} in {:?}", log.axis_names()))
        .to_vec()
}

const DEG_PER_S: f64 = 3600.0;

#[test]
fn an_axis_without_a_unit_beside_axes_with_one_is_refused() {
    // The unit-less column last, and first (where it is the rate column the others follow).
    for (header, column, name) in [
        ("time_s,gx_dps,gy_dps,gz,temp_c", 4, "gz"),
        ("time_s,gx,gy_dps,gz_dps,temp_c", 2, "gx"),
    ] {
        let e = fail(log_text(header).as_bytes(), &ReadOptions::default());
        assert_eq!((e.line, e.column), (1, column), "{header}: {e}");
        for want in [
            &format!("\"{name}\""),
            "states no unit",
            "deg/s",
            "rate_unit",
        ] {
            assert!(e.message.contains(want), "{header}: {want:?} not in: {e}");
        }
    }
}

#[test]
fn rate_unit_given_reads_every_axis_in_it() {
    let o = ReadOptions {
        rate_unit: Some(RateUnit::DegPerSec),
        ..ReadOptions::default()
    };
    let log = read_with(&log_text("time_s,gx_dps,gy_dps,gz,temp_c"), &o);
    for (k, name) in ["gx", "gy", "gz"].into_iter().enumerate() {
        close(&rate(&log, name), &column(k, DEG_PER_S));
    }
}

#[test]
fn axes_with_no_unit_beside_none_or_deg_per_hour_stay_in_deg_per_hour() {
    let log = read(&log_text("time_s,gx,gy,gz,temp_c"));
    for (k, name) in ["gx", "gy", "gz"].into_iter().enumerate() {
        close(&rate(&log, name), &column(k, 1.0));
    }
    // One rate column with no unit: deg/h, as documented.
    let log = read(&log_text("time_s,omega,temp_c"));
    close(&log.omega_dph, &column(0, 1.0));
    // Beside siblings that state deg/h, the default is theirs: nothing to ask.
    let log = read(&log_text("time_s,gx_dph,gy_dph,gz,temp_c"));
    for (k, name) in ["gx", "gy", "gz"].into_iter().enumerate() {
        close(&rate(&log, name), &column(k, 1.0));
    }
}

#[test]
fn axes_that_each_state_their_unit_read_in_their_own() {
    let log = read(&log_text("time_s,gx_dps,gy_rad_s,gz_dph,temp_c"));
    close(&rate(&log, "gx"), &column(0, DEG_PER_S));
    close(
        &rate(&log, "gy"),
        &column(1, 180.0 / std::f64::consts::PI * 3600.0),
    );
    close(&rate(&log, "gz"), &column(2, 1.0));
}

#[test]
fn the_command_line_names_its_flag() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("mixed.csv");
    std::fs::write(&path, log_text("time_s,gx_dps,gy_dps,gz,temp_c")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .arg("inspect")
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "read without refusing: {err}");
    for want in ["mixed.csv:1:4", "\"gz\"", "--rate-unit deg/s"] {
        assert!(err.contains(want), "{want:?} not in: {err}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(["inspect", "--rate-unit", "deg/s"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
