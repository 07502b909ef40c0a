//! Logs from which no calibration can be made get the true reason, never a calibration of
//! numbers standing for nothing: a rate column stuck at one value (a disconnected gyro), and a
//! log none of whose stretches between gaps lasts as long as the rates of T need.

use crate::common::run::{fails, ok, p, sample};

/// The sample calibration log with every data row passed through `row` (`None` drops it).
fn rewritten(dir: &std::path::Path, name: &str, row: impl Fn(&str) -> Option<String>) -> String {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let out: String = text
        .lines()
        .filter_map(|l| {
            if l.starts_with('#') || l.starts_with("time") {
                Some(format!("{l}\n"))
            } else {
                row(l).map(|r| format!("{r}\n"))
            }
        })
        .collect();
    std::fs::write(dir.join(name), out).unwrap();
    p(dir, name)
}

/// The row with its rate (the second cell) replaced by `rate`.
fn with_rate(line: &str, rate: &str) -> String {
    let mut cells: Vec<&str> = line.split(',').collect();
    cells[1] = rate;
    cells.join(",")
}

#[test]
fn a_rate_stuck_at_one_value_is_refused_by_every_command() {
    let dir = tempfile::tempdir().unwrap();
    for value in ["0", "0.5"] {
        let log = rewritten(dir.path(), "stuck.csv", |l| Some(with_rate(l, value)));
        let out = p(dir.path(), "stuck.json");
        let e = fails(&["calibrate", &log, "-o", &out]);
        assert!(
            e.contains("never changes") && e.contains(&format!("reads {value} °/h")),
            "{e}"
        );
        assert!(!std::path::Path::new(&out).exists());
        let e = fails(&["calibrate", &log, "--model", "poly-t", "-o", &out]);
        assert!(e.contains("never changes"), "{e}");
        let e = fails(&["allan", &log]);
        assert!(e.contains("never changes"), "{e}");
    }
}

#[test]
fn a_stuck_log_is_refused_as_a_log_to_judge_on_too() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let log = rewritten(dir.path(), "stuck.csv", |l| Some(with_rate(l, "0")));
    let e = fails(&["evaluate", &cal, &log]);
    assert!(e.contains("never changes"), "{e}");
    // A report draws every log it is given; the reader tells this one's rate is stuck.
    let run = crate::common::run::driftlab(&["report", &cal, &log, "--out", &p(dir.path(), "rep")]);
    assert!(
        String::from_utf8_lossy(&run.stderr).contains("holds one value, 0 °/h"),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &log,
        "--models",
        "poly-t",
        "--json",
    ]))
    .unwrap();
    let judged = &json["models"][0]["logs"][1];
    assert!(
        judged["error"]
            .as_str()
            .unwrap_or_default()
            .contains("never changes"),
        "{judged}"
    );
}

#[test]
fn a_ratio_is_never_taken_over_a_corrected_figure_at_the_rounding_of_the_raw() {
    // A stuck log judged by a calibration that predicts it exactly leaves rounding alone:
    // the figures are n/a, not improvements of 1e15.
    use driftlab::judge::metrics::Comparison;
    use driftlab::judge::metrics::Figures;
    let raw = Figures {
        p2p_dph: 0.5,
        std_dph: 0.1,
        win_mean_max_abs_dph: 0.5,
        win_rms_mean_dph: 0.5,
        ..Figures::default()
    };
    let rounding = Figures {
        p2p_dph: 1e-16,
        std_dph: 2e-17,
        win_mean_max_abs_dph: 5.5e-16,
        win_rms_mean_dph: 2.8e-16,
        ..Figures::default()
    };
    let c = Comparison::from_figures(raw, rounding);
    assert!(c.p2p_ratio.is_nan() && c.win_mean_ratio.is_nan(), "{c:?}");
    let real = Figures {
        p2p_dph: 0.05,
        std_dph: 0.01,
        win_mean_max_abs_dph: 0.05,
        win_rms_mean_dph: 0.05,
        ..Figures::default()
    };
    let c = Comparison::from_figures(raw, real);
    assert!((c.p2p_ratio - 10.0).abs() < 1e-12, "{c:?}");
}

#[test]
fn a_log_whose_stretches_are_all_shorter_than_the_rates_history_is_refused_with_why() {
    let dir = tempfile::tempdir().unwrap();
    // A logger that drops out for 10 s every 170 s: stretches of 160 s, where Ṫ and T̈ need
    // 60 s of smoothing and four 30-s steps (179 samples at 1 s).
    let log = rewritten(dir.path(), "chopped.csv", |l| {
        let t: f64 = l.split(',').next().unwrap().parse().unwrap();
        (t % 170.0 < 160.0).then(|| l.to_string())
    });
    let out = p(dir.path(), "chopped.json");
    for extra in [
        &["--plateau", "3708:7237", "--plateau", "14301:16837"][..],
        &[][..],
        &["--model", "poly-t"][..],
    ] {
        let mut args = vec!["calibrate", log.as_str(), "-o", out.as_str()];
        args.extend_from_slice(extra);
        let e = fails(&args);
        assert!(
            e.contains("need 179 s") && e.contains("longest stretch lasts 160 s"),
            "{extra:?}: {e}"
        );
        assert!(!std::path::Path::new(&out).exists());
    }
    // Shorter windows fit in the stretches: then it calibrates.
    ok(&[
        "calibrate",
        &log,
        "--smooth",
        "20",
        "--step-h",
        "10",
        "--plateau",
        "3708:7237",
        "--plateau",
        "14301:16837",
        "-o",
        &out,
    ]);
}

#[test]
fn a_fast_ramp_in_short_stretches_is_not_said_never_to_change() {
    // 1 kHz, two 3-s stretches a long gap apart, T swinging by 10 °C within each: the rate
    // of T is there (thousands of °C/min), only the 60-s smoothing does not fit.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for base in [0.0, 1e6] {
        for i in 0..3000 {
            let x = f64::from(i);
            text.push_str(&format!(
                "{:.3},{},{}\n",
                base + x * 0.001,
                (x / 50.0).sin(),
                20.0 + 10.0 * (x / 300.0).sin()
            ));
        }
    }
    let log = dir.path().join("fast.csv");
    std::fs::write(&log, text).unwrap();
    let e = fails(&[
        "calibrate",
        &log.display().to_string(),
        "-o",
        &p(dir.path(), "f.json"),
    ]);
    assert!(!e.contains("never changes faster"), "{e}");
    assert!(e.contains("longest stretch lasts 3 s"), "{e}");
}

#[test]
fn a_log_slower_than_the_window_gets_no_window_figures_and_sample_rates_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    // One sample in 1000 s: the windows of 10 min would each be one sample. The figures are n/a with the reason, as `evaluate` refuses the window.
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..500 {
        let t = f64::from(i) * 1000.0;
        let temp = 20.0 + 30.0 * (t / 40_000.0).sin();
        text.push_str(&format!(
            "{t},{},{temp}\n",
            0.3 + 0.01 * temp + (t / 3e3).sin()
        ));
    }
    let log = dir.path().join("slow.csv");
    std::fs::write(&log, text).unwrap();
    let log = log.display().to_string();
    let out = p(dir.path(), "slow.json");
    let printed = ok(&["calibrate", &log, "--model", "poly-t", "-o", &out, "--json"]);
    let json: serde_json::Value = serde_json::from_str(&printed).unwrap();
    let raw = json
        .pointer("/in_sample/comparison/raw")
        .unwrap_or_else(|| panic!("{json}"));
    assert_eq!(raw["windows"], 0, "{raw}");
    assert!(raw["win_mean_max_abs_dph"].is_null(), "{raw}");
    assert_eq!(
        raw["windows_unavailable"], "window_shorter_than_sample",
        "{raw}"
    );
    let e = fails(&[
        "calibrate",
        &log,
        "--time-unit",
        "samples",
        "--sample-rate",
        "1e-300",
        "-o",
        &out,
    ]);
    assert!(e.contains("--sample-rate must be between"), "{e}");
}

#[test]
fn a_rate_stuck_for_part_of_the_log_is_told_by_every_reader() {
    let dir = tempfile::tempdir().unwrap();
    // The gyro reads exactly 0 from 20000 s on: half the run carries no drift.
    let log = rewritten(dir.path(), "half.csv", |l| {
        let t: f64 = l.split(',').next().unwrap().parse().unwrap();
        Some(if t >= 20000.0 {
            with_rate(l, "0")
        } else {
            l.to_string()
        })
    });
    let told = "holds one value, 0 °/h, for 20201 samples from 20000 s to 40200 s";
    let inspect = ok(&["inspect", &log]);
    assert!(inspect.contains(told), "{inspect}");
    let json: serde_json::Value = serde_json::from_str(&ok(&["inspect", &log, "--json"])).unwrap();
    assert!(json.to_string().contains(told), "{json}");
    let run = crate::common::run::driftlab(&["calibrate", &log, "-o", &p(dir.path(), "h.json")]);
    assert!(String::from_utf8_lossy(&run.stderr).contains(told));
    // The sample logs and a quiet stretch of a real gyro are not told.
    let clean = ok(&["inspect", &sample("calibration.csv")]);
    assert!(!clean.contains("holds one value"), "{clean}");
}

#[test]
fn a_unit_calibration_refuses_a_rate_column_that_is_none_of_its_axes() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "unit.json");
    ok(&["calibrate", &sample("imu3-calibration.csv"), "-o", &cal]);
    let held = sample("imu3-validation.csv");
    let out = p(dir.path(), "out.csv");
    // temp_c as a rate would move the temperature the unit reads to the chamber's air.
    let e = fails(&["apply", &cal, &held, "-o", &out, "--rate-col", "temp_c"]);
    assert!(
        e.contains("--rate-col temp_c") && e.contains("none of them"),
        "{e}"
    );
    assert!(!std::path::Path::new(&out).exists());
    let e = fails(&["evaluate", &cal, &held, "--rate-col", "temp_c"]);
    assert!(e.contains("none of them"), "{e}");
    // A column of one of its axes alone would pick that axis, and the unit corrects every
    // axis it has (the option was dropped without a word): refused, for all of them or none.
    for args in [
        vec!["apply", &cal, &held, "-o", &out, "--rate-col", "gy_dps"],
        vec!["evaluate", &cal, &held, "--rate-col", "gy_dps"],
    ] {
        let e = fails(&args);
        assert!(
            e.contains("--rate-col gy_dps: the calibration is a unit of 3 axes (gx, gy, gz)")
                && e.contains("give one --rate-col for each of its axes"),
            "{e}"
        );
    }
    assert!(!std::path::Path::new(&out).exists());
    ok(&[
        "apply",
        &cal,
        &held,
        "-o",
        &out,
        "--rate-col",
        "gx_dps",
        "--rate-col",
        "gy_dps",
        "--rate-col",
        "gz_dps",
    ]);
}

/// The row with its temperature (the third cell) replaced by `temp`.
fn with_temperature(line: &str, temp: &str) -> String {
    let mut cells: Vec<&str> = line.split(',').collect();
    cells[2] = temp;
    cells.join(",")
}

#[test]
fn a_temperature_stuck_while_the_chamber_moves_is_told() {
    let dir = tempfile::tempdir().unwrap();
    // The gyro's sensor reads 25 °C from 10000 s to 30000 s, through the chamber's ramps.
    let log = rewritten(dir.path(), "tstuck.csv", |l| {
        let t: f64 = l.split(',').next().unwrap().parse().unwrap();
        Some(if (10000.0..30000.0).contains(&t) {
            with_temperature(l, "25.000")
        } else {
            l.to_string()
        })
    });
    let told = "the temperature holds one value, 25 °C, for 20000 samples from 10000 s to 29999 s";
    let inspect = ok(&["inspect", &log]);
    assert!(
        inspect.matches(told).count() == 1 && inspect.contains("\"temp_chamber_c\" moves by"),
        "listed once under problems:\n{inspect}"
    );
    // calibrate and evaluate tell it too, once each, and no plateau of the fit lies in the
    // stuck stretch: its one value is not taken for the gyro's temperature.
    let cal = p(dir.path(), "t.json");
    let run = crate::common::run::driftlab(&["calibrate", &log, "-o", &cal]);
    let (out, err) = (
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr),
    );
    assert_eq!(err.matches(told).count(), 1, "{err}");
    let plateaus: Vec<(f64, f64)> = out
        .lines()
        .skip_while(|l| !l.starts_with("Plateaus (K0 points)"))
        .skip(2)
        .map_while(|l| {
            let mut cells = l.split_whitespace().map(|c| c.parse::<f64>());
            Some((cells.next()?.ok()?, cells.next()?.ok()?))
        })
        .collect();
    assert!(!plateaus.is_empty(), "{out}");
    for (start, end) in plateaus {
        assert!(
            end < 10000.0 || start > 29999.0,
            "plateau {start}..{end} s in the stuck stretch:\n{out}"
        );
    }
    let eval = crate::common::run::driftlab(&["evaluate", &cal, &log]);
    let err = String::from_utf8_lossy(&eval.stderr);
    assert_eq!(err.matches(told).count(), 1, "{err}");
    // A plateau read by a coarse sensor (one value while the chamber holds too) is not told.
    let clean = ok(&["inspect", &sample("calibration.csv")]);
    assert!(!clean.contains("holds one value"), "{clean}");
}

#[test]
fn one_sample_thermometer_glitches_are_told_and_left_out_of_the_fit() {
    let dir = tempfile::tempdir().unwrap();
    // A bad register read (127.996 °C) every 2000 s, at 1000 s, 3000 s, ...: 20 rows.
    let glitched = |l: &str| {
        let t: f64 = l.split(',').next().unwrap().parse().unwrap();
        t % 2000.0 == 1000.0
    };
    let log = rewritten(dir.path(), "g.csv", |l| {
        Some(if glitched(l) {
            with_temperature(l, "127.996")
        } else {
            l.to_string()
        })
    });
    // The same log with those rows left out, by hand: what the fit must see.
    let cut = rewritten(dir.path(), "cut.csv", |l| {
        (!glitched(l)).then(|| l.to_string())
    });
    // The line of the first glitch in the file (1-based), counted here.
    let text = std::fs::read_to_string(&log).unwrap();
    let first = 1 + text
        .lines()
        .position(|l| l.split(',').nth(2) == Some("127.996"))
        .unwrap();
    let inspect = crate::common::run::driftlab(&["inspect", &log]);
    let (out, err) = (
        String::from_utf8_lossy(&inspect.stdout),
        String::from_utf8_lossy(&inspect.stderr),
    );
    for words in [
        "the temperature jumps by".to_string(),
        "for one sample and back, 20 times".to_string(),
        format!("first at line {first}"),
        "read as missing".to_string(),
    ] {
        assert!(
            out.contains(&words) && err.contains(&words),
            "{words:?}:\n{out}\n{err}"
        );
    }
    assert!(!out.contains("problems: none"), "{out}");
    // calibrate tells it, and fits what the log without those rows gives: the same held-out
    // figures on the validation run.
    let (g, c) = (p(dir.path(), "g.json"), p(dir.path(), "c.json"));
    let run = crate::common::run::driftlab(&["calibrate", &log, "-o", &g]);
    assert!(run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("the temperature jumps by"), "{err}");
    ok(&["calibrate", &cut, "-o", &c]);
    let figures = |cal: &str| {
        ok(&["evaluate", cal, &sample("validation.csv")])
            .lines()
            .filter(|l| l.contains("drift") || l.contains("RMS"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let (fg, fc) = (figures(&g), figures(&c));
    assert!(!fg.is_empty());
    assert_eq!(fg, fc);
}

#[test]
fn the_only_rate_column_taken_as_the_temperature_is_the_reason_given() {
    let dir = tempfile::tempdir().unwrap();
    let out = p(dir.path(), "never.json");
    for (flag, given) in [
        ("--temp-col", "omega_dph"),
        ("--temp-col", "2"),
        ("--time-col", "omega_dph"),
    ] {
        let what = if flag == "--temp-col" {
            "temperature"
        } else {
            "time"
        };
        for command in ["calibrate", "inspect"] {
            let log = sample("calibration.csv");
            let mut args = vec![command, &log, flag, given];
            if command == "calibrate" {
                args.extend(["-o", &out]);
            }
            let e = fails(&args);
            assert!(
                e.contains(&format!(
                    "column 2 \"omega_dph\", is taken as the {what} by {flag}"
                )) && e.contains(&format!("check {flag}"))
                    && !e.contains("none of"),
                "{command} {flag} {given}: {e}"
            );
        }
    }
    // The time column taken as the rate: that is the reason, not a log without time.
    for given in ["time_s", "1"] {
        let e = fails(&["inspect", &sample("calibration.csv"), "--rate-col", given]);
        assert!(
            e.contains("column 1 \"time_s\", is taken as the gyro rate by --rate-col")
                && e.contains("check --rate-col")
                && !e.contains("no time column among"),
            "--rate-col {given}: {e}"
        );
    }
}

#[test]
fn a_gyro_rate_taken_as_the_temperature_is_told() {
    let e = crate::common::run::driftlab(&[
        "inspect",
        &sample("imu3-calibration.csv"),
        "--temp-col",
        "gx_dps",
    ]);
    let stderr = String::from_utf8_lossy(&e.stderr);
    assert!(
        stderr.contains("\"gx_dps\" is taken as the temperature (--temp-col)"),
        "{stderr}"
    );
}

#[test]
fn a_unit_refuses_rate_columns_that_leave_out_some_of_its_axes() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "unit.json");
    ok(&["calibrate", &sample("imu3-calibration.csv"), "-o", &cal]);
    let e = fails(&[
        "apply",
        &cal,
        &sample("imu3-validation.csv"),
        "-o",
        &p(dir.path(), "o.csv"),
        "--rate-col",
        "gx_dps",
        "--rate-col",
        "gz_dps",
    ]);
    assert!(
        e.contains("the log has none for axis gy") && e.contains("every axis of the unit"),
        "{e}"
    );
}
