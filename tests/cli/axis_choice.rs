//! Which axis a calibration is for is never guessed: a per-axis option given twice for one
//! axis is refused with both values, and a calibration of one axis (which records no column)
//! on a CSV log of several gyro axes is refused until `--rate-col` names the axis, then
//! corrects exactly that column; on a drone log, whose columns are the format's, it corrects
//! the gyro's X axis and says so.

use crate::common::run::{driftlab, fails, ok, p, sample};
use std::path::Path;

/// Asserts that `driftlab ARGS` fails with status 1 and one line holding every one of
/// `words`, and that `out` was not written.
fn refused(args: &[&str], words: &[&str], out: &str) {
    let run = driftlab(args);
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: no {w:?} in {err}");
    }
    assert!(!Path::new(out).exists(), "{args:?} wrote {out}");
}

#[test]
fn an_axis_given_twice_a_model_or_a_recipe_is_refused_with_both() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = sample("imu3-calibration.csv");
    let out = p(d, "unit.json");
    // By name, and by name and letter (one axis).
    for second in ["gx=ieee952", "x=ieee952"] {
        refused(
            &[
                "calibrate",
                &log,
                "--axis-model",
                "gx=poly-t",
                "--axis-model",
                second,
                "-o",
                &out,
            ],
            &[
                &format!("--axis-model gx=poly-t and --axis-model {second}"),
                "both give axis gx",
            ],
            &out,
        );
    }
    let (r1, r2) = (p(d, "r1.json"), p(d, "r2.json"));
    std::fs::write(
        &r1,
        r#"{"k0":{"kind":"pwl","knots":3,"extrapolate":false}}"#,
    )
    .unwrap();
    std::fs::write(
        &r2,
        r#"{"k0":{"kind":"linear","knots":3,"extrapolate":false}}"#,
    )
    .unwrap();
    let (a1, a2) = (format!("gy={r1}"), format!("gy_dps={r2}"));
    refused(
        &[
            "calibrate",
            &log,
            "--axis-recipe",
            &a1,
            "--axis-recipe",
            &a2,
            "-o",
            &out,
        ],
        &[
            &format!("--axis-recipe {a1} and --axis-recipe {a2}"),
            "both give axis gy",
        ],
        &out,
    );
    // One value for each of two axes is taken.
    ok(&[
        "calibrate",
        &log,
        "--axis-model",
        "gx=poly-t",
        "--axis-model",
        "gy=ieee952",
        "-o",
        &out,
    ]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let spec = |k: usize| json["axes"][k]["calibration"]["model"]["spec"]["name"].clone();
    assert_eq!((spec(0), spec(1)), ("poly-t".into(), "ieee952".into()));
}

/// The first `n` values of the column `name` of the stand log `path` (`;` between cells, a
/// decimal comma, `#` comment lines), in deg/s.
fn stand_column(path: &str, name: &str, n: usize) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(';').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .take(n)
        .map(|l| {
            l.split(';')
                .nth(k)
                .unwrap()
                .replace(',', ".")
                .parse()
                .unwrap()
        })
        .collect()
}

#[test]
fn a_calibration_of_one_axis_on_a_log_of_three_needs_the_axis_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "gy.json");
    let (train, held) = (
        sample("imu3-calibration.csv"),
        sample("imu3-validation.csv"),
    );
    ok(&["calibrate", &train, "--rate-col", "gy_dps", "-o", &cal]);
    let cor = p(d, "cor.csv");
    let rep = p(d, "rep");
    let words = ["gy.json", "3 gyro axes (gx, gy, gz)", "--rate-col"];
    refused(&["apply", &cal, &held, "-o", &cor], &words, &cor);
    refused(&["evaluate", &cal, &held], &words, &cor);
    refused(&["report", &cal, &held, "--out", &rep], &words, &rep);

    // Named, the column named is the one corrected: its raw rate is the log's gy, in deg/h.
    ok(&["apply", &cal, &held, "--rate-col", "gy_dps", "-o", &cor]);
    let mut reader = csv::Reader::from_path(&cor).unwrap();
    let raw: Vec<f64> = reader
        .records()
        .take(50)
        .map(|r| r.unwrap()[1].parse().unwrap())
        .collect();
    let (gx, gy) = (
        stand_column(&held, "gx_dps", 50),
        stand_column(&held, "gy_dps", 50),
    );
    for k in 0..50 {
        assert!(
            (raw[k] - gy[k] * 3600.0).abs() <= 1e-9 * gy[k].abs().max(1e-3),
            "{k}"
        );
    }
    assert!(
        raw.iter()
            .zip(&gx)
            .any(|(r, x)| (r - x * 3600.0).abs() > 1e-3)
    );
    ok(&["evaluate", &cal, &held, "--rate-col", "gy_dps"]);

    // A log of one axis takes it as it always has.
    let one = p(d, "one.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &one]);
    ok(&["apply", &one, &sample("validation.csv"), "-o", &cor]);
}

#[test]
fn a_calibration_of_one_axis_on_a_drone_log_corrects_its_x_axis_and_says_so() {
    // A drone log's columns are its format's, not chosen with --rate-col: the one axis is the
    // gyro's X, as export writes a single calibration, and a note says so.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 300;
    let time_s: Vec<f64> = (0..n).map(f64::from).collect();
    let gyro: Vec<[f32; 3]> = (0..n)
        .map(|k| {
            let w = 1e-4 * (1.0 + f64::from(k) / 1000.0);
            [w as f32, 2.0 * w as f32, -3.0 * w as f32]
        })
        .collect();
    let temp: Vec<f32> = (0..n).map(|k| 20.0 + k as f32 * 0.05).collect();
    let ulg = d.join("flight.ulg");
    std::fs::write(
        &ulg,
        crate::common::drone::ulog(&time_s, &gyro, &temp, 2_424_842),
    )
    .unwrap();
    let cal = p(d, "one.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let cor = p(d, "cor.csv");
    let run = driftlab(&["apply", &cal, &ulg.display().to_string(), "-o", &cor]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    assert!(
        err.contains("a calibration of one axis") && err.contains("it corrects gyro_x"),
        "{err}"
    );
    let mut reader = csv::Reader::from_path(&cor).unwrap();
    let to_dph = 180.0 / std::f64::consts::PI * 3600.0;
    let mut rows = 0;
    for (r, g) in reader.records().zip(&gyro) {
        let raw: f64 = r.unwrap()[1].parse().unwrap();
        let x = f64::from(g[0]) * to_dph;
        assert!((raw - x).abs() <= 1e-5 * x.abs(), "{raw} against {x}");
        rows += 1;
    }
    assert_eq!(rows, n as usize);
}

#[test]
fn axes_and_a_single_rate_column_both_choosing_the_axis_are_refused() {
    // `--axes gx --rate-col gy_dps` calibrated gx and dropped --rate-col without a word.
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "both.json");
    let log = sample("imu3-calibration.csv");
    let words = [
        "--axes gx and --rate-col gy_dps both choose the axis",
        "give one of them",
    ];
    refused(
        &[
            "calibrate",
            &log,
            "--axes",
            "gx",
            "--rate-col",
            "gy_dps",
            "-o",
            &cal,
        ],
        &words,
        &cal,
    );
    let e = fails(&["allan", &log, "--axes", "gx", "--rate-col", "gy_dps"]);
    assert!(words.iter().all(|w| e.contains(w)), "{e}");
    let e = fails(&[
        "compare",
        "--train",
        &log,
        "--axes",
        "gx",
        "--rate-col",
        "gy_dps",
        "--models",
        "poly-t",
    ]);
    assert!(words.iter().all(|w| e.contains(w)), "{e}");
}

#[test]
fn inspect_pairs_each_of_four_hundred_axes_with_its_column_and_bounds_the_advice() {
    // 400 rate columns `omega_aaa_dph` … `omega_apj_dph` and 20 rows: each axis is named from
    // its column, and is listed with it.
    let dir = tempfile::tempdir().unwrap();
    let letters = |k: usize| {
        let l = |i: usize| char::from(b'a' + u8::try_from(i).unwrap());
        format!("{}{}{}", l(k / 676), l(k / 26 % 26), l(k % 26))
    };
    let n = 400;
    let mut text = String::from("time_s,");
    for k in 0..n {
        text.push_str(&format!("omega_{}_dph,", letters(k)));
    }
    text.push_str("temp_c\n");
    for r in 0..20 {
        text.push_str(&format!("{r},"));
        for k in 0..n {
            text.push_str(&format!("{:.1},", r as f64 * 0.1 + k as f64));
        }
        text.push_str(&format!("{:.2}\n", 20.0 + r as f64 * 0.01));
    }
    let log = p(dir.path(), "wide.csv");
    std::fs::write(&log, text).unwrap();
    let seen = ok(&["inspect", &log]);
    let axes = seen
        .lines()
        .find(|l| l.starts_with("  gyro axes: "))
        .unwrap_or_else(|| panic!("{seen}"));
    let listed: Vec<&str> = axes["  gyro axes: ".len()..].split(", ").collect();
    assert_eq!(listed.len(), n, "{axes}");
    for (k, item) in listed.iter().enumerate() {
        let w = letters(k);
        assert_eq!(*item, format!("omega_{w} [deg/h] (column omega_{w}_dph)"));
    }
    assert_eq!(letters(n - 1), "apj");
    // Every column listed, the last rate column as column 401.
    assert!(
        seen.contains("   401  omega_apj_dph            OtherAxis [deg/h]"),
        "{seen}"
    );
    // A unit holds at most 64 axes: the advice says so instead of "every axis".
    assert!(
        seen.contains(
            "calibrate fits at most 64 axes into one unit calibration, and this log has 400: \
             choose them (--axes omega_aaa,omega_aab), or one alone (--rate-col NAME);"
        ),
        "{seen}"
    );
}
