//! A corpus of odd but valid logs, as test stands really write them: semicolons and decimal
//! commas, tabs, a byte-order mark, CRLF, quoted fields, comment lines, units in the headers,
//! missing cells, time in milliseconds or minutes, aligned columns. Each is written in the
//! test from known values and must read back as exactly those numbers, converted to driftlab's
//! units (s, °/h, °C) by factors written out here, not taken from the reader.
//!
//! tests/ingest_*.rs hold the reader's unit tests (one feature per test, and the malformed
//! inputs); this file combines the oddities the way whole files from real stands do.

use driftlab::Log;
use driftlab::log::ProblemKind;
use driftlab::log::ingest::{self, ReadOptions};

/// Values that print exactly (multiples of 1/8), so the text holds exactly the number.
fn time_s(i: usize) -> f64 {
    i as f64 * 0.25
}
fn omega(i: usize) -> f64 {
    -1.5 + 0.125 * i as f64 - 0.375 * (i % 3) as f64
}
fn temp(i: usize) -> f64 {
    -12.5 + 0.75 * i as f64
}
fn housing(i: usize) -> f64 {
    -11.0 + 0.5 * i as f64
}

const ROWS: usize = 12;
const DEG_PER_S_IN_DPH: f64 = 3600.0;
const RAD_PER_S_IN_DPH: f64 = 3600.0 * 180.0 / std::f64::consts::PI;

/// A number as a stand with a decimal comma writes it.
fn comma(v: f64) -> String {
    format!("{v}").replace('.', ",")
}

fn read(name: &str, text: &str) -> Log {
    read_with(name, text, &ReadOptions::default())
}

fn read_with(name: &str, text: &str, opts: &ReadOptions) -> Log {
    ingest::read_bytes(name, text.as_bytes(), opts).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Asserts `got` equals `want` to a relative 1e-12 (conversions multiply and divide).
fn same(case: &str, what: &str, got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{case}: {what} length");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= 1e-12 * w.abs().max(1.0),
            "{case}: {what}[{k}] = {g}, wrote {w}"
        );
    }
}

/// Checks the three calibration columns against the values written at rows `rows`, with
/// the rate written in a unit `rate_factor` °/h each.
fn check(case: &str, log: &Log, rows: &[usize], time_factor: f64, rate_factor: f64) {
    let t: Vec<f64> = rows.iter().map(|&i| time_s(i) * time_factor).collect();
    let w: Vec<f64> = rows.iter().map(|&i| omega(i) * rate_factor).collect();
    let c: Vec<f64> = rows.iter().map(|&i| temp(i)).collect();
    same(case, "time", &log.time_s, &t);
    same(case, "omega", &log.omega_dph, &w);
    same(case, "temp", &log.temp_c, &c);
}

fn all_rows() -> Vec<usize> {
    (0..ROWS).collect()
}

#[test]
fn semicolons_decimal_commas_bom_crlf_and_comments() {
    // A Russian stand's export: BOM, CRLF, a comment block, semicolons, decimal commas.
    let mut text = String::from("\u{feff}# Стенд 3, гироскоп № 0042\r\n# 2024-03-01 08:00\r\n");
    text += "time_s;omega_dph;temp_c\r\n";
    for i in 0..ROWS {
        if i == 5 {
            text += "# door opened\r\n\r\n";
        }
        text += &format!(
            "{};{};{}\r\n",
            comma(time_s(i)),
            comma(omega(i)),
            comma(temp(i))
        );
    }
    let log = read("stand3.csv", &text);
    assert_eq!(log.info.delimiter, ';');
    assert!(log.info.decimal_comma);
    check("stand3", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn cyrillic_header_with_units_after_commas() {
    let mut text = String::from("Время, с;Омега, град/ч;Температура, °C\n");
    for i in 0..ROWS {
        text += &format!(
            "{};{};{}\n",
            comma(time_s(i)),
            comma(omega(i)),
            comma(temp(i))
        );
    }
    let log = read("russian.csv", &text);
    check("russian", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn tabs_with_units_in_brackets() {
    let mut text = String::from("Time [s]\tRate [deg/s]\tTemp [°C]\n");
    for i in 0..ROWS {
        text += &format!("{}\t{}\t{}\n", time_s(i), omega(i), temp(i));
    }
    let log = read("tabs.tsv", &text);
    assert_eq!(log.info.delimiter, '\t');
    check("tabs", &log, &all_rows(), 1.0, DEG_PER_S_IN_DPH);
}

#[test]
fn quoted_fields_with_commas_in_names_and_time_in_ms() {
    let mut text = String::from("\"Time, ms\",\"Omega, deg/h\",\"Temperature, °C\"\n");
    for i in 0..ROWS {
        text += &format!(
            "\"{}\",\"{}\",\"{}\"\n",
            time_s(i) * 1000.0,
            omega(i),
            temp(i)
        );
    }
    let log = read("quoted.csv", &text);
    check("quoted", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn quoted_decimal_commas_between_semicolons() {
    let mut text = String::from("\"time\";\"omega\";\"temp\"\n");
    for i in 0..ROWS {
        text += &format!(
            "\"{}\";\"{}\";\"{}\"\n",
            comma(time_s(i)),
            comma(omega(i)),
            comma(temp(i))
        );
    }
    let log = read("quoted-semicolons.csv", &text);
    check("quoted-semicolons", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn unit_suffixes_in_names_ms_and_rad_per_s() {
    let mut text = String::from("time_ms,gyro_x_rad_s,temp_c\n");
    for i in 0..ROWS {
        text += &format!("{},{},{}\n", time_s(i) * 1000.0, omega(i), temp(i));
    }
    let log = read("suffixes.csv", &text);
    check("suffixes", &log, &all_rows(), 1.0, RAD_PER_S_IN_DPH);
}

#[test]
fn minutes_and_kelvin() {
    let mut text = String::from("t [min],omega_dph,Temp [K]\n");
    for i in 0..ROWS {
        text += &format!("{},{},{}\n", time_s(i), omega(i), temp(i) + 273.15);
    }
    let log = read("minutes.csv", &text);
    same(
        "minutes",
        "time",
        &log.time_s,
        &(0..ROWS).map(|i| time_s(i) * 60.0).collect::<Vec<_>>(),
    );
    same(
        "minutes",
        "omega",
        &log.omega_dph,
        &(0..ROWS).map(omega).collect::<Vec<_>>(),
    );
    // 273.15 is not exact in binary: K → °C is exact to rounding of the sum.
    for (i, &c) in log.temp_c.iter().enumerate() {
        assert!(
            (c - temp(i)).abs() < 1e-9,
            "temp[{i}] = {c}, wrote {}",
            temp(i)
        );
    }
}

#[test]
fn missing_cells_drop_the_row_or_leave_a_gap_in_an_extra_channel() {
    // Row 3 has no rate, row 7 a NaN temperature, row 9 a blank housing temperature (an extra
    // channel: kept, NaN there).
    let mut text = String::from("time;omega;temp;temp_housing\n");
    for i in 0..ROWS {
        let w = if i == 3 {
            String::new()
        } else {
            comma(omega(i))
        };
        let c = if i == 7 { "NaN".into() } else { comma(temp(i)) };
        let h = if i == 9 {
            String::new()
        } else {
            comma(housing(i))
        };
        text += &format!("{};{w};{c};{h}\n", comma(time_s(i)));
    }
    let log = read("missing.csv", &text);
    let kept: Vec<usize> = (0..ROWS).filter(|&i| i != 3 && i != 7).collect();
    check("missing", &log, &kept, 1.0, 1.0);
    let h = &log.channel("temp_housing").expect("housing channel").values;
    for (k, &i) in kept.iter().enumerate() {
        if i == 9 {
            assert!(h[k].is_nan());
        } else {
            assert_eq!(h[k], housing(i));
        }
    }
    // Each dropped row is reported with its line and column (header on line 1, row i on
    // line i + 2).
    let missing: Vec<(usize, Option<usize>, usize)> = log
        .info
        .problems
        .iter()
        .filter(|p| p.kind == ProblemKind::MissingValue)
        .map(|p| (p.line, p.column, p.count))
        .collect();
    assert_eq!(missing, [(5, Some(2), 1), (9, Some(3), 1)]);
}

#[test]
fn whitespace_aligned_columns() {
    let mut text = String::from("      time       omega        temp\n");
    for i in 0..ROWS {
        text += &format!("{:>10} {:>11} {:>11}\n", time_s(i), omega(i), temp(i));
    }
    let log = read("aligned.txt", &text);
    assert_eq!(log.info.delimiter, ' ');
    check("aligned", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn no_header_semicolons_and_decimal_commas() {
    let mut text = String::new();
    for i in 0..ROWS {
        text += &format!(
            "{};{};{}\n",
            comma(time_s(i)),
            comma(omega(i)),
            comma(temp(i))
        );
    }
    let log = read("bare.csv", &text);
    assert!(!log.info.has_header);
    check("bare", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn extra_channels_trailing_separators_and_no_final_line_end() {
    let mut text = String::from("time,omega,temp_c,temp_housing_c,laser_power_mw,\n");
    for i in 0..ROWS {
        text += &format!(
            "{},{},{},{},{},\n",
            time_s(i),
            omega(i),
            temp(i),
            housing(i),
            0.5 + 0.0625 * i as f64
        );
    }
    text.pop(); // no line end after the last row
    let log = read("extras.csv", &text);
    check("extras", &log, &all_rows(), 1.0, 1.0);
    same(
        "extras",
        "temp_housing_c",
        &log.channel("temp_housing_c").expect("housing").values,
        &(0..ROWS).map(housing).collect::<Vec<_>>(),
    );
    same(
        "extras",
        "laser_power_mw",
        &log.channel("laser_power_mw").expect("laser power").values,
        &(0..ROWS)
            .map(|i| 0.5 + 0.0625 * i as f64)
            .collect::<Vec<_>>(),
    );
}

#[test]
fn scientific_notation_and_explicit_signs() {
    let mut text = String::from("time,omega,temp\n");
    for i in 0..ROWS {
        text += &format!("{:e},{:+},{:E}\n", time_s(i), omega(i), temp(i));
    }
    let log = read("sci.csv", &text);
    check("sci", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn sample_counter_with_a_sample_rate() {
    let mut text = String::from("sample;omega_dph;temp_c\n");
    for i in 0..ROWS {
        text += &format!("{};{};{}\n", i, comma(omega(i)), comma(temp(i)));
    }
    let opts = ReadOptions {
        sample_rate_hz: Some(4.0),
        ..ReadOptions::default()
    };
    let log = read_with("counter.csv", &text, &opts);
    // 4 Hz: sample i at i/4 s, which is time_s(i).
    check("counter", &log, &all_rows(), 1.0, 1.0);
}

#[test]
fn everything_at_once() {
    // BOM, comments, quoted header with units, semicolons, decimal commas, CRLF, a blank
    // extra cell, a trailing comment and blank lines.
    let mut text = String::from("\u{feff}# exported by stand software 2.1\r\n");
    text += "\"Time [ms]\";\"Rate [deg/s]\";\"Temp [°C]\";\"Temp housing [°C]\"\r\n";
    for i in 0..ROWS {
        let h = if i == 4 {
            String::new()
        } else {
            comma(housing(i))
        };
        text += &format!(
            "{};{};{};{h}\r\n",
            comma(time_s(i) * 1000.0),
            comma(omega(i)),
            comma(temp(i))
        );
    }
    text += "# end of run\r\n\r\n";
    let log = read("everything.csv", &text);
    check("everything", &log, &all_rows(), 1.0, DEG_PER_S_IN_DPH);
    assert_eq!(log.extra.len(), 1);
    let h = &log.extra[0].values;
    assert!(h[4].is_nan());
    assert_eq!(h[5], housing(5));
}
