//! The firmware export of a unit (every gyro axis of an IMU): one C header whose one push
//! corrects every axis, compiled strictly and run on the three-axis validation log, each axis
//! compared sample by sample with driftlab's streaming corrector of that axis; and the unit's
//! lookup tables, one file with an axis column, read back against each axis's curves.

use driftlab::Log;
use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::files::calibration;
use driftlab::models::{DriftModel, UnitCalibration};
use std::path::Path;

use crate::common;
use common::firmware::*;

/// Reads `t,temp,omega_0,...,omega_{n-1}` lines from stdin and prints, for each sample, one
/// line per axis of every field of its corrected sample.
const DRIVER_C: &str = r#"#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "calibration.h"

void other_file_push(driftlab_state *st, double t, const double *omega, double temp,
                     double *cor);

int main(void)
{
    static driftlab_state st;
    static const char *const names[DRIFTLAB_N_AXES] = DRIFTLAB_AXIS_NAMES;
    char line[1024];
    driftlab_init(&st);
    if (names[0] == NULL) {
        return 3;
    }
    while (fgets(line, sizeof line, stdin) != NULL) {
        double t, temp, omega[DRIFTLAB_N_AXES], cor[DRIFTLAB_N_AXES];
        driftlab_sample s[DRIFTLAB_N_AXES];
        char *p = line, *end;
        size_t k;
        t = strtod(p, &end);
        if (end == p || *end != ',') {
            return 2;
        }
        p = end + 1;
        temp = strtod(p, &end);
        for (k = 0; k < DRIFTLAB_N_AXES; k++) {
            if (end == p || *end != ',') {
                return 2;
            }
            p = end + 1;
            omega[k] = strtod(p, &end);
        }
        driftlab_push_detail(&st, t, omega, temp, cor, s);
        for (k = 0; k < DRIFTLAB_N_AXES; k++) {
            if (memcmp(&cor[k], &s[k].omega_cor_dph, sizeof cor[k]) != 0) {
                return 4;
            }
            printf("%.17g,%.17g,%.17g,%.17g,%d,%d\n", s[k].omega_cor_dph, s[k].omega_pred_dph,
                   s[k].tdot_c_s, s[k].tddot_c_s2, s[k].regime, s[k].outside);
        }
    }
    return 0;
}
"#;

/// A second file including the header and calling the push without details.
const OTHER_C: &str = r#"#include "calibration.h"

void other_file_push(driftlab_state *st, double t, const double *omega, double temp,
                     double *cor)
{
    driftlab_push(st, t, omega, temp, cor);
}
"#;

/// A unit calibrated on the three-axis calibration run by the command line, as a user makes
/// it (`extra` are more `calibrate` arguments).
fn calibrate_unit(dir: &Path, extra: &[&str]) -> UnitCalibration {
    let out = dir.join("unit.json");
    let cal = sample("imu3-calibration.csv");
    let mut args = vec!["calibrate", cal.to_str().unwrap(), "--out"];
    args.push(out.to_str().unwrap());
    args.extend_from_slice(extra);
    let run = driftlab(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let unit = calibration::load_unit(&out).unwrap();
    assert!(unit.is_unit());
    assert_eq!(unit.axis_names(), ["gx", "gy", "gz"]);
    unit
}

/// Each axis's rate on `log`, in the unit's order.
fn rates<'a>(unit: &UnitCalibration, log: &'a Log) -> Vec<&'a [f64]> {
    unit.axes
        .iter()
        .map(|a| {
            let name = log
                .matching_axis(&a.name, &a.rate_column)
                .unwrap_or_else(|| panic!("axis {} in {}", a.name, log.source));
            log.axis_rate(&name).unwrap()
        })
        .collect()
}

/// The sampling period a model's own streaming corrector runs at.
fn model_dt(model: &DriftModel) -> f64 {
    match model {
        DriftModel::Vakhrameev(c) => c.resolved.dt_s,
        DriftModel::Regression(r) => r.model.dt_s,
    }
}

/// How far the C is from driftlab on one log, over every axis.
#[derive(Debug, Default)]
pub(crate) struct Agreement {
    /// Axis samples compared.
    pub(crate) compared: usize,
    /// Of them, those whose corrected rate, prediction, Ṫ, T̈, regime and flag are driftlab's.
    pub(crate) identical: usize,
    /// Largest |C − driftlab| of the corrected rate, °/h.
    pub(crate) max_dph: f64,
}

/// Compiles the unit's header, runs it on `log` and compares every axis of every sample with
/// a streaming corrector of that axis alone; `None` without a C compiler.
pub(crate) fn c_unit_agrees(
    unit: &UnitCalibration,
    log: &Log,
) -> Option<(Agreement, Vec<CSample>)> {
    let header = firmware::export_unit(unit, Format::CHeader, &ExportOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    // Vakhrameev axes call no libm function: nothing to link unless a regression axis does.
    let regression = unit
        .axes
        .iter()
        .any(|a| matches!(a.model, DriftModel::Regression(_)));
    let libs: &[&str] = if regression { &["-lm"] } else { &[] };
    let exe = compile(dir.path(), &header, [DRIVER_C, OTHER_C], libs)?;
    let rates = rates(unit, log);
    let mut input = String::new();
    for i in 0..log.len() {
        // Round-trip decimals: the C reads exactly the doubles driftlab holds.
        input.push_str(&format!("{:?},{:?}", log.time_s[i], log.temp_c[i]));
        for r in &rates {
            input.push_str(&format!(",{:?}", r[i]));
        }
        input.push('\n');
    }
    let mut runs = drive(&exe, input);
    let c = runs.swap_remove(0);
    let n = unit.axes.len();
    assert_eq!(c.len(), n * log.len());
    let mut a = Agreement::default();
    for (k, ax) in unit.axes.iter().enumerate() {
        let mut stream = ax.model.corrector_for(model_dt(&ax.model)).unwrap();
        let mut outside = 0;
        for i in 0..log.len() {
            let s = stream.push(log.time_s[i], rates[k][i], log.temp_c[i], 0.0, &[]);
            let got = c[i * n + k];
            a.compared += 1;
            a.max_dph = a.max_dph.max((got.cor - s.omega_cor_dph).abs());
            // A regression axis's flags are counted against its batch correction below.
            let flag = match &ax.model {
                DriftModel::Vakhrameev(cal) => {
                    cal.is_outside(log.temp_c[i], s.tdot, s.tddot, s.regime)
                }
                DriftModel::Regression(_) => got.outside,
            };
            outside += usize::from(got.outside);
            let same = |x: f64, y: f64| x.to_bits() == y.to_bits();
            if same(got.cor, s.omega_cor_dph)
                && same(got.pred, s.omega_pred_dph)
                && same(got.tdot, s.tdot)
                && same(got.tddot, s.tddot)
                && got.regime == s.regime as u8
                && got.outside == flag
            {
                a.identical += 1;
            } else if a.identical + 20 > a.compared {
                eprintln!(
                    "axis {} sample {i}: C {got:?}, driftlab {s:?}, outside {flag}",
                    ax.name
                );
            }
        }
        if let DriftModel::Regression(_) = &ax.model {
            let mut axis_log = log.clone();
            assert!(axis_log.select_axis(&log.matching_axis(&ax.name, &ax.rate_column).unwrap()));
            let batch = ax.model.correct(&axis_log).unwrap();
            assert_eq!(
                outside,
                batch.outside_by_regime.iter().sum::<usize>(),
                "axis {}: outside flags",
                ax.name
            );
        }
        println!(
            "axis {} ({}) on {}: {} samples, {outside} outside the calibrated ranges",
            ax.name,
            ax.model.tag(),
            log.source,
            log.len()
        );
    }
    println!(
        "unit header on {}: {} of {} axis samples bit-identical, max |C - driftlab| {:.3e} deg/h",
        log.source, a.identical, a.compared, a.max_dph
    );
    Some((a, c))
}

#[test]
fn unit_header_corrects_every_axis_of_the_validation_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(dir.path(), &[]);
    let log = read("imu3-validation.csv");
    assert_eq!(log.axis_names().len(), 3, "{:?}", log.axis_names());
    let Some((a, c)) = c_unit_agrees(&unit, &log) else {
        return;
    };
    assert_eq!(a.compared, 3 * log.len());
    assert_eq!(a.identical, a.compared, "{a:?}");
    assert_eq!(a.max_dph, 0.0);
    // And what `driftlab apply` writes for the unit, column by column (round-trip decimals).
    let applied = dir.path().join("applied.csv");
    let val = sample("imu3-validation.csv");
    let run = driftlab(&[
        "apply",
        dir.path().join("unit.json").to_str().unwrap(),
        val.to_str().unwrap(),
        "--out",
        applied.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(&applied).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let cols: Vec<usize> = ["gx", "gy", "gz"]
        .iter()
        .map(|ax| {
            let name = format!("{ax}_cor_dph");
            header
                .iter()
                .position(|h| *h == name)
                .expect("a cor column")
        })
        .collect();
    let (mut same, mut rows, mut worst) = (0, 0, 0.0f64);
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        for (k, &col) in cols.iter().enumerate() {
            let applied: f64 = cells[col].parse().unwrap();
            let got = c[i * 3 + k].cor;
            worst = worst.max((got - applied).abs());
            same += usize::from(got.to_bits() == applied.to_bits());
        }
        rows += 1;
    }
    println!(
        "unit header against driftlab apply: {same} of {} axis samples bit-identical, max \
         difference {worst:.3e} deg/h",
        3 * rows
    );
    assert_eq!(rows, log.len());
    assert_eq!(same, 3 * rows);
    // The temperature history is held once: one smoothing buffer and one pair of rings.
    let header = firmware::export_unit(&unit, Format::CHeader, &ExportOptions::default()).unwrap();
    assert_eq!(header.matches("double smooth_buf[").count(), 1);
    for axis in ["gx", "gy", "gz"] {
        assert!(header.contains(&format!("driftlab_{axis}_k0")), "{axis}");
        assert!(
            header.contains(&format!("driftlab_{axis}_predict(")),
            "{axis}"
        );
    }
    assert!(!header.contains("malloc("));
}

#[test]
fn unit_header_restarts_every_axis_after_a_dropout_as_driftlab() {
    // Ten minutes and four periods (just beyond the 2.5 that make a gap) cut from the
    // validation run: the push sees them in the time stamps and restarts T's history, as
    // driftlab's streaming corrector of each axis does.
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(dir.path(), &[]);
    let log = read("imu3-validation.csv");
    let dt = log.timing().nominal_dt_s;
    let ten_min = (600.0 / dt) as usize;
    let gapped = with_dropout(&with_dropout(&log, 30_000..30_004), 9_000..9_000 + ten_min);
    let timing = gapped.timing();
    assert_eq!(timing.segments.len(), 3, "{:?}", timing.gaps);
    let Some((a, _)) = c_unit_agrees(&unit, &gapped) else {
        return;
    };
    assert_eq!(a.identical, a.compared, "{a:?}");
}

#[test]
fn unit_header_with_a_regression_axis_keeps_its_own_corrector_and_agrees() {
    // gy (T through a lag) and gz fitted as regression models: each one's corrector lives
    // inside the unit's state, the Vakhrameev axis gx reads the shared T.
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(
        dir.path(),
        &["--axis-model", "gy=coil-lag", "--axis-model", "gz=poly-t"],
    );
    let DriftModel::Regression(gy) = &unit.axes[1].model else {
        panic!("gy is not a regression axis");
    };
    assert!(
        gy.model.lag_s.is_some_and(|l| l > 0.0),
        "{:?}",
        gy.model.lag_s
    );
    assert!(matches!(unit.axes[2].model, DriftModel::Regression(_)));
    let header = firmware::export_unit(&unit, Format::CHeader, &ExportOptions::default()).unwrap();
    assert!(
        header.contains("driftlab_gy_state driftlab_gy;"),
        "{header}"
    );
    assert!(
        header.contains("driftlab_gz_state driftlab_gz;"),
        "{header}"
    );
    let log = read("imu3-validation.csv");
    let Some((a, _)) = c_unit_agrees(&unit, &log) else {
        return;
    };
    assert_eq!(a.identical, a.compared, "{a:?}");
    // After a dropout the regression axes restart their own filters, the shared T its history.
    let gapped = with_dropout(&log, 9_000..12_000);
    let Some((a, _)) = c_unit_agrees(&unit, &gapped) else {
        return;
    };
    assert_eq!(a.identical, a.compared, "{a:?}");
}

#[test]
fn unit_header_of_the_firmware_forms_agrees_bit_for_bit() {
    // Each axis a polynomial in T - Tref: its own Tref and powers under the axis's names.
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(
        dir.path(),
        &[
            "--axis-model",
            "gx=px4",
            "--axis-model",
            "gy=ardupilot",
            "--axis-model",
            "gz=poly-t5",
        ],
    );
    let header = firmware::export_unit(&unit, Format::CHeader, &ExportOptions::default()).unwrap();
    for (axis, t_ref) in ["gx", "gy", "gz"].iter().zip(&unit.axes) {
        let DriftModel::Regression(r) = &t_ref.model else {
            panic!("{axis} is not a regression axis");
        };
        let line = format!(
            "#define DRIFTLAB_{}_T_REF_C {:?}\n",
            axis.to_uppercase(),
            r.model.t_ref_c.unwrap()
        );
        assert!(header.contains(&line), "{line}");
    }
    let log = read("imu3-validation.csv");
    let Some((a, _)) = c_unit_agrees(&unit, &log) else {
        return;
    };
    assert_eq!(a.identical, a.compared, "{a:?}");
}

#[test]
fn a_single_axis_calibration_exports_as_it_always_has() {
    let cal = calibrate(
        &read("calibration.csv"),
        [driftlab::models::approx::ApproxKind::Parabolic; 3],
        false,
    );
    let model = DriftModel::Vakhrameev(Box::new(cal));
    let unit = UnitCalibration::single(model.clone());
    assert!(!unit.is_unit());
    let opts = ExportOptions::default();
    for format in [Format::CHeader, Format::CsvTable] {
        assert_eq!(
            firmware::export_unit(&unit, format, &opts).unwrap(),
            firmware::export_model(&model, format, &opts).unwrap(),
            "{format}"
        );
    }
}

/// The rows of `axis` in a unit's table file: its header's columns and the numbers.
fn table_rows(text: &str, axis: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    assert_eq!(header[0], "axis");
    let rows = lines
        .filter_map(|l| l.strip_prefix(&format!("{axis},")))
        .map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap()).collect())
        .collect();
    (header[1..].to_vec(), rows)
}

#[test]
fn unit_tables_hold_each_axis_curves_at_their_grid_points() {
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(dir.path(), &[]);
    let opts = ExportOptions {
        points: 21,
        ..ExportOptions::default()
    };
    let text = firmware::export_unit(&unit, Format::CsvTable, &opts).unwrap();
    for ax in &unit.axes {
        let DriftModel::Vakhrameev(cal) = &ax.model else {
            panic!("{} is not a Vakhrameev axis", ax.name);
        };
        let (columns, rows) = table_rows(&text, &ax.name);
        assert_eq!(columns.len(), 10, "{columns:?}");
        assert_eq!(rows.len(), 21, "axis {}", ax.name);
        let curves = [
            &cal.k0,
            &cal.k1_plus,
            &cal.k1_minus,
            &cal.k2_plus,
            &cal.k2_minus,
        ];
        for (j, row) in rows.iter().enumerate() {
            for (c, a) in curves.iter().enumerate() {
                let (x, k) = (row[2 * c], row[2 * c + 1]);
                assert_eq!(
                    k,
                    a.eval(x),
                    "axis {} row {j} column {}",
                    ax.name,
                    columns[c]
                );
            }
            if j == 0 {
                assert_eq!(row[0], cal.k0.x_min());
            }
            if j == 20 {
                assert_eq!(row[0], cal.k0.x_max());
            }
        }
        assert!(
            text.contains(&format!("# axis {}: driftlab", ax.name)),
            "{}",
            ax.name
        );
    }
    // A unit mixing a Vakhrameev and a regression axis has tables of different columns.
    let mixed_dir = tempfile::tempdir().unwrap();
    let mixed = calibrate_unit(mixed_dir.path(), &["--axis-model", "gz=poly-t"]);
    let e = firmware::export_unit(&mixed, Format::CsvTable, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("gx") && e.contains("gz") && e.contains("export each axis alone"),
        "{e}"
    );
}

#[test]
fn export_command_writes_the_unit_and_one_axis_of_it() {
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(dir.path(), &[]);
    let path = dir.path().join("unit.json");
    let path = path.to_str().unwrap();
    let run = |args: &[&str]| {
        let out = driftlab(&[&["export", path][..], args].concat());
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let opts = ExportOptions::default();
    assert_eq!(
        run(&["--format", "c-header"]),
        firmware::export_unit(&unit, Format::CHeader, &opts).unwrap()
    );
    assert_eq!(
        run(&["--format", "csv-table"]),
        firmware::export_unit(&unit, Format::CsvTable, &opts).unwrap()
    );
    // One axis alone is that axis's single-axis header, naming the axis
    // (tests/export/flight_one_axis.rs holds it line for line).
    let gy = &unit.axis("gy").unwrap().model;
    let alone = run(&["--format", "c-header", "--axis", "gy"]);
    assert_eq!(
        alone.len(),
        firmware::export_model(gy, Format::CHeader, &opts).unwrap().len()
            + "#define DRIFTLAB_AXIS \"gy\"\n".len()
            + " *   axis:      gy (rate column gy_dps), one of the unit's axes gx, gy, gz, exported alone\n".len()
    );
    let out = driftlab(&["export", path, "--format", "c-header", "--axis", "roll"]);
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("no axis roll") && e.contains("gx, gy, gz"),
        "{e}"
    );
}

#[test]
fn a_regression_axis_reading_a_second_temperature_is_refused_by_name() {
    // The unit's push takes one temperature: an axis whose model reads a second sensor cannot
    // be corrected by it, and the refusal says which axis and how to export it.
    let dir = tempfile::tempdir().unwrap();
    // Sukhanov's model reads the chamber's temperature as its second sensor.
    let unit = calibrate_unit(dir.path(), &["--axis-model", "gz=sukhanov"]);
    let e = firmware::export_unit(&unit, Format::CHeader, &ExportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("axis gz")
            && e.contains("temp_chamber_c")
            && e.contains("export that axis alone"),
        "{e}"
    );
}

/// The lines of `text` from the first that starts with `from` to the first after it that starts
/// with `to`, both included, trimmed of their indentation.
fn block<'a>(text: &'a str, from: &str, to: &str) -> Vec<&'a str> {
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let start = lines
        .iter()
        .position(|l| l.starts_with(from))
        .unwrap_or_else(|| panic!("no line {from}"));
    let len = lines[start..]
        .iter()
        .position(|l| l.starts_with(to))
        .unwrap_or_else(|| panic!("no line {to} after {from}"));
    lines[start..=start + len].to_vec()
}

#[test]
fn one_axis_and_a_unit_run_the_same_curve_evaluator_and_temperature_history() {
    // One C runtime: the single-axis header keeps T's history inside its state (st->), the
    // unit's header in a history of its own (t->); the statements are the same.
    let dir = tempfile::tempdir().unwrap();
    let unit = calibrate_unit(dir.path(), &[]);
    let opts = ExportOptions::default();
    let unit_h = firmware::export_unit(&unit, Format::CHeader, &opts).unwrap();
    let one_h = firmware::export_model(&unit.axes[0].model, Format::CHeader, &opts).unwrap();
    let (from, to) = ("/* Causal moving average", "t->slot = slot + 1 == len");
    let in_state: Vec<String> = block(&unit_h, from, to)
        .iter()
        .map(|l| l.replace("t->", "st->"))
        .collect();
    let one = block(&one_h, from, &format!("s{to}"));
    assert!(in_state.len() > 15, "{in_state:?}");
    assert_eq!(in_state, one);
    let (from, to) = (
        "static inline double driftlab_curve_eval",
        "return ((s[3] * u + s[2]) * u + s[1]) * u + s[0];",
    );
    assert_eq!(block(&unit_h, from, to), block(&one_h, from, to));
}

#[test]
fn unit_header_compiles_and_agrees_with_axes_named_like_its_own_identifiers() {
    // Axes named as the header's own identifiers and macros, as a column (`k0_dph`), with
    // characters C does not take in a name, and names equal once made into identifiers;
    // every third axis a regression model (its corrector renamed under the axis).
    let dir = tempfile::tempdir().unwrap();
    let base = calibrate_unit(dir.path(), &["--axis-model", "gz=poly-t"]);
    let names = [
        "names",
        "k0",
        "k1_plus",
        "k1_minus",
        "k2_plus",
        "k2_minus",
        "k0_dph",
        "state",
        "temperature",
        "axis1",
        "gx",
        "GX",
        "g x",
        "1st axis",
        "ω-x",
        "*/ int x; /*",
        "quote \" and \\ backslash ??/",
        "line // break",
        "",
    ];
    let mut unit = base.clone();
    unit.axes = names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let mut a = base.axes[k % 3].clone();
            a.name = if n.is_empty() {
                "#".to_string()
            } else {
                n.to_string()
            };
            a
        })
        .collect();
    let header = firmware::export_unit(&unit, Format::CHeader, &ExportOptions::default()).unwrap();
    // The names only in comments and strings: every axis's index macro, and the names array
    // holding each name as it is.
    assert_eq!(
        header.matches("#define DRIFTLAB_AXIS_").count(),
        names.len() + 1
    );
    assert!(header.contains("#define DRIFTLAB_AXIS_NAMES { \"names\", \"k0\", "));
    assert!(header.contains("\"quote \\\" and \\\\ backslash \\?\\?/\""));
    assert!(header.contains("\"line // break\""));
    assert!(
        header.contains("driftlab_gx_predict("),
        "an ordinary name keeps its part"
    );
    // Compiled strictly and run on a stretch of the validation run: every axis bit for bit
    // as driftlab's corrector of its model.
    let log = read("imu3-validation.csv");
    let log = with_dropout(&log, 6_000..log.len());
    let Some((a, _)) = c_unit_agrees(&unit, &log) else {
        return;
    };
    assert_eq!(a.compared, names.len() * log.len());
    assert_eq!(a.identical, a.compared, "{a:?}");
}
