//! The window of the windowed figures (`max |W mean|`, `mean W RMS`) is a whole number of the
//! log's samples, at least two, and the figures are labelled with the length they were
//! computed over: a window the step cannot make is refused with the lengths it can, one of a
//! single sample is refused, and the default one is told where the step does not make it.
//!
//! The truth is the log's own sampling: a label of W seconds on a log sampled every dt holds
//! W/dt samples, so the number of whole windows the JSON counts is the samples over W/dt.

use serde_json::Value;

use crate::common;
use common::run::{driftlab, fails, ok, p, sample};

/// `validation.csv` (1 Hz) kept at every `every`-th second: a log sampled every `every` s.
fn thinned(dir: &std::path::Path, every: u64) -> String {
    let text = std::fs::read_to_string(sample("validation.csv")).unwrap();
    let kept: String = text
        .lines()
        .filter(|l| match l.split(',').next().unwrap().parse::<u64>() {
            Ok(t) => t % every == 0,
            Err(_) => true,
        })
        .map(|l| format!("{l}\n"))
        .collect();
    let path = p(dir, &format!("every{every}.csv"));
    std::fs::write(&path, kept).unwrap();
    path
}

fn calibrated(dir: &std::path::Path) -> String {
    let cal = p(dir, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    cal
}

/// The raw figures' sample and window counts of `evaluate --json`.
fn counts(v: &Value) -> (u64, u64) {
    let raw = &v["evaluation"]["comparison"]["raw"];
    (
        raw["samples"].as_u64().unwrap(),
        raw["windows"].as_u64().unwrap(),
    )
}

#[test]
fn a_window_of_one_sample_or_of_no_whole_number_of_samples_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibrated(dir.path());
    let log = sample("validation.csv");
    let out = p(dir.path(), "report");
    // One sample of a 1 Hz log, whatever it is called: the figures would be the samples.
    for w in ["0.99", "1", "1.2", "1.4"] {
        for args in [
            vec!["evaluate", &cal, &log, "--window", w],
            vec!["compare", "--train", &log, "--test", &log, "--window", w],
            vec!["report", &cal, &log, "--window", w, "--out", &out],
        ] {
            let e = fails(&args);
            assert!(
                e.contains(&format!("window_s (--window): {w} s is one sample of"))
                    && e.contains("at least 2 samples (2 s)"),
                "{args:?}: {e}"
            );
        }
    }
    // Between two whole numbers of samples: refused, offering both.
    for (w, instead) in [
        ("2.5", "give 2 s (2 samples) or 3 s (3 samples)"),
        ("100.4", "give 100 s (100 samples) or 101 s (101 samples)"),
        ("1.6", "give 2 s (2 samples)"),
    ] {
        let e = fails(&["evaluate", &cal, &log, "--window", w]);
        assert!(
            e.contains(&format!("window_s (--window): {w} s is")) && e.contains(instead),
            "{w}: {e}"
        );
    }
    assert!(!std::path::Path::new(&out).exists());
}

#[test]
fn a_window_taken_is_computed_over_the_length_it_is_labelled_with() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibrated(dir.path());
    let log = sample("validation.csv");
    for (w, label) in [
        ("2", "max |2-s mean|"),
        ("3", "max |3-s mean|"),
        ("90", "max |90-s mean|"),
    ] {
        let text = ok(&["evaluate", &cal, &log, "--window", w]);
        assert!(text.contains(label), "{w}: {text}");
        let v: Value =
            serde_json::from_str(&ok(&["evaluate", &cal, &log, "--window", w, "--json"])).unwrap();
        let (samples, windows) = counts(&v);
        let per: u64 = w.parse().unwrap();
        assert_eq!(windows, samples / per, "--window {w}: {samples} samples");
    }
}

#[test]
fn the_default_window_on_a_log_whose_step_does_not_make_it_is_told_or_na() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibrated(dir.path());
    // A sample every 7 s: 600 s is 85.7 samples, computed over 86 (602 s), and told.
    let seven = thinned(dir.path(), 7);
    let run = driftlab(&["evaluate", &cal, &seven, "--json"]);
    assert!(run.status.success());
    let err = String::from_utf8(run.stderr).unwrap();
    assert!(
        err.contains("the default 600 s is 85.7143 samples of")
            && err.contains("computed over 602 s and labelled 600 s")
            && err.contains("give 595 s (85 samples) or 602 s (86 samples)"),
        "{err}"
    );
    let v: Value = serde_json::from_str(&String::from_utf8(run.stdout).unwrap()).unwrap();
    let (samples, windows) = counts(&v);
    assert_eq!(windows, samples / 86, "{samples} samples");
    // 602 s, given, is whole: taken, labelled, nothing told.
    let run = driftlab(&["evaluate", &cal, &seven, "--window", "602"]);
    assert!(run.status.success());
    assert!(
        String::from_utf8(run.stdout)
            .unwrap()
            .contains("max |602-s mean|")
    );
    assert!(!String::from_utf8(run.stderr).unwrap().contains("window_s"));
    // A sample every 500 s: 600 s rounds to one sample, so the window figures are n/a with
    // the reason, not the samples themselves labelled 10 min.
    let slow = thinned(dir.path(), 500);
    let text = ok(&["evaluate", &cal, &slow]);
    assert!(
        text.contains("window figures n/a: the window holds one sample"),
        "{text}"
    );
    let v: Value = serde_json::from_str(&ok(&["evaluate", &cal, &slow, "--json"])).unwrap();
    let raw = &v["evaluation"]["comparison"]["raw"];
    assert_eq!(raw["windows_unavailable"], "window_shorter_than_sample");
    assert!(raw["win_mean_max_abs_dph"].is_null(), "{raw}");
}
