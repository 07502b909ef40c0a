//! The firmware export. The generated C header, compiled with the machine's C compiler, corrects
//! a held-out log as driftlab's streaming and batch corrections do, for every approximation
//! kind; the lookup tables give driftlab's values at their grid points and stay within the error
//! bound of linear interpolation between them; `driftlab export` writes both.

use driftlab::approx::{Approx, ApproxKind, ApproxSpec, Curve};
use driftlab::drift_model::{self, DriftModel};
use driftlab::firmware::{self, ExportError, ExportOptions, Format};
use driftlab::ingest::{self, ReadOptions};
use driftlab::model::{self, Calibration, Regime};
use driftlab::presets::{ModelChoice, Preset};
use driftlab::recipe::Recipe;
use driftlab::regression::terms::parse_terms;
use driftlab::regression::{DelaySpec, LagSpec, RegressionSpec};
use driftlab::{Log, calfile};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// What the C must agree with driftlab to, °/h.
const TOLERANCE_DPH: f64 = 1e-6;

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

fn read(name: &str) -> Log {
    ingest::read_path(&sample(name), &ReadOptions::default()).expect("sample log reads")
}

/// A calibration on the bundled calibration log with these kinds for K0, K1± and K2±.
fn calibrate(log: &Log, [k0, k1, k2]: [ApproxKind; 3], extrapolate_k1: bool) -> Calibration {
    let mut r = Recipe {
        gyro_id: format!("SIM-{k0}-{k1}-{k2}"),
        ..Recipe::default()
    };
    // Four plateaus at three temperatures carry three K0 parameters at most.
    r.k0 = ApproxSpec {
        kind: k0,
        knots: 3,
        extrapolate: false,
    };
    for (spec, kind, extrapolate) in [
        (&mut r.k1_plus, k1, extrapolate_k1),
        (&mut r.k1_minus, k1, extrapolate_k1),
        (&mut r.k2_plus, k2, false),
        (&mut r.k2_minus, k2, false),
    ] {
        *spec = ApproxSpec {
            kind,
            knots: 6,
            extrapolate,
        };
    }
    let cal = model::fit(log, &r).expect("fit").calibration;
    // The kinds asked for are the curves fitted (no fallback to a simpler curve).
    for (a, kind) in [
        (&cal.k0, k0),
        (&cal.k1_plus, k1),
        (&cal.k1_minus, k1),
        (&cal.k2_plus, k2),
        (&cal.k2_minus, k2),
    ] {
        let form_ok = match (kind, a.curve()) {
            (ApproxKind::Linear, Curve::Polynomial { coeffs }) => coeffs.len() == 2,
            (ApproxKind::Parabolic, Curve::Polynomial { coeffs }) => coeffs.len() == 3,
            (ApproxKind::Pwl, Curve::Pwl { .. }) => true,
            (ApproxKind::Spline, Curve::CatmullRom { .. }) => true,
            _ => false,
        };
        assert!(form_ok, "{kind} fitted as {:?}", a.curve());
    }
    cal
}

/// The C compiler: `CC` (program and flags) or `cc`; `None` when there is none.
fn compiler() -> Option<Vec<String>> {
    let cc = std::env::var("CC")
        .ok()
        .filter(|s| !s.trim().is_empty())
        .unwrap_or_else(|| "cc".to_string());
    let words: Vec<String> = cc.split_whitespace().map(str::to_string).collect();
    let ok = Command::new(&words[0])
        .args(&words[1..])
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    ok.then_some(words)
}

/// Reads samples `t,omega,temp` from stdin (a line `reset` resets the corrector) and prints
/// every field of each corrected sample.
const DRIVER_C: &str = r#"#include <stdio.h>
#include "calibration.h"

double other_file_push(driftlab_state *st, double omega_dph, double temp_c);

int main(void)
{
    static driftlab_state st;
    char line[256];
    driftlab_init(&st);
    while (fgets(line, sizeof line, stdin) != NULL) {
        double t, omega, temp;
        driftlab_sample s;
        if (line[0] == 'r') {
            driftlab_reset(&st);
            printf("reset\n");
            continue;
        }
        if (sscanf(line, "%lf,%lf,%lf", &t, &omega, &temp) != 3) {
            return 2;
        }
        driftlab_push_detail(&st, omega, temp, &s);
        printf("%.17g,%.17g,%.17g,%.17g,%d,%d\n", s.omega_cor_dph, s.omega_pred_dph,
               s.tdot_c_s, s.tddot_c_s2, s.regime, s.outside);
    }
    return 0;
}
"#;

/// A second file including the header: it can be included more than once in a program.
const OTHER_C: &str = r#"#include "calibration.h"

double other_file_push(driftlab_state *st, double omega_dph, double temp_c)
{
    return driftlab_push(st, omega_dph, temp_c);
}
"#;

/// A file including the header and using none of it: no unused-code warnings.
const UNUSED_C: &str = r#"#include "calibration.h"

int unused_file_step(void)
{
    return DRIFTLAB_STEP_SAMPLES;
}
"#;

/// Builds the driver with `header`; `None` (after saying so) when there is no C compiler.
fn build_driver(dir: &Path, header: &str) -> Option<PathBuf> {
    compile(dir, header, [DRIVER_C, OTHER_C], &[])
}

/// Writes `header` and three C files including it (the driver, another file calling it, one
/// using nothing of it) and compiles them strictly, with `libs`; `None` without a compiler.
fn compile(dir: &Path, header: &str, [driver, other]: [&str; 2], libs: &[&str]) -> Option<PathBuf> {
    let Some(cc) = compiler() else {
        println!("no C compiler (CC or cc): the compiled-C checks are skipped");
        return None;
    };
    std::fs::write(dir.join("calibration.h"), header).unwrap();
    let sources = [
        ("driver.c", driver),
        ("other.c", other),
        ("unused.c", UNUSED_C),
    ];
    for (name, text) in sources {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let exe = dir.join("driver");
    let out = Command::new(&cc[0])
        .args(&cc[1..])
        .args([
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-O2",
        ])
        .args(sources.iter().map(|(n, _)| dir.join(n)))
        .arg("-o")
        .arg(&exe)
        .args(libs)
        .output()
        .expect("the compiler runs");
    assert!(
        out.status.success(),
        "the generated header does not compile:\n{}\n{header}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

/// One line of the driver's output.
#[derive(Debug, Clone, Copy)]
struct CSample {
    cor: f64,
    pred: f64,
    tdot: f64,
    tddot: f64,
    regime: u8,
    outside: bool,
}

/// Runs the driver over `logs`, resetting the corrector between them.
fn run_driver(exe: &Path, logs: &[&Log]) -> Vec<Vec<CSample>> {
    let mut input = String::new();
    for (k, log) in logs.iter().enumerate() {
        if k > 0 {
            input.push_str("reset\n");
        }
        for i in 0..log.len() {
            // Round-trip decimals: the C reads exactly the doubles driftlab holds.
            input.push_str(&format!(
                "{:?},{:?},{:?}\n",
                log.time_s[i], log.omega_dph[i], log.temp_c[i]
            ));
        }
    }
    let mut child = Command::new(exe)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("the driver runs");
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    assert!(out.status.success(), "driver failed: {:?}", out.status);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut runs = vec![Vec::new()];
    for line in text.lines() {
        if line == "reset" {
            runs.push(Vec::new());
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 6, "{line}");
        let num = |k: usize| f[k].parse::<f64>().unwrap();
        runs.last_mut().unwrap().push(CSample {
            cor: num(0),
            pred: num(1),
            tdot: num(2),
            tddot: num(3),
            regime: f[4].parse().unwrap(),
            outside: f[5] == "1",
        });
    }
    runs
}

/// How far the C is from driftlab on one run.
#[derive(Debug, Default, Clone, Copy)]
struct Agreement {
    /// Largest |C − StreamCorrector| of the corrected rate, °/h.
    vs_stream_dph: f64,
    /// Largest |C − batch correction| of the corrected rate, °/h.
    vs_batch_dph: f64,
    /// Samples whose corrected rate, prediction, Ṫ and T̈ are the same doubles as driftlab's.
    identical: usize,
    /// Samples the C flagged outside the calibrated ranges.
    outside: usize,
    samples: usize,
}

fn compare(cal: &Calibration, log: &Log, c: &[CSample]) -> Agreement {
    assert_eq!(c.len(), log.len());
    let batch = cal.correct(log);
    let mut stream = cal.corrector().unwrap();
    let mut a = Agreement {
        samples: log.len(),
        ..Agreement::default()
    };
    for (i, c) in c.iter().enumerate() {
        let s = stream.push(log.time_s[i], log.omega_dph[i], log.temp_c[i]);
        a.vs_stream_dph = a.vs_stream_dph.max((c.cor - s.omega_cor_dph).abs());
        a.vs_batch_dph = a.vs_batch_dph.max((c.cor - batch.cor_dph[i]).abs());
        assert_eq!(c.regime, s.regime as u8, "regime of sample {i}");
        let outside = cal.is_outside(log.temp_c[i], s.tdot, s.tddot, s.regime);
        assert_eq!(c.outside, outside, "outside flag of sample {i}");
        a.outside += usize::from(c.outside);
        let same = |x: f64, y: f64| x.to_bits() == y.to_bits() || x == y;
        if same(c.cor, s.omega_cor_dph)
            && same(c.pred, s.omega_pred_dph)
            && same(c.tdot, s.tdot)
            && same(c.tddot, s.tddot)
        {
            a.identical += 1;
        }
    }
    a
}

/// Exports `cal` as a header, compiles it, runs it on the validation log and on the calibration
/// log (after a reset), and checks every sample against driftlab.
fn c_agrees_with_driftlab(label: &str, cal: &Calibration, logs: &[&Log]) -> Option<Agreement> {
    let header = firmware::export(cal, Format::CHeader, &ExportOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let exe = build_driver(dir.path(), &header)?;
    let runs = run_driver(&exe, logs);
    assert_eq!(runs.len(), logs.len());
    let mut total = Agreement::default();
    for (log, run) in logs.iter().zip(&runs) {
        let a = compare(cal, log, run);
        println!(
            "{label} on {}: max |C - stream| {:.3e} deg/h, max |C - batch| {:.3e} deg/h, \
             {} of {} samples bit-identical, {} outside the calibrated ranges",
            log.source, a.vs_stream_dph, a.vs_batch_dph, a.identical, a.samples, a.outside
        );
        assert!(
            a.vs_stream_dph <= TOLERANCE_DPH && a.vs_batch_dph <= TOLERANCE_DPH,
            "{label}: {a:?}"
        );
        total.vs_stream_dph = total.vs_stream_dph.max(a.vs_stream_dph);
        total.vs_batch_dph = total.vs_batch_dph.max(a.vs_batch_dph);
        total.identical += a.identical;
        total.outside += a.outside;
        total.samples += a.samples;
    }
    Some(total)
}

#[test]
fn c_header_corrects_as_driftlab_for_each_kind() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    for kind in ApproxKind::ALL {
        let cal = calibrate(&cal_log, [kind; 3], false);
        let label = format!("K0, K1, K2 all {kind}");
        let Some(a) = c_agrees_with_driftlab(&label, &cal, &[&val_log, &cal_log]) else {
            return;
        };
        // The validation log's 1.5 °C/min ramps lie beyond the calibration's Ṫ range, so the
        // edge holding was exercised.
        assert!(a.outside > 0, "{label}: no sample outside the ranges");
    }
}

#[test]
fn c_header_corrects_as_driftlab_for_mixed_kinds_and_extrapolation() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    use ApproxKind::{Linear, Parabolic, Pwl, Spline};
    // Every kind once for each coefficient; K1 extrapolating in two of them.
    let combos = [
        ([Parabolic, Spline, Pwl], true),
        ([Pwl, Linear, Spline], false),
        ([Spline, Parabolic, Linear], true),
        ([Linear, Pwl, Parabolic], false),
    ];
    for (kinds, extrapolate) in combos {
        let mut cal = calibrate(&cal_log, kinds, extrapolate);
        // A gyro id that must not break the C: comment ends, quotes, trigraphs, UTF-8.
        cal.gyro_id = "FOG */ \"7\" ??/ ??= ünï\\".to_string();
        let label = format!("K0 {}, K1 {}, K2 {}", kinds[0], kinds[1], kinds[2]);
        if c_agrees_with_driftlab(&label, &cal, &[&val_log]).is_none() {
            return;
        }
    }
}

#[test]
fn c_header_follows_hand_edited_curves() {
    // A calibration file edited by hand: K1+ knots no longer equally spaced (the C searches
    // for the segment) and K0 a polynomial of degree 4 (the general Horner sum).
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    use ApproxKind::{Parabolic, Spline};
    let cal = calibrate(&cal_log, [Parabolic, Spline, Spline], false);
    let mut v: serde_json::Value = serde_json::from_str(&calfile::to_json(&cal)).unwrap();
    let body = &mut v["calibration"];
    let kx = body["k1_plus"]["curve"]["knots_x"].as_array_mut().unwrap();
    let (a, b) = (kx[1].as_f64().unwrap(), kx[2].as_f64().unwrap());
    kx[1] = serde_json::json!(a + 0.3 * (b - a));
    let coeffs = body["k0"]["curve"]["coeffs"].as_array_mut().unwrap();
    coeffs.push(serde_json::json!(1e-9));
    coeffs.push(serde_json::json!(-2e-11));
    let edited = calfile::from_json(Path::new("edited.json"), &v.to_string()).unwrap();
    assert_eq!(edited.k1_plus.segment_cubics().unwrap().inv_step, 0.0);
    c_agrees_with_driftlab("hand-edited", &edited, &[&val_log, &cal_log]);
}

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
            let text = firmware::export(&cal, Format::CsvTable, &ExportOptions { points }).unwrap();
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
        let e = firmware::export(&cal, Format::CsvTable, &ExportOptions { points });
        assert_eq!(e, Err(want));
    }
}

#[test]
fn formats_parse_by_name() {
    for f in Format::ALL {
        assert_eq!(f.to_string().parse::<Format>(), Ok(f));
    }
    assert!("xml".parse::<Format>().unwrap_err().contains("c-header"));
}

// ---- The command -----------------------------------------------------------------------

fn driftlab(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("driftlab runs")
}

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
    let loaded = calfile::load(Path::new(&cal)).unwrap();

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

// ---- Regression models -----------------------------------------------------------------

/// What the C must agree with driftlab to for a regression model, °/h.
const REGRESSION_TOLERANCE_DPH: f64 = 1e-9;

/// Reads samples `t,omega,temp,temp2,channels...` from stdin (a line `reset` resets the
/// corrector) and prints every field of each corrected sample.
const REGRESSION_DRIVER_C: &str = r#"#include <stdio.h>
#include <stdlib.h>
#include "calibration.h"

double other_file_push(driftlab_state *st, double t, double omega_dph, double temp_c);

int main(void)
{
    static driftlab_state st;
    static char line[4096];
    double ch[DRIFTLAB_N_CHANNELS + 1] = { 0.0 };
    driftlab_init(&st);
    while (fgets(line, sizeof line, stdin) != NULL) {
        double v[4];
        char *p = line, *end;
        int k;
        driftlab_sample s;
        if (line[0] == 'r') {
            driftlab_reset(&st);
            printf("reset\n");
            continue;
        }
        for (k = 0; k < 4 + DRIFTLAB_N_CHANNELS; k++) {
            double x = strtod(p, &end);
            if (end == p) {
                return 2;
            }
            if (k < 4) {
                v[k] = x;
            } else {
                ch[k - 4] = x;
            }
            p = *end == ',' ? end + 1 : end;
        }
        driftlab_push_detail(&st, v[0], v[1], v[2], v[3], ch, &s);
        printf("%.17g,%.17g,%.17g,%.17g,%d,%d\n", s.omega_cor_dph, s.omega_pred_dph,
               s.tdot_c_s, s.tddot_c_s2, s.regime, s.outside);
    }
    return 0;
}
"#;

const REGRESSION_OTHER_C: &str = r#"#include "calibration.h"

double other_file_push(driftlab_state *st, double t, double omega_dph, double temp_c)
{
    double ch[DRIFTLAB_N_CHANNELS + 1] = { 0.0 };
    return driftlab_push(st, t, omega_dph, temp_c, 20.0, ch);
}
"#;

/// Builds the regression driver with `header`, linking libm (exp); `None` without a compiler.
fn build_regression_driver(dir: &Path, header: &str) -> Option<PathBuf> {
    compile(
        dir,
        header,
        [REGRESSION_DRIVER_C, REGRESSION_OTHER_C],
        &["-lm"],
    )
}

/// Runs the regression driver over `logs`, resetting between them.
fn run_regression_driver(exe: &Path, model: &DriftModel, logs: &[&Log]) -> Vec<Vec<CSample>> {
    let mut input = String::new();
    for (k, log) in logs.iter().enumerate() {
        if k > 0 {
            input.push_str("reset\n");
        }
        let (t2, ch) = drift_model::stream_inputs(model, log).unwrap();
        for i in 0..log.len() {
            input.push_str(&format!(
                "{:?},{:?},{:?},{:?}",
                log.time_s[i], log.omega_dph[i], log.temp_c[i], t2[i]
            ));
            for c in &ch {
                input.push_str(&format!(",{:?}", c[i]));
            }
            input.push('\n');
        }
    }
    let mut child = Command::new(exe)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("the driver runs");
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    assert!(out.status.success(), "driver failed: {:?}", out.status);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut runs = vec![Vec::new()];
    for line in text.lines() {
        if line == "reset" {
            runs.push(Vec::new());
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 6, "{line}");
        let num = |k: usize| f[k].parse::<f64>().unwrap();
        runs.last_mut().unwrap().push(CSample {
            cor: num(0),
            pred: num(1),
            tdot: num(2),
            tddot: num(3),
            regime: f[4].parse().unwrap(),
            outside: f[5] == "1",
        });
    }
    runs
}

/// Exports a regression model as a header, compiles it, runs it over `logs` (reset between)
/// and compares every sample with `RegressionCorrector` and the batch correction; returns the
/// largest difference of the corrected rate and the number of bit-identical samples.
fn regression_c_agrees(label: &str, model: &DriftModel, logs: &[&Log]) -> Option<(f64, usize)> {
    let DriftModel::Regression(rc) = model else {
        panic!("{label}: not a regression model");
    };
    let m = &rc.model;
    let header = firmware::export_model(model, Format::CHeader, &ExportOptions::default()).unwrap();
    for name in m.channel_names() {
        assert!(
            header.contains(&name),
            "{label}: channel {name} not documented"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let exe = build_regression_driver(dir.path(), &header)?;
    let runs = run_regression_driver(&exe, model, logs);
    assert_eq!(runs.len(), logs.len());
    let (mut worst, mut identical, mut total) = (0.0f64, 0, 0);
    for (log, run) in logs.iter().zip(&runs) {
        assert_eq!(run.len(), log.len());
        assert_eq!(
            log.nominal_dt_s(),
            m.dt_s,
            "{label}: {} sampled differently",
            log.source
        );
        let batch = m.correct(log).unwrap();
        let (t2, ch) = drift_model::stream_inputs(model, log).unwrap();
        let mut stream = m.corrector_for(m.dt_s).unwrap();
        let mut row = vec![0.0; ch.len()];
        let (mut vs_stream, mut vs_batch, mut same_n, mut outside) = (0.0f64, 0.0f64, 0, 0);
        for (i, c) in run.iter().enumerate() {
            for (r, col) in row.iter_mut().zip(&ch) {
                *r = col[i];
            }
            let s = stream.push(log.time_s[i], log.omega_dph[i], log.temp_c[i], t2[i], &row);
            vs_stream = vs_stream.max((c.cor - s.omega_cor_dph).abs());
            vs_batch = vs_batch.max((c.cor - batch.cor_dph[i]).abs());
            assert_eq!(c.regime, s.regime as u8, "{label}: regime of sample {i}");
            outside += usize::from(c.outside);
            let same = |x: f64, y: f64| x.to_bits() == y.to_bits() || x == y;
            if same(c.cor, s.omega_cor_dph)
                && same(c.pred, s.omega_pred_dph)
                && same(c.tdot, s.tdot)
                && same(c.tddot, s.tddot)
            {
                same_n += 1;
            }
        }
        // The C flags the samples the batch correction counts as outside the ranges.
        assert_eq!(
            outside,
            batch.outside_by_regime.iter().sum::<usize>(),
            "{label} on {}: outside flags",
            log.source
        );
        println!(
            "{label} on {}: max |C - stream| {vs_stream:.3e} deg/h, max |C - batch| \
             {vs_batch:.3e} deg/h, {same_n} of {} samples bit-identical, {outside} outside",
            log.source,
            log.len()
        );
        assert!(
            vs_stream <= REGRESSION_TOLERANCE_DPH && vs_batch <= REGRESSION_TOLERANCE_DPH,
            "{label} on {}: C differs from driftlab by {vs_stream:e} (stream), {vs_batch:e} (batch)",
            log.source
        );
        worst = worst.max(vs_stream).max(vs_batch);
        identical += same_n;
        total += log.len();
    }
    println!(
        "{label}: {identical} of {total} samples bit-identical, max difference {worst:.3e} deg/h"
    );
    Some((worst, identical))
}

fn regression_presets() -> Vec<Preset> {
    Preset::ALL
        .into_iter()
        .filter(|p| *p != Preset::Vakhrameev)
        .collect()
}

#[test]
fn c_header_corrects_as_driftlab_for_every_preset_on_the_laser_gyro() {
    let (cal_log, held_out) = (read("laser-gyro.csv"), read("laser-gyro-2.csv"));
    for p in regression_presets() {
        let model =
            drift_model::fit(&cal_log, &ModelChoice::Preset(p), &Recipe::default()).unwrap();
        let label = format!("{} (laser gyro)", p.name());
        if regression_c_agrees(&label, &model, &[&held_out, &cal_log]).is_none() {
            return;
        }
    }
}

#[test]
fn c_header_corrects_as_driftlab_for_every_preset_on_the_fog() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    for p in regression_presets() {
        let model =
            drift_model::fit(&cal_log, &ModelChoice::Preset(p), &Recipe::default()).unwrap();
        let label = format!("{} (FOG)", p.name());
        if regression_c_agrees(&label, &model, &[&val_log, &cal_log]).is_none() {
            return;
        }
    }
}

#[test]
fn c_header_corrects_as_driftlab_for_a_custom_model_with_every_feature() {
    let (cal_log, held_out) = (read("laser-gyro.csv"), read("laser-gyro-2.csv"));
    let mut spec = RegressionSpec::new(
        "custom",
        parse_terms(
            "1,T,T^2,T^3,Tdot,Tddot,T*Tdot,|Tdot|,T*Tddot,sgn(Tdot)*Tddot,dT,dT^2,selfheat,\
             ch:laser_power_mw,ch^2:piezo_v,ch:dither_amp_arcsec,pwlT:4",
        )
        .unwrap(),
    );
    spec.delay = DelaySpec::Bands {
        bands: 3,
        max_s: 600.0,
    };
    spec.lag = LagSpec::Fixed {
        seconds: 300.0,
        per_c: 0.01,
    };
    let mut model =
        drift_model::fit(&cal_log, &ModelChoice::Custom(spec), &Recipe::default()).unwrap();
    if let DriftModel::Regression(r) = &mut model {
        assert!(r.model.delay.points.len() >= 2, "{:?}", r.model.delay);
        assert!(r.model.lambda_s.is_some() && r.model.lag_s == Some(300.0));
        // A gyro id that must not break the C.
        r.gyro_id = "RLG */ \"9\" ??/ ??= ünï\\".to_string();
    }
    regression_c_agrees(
        "custom (lag, delay bands, selfheat, pwlT, channels)",
        &model,
        &[&held_out, &cal_log],
    );
}

#[test]
fn regression_csv_table_lists_every_coefficient_exactly() {
    let log = read("laser-gyro.csv");
    let model = drift_model::fit(
        &log,
        &ModelChoice::Preset(Preset::Sukhanov),
        &Recipe::default(),
    )
    .unwrap();
    let DriftModel::Regression(r) = &model else {
        panic!("not a regression model");
    };
    let text = firmware::export_model(&model, Format::CsvTable, &ExportOptions::default()).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(rows.next(), Some("term,coefficient,std_error"));
    let rows: Vec<Vec<&str>> = rows.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), r.model.coefficients.len());
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[0], r.model.names[k]);
        assert_eq!(row[1].parse::<f64>().unwrap(), r.model.coefficients[k]);
        assert_eq!(row[2].parse::<f64>().unwrap(), r.model.std_errors[k]);
    }
    for name in r.model.channel_names() {
        assert!(text.contains(&format!("{name} range (clamped)")), "{text}");
    }
}

#[test]
fn export_command_writes_a_regression_header() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let (cal, h, csv) = (p("cal.json"), p("gyro.h"), p("gyro.csv"));
    let log = sample("laser-gyro.csv").display().to_string();
    let out = driftlab(&["calibrate", &log, "--model", "sukhanov", "--out", &cal]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let loaded = calfile::load_model(Path::new(&cal)).unwrap();
    let want = firmware::export_model(&loaded, Format::CHeader, &ExportOptions::default()).unwrap();
    let out = driftlab(&["export", &cal, "--format", "c-header", "--out", &h]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = std::fs::read_to_string(&h).unwrap();
    assert_eq!(header, want);
    assert!(header.contains("regression \"sukhanov\""));
    assert!(header.contains("channels[0] = laser_power_mw"), "{header}");
    let out = driftlab(&["export", &cal, "--format", "csv-table", "--out", &csv]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::fs::read_to_string(&csv)
            .unwrap()
            .contains("term,coefficient,std_error")
    );
}

#[test]
fn c_header_corrects_as_driftlab_with_one_delay_a_lag_and_a_fixed_lambda() {
    // One delay for every temperature (a single τd point, between samples), a lag and λ
    // given, and the chamber's temperature read as an extra channel, on the FOG.
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    let mut spec = RegressionSpec::new(
        "custom-fog",
        parse_terms("1,T,T^3,Tdot,T*Tdot,selfheat,ch^2:temp_chamber_c").unwrap(),
    );
    spec.delay = DelaySpec::Fixed { seconds: 250.5 };
    spec.lag = LagSpec::Fixed {
        seconds: 120.0,
        per_c: 0.0,
    };
    spec.lambda = driftlab::regression::LambdaSpec::Fixed { seconds: 1200.0 };
    let model = drift_model::fit(&cal_log, &ModelChoice::Custom(spec), &Recipe::default()).unwrap();
    if let DriftModel::Regression(r) = &model {
        assert_eq!(r.model.delay.points, vec![[0.0, 250.5]]);
        assert_eq!(r.model.lag_s, Some(120.0));
        assert_eq!(r.model.lambda_s, Some(1200.0));
    }
    regression_c_agrees(
        "custom (one delay, lag, fixed lambda)",
        &model,
        &[&val_log, &cal_log],
    );
}
