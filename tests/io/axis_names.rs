//! Two rate columns never share an axis: columns whose names read as one axis (`gx_dph` and
//! `gx_mdps`, `GX_dph` and `gx_dph`, three columns named `omega_dph`) each become an axis of
//! their own, named by its column, and every command analyses each column's own samples.

use crate::common::ingest::{close, read};
use std::process::Command;

/// A log of `n` rows whose rate columns hold distinct known values: row `i` of column `k` is
/// `(k + 1) * 100 + i` in the column's own unit.
fn log_text(header: &str, n: usize) -> String {
    let rates = header.split(',').count() - 2;
    let mut text = format!("{header}\n");
    for i in 0..n {
        let cells: Vec<String> = (0..rates)
            .map(|k| format!("{}", (k + 1) * 100 + i))
            .collect();
        text.push_str(&format!(
            "{i},{},{}\n",
            cells.join(","),
            20.0 + i as f64 * 1e-3
        ));
    }
    text
}

/// The rate of the axis named `name`, °/h.
fn rate(log: &driftlab::Log, name: &str) -> Vec<f64> {
    log.axis_rate(name)
        .unwrap_or_else(|| panic!("no axis {name} in {:?}", log.axis_names()))
        .to_vec()
}

/// The values `log_text` put in column `k`, scaled to °/h by `to_dph`.
fn column(k: usize, n: usize, to_dph: f64) -> Vec<f64> {
    (0..n)
        .map(|i| ((k + 1) * 100 + i) as f64 * to_dph)
        .collect()
}

#[test]
fn columns_that_read_as_one_axis_are_each_their_own_axis() {
    let n = 50;
    let log = read(&log_text("time_s,gx_dph,gx_raw_dph,gx_mdps,temp_c", n));
    assert_eq!(log.axis_names(), ["gx_dph", "gx_raw", "gx_mdps"]);
    close(&rate(&log, "gx_dph"), &column(0, n, 1.0));
    close(&rate(&log, "gx_raw"), &column(1, n, 1.0));
    // 1 mdeg/s = 3.6 deg/h.
    close(&rate(&log, "gx_mdps"), &column(2, n, 3.6));
    assert_eq!(log.rate_column().as_deref(), Some("gx_dph"));
    assert_eq!(log.find_axis("gx_mdps").as_deref(), Some("gx_mdps"));

    let log = read(&log_text("time_s,gx_dph,GX_dph,gy_dph,temp_c", n));
    assert_eq!(log.axis_names(), ["gx_dph", "GX_dph", "gy"]);
    close(&rate(&log, "GX_dph"), &column(1, n, 1.0));
}

#[test]
fn columns_of_one_name_are_told_apart_by_their_number() {
    let n = 50;
    let mut log = read(&log_text("time_s,omega_dph,omega_dph,omega_dph,temp_c", n));
    let names = log.axis_names();
    assert_eq!(names, ["omega_col2", "omega_col3", "omega_col4"]);
    for (k, name) in names.iter().enumerate() {
        close(&rate(&log, name), &column(k, n, 1.0));
    }
    // Selecting an axis swaps in its own column, and the column it came from is found again.
    assert!(log.select_axis("omega_col4"));
    close(&log.omega_dph, &column(2, n, 1.0));
    assert_eq!(log.rate_column().as_deref(), Some("omega_dph"));
}

#[test]
fn a_blank_or_invisible_character_in_a_column_name_stays_out_of_its_axis_name() {
    // Characters that print as nothing or as a blank without being Unicode format characters
    // (Hangul fillers, the braille blank, the combining grapheme joiner, a variation
    // selector, a Khmer inherent vowel, spaces other than the ASCII one), a noncharacter, an
    // unassigned and a private-use code point: a column `omega_y` with one of them named the
    // axis `omega_y` and the character, which printed as `omega_y` and was another axis to
    // every output. The axis is named as the column prints, each column's own values read.
    let n = 20;
    for c in [
        '\u{3164}', '\u{115f}', '\u{1160}', '\u{ffa0}', '\u{2800}', '\u{34f}', '\u{fe0f}',
        '\u{17b4}', '\u{a0}', '\u{2000}', '\u{3000}', '\u{fffe}', '\u{378}', '\u{e000}',
    ] {
        let header = format!("time_s,omega_x_dph,omega_y{c}_dph,omega_z_dph{c},temp_c");
        let log = read(&log_text(&header, n));
        assert_eq!(
            log.axis_names(),
            ["omega_x", "omega_y", "omega_z"],
            "U+{:04X}",
            c as u32
        );
        for (k, name) in ["omega_x", "omega_y", "omega_z"].iter().enumerate() {
            close(&rate(&log, name), &column(k, n, 1.0));
        }
    }
    // A space other than the ASCII one still parts two words, as a space does: the unit
    // after it is read (1 deg/s = 3600 deg/h).
    let log = read(&log_text("time_s,gx\u{a0}dps,temp_c", n));
    assert_eq!(log.axis_names(), ["gx"]);
    close(&rate(&log, "gx"), &column(0, n, 3600.0));
}

#[test]
fn allan_analyses_each_columns_own_samples() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("unit.csv");
    // White noise of three different sizes, one column each, all read as axis "gx".
    let mut noise = crate::common::Noise::new(7);
    let mut text = String::from("time_s,gx_dph,gx_raw_dph,gx_mdps,temp_c\n");
    for i in 0..4096 {
        let (a, b, c) = (noise.normal(), noise.normal(), noise.normal());
        text.push_str(&format!("{i},{},{},{},20\n", a, 10.0 * b, 100.0 * c));
    }
    std::fs::write(&path, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(["allan", "--json"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let axes = json["axes"].as_array().expect("axes");
    let first: Vec<f64> = axes
        .iter()
        .map(|a| a["adev"][0].as_f64().expect("adev at the first tau"))
        .collect();
    let names: Vec<&str> = axes.iter().map(|a| a["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["gx_dph", "gx_raw", "gx_mdps"]);
    // σ(τ0) of white noise is its standard deviation: 1, 10 and 100 × 3.6 deg/h.
    for (got, want) in first.iter().zip([1.0, 10.0, 360.0]) {
        assert!((got / want - 1.0).abs() < 0.1, "{first:?}");
    }
}
