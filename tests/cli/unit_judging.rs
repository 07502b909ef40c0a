//! `evaluate`, `compare`, `allan`, `report` and `inspect` on a unit of three gyro axes: a unit
//! calibrated on the bundled three-axis calibration run and judged on its validation run gives,
//! for every axis, exactly the figures the single-axis command gives on that axis alone (a
//! single-axis calibration of that column, `--rate-col gy_dps`): the independent truth is the
//! single-axis path, which has its own tests against known coefficients.

use serde_json::Value;
use std::path::PathBuf;
use std::sync::OnceLock;

use crate::common;
use common::run::{fails, ok, sample};

const AXES: [&str; 3] = ["gx", "gy", "gz"];

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(args)).unwrap_or_else(|e| panic!("driftlab {args:?}: {e}"))
}

/// The calibrations every test judges, made once: the unit of every axis, the same unit with
/// poly-t on every axis (which makes some figures worse than raw on the validation run), and a
/// single-axis calibration of each column.
struct Calibrations {
    _dir: tempfile::TempDir,
    unit: String,
    poly_unit: String,
    single: Vec<String>,
}

fn calibrations() -> &'static Calibrations {
    static CAL: OnceLock<Calibrations> = OnceLock::new();
    CAL.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let at = |name: &str| dir.path().join(name).display().to_string();
        let log = sample("imu3-calibration.csv");
        let unit = at("unit.json");
        ok(&["calibrate", &log, "--out", &unit]);
        let poly_unit = at("poly-unit.json");
        ok(&["calibrate", &log, "--model", "poly-t", "--out", &poly_unit]);
        let single = AXES
            .iter()
            .map(|a| {
                let out = at(&format!("{a}.json"));
                ok(&[
                    "calibrate",
                    &log,
                    "--rate-col",
                    &format!("{a}_dps"),
                    "--out",
                    &out,
                ]);
                out
            })
            .collect();
        Calibrations {
            _dir: dir,
            unit,
            poly_unit,
            single,
        }
    })
}

/// The ratios below 1 of an evaluation's comparison.
fn worse_count(evaluation: &Value) -> usize {
    ["p2p_ratio", "std_ratio", "win_mean_ratio", "win_rms_ratio"]
        .iter()
        .filter(|k| evaluation["comparison"][**k].as_f64().unwrap() < 1.0)
        .count()
}

#[test]
fn evaluate_gives_every_axis_what_the_single_axis_command_gives() {
    let c = calibrations();
    for log in ["imu3-validation.csv", "imu3-calibration.csv"] {
        let log = sample(log);
        let unit = json(&["evaluate", &c.unit, &log, "--json"]);
        let axes = unit["axes"].as_array().unwrap();
        assert_eq!(axes.len(), 3);
        for (k, axis) in AXES.iter().enumerate() {
            let col = format!("{axis}_dps");
            let single = json(&["evaluate", &c.single[k], &log, "--rate-col", &col, "--json"]);
            let got = &axes[k];
            assert_eq!(got["name"], *axis);
            assert_eq!(got["log_axis"], *axis);
            for key in ["evaluation", "options", "in_sample", "model", "log"] {
                assert_eq!(got[key], single[key], "{axis} on {log}: {key}");
            }
        }
    }
    // In-sample on the calibration run, held out on the validation run.
    let held = json(&[
        "evaluate",
        &c.unit,
        &sample("imu3-validation.csv"),
        "--json",
    ]);
    assert!(
        held["axes"]
            .as_array()
            .unwrap()
            .iter()
            .all(|a| a["in_sample"] == false)
    );
}

#[test]
fn evaluate_prints_a_table_per_axis_and_a_summary_marking_what_is_worse() {
    let c = calibrations();
    let log = sample("imu3-validation.csv");
    let v = json(&["evaluate", &c.poly_unit, &log, "--json"]);
    let expected: usize = v["axes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| worse_count(&a["evaluation"]))
        .sum();
    assert!(
        expected > 0,
        "poly-t should make some figure worse than raw on the validation run"
    );
    let text = ok(&["evaluate", &c.poly_unit, &log]);
    for axis in AXES {
        assert!(text.contains(&format!("=== Axis {axis}")), "{text}");
    }
    let summary = text
        .split("Unit summary")
        .nth(1)
        .unwrap_or_else(|| panic!("no summary in {text}"));
    let rows: Vec<&str> = summary
        .lines()
        .filter(|l| AXES.iter().any(|a| l.starts_with(&format!("  {a} "))))
        .collect();
    assert_eq!(rows.len(), 3, "{summary}");
    let marked: usize = rows.iter().map(|l| l.matches("x worse").count()).sum();
    assert_eq!(marked, expected, "{summary}");
}

#[test]
fn evaluate_names_an_axis_the_log_lacks() {
    let c = calibrations();
    let e = fails(&["evaluate", &c.unit, &sample("validation.csv")]);
    assert!(
        e.contains("no gyro axis gx") && e.contains("rename them in its header"),
        "{e}"
    );
}

#[test]
fn allan_gives_every_axis_what_it_gives_that_axis_alone() {
    let log = sample("imu3-validation.csv");
    let all = json(&["allan", &log, "--json"]);
    let axes = all["axes"].as_array().unwrap();
    assert_eq!(axes.len(), 3);
    for (k, axis) in AXES.iter().enumerate() {
        let single = json(&[
            "allan",
            &log,
            "--rate-col",
            &format!("{axis}_dps"),
            "--json",
        ]);
        let mut got = axes[k].clone();
        assert_eq!(got["name"], *axis);
        got.as_object_mut().unwrap().remove("name");
        let mut want = single.clone();
        want.as_object_mut().unwrap().remove("kalibr");
        // The log's temperature is the log's, given once at the top.
        want.as_object_mut().unwrap().remove("temperature");
        assert_eq!(all["temperature"], single["temperature"]);
        assert_eq!(got, want, "{axis}");
        // Kalibr's gyro values are the axis analysed (the noisiest of every axis only when
        // every axis is analysed); its accelerometer pair is every accelerometer axis's.
        for key in ["noise_density", "random_walk"] {
            let value = &single["kalibr"]["gyroscope"][key]["value"];
            if !value.is_null() {
                assert_eq!(value["axis"], *axis, "{axis} {key}");
            }
        }
        assert_eq!(
            all["kalibr"]["accelerometer"], single["kalibr"]["accelerometer"],
            "{axis}"
        );
    }
    // The first axis stays at the top, as for a log of one axis.
    assert_eq!(all["adev"], axes[0]["adev"]);
    // --axes chooses, by name, column or ending letter.
    let two = json(&["allan", &log, "--axes", "z,gy_dps", "--json"]);
    let names: Vec<&str> = two["axes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["gz", "gy"]);
    let e = fails(&["allan", &log, "--axes", "q"]);
    assert!(e.contains("--axes q") && e.contains("gx, gy, gz"), "{e}");
    // The text: a table per axis, then the read-outs of every axis.
    let text = ok(&["allan", &log]);
    for axis in AXES {
        assert!(text.contains(&format!("=== Axis {axis} ===")), "{text}");
    }
    assert!(text.contains("read-outs of every axis analysed"), "{text}");
}

#[test]
fn compare_gives_every_axis_what_it_gives_that_axis_alone() {
    let (train, test) = (
        sample("imu3-calibration.csv"),
        sample("imu3-validation.csv"),
    );
    let args = |extra: &[&str]| -> Value {
        let mut a = vec![
            "compare",
            "--train",
            &train,
            "--test",
            &test,
            "--models",
            "vakhrameev,poly-t",
            "--json",
        ];
        a.extend_from_slice(extra);
        json(&a)
    };
    let all = args(&[]);
    let axes = all["axes"].as_array().unwrap();
    assert_eq!(axes.len(), 3);
    for (k, axis) in AXES.iter().enumerate() {
        let col = format!("{axis}_dps");
        let single = args(&["--rate-col", &col]);
        assert_eq!(axes[k]["name"], *axis);
        assert_eq!(axes[k]["models"], single["models"], "{axis}");
    }
    assert_eq!(all["models"], axes[0]["models"]);
    let one = args(&["--axes", "gz"]);
    assert_eq!(one["axes"].as_array().unwrap().len(), 1);
    assert_eq!(one["axes"][0]["models"], axes[2]["models"]);
    // The text: a table per axis, then each model's corrected peak-to-peak on every axis, a
    // ratio below 1 marked, and every other figure worse than raw named below.
    let text = ok(&[
        "compare", "--train", &train, "--test", &test, "--models", "poly-t",
    ]);
    for axis in AXES {
        assert!(text.contains(&format!("=== Axis {axis} ===")), "{text}");
    }
    let summary = text.split("Summary of every axis").nth(1).unwrap();
    let poly: Vec<&Value> = axes
        .iter()
        .map(|a| &a["models"][1]["logs"][1]["evaluation"])
        .collect();
    let p2p_worse = poly
        .iter()
        .filter(|e| e["comparison"]["p2p_ratio"].as_f64().unwrap() < 1.0)
        .count();
    let held_out = summary.split("(held out)").nth(1).unwrap();
    let row = held_out
        .lines()
        .find(|l| l.trim_start().starts_with("poly-t "))
        .unwrap();
    assert_eq!(row.matches("x worse").count(), p2p_worse, "{summary}");
    let named = held_out
        .lines()
        .filter(|l| l.contains("poly-t, axis") && l.contains("worse than raw"))
        .count();
    let any_worse = poly.iter().filter(|e| worse_count(e) > 0).count();
    assert!(any_worse > 0);
    assert_eq!(named, any_worse, "{summary}");
}

/// The cells of the unit page's summary row of `axis` in the table of `log`.
fn summary_row(page: &str, log: &str, axis: &str) -> Vec<String> {
    let table = page
        .split(&format!(
            "<table class=\"unit-summary\" data-log=\"{log}\">"
        ))
        .nth(1)
        .unwrap_or_else(|| panic!("no summary of {log}"));
    let table = &table[..table.find("</table>").unwrap()];
    let row = table
        .split(&format!("<tr data-axis=\"{axis}\">"))
        .nth(1)
        .unwrap_or_else(|| panic!("no row {axis} for {log}"));
    let row = &row[..row.find("</tr>").unwrap()];
    row.split("<td")
        .skip(1)
        .map(|c| {
            let c = &c[c.find('>').unwrap() + 1..];
            c[..c.find("</td>").unwrap()].to_string()
        })
        .collect()
}

/// What a single-axis page holds after its identity, and an axis's section of a unit's page,
/// both brought to the same heading levels and figure paths (`gy/k0.png` named `k0.png`).
fn single_body(page: &str) -> String {
    let start = page.find("<h2>Figures of merit</h2>").unwrap();
    let end = page.rfind("</body>").unwrap();
    page[start..end].to_string()
}

fn axis_body(page: &str, axis: &str) -> String {
    let start = page
        .find(&format!("<h2 class=\"axis\" id=\"axis-{axis}\">"))
        .unwrap();
    let rest = &page[start..];
    let start = rest.find("<h3>Figures of merit</h3>").unwrap();
    let rest = &rest[start..];
    let end = rest
        .find("<h2 class=\"axis\"")
        .or_else(|| rest.rfind("</body>"))
        .unwrap();
    rest[..end]
        .replace("<h3>", "<h2>")
        .replace("</h3>", "</h2>")
        .replace("<h4>", "<h3>")
        .replace("</h4>", "</h3>")
        .replace(&format!("also {axis}/"), "also ")
}

#[test]
fn report_holds_every_axis_as_its_single_axis_report_and_a_summary() {
    let c = calibrations();
    let dir = tempfile::tempdir().unwrap();
    let (cal_log, val_log) = (
        sample("imu3-calibration.csv"),
        sample("imu3-validation.csv"),
    );
    let unit_dir = dir.path().join("unit").display().to_string();
    let text = ok(&["report", &c.unit, &cal_log, &val_log, "--out", &unit_dir]);
    let page = std::fs::read_to_string(PathBuf::from(&unit_dir).join("report.html")).unwrap();
    for (k, axis) in AXES.iter().enumerate() {
        assert!(text.contains(&format!("axis {axis}")), "{text}");
        assert!(
            PathBuf::from(&unit_dir)
                .join(axis)
                .join("drift-imu3-validation.svg")
                .is_file()
        );
        let single_dir = dir.path().join(axis).display().to_string();
        let col = format!("{axis}_dps");
        ok(&[
            "report",
            &c.single[k],
            &cal_log,
            &val_log,
            "--rate-col",
            &col,
            "--out",
            &single_dir,
        ]);
        let single =
            std::fs::read_to_string(PathBuf::from(&single_dir).join("report.html")).unwrap();
        // The axis's section is the single-axis page's body: tables, figures and notes.
        assert!(
            axis_body(&page, axis) == single_body(&single),
            "axis {axis}: its section differs from its single-axis report"
        );
        // The summary row holds the single-axis figures of merit.
        for (name, log) in [
            ("imu3-calibration.csv", &cal_log),
            ("imu3-validation.csv", &val_log),
        ] {
            let e = json(&["evaluate", &c.single[k], log, "--rate-col", &col, "--json"]);
            let cmp = &e["evaluation"]["comparison"];
            let row = summary_row(&page, name, axis);
            let f = |part: &str, key: &str| format!("{:.4}", cmp[part][key].as_f64().unwrap());
            assert_eq!(row[0], *axis);
            assert_eq!(row[2], f("raw", "p2p_dph"), "{axis} {name}");
            assert_eq!(row[3], f("corrected", "p2p_dph"), "{axis} {name}");
            assert_eq!(row[5], f("raw", "std_dph"), "{axis} {name}");
            assert_eq!(
                row[9],
                f("corrected", "win_mean_max_abs_dph"),
                "{axis} {name}"
            );
            assert_eq!(row[12], f("corrected", "win_rms_mean_dph"), "{axis} {name}");
        }
    }
}

#[test]
fn report_marks_every_figure_worse_than_raw_in_its_summary() {
    let c = calibrations();
    let dir = tempfile::tempdir().unwrap();
    let log = sample("imu3-validation.csv");
    let out = dir.path().display().to_string();
    ok(&["report", &c.poly_unit, &log, "--out", &out]);
    let page = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    let v = json(&["evaluate", &c.poly_unit, &log, "--json"]);
    let expected: usize = v["axes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| worse_count(&a["evaluation"]))
        .sum();
    assert!(expected > 0);
    let summary = &page[page.find("unit-summary").unwrap()..page.find("class=\"axis\"").unwrap()];
    assert_eq!(summary.matches("class=\"num worse\"").count(), expected);
    assert_eq!(summary.matches("× worse</td>").count(), expected);
}

#[test]
fn inspect_lists_every_gyro_axis_with_its_unit() {
    let log = sample("imu3-calibration.csv");
    let v = json(&["inspect", &log, "--json"]);
    let axes = v["gyro_axes"].as_array().unwrap();
    for (a, name) in axes.iter().zip(AXES) {
        assert_eq!(a["name"], name);
        assert_eq!(a["column"], format!("{name}_dps"));
        assert_eq!(a["unit"], "deg/s");
    }
    assert_eq!(axes.len(), 3);
    let text = ok(&["inspect", &log]);
    assert!(
        text.contains("calibrate fits every axis into one unit calibration"),
        "{text}"
    );
    // The accelerometer columns are recognised as such, listed and kept, in g; the chamber's
    // temperature is kept but is no accelerometer.
    for c in ["ax_g", "ay_g", "az_g"] {
        assert!(
            text.lines()
                .any(|l| l.contains(c) && l.contains("[g] (accelerometer, kept)")),
            "{text}"
        );
    }
    assert!(
        text.lines()
            .any(|l| l.contains("temp_chamber_c") && !l.contains("accelerometer")),
        "{text}"
    );
    let accels: Vec<(&str, &str)> = v["accelerometers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| (a["name"].as_str().unwrap(), a["unit"].as_str().unwrap()))
        .collect();
    assert_eq!(accels, [("ax_g", "g"), ("ay_g", "g"), ("az_g", "g")]);
}

/// A unit calibration on a log that names its axes otherwise is refused with the one remedy
/// that works (its columns named as the calibration's log named them), not an option that
/// does not map them.
#[test]
fn a_unit_on_a_log_with_other_axis_names_is_refused_with_the_remedy_that_works() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = crate::common::run::p(d, "unit.json");
    crate::common::run::ok(&[
        "calibrate",
        &crate::common::run::sample("imu3-calibration.csv"),
        "-o",
        &cal,
    ]);
    let text = std::fs::read_to_string(crate::common::run::sample("imu3-validation.csv")).unwrap();
    let renamed = text.replacen("gx_dps;gy_dps;gz_dps", "wx_dps;wy_dps;wz_dps", 1);
    assert_ne!(renamed, text);
    let log = d.join("renamed.csv");
    std::fs::write(&log, renamed).unwrap();
    let out = crate::common::run::p(d, "out.csv");
    for args in [
        vec!["apply", &cal, log.to_str().unwrap(), "-o", &out],
        vec!["evaluate", &cal, log.to_str().unwrap()],
    ] {
        let e = crate::common::run::fails(&args);
        assert!(
            e.contains("no gyro axis gx") && e.contains("rename them in its header"),
            "{e}"
        );
        assert!(!e.contains("--rate-col"), "{e}");
    }
}
