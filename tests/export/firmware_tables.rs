//! The firmware export's lookup tables give driftlab's values at their grid points and stay
//! within the error bound of linear interpolation between them; `driftlab export` writes
//! both the header and the tables, and refuses bad input with a reason.

use driftlab::export::firmware::{self, ExportError, ExportOptions, Format};
use driftlab::files::calibration;
use driftlab::models::approx::{Approx, ApproxKind, Curve};
use driftlab::models::vakhrameev::Regime;
use std::path::Path;

use crate::common;
use common::firmware::*;

// ---- Tables ----------------------------------------------------------------------------

/// One table: its arguments and the coefficient's values there.
type Table = (Vec<f64>, Vec<f64>);

/// The header and tables of a csv-table export (K0, K1+, K1−, K2+, K2− in that order).
fn parse_table(text: &str) -> (Vec<String>, Vec<Table>) {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let mut tables = vec![(Vec::new(), Vec::new()); 5];
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(v.len(), 10, "{line}");
        for (k, t) in tables.iter_mut().enumerate() {
            t.0.push(v[2 * k]);
            t.1.push(v[2 * k + 1]);
        }
    }
    (header, tables)
}

/// Linear interpolation in a table as the module documentation tells firmware to do it.
fn interpolate(xs: &[f64], ks: &[f64], v: f64) -> f64 {
    let n = xs.len();
    if v <= xs[0] {
        return ks[0];
    }
    if v >= xs[n - 1] {
        return ks[n - 1];
    }
    let h = (xs[n - 1] - xs[0]) / (n - 1) as f64;
    let mut j = (((v - xs[0]) / h) as usize).min(n - 2);
    // Rounding in v/h can land one row off; the row is the last one with x_j <= v.
    while j > 0 && xs[j] > v {
        j -= 1;
    }
    while j + 2 < n && xs[j + 1] <= v {
        j += 1;
    }
    let t = (v - xs[j]) / (xs[j + 1] - xs[j]);
    ks[j] + t * (ks[j + 1] - ks[j])
}

/// The bound on |linear interpolation − curve| over `[lo, hi]`: `(hi−lo)²/8·max|K''|` where
/// the curve is C¹ (polynomials, Catmull-Rom), and `(hi−lo)/4·Σ|jump of slope|` over the kinks
/// of a piecewise-linear curve inside the step.
fn interpolation_bound(a: &Approx, lo: f64, hi: f64) -> f64 {
    let h = hi - lo;
    match a.curve() {
        Curve::Polynomial { coeffs } => {
            let r = lo.abs().max(hi.abs());
            let m: f64 = coeffs
                .iter()
                .enumerate()
                .skip(2)
                .map(|(k, c)| (k * (k - 1)) as f64 * c.abs() * r.powi(k as i32 - 2))
                .sum();
            h * h / 8.0 * m
        }
        Curve::Pwl { .. } => {
            let s = a.segment_cubics().unwrap();
            let slope = |i: usize| s.coeffs[i][1] / (s.knots_x[i + 1] - s.knots_x[i]);
            let jumps: f64 = (1..s.knots_x.len() - 1)
                .filter(|&m| s.knots_x[m] > lo && s.knots_x[m] < hi)
                .map(|m| (slope(m) - slope(m - 1)).abs())
                .sum();
            h / 4.0 * jumps
        }
        Curve::CatmullRom { .. } => {
            // K'' on segment i is (2c2 + 6c3·u)/Δ², largest at an end of the segment.
            let s = a.segment_cubics().unwrap();
            let m = (0..s.coeffs.len())
                .filter(|&i| s.knots_x[i] < hi && s.knots_x[i + 1] > lo)
                .map(|i| {
                    let c = s.coeffs[i];
                    let d = s.knots_x[i + 1] - s.knots_x[i];
                    (2.0 * c[2]).abs().max((2.0 * c[2] + 6.0 * c[3]).abs()) / (d * d)
                })
                .fold(0.0, f64::max);
            h * h / 8.0 * m
        }
    }
}

#[test]
fn tables_give_the_curves_at_grid_points_and_stay_within_the_bound_between() {
    let cal_log = read("calibration.csv");
    for kind in ApproxKind::ALL {
        let cal = calibrate(&cal_log, [kind; 3], false);
        for points in [101, 7, 2] {
            let text = firmware::export(
                &cal,
                Format::CsvTable,
                &ExportOptions {
                    points,
                    ..ExportOptions::default()
                },
            )
            .unwrap();
            let (header, tables) = parse_table(&text);
            assert_eq!(header[0], "T [degC]");
            assert_eq!(header[3], "K1+ [(deg/h)/(degC/s)]");
            assert_eq!(header[9], "K2- [(deg/h)/(degC/s^2)]");
            let (mut worst_share, mut worst_err): (f64, f64) = (0.0, 0.0);
            for ((name, a), (xs, ks)) in cal.approximations().into_iter().zip(&tables) {
                assert_eq!(xs.len(), points);
                assert_eq!((xs[0], xs[points - 1]), (a.x_min(), a.x_max()), "{name}");
                let scale = ks.iter().fold(0.0f64, |m, k| m.max(k.abs())).max(1e-300);
                let slack = 1e-12 * scale;
                for j in 0..points {
                    // At the grid points: driftlab's value, exactly.
                    assert_eq!(ks[j], a.eval(xs[j]), "{name} row {j}");
                    assert_eq!(interpolate(xs, ks, xs[j]), ks[j], "{name} row {j}");
                    if j + 1 == points {
                        continue;
                    }
                    let (lo, hi) = (xs[j], xs[j + 1]);
                    let bound = interpolation_bound(a, lo, hi);
                    for k in 1..16 {
                        let x = lo + (hi - lo) * k as f64 / 16.0;
                        let err = (interpolate(xs, ks, x) - a.eval(x)).abs();
                        assert!(
                            err <= bound + slack,
                            "{kind}, {points} points, {name} at {x}: error {err:e} > bound {bound:e}"
                        );
                        worst_err = worst_err.max(err);
                        if bound > slack {
                            worst_share = worst_share.max(err / bound);
                        }
                    }
                }
                // Beyond the range: the edge values, as driftlab holds them.
                let span = a.x_max() - a.x_min();
                assert_eq!(interpolate(xs, ks, a.x_min() - span - 1.0), ks[0]);
                assert_eq!(interpolate(xs, ks, a.x_max() + span + 1.0), ks[points - 1]);
            }
            println!(
                "{kind}, {points} points: largest interpolation error {worst_err:.3e}, \
                 {:.0}% of its bound (0: no curvature, exact up to rounding)",
                worst_share * 100.0
            );
        }
    }
}

#[test]
fn tables_refuse_fewer_than_two_points() {
    let cal = calibrate(&read("calibration.csv"), [ApproxKind::Linear; 3], false);
    for (points, want) in [
        (0, ExportError::TooFewPoints(0)),
        (1, ExportError::TooFewPoints(1)),
        (
            firmware::MAX_TABLE_POINTS + 1,
            ExportError::TooManyPoints(firmware::MAX_TABLE_POINTS + 1),
        ),
    ] {
        let e = firmware::export(
            &cal,
            Format::CsvTable,
            &ExportOptions {
                points,
                ..ExportOptions::default()
            },
        );
        assert_eq!(e, Err(want));
    }
}

#[test]
fn formats_parse_by_name() {
    for f in Format::ALL {
        assert_eq!(f.to_string().parse::<Format>(), Ok(f));
    }
    assert!(
        "xml"
            .parse::<Format>()
            .unwrap_err()
            .to_string()
            .contains("c-header")
    );
}

// ---- The command -----------------------------------------------------------------------

#[test]
fn export_command_writes_header_and_table() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let (cal, h, csv) = (p("cal.json"), p("gyro.h"), p("gyro.csv"));
    let log = sample("calibration.csv").display().to_string();
    let out = driftlab(&[
        "calibrate",
        &log,
        "--out",
        &cal,
        "--k1",
        "spline",
        "--gyro-id",
        "FOG-0007",
    ]);
    assert!(out.status.success());
    let loaded = calibration::load(Path::new(&cal)).unwrap();

    // To standard output, and atomically to a file: the engine's text either way.
    let want = firmware::export(&loaded, Format::CHeader, &ExportOptions::default()).unwrap();
    let out = driftlab(&["export", &cal, "--format", "c-header"]);
    assert!(out.status.success());
    assert_eq!(String::from_utf8(out.stdout).unwrap(), want);
    let out = driftlab(&["export", &cal, "--format", "c-header", "--out", &h]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = std::fs::read_to_string(&h).unwrap();
    assert_eq!(header, want);
    assert!(header.contains("#define DRIFTLAB_GYRO_ID \"FOG-0007\""));
    assert!(header.contains(&loaded.source.sha256));
    assert!(header.contains("calibration.csv"));

    let out = driftlab(&[
        "export",
        &cal,
        "--format",
        "csv-table",
        "--points",
        "11",
        "--out",
        &csv,
    ]);
    assert!(out.status.success());
    let (header, tables) = parse_table(&std::fs::read_to_string(&csv).unwrap());
    assert_eq!(header.len(), 10);
    assert!(tables.iter().all(|(xs, _)| xs.len() == 11));
    // Nothing but the two outputs and the calibration in the folder (no temporary files).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);

    let help = String::from_utf8(driftlab(&["export", "--help"]).stdout).unwrap();
    assert!(
        help.contains("c-header") && help.contains("--points"),
        "{help}"
    );
}

#[test]
fn export_command_refuses_bad_input_with_a_reason() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let fails = |args: &[&str]| {
        let out = driftlab(args);
        assert!(!out.status.success(), "{args:?} should fail");
        String::from_utf8(out.stderr).unwrap()
    };
    let e = fails(&["export", &p("missing.json"), "--format", "c-header"]);
    assert!(e.contains("missing.json"), "{e}");
    std::fs::write(
        p("bad.json"),
        "{\"format\": \"driftlab-calibration\", \"version\": 1",
    )
    .unwrap();
    let e = fails(&["export", &p("bad.json"), "--format", "csv-table"]);
    assert!(e.contains("bad.json"), "{e}");
    let e = fails(&["export", &p("bad.json"), "--format", "fortran"]);
    assert!(e.contains("c-header"), "{e}");

    let cal = p("cal.json");
    let log = sample("calibration.csv").display().to_string();
    assert!(
        driftlab(&["calibrate", &log, "--out", &cal])
            .status
            .success()
    );
    let e = fails(&["export", &cal, "--format", "csv-table", "--points", "1"]);
    assert!(e.contains("at least 2 points"), "{e}");
    let e = fails(&[
        "export",
        &cal,
        "--format",
        "c-header",
        "--out",
        &p("no/such/dir/x.h"),
    ]);
    assert!(e.contains("x.h"), "{e}");
}

#[test]
fn regimes_are_numbered_as_in_the_header() {
    // The C's DRIFTLAB_REGIME_* values are driftlab's Regime discriminants.
    assert_eq!(Regime::Static as u8, 0);
    assert_eq!(Regime::Plus as u8, 1);
    assert_eq!(Regime::Minus as u8, 2);
}

#[test]
fn an_unknown_format_is_a_typed_error_naming_it() {
    let e = "xml".parse::<Format>().unwrap_err();
    assert_eq!(e, firmware::UnknownFormat("xml".to_string()));
    assert!(e.to_string().contains("\"xml\""), "{e}");
}
