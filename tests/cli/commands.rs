//! The command line end to end, as a user runs it: simulate, calibrate, apply, evaluate,
//! inspect, on the bundled sample logs and on fresh simulated runs.

use serde_json::{Value, json};
use std::path::{Path, PathBuf};

use crate::common;
use common::run::{driftlab, fails, ok, p, sample};

fn evaluate(cal: &str, log: &str) -> Value {
    serde_json::from_str(&ok(&["evaluate", cal, log, "--json"])).unwrap()
}

fn ratio(v: &Value) -> f64 {
    v["evaluation"]["comparison"]["p2p_ratio"].as_f64().unwrap()
}

#[test]
fn sample_logs_calibrate_and_hold_out() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--out",
        &cal,
        "--gyro-id",
        "SIM-1",
    ]);
    let ins = evaluate(&cal, &sample("calibration.csv"));
    assert_eq!(ins["in_sample"], Value::Bool(true));
    let held = evaluate(&cal, &sample("validation.csv"));
    assert_eq!(held["in_sample"], Value::Bool(false));
    // Measured 4.7x in-sample and 4.7x held out; the noise floor of these logs allows ~12x.
    assert!(ratio(&ins) > 3.5, "in-sample p2p ratio {}", ratio(&ins));
    assert!(ratio(&held) > 3.5, "held-out p2p ratio {}", ratio(&held));
}

#[test]
fn held_out_runs_are_never_made_worse() {
    // Other runs of the same gyro: no plateaus at all, and ramps twice as fast as any in the
    // calibration (beyond its Ṫ and T̈ ranges, where the coefficients are held at their edges).
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    for profile in ["no-plateaus", "fast-ramps", "validation"] {
        let log = p(dir.path(), &format!("{profile}.csv"));
        ok(&[
            "simulate",
            "--profile",
            profile,
            "--seed",
            "11",
            "--out",
            &log,
        ]);
        let e = evaluate(&cal, &log);
        let c = &e["evaluation"]["comparison"];
        for key in ["p2p_ratio", "std_ratio", "win_mean_ratio", "win_rms_ratio"] {
            assert!(
                c[key].as_f64().unwrap() > 1.0,
                "{profile}: {key} = {}",
                c[key]
            );
        }
        assert!(ratio(&e) > 2.5, "{profile}: p2p ratio {}", ratio(&e));
    }
}

#[test]
fn apply_writes_raw_minus_prediction() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, out) = (p(dir.path(), "cal.json"), p(dir.path(), "out.csv"));
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--out",
        &cal,
        "--k1",
        "spline",
        "--knots",
        "6",
    ]);
    ok(&["apply", &cal, &sample("validation.csv"), "--out", &out]);
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c")
    );
    let mut rows = 0;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(v.len(), 5);
        assert!((v[1] - v[2] - v[3]).abs() < 1e-9, "{line}");
        rows += 1;
    }
    let source = std::fs::read_to_string(sample("validation.csv")).unwrap();
    let data_rows = source.lines().filter(|l| !l.starts_with('#')).count() - 1;
    assert_eq!(rows, data_rows);
}

#[test]
fn recipe_saved_and_reused_gives_the_same_calibration() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, r) = (
        p(dir.path(), "a.json"),
        p(dir.path(), "b.json"),
        p(dir.path(), "recipe.json"),
    );
    let log = sample("calibration.csv");
    ok(&[
        "calibrate",
        &log,
        "--out",
        &a,
        "--k0",
        "pwl",
        "--k2",
        "parabolic",
        "--step-h",
        "20",
        "--plateau",
        "4000:7000",
        "--plateau",
        "15000:16800",
        "--plateau",
        "28500:30600",
        "--save-recipe",
        &r,
    ]);
    ok(&["calibrate", &log, "--out", &b, "--recipe", &r]);
    let strip = |path: &str| {
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        v["calibration"]["created"] = Value::Null;
        v
    };
    let (va, vb) = (strip(&a), strip(&b));
    assert_eq!(va, vb);
    let plateaus = va["calibration"]["plateaus"].as_array().unwrap();
    assert_eq!(plateaus.len(), 3);
    assert_eq!(va["calibration"]["k0"]["kind"], "pwl");
    assert_eq!(va["calibration"]["recipe"]["step_h_s"], 20.0);
    // A calibration file serves as a recipe too.
    ok(&["calibrate", &log, "--out", &b, "--recipe", &a]);
    assert_eq!(strip(&b), va);
}

#[test]
fn inspect_reports_columns_plateaus_and_sampling() {
    let v: Value =
        serde_json::from_str(&ok(&["inspect", &sample("calibration.csv"), "--json"])).unwrap();
    assert_eq!(v["step_s"], 1.0);
    let temps: Vec<f64> = v["plateaus"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["temp_c"].as_f64().unwrap())
        .collect();
    assert_eq!(temps.len(), 4, "{temps:?}");
    for (got, want) in temps.iter().zip([20.0, 60.0, -50.0, 20.0]) {
        assert!((got - want).abs() < 0.1);
    }
    assert!((v["temp_min_c"].as_f64().unwrap() + 50.0).abs() < 0.01);
    assert_eq!(v["extra_channels"][0], "temp_chamber_c");
    assert_eq!(v["problems"], serde_json::json!([]));
    // A null says why, as the text does: read in ms, the log is 40 s long, shorter than the
    // T history a rate needs.
    let v: Value = serde_json::from_str(&ok(&[
        "inspect",
        &sample("calibration.csv"),
        "--json",
        "--time-unit",
        "ms",
    ]))
    .unwrap();
    assert!(v["max_abs_rate_c_per_min"].is_null());
    let why = v["problems"][0].as_str().unwrap_or_default();
    assert!(why.starts_with("no temperature rate"), "{v}");
    let text = ok(&["inspect", &sample("validation.csv")]);
    assert!(
        text.contains("plateaus found (4)"),
        "start, 0, 40 and -30 degC holds: {text}"
    );
}

#[test]
fn bad_input_gives_a_located_error_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(
        &bad,
        "time_s,omega_dph,temp_c\n0,0.1,20\n1,0.2,20\n2,abc,20\n",
    )
    .unwrap();
    let cal = p(dir.path(), "cal.json");
    let err = fails(&["calibrate", bad.to_str().unwrap(), "--out", &cal]);
    assert!(err.contains("bad.csv:4:2"), "{err}");
    assert!(!Path::new(&cal).exists());

    let junk = dir.path().join("junk.json");
    std::fs::write(
        &junk,
        "{\"format\": \"driftlab-calibration\", \"version\": 99}",
    )
    .unwrap();
    let err = fails(&[
        "evaluate",
        junk.to_str().unwrap(),
        &sample("validation.csv"),
    ]);
    assert!(
        err.contains("junk.json") && err.contains("version 99"),
        "{err}"
    );

    let missing: PathBuf = dir.path().join("nope.csv");
    let err = fails(&["inspect", missing.to_str().unwrap()]);
    assert!(err.contains("nope.csv"), "{err}");

    let err = fails(&[
        "calibrate",
        &sample("calibration.csv"),
        "--out",
        &cal,
        "--k1",
        "cubic",
    ]);
    assert!(err.contains("cubic"), "{err}");
    let err = fails(&[
        "calibrate",
        &sample("calibration.csv"),
        "--out",
        &cal,
        "--plateau",
        "9:3",
    ]);
    assert!(err.contains("9:3"), "{err}");
    let err = fails(&[
        "simulate",
        "--profile",
        "moon",
        "--out",
        &p(dir.path(), "x.csv"),
    ]);
    assert!(err.contains("calibration"), "lists the profiles: {err}");
}

#[test]
fn explicit_column_mapping_and_units() {
    // A semicolon, decimal-comma log in deg/s with time in minutes and columns in another order.
    let dir = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let mut out = String::from("T;t;w\n");
    for line in src.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
        out += &format!("{};{};{}\n", v[2], v[0] / 60.0, v[1] / 3600.0).replace('.', ",");
    }
    let odd = dir.path().join("odd.csv");
    std::fs::write(&odd, out).unwrap();
    let (a, b) = (p(dir.path(), "a.json"), p(dir.path(), "b.json"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &a]);
    ok(&[
        "calibrate",
        odd.to_str().unwrap(),
        "--out",
        &b,
        "--time-col",
        "2",
        "--rate-col",
        "w",
        "--temp-col",
        "T",
        "--rate-unit",
        "deg/s",
        "--time-unit",
        "min",
    ]);
    let k0 = |path: &str| {
        let v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        v["calibration"]["k0"]["curve"]["coeffs"].clone()
    };
    let (ka, kb) = (k0(&a), k0(&b));
    for i in 0..3 {
        let (x, y) = (ka[i].as_f64().unwrap(), kb[i].as_f64().unwrap());
        assert!(
            (x - y).abs() < 1e-6 * x.abs().max(1e-3),
            "K0 coefficient {i}: {x} vs {y}"
        );
    }
}

#[test]
fn compare_judges_presets_and_a_custom_model_and_fit_chooses_its_samples() {
    let out = ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &sample("validation.csv"),
        "--models",
        "vakhrameev,poly-t",
        "--custom",
        "1,T,Tdot",
        "--fit",
        "staged",
        "--json",
    ]);
    let v: Value = serde_json::from_str(&out).unwrap();
    let models = v["models"].as_array().unwrap();
    let names: Vec<&str> = models
        .iter()
        .map(|m| m["model"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["vakhrameev", "poly-t", "custom"]);
    for m in models {
        assert!(m["error"].is_null(), "{m}");
        let logs = m["logs"].as_array().unwrap();
        let held: Vec<bool> = logs
            .iter()
            .map(|l| l["held_out"].as_bool().unwrap())
            .collect();
        assert_eq!(held, [false, true]);
        for l in logs {
            let r = l["evaluation"]["comparison"]["p2p_ratio"].as_f64().unwrap();
            assert!(r.is_finite() && r > 0.0, "{r}");
        }
    }

    // The same choice reaches a calibration file through `calibrate --fit`.
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("custom.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--model",
        "custom",
        "--terms",
        "1,T,Tdot",
        "--fit",
        "staged",
        "--out",
        cal.to_str().unwrap(),
    ]);
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    assert_eq!(file["calibration"]["model"]["spec"]["samples"], "staged");

    let err = fails(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--custom",
        "1,T",
        "--fit",
        "sometimes",
    ]);
    assert!(err.contains("--fit") && err.contains("staged"), "{err}");
}

/// Least-squares line of Ω over T on the samples of `log` whose time lies in one of `ranges`
/// (inclusive), computed here from the file's own numbers: (slope, intercept).
fn line_on_ranges(log: &str, ranges: &[(f64, f64)]) -> (f64, f64) {
    let text = std::fs::read_to_string(log).unwrap();
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        if ranges.iter().any(|&(a, b)| (a..=b).contains(&f[0])) {
            xs.push(f[2]);
            ys.push(f[1]);
        }
    }
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    (sxy / sxx, my - sxy / sxx * mx)
}

#[test]
fn signal_settings_reach_a_regression_model() {
    // IEEE 952 fitted in stages takes T and bias from the plateaus: given by hand, the static
    // line must be the least-squares line through exactly those samples, and H and the
    // smoothing must be the ones asked for.
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    let cal = p(dir.path(), "b.json");
    ok(&[
        "calibrate",
        &log,
        "--model",
        "ieee952",
        "--plateau",
        "3600:7200",
        "--plateau",
        "14000:16800",
        "--step-h",
        "5",
        "--smooth",
        "5",
        "--out",
        &cal,
    ]);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let m = &v["calibration"]["model"];
    assert_eq!(m["spec"]["step_h_s"], 5.0);
    assert_eq!(m["spec"]["smoothing_s"], 5.0);
    assert_eq!(m["names"][0], "T");
    assert_eq!(m["names"][2], "1");
    let (slope, intercept) = line_on_ranges(&log, &[(3600.0, 7200.0), (14000.0, 16800.0)]);
    let c = |k: usize| m["coefficients"][k].as_f64().unwrap();
    assert!(
        (c(0) - slope).abs() < 1e-9 * slope.abs(),
        "{} vs {slope}",
        c(0)
    );
    assert!((c(2) - intercept).abs() < 1e-9, "{} vs {intercept}", c(2));
}

#[test]
fn an_option_a_model_cannot_use_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    let out = p(dir.path(), "x.json");
    for (args, option) in [
        (
            &["--model", "poly-t", "--plateau", "3600:7200"][..],
            "--plateau",
        ),
        (&["--model", "ieee952", "--k1", "spline"][..], "--k1"),
        (&["--model", "coil-lag", "--knots", "5"][..], "--knots"),
        (
            &["--model", "sukhanov", "--deadband-tdot", "0.01"][..],
            "--deadband-tdot",
        ),
        (&["--delay", "auto"][..], "--delay"),
        (&["--model", "ieee952", "--lag", "auto"][..], "--lag"),
        (&["--model", "yan-cross", "--terms", "T,1"][..], "--terms"),
    ] {
        let mut all = vec!["calibrate", &log, "--out", &out];
        all.extend_from_slice(args);
        let err = fails(&all);
        assert!(err.contains(option), "{args:?}: {err}");
        assert!(!Path::new(&out).exists(), "{args:?} wrote a file");
    }
    // A recipe file's Vakhrameev settings are said to be ignored, not silently dropped.
    let recipe = p(dir.path(), "r.json");
    std::fs::write(
        &recipe,
        r#"{ "k1_plus": { "kind": "spline", "knots": 5 } }"#,
    )
    .unwrap();
    let run = common::run::driftlab(&[
        "calibrate",
        &log,
        "--model",
        "ieee952",
        "--recipe",
        &recipe,
        "--out",
        &out,
    ]);
    assert!(run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("k1_plus") && err.contains("not used"), "{err}");
}

#[test]
fn compare_fails_when_no_model_can_be_fitted_and_says_why_for_each() {
    // A run with no plateau: every model fitted on plateaus fails; the comparison is empty.
    let dir = tempfile::tempdir().unwrap();
    let log = p(dir.path(), "no-plateaus.csv");
    ok(&["simulate", "--profile", "no-plateaus", "--out", &log]);
    for json in [false, true] {
        let mut args = vec![
            "compare",
            "--train",
            &log,
            "--models",
            "vakhrameev,yan-cross",
        ];
        if json {
            args.push("--json");
        }
        let run = driftlab(&args);
        let (out, err) = (
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr),
        );
        assert!(
            !run.status.success(),
            "json {json}: exit 0 with no model\n{out}"
        );
        assert!(err.contains("no model could be fitted"), "{err}");
        // Each model's own reason is still given, in the table or the JSON.
        assert_eq!(out.matches("no plateaus").count(), 1, "{out}");
        assert!(
            out.contains("yan-cross") && out.contains("has none"),
            "{out}"
        );
    }
    // One model that fits is a comparison: exit 0.
    ok(&["compare", "--train", &log, "--models", "vakhrameev,poly-t"]);
}

#[test]
fn a_one_sample_plateau_has_no_deviation_in_the_file_or_the_table() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "one.json");
    let log = sample("calibration.csv");
    let plateaus = ["1000:3500", "3600.5:3601.4", "7000:11900", "21000:24000"];
    let mut args = vec!["calibrate", &log, "--out", &cal];
    for r in &plateaus {
        args.extend(["--plateau", r]);
    }
    let table = ok(&args);
    let row = table
        .lines()
        .find(|l| l.trim_end().ends_with(" 1") && l.contains("3601"))
        .unwrap_or_else(|| panic!("{table}"));
    assert!(row.contains("n/a"), "{row}");
    // `null` in the file, where 0 would claim a noiseless reading.
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let one = &v["calibration"]["plateaus"][1];
    assert_eq!(one["samples"], 1, "{one}");
    assert!(
        one["omega_std_dph"].is_null() && one["omega_sem_dph"].is_null(),
        "{one}"
    );
    let other = &v["calibration"]["plateaus"][0];
    assert!(other["omega_std_dph"].as_f64().unwrap() > 0.0, "{other}");
    let applied = p(dir.path(), "applied.csv");
    ok(&["apply", &cal, &log, "--out", &applied]);
    // A file written before held 0 there: it loads, and means the same.
    let edited = p(dir.path(), "edited.json");
    for (value, loads) in [(json!(0.0), true), (json!(0.5), false)] {
        v["calibration"]["plateaus"][1]["omega_std_dph"] = value.clone();
        v["calibration"]["plateaus"][1]["omega_sem_dph"] = value.clone();
        std::fs::write(&edited, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let run = driftlab(&["apply", &edited, &log, "--out", &applied]);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.success(), loads, "{value}: {err}");
        if !loads {
            assert!(
                err.contains("plateaus[1].omega_std_dph: is 0.5 on a plateau of 1 sample"),
                "{err}"
            );
        }
    }
}

/// `simulate --campaign` writes one CSV per run, `<campaign>-<run>.csv`, by the one writer;
/// the repeat's rates are its run's with the turn-on offset added, to the 0.0001 °/h written.
#[test]
fn simulate_campaign_writes_one_log_per_run_with_its_offset() {
    let dir = tempfile::tempdir().unwrap();
    let out = p(dir.path(), "camp");
    ok(&[
        "simulate",
        "--campaign",
        "tiny-three-runs",
        "--out-dir",
        &out,
    ]);
    let c = driftlab::sim::campaign("tiny-three-runs").unwrap();
    for (run, rows) in c.runs.iter().zip([10_801, 10_801, 9_601]) {
        let text = std::fs::read_to_string(Path::new(&out).join(c.file_name(run))).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next(),
            Some("# driftlab simulate --campaign tiny-three-runs")
        );
        assert_eq!(lines.next(), Some("time_s,omega_dph,temp_c,temp_chamber_c"));
        let rates: Vec<f64> = lines
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(rates.len(), rows, "{}", run.name);
        let plain = driftlab::sim::simulate(&run.profile, run.seed);
        for (written, omega) in rates.iter().zip(&plain.omega_dph) {
            let expected = omega + run.turn_on_offset_dph;
            assert!((written - expected).abs() <= 0.00005 + 1e-9, "{}", run.name);
        }
    }
    let err = fails(&[
        "simulate",
        "--campaign",
        "tiny-three-runs",
        "--seed",
        "4",
        "--out-dir",
        &out,
    ]);
    assert!(err.contains("--seed"), "{err}");
}
