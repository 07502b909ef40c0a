//! A figure that could not be computed reads `n/a` wherever it is shown, never `NaN`, `∞` or
//! a 0 that reads as a figure: the report and `compare` on a log too short for a window; the
//! RMS residual and R² of a curve fitted to no point, in the report, the C header and the
//! file (`null`, and only where nothing was computed); the peak-to-peak and std of a judged
//! stretch shorter than twice the filter, in `evaluate` and `compare`, text and JSON.

use crate::common::run::{fails, ok, sample};

fn p(d: &std::path::Path, name: &str) -> String {
    d.join(name).display().to_string()
}

/// validation.csv's first `rows` data rows.
fn short_log(d: &std::path::Path, rows: usize) -> String {
    let text = std::fs::read_to_string(sample("validation.csv")).unwrap();
    let kept: Vec<&str> = text.lines().take(2 + rows).collect();
    let path = p(d, &format!("short{rows}.csv"));
    std::fs::write(&path, kept.join("\n") + "\n").unwrap();
    path
}

#[test]
fn figures_of_a_log_too_short_read_n_a() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let short = short_log(d, 700);
    for (k, extra) in [vec![], vec!["--filter", "650"]].into_iter().enumerate() {
        let out = p(d, &format!("report{k}"));
        let mut args = vec![
            "report",
            cal.as_str(),
            short.as_str(),
            "--out",
            out.as_str(),
        ];
        args.extend(extra);
        ok(&args);
        let html = std::fs::read_to_string(format!("{out}/report.html")).unwrap();
        for bad in ["NaN", "∞", ">inf<"] {
            assert!(!html.contains(bad), "{bad} in the report ({args:?})");
        }
        assert!(html.contains("n/a"), "{args:?}");
    }
    let short250 = short_log(d, 250);
    let text = ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &short250,
        "--models",
        "vakhrameev",
    ]);
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    let row = text
        .lines()
        .skip_while(|l| !l.contains("short250.csv"))
        .find(|l| l.trim_start().starts_with("vakhrameev"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(row.contains("n/a"), "{row}");
}

#[test]
fn statistics_of_no_point_read_n_a_and_are_null_only_there() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A dead-band wider than every rate leaves K1± no point.
    let cal = p(d, "cal.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--deadband-tdot",
        "0.5",
        "-o",
        &cal,
    ]);
    let header = p(d, "cal.h");
    ok(&["export", &cal, "--format", "c-header", "--out", &header]);
    let h = std::fs::read_to_string(&header).unwrap();
    assert!(h.contains("0 points, rmse n/a, R2 n/a"), "{h}");
    assert!(!h.contains("rmse 0e0"), "{h}");
    let out = p(d, "report");
    ok(&["report", &cal, &sample("validation.csv"), "--out", &out]);
    let html = std::fs::read_to_string(format!("{out}/report.html")).unwrap();
    // K1+'s row of the coefficients (the figures' paragraph names K1+ too, as left out).
    let k1 = html
        .split("<tr>")
        .find(|r| r.starts_with("<td>K1+"))
        .expect("K1+'s row");
    assert!(k1.contains("n/a"), "{k1}");
    // A hand-edited file saying nothing was computed over points that were: refused.
    let text = std::fs::read_to_string(&cal).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let k0 = &mut json["calibration"]["k0"]["stats"];
    assert!(k0["n"].as_u64().unwrap() > 1, "{k0}");
    k0["r2"] = serde_json::Value::Null;
    let edited = p(d, "edited.json");
    std::fs::write(&edited, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    let err = fails(&[
        "apply",
        &edited,
        &sample("validation.csv"),
        "-o",
        &p(d, "x.csv"),
    ]);
    assert!(
        err.contains("r2 is null (not computed), but the fit was over") && err.contains("line"),
        "{err}"
    );
}

/// A judged stretch (after the warm-up) of 300 to 599 samples under a 300-s filter holds no two
/// filter windows apart: `evaluate` and `compare` print its peak-to-peak and std n/a with the
/// reason and advice, never 0.0000 with "reproduces the record to its rounding" or a ratio;
/// JSON has `null` and `filter_overlaps_itself`. A 100-s filter over the same log has them.
#[test]
fn a_filter_over_half_the_judged_stretch_gives_no_spread() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let short = short_log(d, 600);
    let text = ok(&[
        "evaluate", &cal, &short, "--filter", "300", "--window", "60",
    ]);
    for row in text.lines().filter(|l| l.contains("of filtered drift")) {
        assert!(
            !row.contains("0.0000") && !row.contains('x'),
            "{row}\n{text}"
        );
        assert!(row.matches("n/a").count() == 3, "{row}");
    }
    assert!(
        text.contains("peak-to-peak and std n/a: the filter is longer than half of the judged")
            && text.contains("shorten the filter or judge a longer log")
            && !text.contains("rounding"),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "evaluate", &cal, &short, "--filter", "300", "--window", "60", "--json",
    ]))
    .unwrap();
    let c = &json["evaluation"]["comparison"];
    for side in ["raw", "corrected"] {
        assert!(
            c[side]["p2p_dph"].is_null() && c[side]["std_dph"].is_null(),
            "{c}"
        );
        assert_eq!(
            c[side]["filtered_unavailable"], "filter_overlaps_itself",
            "{c}"
        );
    }
    assert!(
        c["p2p_ratio"].is_null() && c.get("ratios_unavailable").is_none(),
        "{c}"
    );
    // The same log under a 100-s filter: figures.
    let text = ok(&[
        "evaluate", &cal, &short, "--filter", "100", "--window", "60",
    ]);
    assert!(!text.contains("peak-to-peak and std n/a"), "{text}");
    let text = ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &short,
        "--models",
        "vakhrameev",
        "--filter",
        "300",
        "--window",
        "60",
    ]);
    let tail: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.contains("short600.csv"))
        .collect();
    let row = tail
        .iter()
        .find(|l| l.trim_start().starts_with("vakhrameev"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        row.matches("n/a").count() >= 4 && !row.contains("0.0000"),
        "{row}"
    );
    assert!(
        tail.iter()
            .any(|l| l.contains("peak-to-peak and std n/a: the filter is longer than half")),
        "{text}"
    );
}

/// A judged stretch of one whole window has a largest |window mean| but no spread of the
/// window means: evaluate, its JSON and the report gave 0.0000, a perfectly flat drift (the
/// twenty-second attack). It reads n/a with its reason; over two windows it is a figure again.
#[test]
fn the_window_means_of_one_window_have_no_peak_to_peak() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let short = short_log(d, 900);
    let judged = |window: &str| -> serde_json::Value {
        serde_json::from_str(&ok(&[
            "evaluate", &cal, &short, "--window", window, "--json",
        ]))
        .unwrap()
    };
    // The samples judged after the warm-up (1 Hz), and a window that fits once, then twice.
    let samples = judged("60")["evaluation"]["comparison"]["raw"]["samples"]
        .as_u64()
        .unwrap();
    assert!(samples > 300, "{samples}");
    let once = (samples * 3 / 4).to_string();
    let twice = (samples * 9 / 20).to_string();
    let c = judged(&once)["evaluation"]["comparison"].clone();
    for side in ["raw", "corrected"] {
        assert_eq!(c[side]["windows"], 1, "{c}");
        assert!(c[side]["win_mean_p2p_dph"].is_null(), "{c}");
        assert_eq!(c[side]["win_mean_p2p_unavailable"], "one_window", "{c}");
        assert!(
            c[side]["win_mean_max_abs_dph"].as_f64().unwrap() > 0.0,
            "{c}"
        );
    }
    let text = ok(&["evaluate", &cal, &short, "--window", &once]);
    assert!(
        text.contains("peak-to-peak of the window means n/a: the log holds one whole window"),
        "{text}"
    );
    let c = judged(&twice)["evaluation"]["comparison"].clone();
    for side in ["raw", "corrected"] {
        assert_eq!(c[side]["windows"], 2, "{c}");
        assert!(c[side]["win_mean_p2p_dph"].as_f64().unwrap() > 0.0, "{c}");
        assert!(c[side].get("win_mean_p2p_unavailable").is_none(), "{c}");
    }
    let out = p(d, "report");
    ok(&["report", &cal, &short, "--out", &out, "--window", &once]);
    let html = std::fs::read_to_string(format!("{out}/report.html")).unwrap();
    let row = html
        .split("<tr>")
        .find(|r| r.contains("peak-to-peak of") && r.contains("means"))
        .unwrap_or_else(|| panic!("no row of the window means' peak-to-peak"));
    assert!(row.contains("n/a") && !row.contains("0.0000"), "{row}");
}
