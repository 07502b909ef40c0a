//! Options at their edges: each is honoured, refused with its name, or told about, never
//! dropped or quietly turned into something else (a window of 1e-300 s labelled as such but
//! one sample long, a unit that multiplies the rates by 206 265 without a word).

use std::path::Path;

use crate::common;
use common::run::{driftlab, fails, ok, p, sample};

#[test]
fn an_option_that_would_be_silent_nonsense_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (log, held) = (sample("calibration.csv"), sample("validation.csv"));
    let cal = p(d, "cal.json");
    ok(&["calibrate", &log, "--out", &cal]);
    let out = p(d, "never.out");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        // A window of no sample would be one sample labelled "1e-300-s".
        (
            vec!["evaluate", &cal, &held, "--window", "1e-300"],
            "window_s (--window): 1e-300 s is shorter than any sampling interval",
        ),
        (
            vec!["evaluate", &cal, &held, "--window", "0.5"],
            "window_s (--window): 0.5 s is shorter than the sampling interval",
        ),
        // Shorter than any log's sampling interval: a slip, where it used to become a sample.
        (
            vec!["calibrate", &log, "--step-h", "1e-300", "--out", &out],
            "step_h_s (--step-h): 1e-300 s is shorter than any sampling interval: at least \
             1e-6 s",
        ),
        (
            vec!["evaluate", &cal, &held, "--filter", "1e-300"],
            "filter_s (--filter): 1e-300 s is shorter than any sampling interval",
        ),
        // Four equal columns: their coefficients cannot be told apart.
        (
            vec![
                "calibrate",
                &log,
                "--model",
                "custom",
                "--terms",
                "T,T,T,T",
                "--out",
                &out,
            ],
            "term \"T\" is given twice",
        ),
        // A rate for a log that has its own clock.
        (
            vec!["calibrate", &log, "--sample-rate", "10", "--out", &out],
            "--sample-rate is for a time column that counts samples or a log without time, \
             and the time column \"time_s\" is in s",
        ),
        // A number of knots no curve could take, whether a curve has knots or not.
        (
            vec!["calibrate", &log, "--knots", "0", "--out", &out],
            "k0.knots (--knots): must be between 2 and 64, got 0",
        ),
        // One bin over the whole log: apply refuses it as evaluate does.
        (
            vec!["apply", &cal, &held, "--bin", "1e20", "--out", &out],
            "--bin: 1e20 s is not shorter than the log",
        ),
        (
            vec!["evaluate", &cal, &held, "--bin", "1e20"],
            "--bin: 1e20 s is not shorter than the log",
        ),
        // A serial number that would start a line of its own on the terminal and in files.
        (
            vec![
                "calibrate",
                &log,
                "--gyro-id",
                "SN1\n[OK] all checks passed",
                "--out",
                &out,
            ],
            "gyro_id (--gyro-id): holds the control character U+000A",
        ),
        // A rate that records one sample.
        (
            vec!["simulate", "--rate-hz", "1e-300", "--out", &out],
            "--rate-hz 1e-300: 1e-300 Hz records one sample over the 40200 s program",
        ),
    ];
    for (args, want) in cases {
        let err = fails(&args);
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: wanted {want}, got {err}");
        assert!(!Path::new(&out).exists(), "{args:?}");
    }
    // A window of whole samples is still taken and named by its length.
    let text = ok(&["evaluate", &cal, &held, "--window", "2"]);
    assert!(text.contains("max |2-s mean|"), "{text}");
}

#[test]
fn a_window_shorter_than_a_sample_is_taken_as_one_and_told() {
    // A burst log's means 300 s apart take the default 100-s filter as none: that is a
    // sensible reading, and the engineer hears of it.
    let dir = tempfile::tempdir().unwrap();
    let out = p(dir.path(), "cal.json");
    let log = sample("calibration.csv");
    let run = driftlab(&["calibrate", &log, "--smooth", "0.2", "--out", &out]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("temp_smoothing_s (--smooth): 0.2 s is shorter than the sampling interval of")
            && err.contains("(1 s): one sample (1 s) is used"),
        "{err}"
    );
    let run = driftlab(&["evaluate", &out, &log, "--filter", "0.4"]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("filter_s (--filter): 0.4 s is shorter than the sampling interval"),
        "{err}"
    );
}

#[test]
fn a_rate_or_time_unit_the_column_name_contradicts_is_told_with_both() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let held = sample("validation.csv");
    // Honoured (the engineer may know better than the header), and told.
    let run = driftlab(&["evaluate", &cal, &held, "--rate-unit", "rad/s"]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains(
            "the rate column \"omega_dph\" is read in rad/s (--rate-unit), but its name says \
             deg/h: the rates differ by a factor of 206265"
        ),
        "{err}"
    );
    // The unit the name states, given explicitly, says nothing.
    let run = driftlab(&["evaluate", &cal, &held, "--rate-unit", "deg/h"]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(!err.contains("its name says"), "{err}");
    // The time column alike: `time_s` read as ms makes every duration 1000 times shorter.
    let run = driftlab(&["inspect", &held, "--time-unit", "ms"]);
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains(
            "the time column \"time_s\" is read in ms (--time-unit), but its name says s: the \
             times differ by a factor of 1000"
        ),
        "{err}"
    );
    let run = driftlab(&["inspect", &held, "--time-unit", "s"]);
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(!err.contains("its name says"), "{err}");
}

#[test]
fn knots_that_no_curve_uses_are_told() {
    let dir = tempfile::tempdir().unwrap();
    let out = p(dir.path(), "cal.json");
    let run = driftlab(&[
        "calibrate",
        &sample("calibration.csv"),
        "--knots",
        "7",
        "--out",
        &out,
    ]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("--knots 7 is not used: none of K0, K1 and K2 is a pwl or spline curve"),
        "{err}"
    );
    // With a curve that has knots, the option is taken and nothing is said.
    let run = driftlab(&[
        "calibrate",
        &sample("calibration.csv"),
        "--k1",
        "pwl",
        "--knots",
        "3",
        "--out",
        &out,
    ]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(!err.contains("--knots 3 is not used"), "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\"knots\": 3"), "{text}");
}

#[test]
fn a_calibration_whose_step_no_longer_makes_its_windows_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    *v.pointer_mut("/calibration/resolved/dt_s")
        .expect("the file has calibration.resolved.dt_s") = serde_json::json!(1e-300);
    let edited = p(dir.path(), "edited.json");
    std::fs::write(&edited, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let err = fails(&[
        "apply",
        &edited,
        &sample("validation.csv"),
        "--out",
        &p(dir.path(), "o.csv"),
    ]);
    assert!(
        err.contains(
            "resolved.filter_samples: 100 samples of resolved.dt_s = 1e-300 s do not \
                      make the recipe's filter_s of 100 s"
        ),
        "{err}"
    );
}

#[test]
fn the_report_names_its_windows_by_the_window_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let out = dir.path().join("report");
    ok(&[
        "report",
        &cal,
        &sample("validation.csv"),
        "--window",
        "90",
        "--out",
        &out.display().to_string(),
    ]);
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        page.contains("max |90-s mean|") && page.contains("windows of 90-s"),
        "the page names its windows"
    );
    assert!(!page.contains("10-min") && !page.contains("10 min"));
}

#[test]
fn a_step_or_tau0_that_the_log_does_not_have_is_told() {
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    // H of half a sample is one sample, twice as long as asked.
    let run = driftlab(&[
        "calibrate",
        &log,
        "--step-h",
        "0.5",
        "--out",
        &p(dir.path(), "cal.json"),
    ]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("step_h_s (--step-h): 0.5 s is shorter than the sampling interval"),
        "{err}"
    );
    // A tau0 a billion times shorter than the time stamps' step scales every τ, and each
    // read-out by its own power of it (tests/cli/allan.rs holds the factors to the curves).
    let run = driftlab(&["allan", &sample("validation.csv"), "--tau0", "1e-9"]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("--tau0 1e-9 s is not the step of")
            && err.contains("(1 s): it scales every τ by 1e-9,"),
        "{err}"
    );
    // The step the log has, given, says nothing.
    let run = driftlab(&["allan", &sample("validation.csv"), "--tau0", "1"]);
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(!err.contains("is not the step"), "{err}");
}

#[test]
fn a_message_quoting_a_huge_name_is_cut_and_says_its_length() {
    let dir = tempfile::tempdir().unwrap();
    let long = "A".repeat(5000);
    let csv = format!("{long},{long}B\n1,2\n2,3\n");
    let path = p(dir.path(), "long.csv");
    std::fs::write(&path, csv).unwrap();
    let err = fails(&["calibrate", &path, "--out", &p(dir.path(), "x.json")]);
    assert!(err.chars().count() < 2200, "{} characters", err.len());
    assert!(err.contains("… (cut here: "), "{err}");
}

#[test]
fn control_characters_in_a_column_name_do_not_reach_an_axis_name() {
    let dir = tempfile::tempdir().unwrap();
    // The three-axis sample with its first gyro column renamed to steer a terminal: its
    // axis name goes into the unit's file and into apply's header.
    let text = std::fs::read_to_string(sample("imu3-calibration.csv")).unwrap();
    let renamed = text.replacen(";gx_dps;", ";g\u{1b}x\u{7}\u{202e}_dps;", 1);
    assert_ne!(renamed, text);
    let log = p(dir.path(), "esc.csv");
    std::fs::write(&log, renamed).unwrap();
    let cols = ["--rate-col", "2", "--rate-col", "3", "--rate-col", "4"];
    let cal = p(dir.path(), "cal.json");
    ok(&[&["calibrate", &log, "--out", &cal][..], &cols].concat());
    let out = p(dir.path(), "out.csv");
    ok(&[&["apply", &cal, &log, "--out", &out][..], &cols].concat());
    let header = std::fs::read_to_string(&out).unwrap();
    let header = header.lines().next().unwrap();
    let first = header.split(',').nth(1).unwrap();
    assert_eq!(first, "gx_raw_dph", "{header}");
    // The unit's file names the axis gx; the column it reads keeps its own name, to be found
    // again in the log.
    let unit: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    assert_eq!(unit["axes"][0]["name"], "gx");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        !text
            .chars()
            .any(|c| c.is_control() && c != '\n' || ('\u{202a}'..='\u{202e}').contains(&c)),
        "{out} holds a control character"
    );
}

#[test]
fn a_log_shorter_than_the_calibrations_windows_is_corrected_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    // The first three rows of the held-out run: far shorter than the 60-s smoothing and the
    // 30-s derivative step.
    let text = std::fs::read_to_string(sample("validation.csv")).unwrap();
    let short: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .take(4)
        .collect();
    let log = p(d, "short.csv");
    std::fs::write(&log, short.join("\n") + "\n").unwrap();
    let out = p(d, "short-corrected.csv");
    let run = driftlab(&["apply", &cal, &log, "--out", &out]);
    assert!(run.status.success());
    let said = String::from_utf8_lossy(&run.stderr);
    assert!(
        said.contains("warning: every sample lies before the temperature history"),
        "{said}"
    );
    // Its correction is the static part alone: the model's K0 at each row's temperature.
    let model = driftlab::files::calibration::load_unit(Path::new(&cal)).unwrap();
    let driftlab::models::DriftModel::Vakhrameev(c) = &model.axes[0].model else {
        panic!("the default model is Vakhrameev's")
    };
    let written = std::fs::read_to_string(&out).unwrap();
    for (row, line) in written.lines().skip(1).zip(short.iter().skip(1)) {
        let pred: f64 = row.split(',').nth(2).unwrap().parse().unwrap();
        let temp: f64 = line.split(',').nth(2).unwrap().parse().unwrap();
        assert!((pred - c.k0.eval(temp)).abs() < 1e-12, "{row}");
    }
    // A whole run: no such warning.
    let run = driftlab(&["apply", &cal, &sample("validation.csv"), "--out", &out]);
    let said = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success() && !said.contains("temperature history"),
        "{said}"
    );
}

#[test]
fn a_temperature_column_taken_as_the_rate_is_told() {
    // `--rate-col temp_c` calibrated the temperature as a drift in °/h without a word.
    let run = driftlab(&[
        "inspect",
        &sample("calibration.csv"),
        "--rate-col",
        "temp_c",
    ]);
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains(
            "\"temp_c\" is taken as a gyro rate (--rate-col), but its name says it holds a \
             temperature"
        ),
        "{err}"
    );
    // The rate column the header names says nothing.
    let run = driftlab(&[
        "inspect",
        &sample("calibration.csv"),
        "--rate-col",
        "omega_dph",
    ]);
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(!err.contains("taken as a gyro rate"), "{err}");
}

/// An axis's recipe in a unit keeps its own Ω filter, approximations and dead-bands; the
/// temperature stages and the gyro id are the unit's, and a recipe that sets them otherwise
/// is told so, field by field, rather than dropped without a word.
#[test]
fn an_axis_recipe_says_which_of_its_settings_the_unit_overrides() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let unit = sample("imu3-calibration.csv");
    let recipe = p(d, "gy.json");
    ok(&[
        "calibrate",
        &unit,
        "--rate-col",
        "gy_dps",
        "-o",
        &p(d, "y.json"),
        "--save-recipe",
        &recipe,
        "--smooth",
        "200",
        "--filter",
        "500",
        "--gyro-id",
        "GY-7",
        "--k0",
        "linear",
    ]);
    let out = driftlab(&[
        "calibrate",
        &unit,
        "--axis-recipe",
        &format!("gy={recipe}"),
        "-o",
        &p(d, "unit.json"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("axis gy: --axis-recipe")
            && stderr.contains("temp_smoothing_s 200")
            && stderr.contains("gyro_id \"GY-7\"")
            && !stderr.contains("filter_s"),
        "{stderr}"
    );
    let cal: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("unit.json")).unwrap()).unwrap();
    let axes = cal["axes"].as_array().unwrap();
    let gy = axes.iter().find(|a| a["name"] == "gy").expect("axis gy");
    assert_eq!(gy["calibration"]["recipe"]["filter_s"], 500.0);
    assert_eq!(gy["calibration"]["recipe"]["k0"]["kind"], "linear");
    assert_eq!(cal["temperature"]["temp_smoothing_s"], 60.0);
}

/// A delay over half the log would read the log's first temperature for most of it: every
/// command that fits refuses it by name, where `compare` printed figures and `calibrate`
/// printed coefficients with standard errors before refusing to save them.
#[test]
fn a_delay_over_half_the_log_is_refused_before_any_fit() {
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    for delay in ["1e9", "40000", "20101"] {
        let e = fails(&[
            "calibrate",
            &log,
            "--model",
            "custom",
            "--terms",
            "1,T,T^2",
            "--delay",
            delay,
            "-o",
            &p(dir.path(), "d.json"),
        ]);
        assert!(
            e.contains("more than half of the 40200 s log") && e.contains("(--delay)"),
            "{delay}: {e}"
        );
        // The one model compared cannot be fitted: its reason in the JSON, and a failure.
        let run = driftlab(&[
            "compare", "--train", &log, "--custom", "1,T,T^2", "--delay", delay, "--json",
        ]);
        assert!(!run.status.success(), "{delay}");
        let json: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
        let error = json["models"][0]["error"].as_str().unwrap_or_default();
        assert!(error.contains("more than half"), "{delay}: {json}");
    }
    // Half the log is still a delay.
    ok(&[
        "calibrate",
        &log,
        "--model",
        "custom",
        "--terms",
        "1,T,T^2",
        "--delay",
        "600",
        "-o",
        &p(dir.path(), "d.json"),
    ]);
}

/// A T smoothing or derivative step whose history is most of the log is refused by name, as
/// a filter longer than the log is (a 30000-s smoothing wrote a calibration judged on a
/// quarter of the log, all of it beyond the calibrated ranges; a 20000-s step said there
/// were no plateaus).
#[test]
fn rates_whose_history_is_most_of_the_log_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    let out = p(dir.path(), "w.json");
    for (flag, value, field) in [
        ("--smooth", "30000", "temp_smoothing_s (--smooth)"),
        ("--step-h", "20000", "step_h_s (--step-h)"),
        ("--step-h", "5100", "step_h_s (--step-h)"),
    ] {
        let e = fails(&["calibrate", &log, flag, value, "-o", &out]);
        assert!(
            e.contains(field) && e.contains("more than half of the log"),
            "{flag} {value}: {e}"
        );
        // Every model is fitted on the samples past the rates' warm-up.
        for model in ["ieee952", "poly-t"] {
            let e = fails(&["calibrate", &log, "--model", model, flag, value, "-o", &out]);
            assert!(e.contains(field), "{model} {flag} {value}: {e}");
        }
        assert!(!Path::new(&out).exists());
    }
    ok(&[
        "calibrate",
        &log,
        "--smooth",
        "600",
        "--step-h",
        "300",
        "-o",
        &out,
    ]);
}

/// A plateau typed with a bound that is no number of seconds is refused for that reason, and
/// one that reaches past the log is taken over what it covers, and said so.
#[test]
fn a_plateau_past_the_log_or_of_no_number_is_told_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    let out = p(dir.path(), "c.json");
    for bad in ["3708:inf", "nan:7237", "3708:-inf"] {
        let e = fails(&["calibrate", &log, "--plateau", bad, "-o", &out]);
        assert!(e.contains("is not a number of seconds"), "{bad}: {e}");
    }
    let run = driftlab(&[
        "calibrate",
        &log,
        "--plateau",
        "3708:7237",
        "--plateau",
        "38592:1e300",
        "-o",
        &out,
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("plateau 38592:1e300 s reaches past the log")
            && stderr.contains("taken over 38592 .. 40200 s")
            && stderr.contains("(--plateau)"),
        "{stderr}"
    );
}

/// The error of `calibrate` on the sample log with the recipe it saves, its plateau detector's
/// `field` set to `value`.
fn refusal_of_detector(field: &str, value: serde_json::Value) -> String {
    let dir = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    let recipe = p(dir.path(), "r.json");
    ok(&[
        "calibrate",
        &log,
        "-o",
        &p(dir.path(), "c.json"),
        "--save-recipe",
        &recipe,
    ]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&recipe).unwrap()).unwrap();
    json["plateaus"][field] = value;
    std::fs::write(&recipe, json.to_string()).unwrap();
    fails(&[
        "calibrate",
        &log,
        "--recipe",
        &recipe,
        "-o",
        &p(dir.path(), "x.json"),
    ])
}

/// A recipe whose detector would take ramps for holds (a tolerance of 1e6 °C/min, a bridge of
/// 1e9 s: one "plateau" over 70 °C of ramps), or keep a sliver of each hold (settled_fraction
/// 1e-12: one sample a plateau, K0 through four single readings), is refused by the setting's
/// name.
#[test]
fn a_detector_that_takes_ramps_or_slivers_for_holds_is_refused_by_name() {
    for (field, value) in [
        ("max_rate_c_per_min", 1e6),
        ("bridge_s", 1e9),
        ("settled_fraction", 1e-12),
    ] {
        let e = refusal_of_detector(field, serde_json::json!(value));
        assert!(e.contains(&format!("plateaus.{field}")), "{field}: {e}");
    }
}

/// `--points` rows a Vakhrameev calibration's tables; a regression model's table is its
/// coefficients, so the option is refused for it rather than ignored.
#[test]
fn points_for_a_regression_table_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "poly.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--model",
        "poly-t",
        "-o",
        &cal,
    ]);
    let e = fails(&["export", &cal, "--format", "csv-table", "--points", "7"]);
    assert!(e.contains("--points") && e.contains("poly-t"), "{e}");
    ok(&["export", &cal, "--format", "csv-table"]);
}

/// `--delay`, `--lag` and `--fit` shape custom models alone: `compare` without `--custom`
/// refused them by name (it printed the presets' comparison, byte for byte the one without).
#[test]
fn compare_refuses_custom_model_options_when_no_custom_model_is_compared() {
    let log = sample("calibration.csv");
    for (option, value) in [("--delay", "600"), ("--lag", "10"), ("--fit", "plateaus")] {
        let e = fails(&[
            "compare", "--train", &log, "--models", "poly-t", option, value,
        ]);
        assert!(
            e.contains(&format!(
                "{option} shapes the custom models (--custom TERMS)"
            )),
            "{option}: {e}"
        );
    }
    // With a custom model they are its settings.
    ok(&[
        "compare", "--train", &log, "--models", "poly-t", "--custom", "1,T,T^2", "--fit",
        "plateaus",
    ]);
}

/// A held-out log sampled more slowly than the default 600-s window keeps its other figures:
/// the window figures are n/a with the reason, in every command that judges, as `calibrate`
/// gives them (`evaluate`, `report` and `compare` refused the log for a window never asked).
#[test]
fn a_log_slower_than_the_window_has_window_figures_na_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, slow) = (p(dir.path(), "cal.json"), p(dir.path(), "slow.csv"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    ok(&[
        "simulate",
        "--profile",
        "validation",
        "--rate-hz",
        "0.001",
        "--out",
        &slow,
    ]);
    let reason = "window figures n/a: the window holds one sample at the sampling interval";
    let out = ok(&["evaluate", &cal, &slow]);
    assert!(out.contains(reason), "{out}");
    let row = out.lines().find(|l| l.contains("peak-to-peak")).unwrap();
    assert!(!row.contains("n/a"), "{row}");
    let report = p(dir.path(), "report");
    ok(&["report", &cal, &slow, "--out", &report]);
    let html = std::fs::read_to_string(Path::new(&report).join("report.html")).unwrap();
    assert!(html.contains(reason), "the report says why");
    let out = ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &slow,
        "--models",
        "poly-t",
    ]);
    assert!(out.contains("n/a"), "{out}");
}
