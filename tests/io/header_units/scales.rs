//! A scale beside a rate unit in a header (a number, a sign and a number, a fraction, a ratio,
//! a word that scales, a number glued to the unit): never read as the unit beside it. The
//! rates are written in mdeg/s, so that read as deg/s they would be a thousand times off;
//! each header is refused, naming the column, and given the unit the column reads the truth.
//! A one, words after the unit and a sensor's number glued to its word leave the unit read.

use super::*;

/// Each header of `cases` (with what its refusal quotes of it) over rates in mdeg/s: refused,
/// naming the column, what it states and rate_unit, and `odd` of the message said nothing
/// against it; given rate_unit mdeg/s, the column reads the truth. What failed, in words.
fn refused_in_mdeg(
    cases: &[(&str, &str)],
    odd: impl Fn(&str, &str) -> Option<String>,
) -> Vec<String> {
    let mut failures = Vec::new();
    let given = ReadOptions {
        rate_unit: Some(RateUnit::MilliDegPerSec),
        ..opts()
    };
    for &(name, shown) in cases {
        let text = log_text("time_s", SECOND, name, MDEG_PER_S);
        match refusal(&text, name, &format!("\"{shown}\""), "rate_unit") {
            Ok(m) => failures.extend(odd(name, &m)),
            Err(e) => failures.push(e),
        }
        if let Err(e) = truth_of(&text, &given) {
            failures.push(format!("with rate_unit mdeg/s: {e}"));
        }
    }
    failures
}

#[test]
fn a_scale_beside_a_rate_unit_is_refused_not_dropped() {
    // The same rates in mdeg/s under headers that say so with a number beside deg/s: read as
    // deg/s they would be a thousand times too large, as deg/h (a count glued to the unit)
    // 3.6 times too small. Each is refused, naming the column and what it states, and pointing
    // to rate_unit and mdeg/s; given the unit, the column reads the truth.
    let cases: Vec<(&str, &str)> = vec![
        ("omega [deg/s/1000]", "deg/s/1000"),
        ("omega [deg/s x 1e-3]", "deg/s x 1e-3"),
        ("omega [deg/s]/1000", "[deg/s] 1000"),
        ("omega (deg/s)*1000", "[deg/s] 1000"),
        ("omega 1000*[deg/s]", "1000 [deg/s]"),
        ("omega_dps_div1000", "dps_div1000"),
        ("omega_dps_x1000", "dps_x1000"),
        ("omega_dps_x_1000", "dps_x_1000"),
        ("omega_1000dps", "1000dps"),
        ("omega_1000_dps", "1000_dps"),
        ("x [deg/s]/1000", "[deg/s] 1000"),
    ];
    let mut failures = refused_in_mdeg(&cases, |name, m| {
        (!m.contains("mdeg/s")).then(|| format!("{name}: no mdeg/s in: {m}"))
    });
    // A second axis so named beside one whose unit reads: refused for its scale.
    let gy = log_text("time_s", SECOND, "gx_mdps", MDEG_PER_S).replace(
        "time_s,gx_mdps,temp_c",
        "time_s,gx_mdps,gy_dps_div1000,temp_c",
    );
    let gy: String = gy
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let f: Vec<&str> = l.split(',').collect();
            if i == 0 {
                format!("{l}\n")
            } else {
                format!("{},{},{},{}\n", f[0], f[1], f[1], f[2])
            }
        })
        .collect();
    if let Err(e) = refusal(&gy, "gy_dps_div1000", "\"dps_div1000\"", "rate_unit") {
        failures.push(e);
    }
    none_failed(failures);
    // The command line names its own option.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scaled.csv");
    std::fs::write(
        &path,
        log_text("time_s", SECOND, "omega [deg/s]/1000", MDEG_PER_S),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .arg("inspect")
        .arg(&path)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("\"omega [deg/s]/1000\"")
            && err.contains("--rate-unit")
            && err.contains("mdeg/s"),
        "{err}"
    );
}

#[test]
fn a_fraction_a_ratio_a_scale_word_or_a_glued_number_beside_a_rate_unit_is_refused() {
    // Scales written in other ways than a number beside the unit: a fraction, a ratio sign, a
    // word that scales, a number glued after the unit. Read, the first eight were taken for
    // deg/s and the glued ones for the default deg/h, each without a word. The rates are
    // written in mdeg/s: each header is refused, naming the column, what it states and
    // rate_unit (no command-line option: the library names none), and given rate_unit mdeg/s
    // the column reads the truth.
    let cases: Vec<(&str, &str)> = vec![
        ("omega [deg/s] (1/1000)", "[deg/s] 1 1000"),
        ("omega [deg/s] per 1000", "[deg/s] per 1000"),
        ("omega [thousandths of deg/s]", "thousandths of deg/s"),
        ("omega [deg/s] (milli)", "[deg/s] milli"),
        ("omega [deg/s] ‰", "[deg/s] ‰"),
        ("omega [% of deg/s]", "% of deg/s"),
        ("omega [ppm deg/s]", "ppm deg/s"),
        ("omega_dps_k", "dps_k"),
        ("omega_dps_per_lsb", "dps_per_lsb"),
        ("omega_dps3", "dps3"),
        ("omega_mdps2", "mdps2"),
        ("gyro_x_rad_s2", "rad_s2"),
        ("omega_1dps", "1dps"),
    ];
    let failures = refused_in_mdeg(&cases, |name, m| {
        m.contains("--")
            .then(|| format!("{name}: an option in: {m}"))
    });
    none_failed(failures);
    // The command line words the same refusal with its own option.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("glued.csv");
    std::fs::write(&path, log_text("time_s", SECOND, "omega_dps3", DEG_PER_S)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .arg("inspect")
        .arg(&path)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("\"omega_dps3\"") && err.contains("--rate-unit") && !err.contains("rate_unit"),
        "{err}"
    );
}

#[test]
fn a_sensors_number_is_judged_alike_wherever_it_stands() {
    // Glued to the word it numbers, a sensor's or an axis's number is a note before the unit,
    // after it or away from it: each column reads the truth in deg/s.
    for name in [
        "gyro1_dps",
        "imu2_omega_dps",
        "omega_x1_dps",
        "omega_y2_dps",
        "omega_dps_imu2",
        "gyro_x2_raw_dps",
    ] {
        let log = reads_truth(&log_text("time_s", SECOND, name, DEG_PER_S), &opts());
        assert_eq!(unit_of(&log, ColumnRole::Rate), "deg/s", "{name}");
    }
    // Standing alone beside the unit, a number may be a sensor's or a scale, before the unit
    // or after it: refused, and the message says how a sensor's number is read.
    let mut failures = Vec::new();
    for (name, shown) in [("gyro_2_dps", "2_dps"), ("omega_dps_3", "dps_3")] {
        let text = log_text("time_s", SECOND, name, DEG_PER_S);
        match refusal(&text, name, &format!("\"{shown}\""), "rate_unit") {
            Ok(m) if !m.contains("gyro2_dps") => {
                failures.push(format!("{name}: no word of a sensor's number in: {m}"))
            }
            Ok(_) => {}
            Err(e) => failures.push(e),
        }
    }
    none_failed(failures);
}

#[test]
fn a_one_or_a_word_beside_a_rate_unit_leaves_it_read() {
    // One of a unit is that unit; words after a unit, a sensor's number among them, say what
    // the column is.
    for (name, factor, unit) in [
        ("omega_1_dps", DEG_PER_S, "deg/s"),
        ("omega [deg/s] x1", DEG_PER_S, "deg/s"),
        ("omega_dps_x", DEG_PER_S, "deg/s"),
        ("Rate (deg/s) gyro 2", DEG_PER_S, "deg/s"),
        ("gyro2_dps", DEG_PER_S, "deg/s"),
        ("omega_dps_imu2", DEG_PER_S, "deg/s"),
    ] {
        let log = reads_truth(&log_text("time_s", SECOND, name, factor), &opts());
        assert_eq!(unit_of(&log, ColumnRole::Rate), unit, "{name}");
    }
}

#[test]
fn a_one_column_series_refuses_a_scale_beside_its_unit() {
    // Allan's rate series (one column, no time): read in deg/s, these mdeg/s rates would be a
    // thousand times too large.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("series.csv");
    let values: String = (0..N)
        .map(|i| format!("{}\n", drift_dph(i) / MDEG_PER_S))
        .collect();
    for name in ["omega [deg/s]/1000", "omega_dps_x1000", "omega_1000dps"] {
        std::fs::write(&path, format!("{name}\n{values}")).unwrap();
        let e = driftlab::log::ingest::read_rate_series(&path, &opts())
            .expect_err(name)
            .to_string();
        assert!(
            e.contains(&format!("\"{name}\"")) && e.contains("rate_unit") && e.contains("mdeg/s"),
            "{name}: {e}"
        );
        let given = ReadOptions {
            rate_unit: Some(RateUnit::MilliDegPerSec),
            ..opts()
        };
        let s = driftlab::log::ingest::read_rate_series(&path, &given)
            .unwrap()
            .unwrap();
        close(&s.omega_dph, &truth_rate());
    }
}
