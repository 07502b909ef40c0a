//! `compare` says of a test log what the training log's sketch tells: in-sample, held out, or
//! that it cannot tell (and why), never "held out" of a log it could not tell apart from the
//! training log. Its JSON holds the reason in `cannot_tell` with `held_out` false.

use crate::common::run::{ok, sample};

#[test]
fn a_test_log_the_sketch_cannot_tell_is_not_called_held_out() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The training log's rates written in steps of 0.001 °/h (its own: 0.0001), and the
    // training log thinned to every 1000th row (40 rows).
    let coarse =
        crate::common::calibration_derived(d, "coarse.csv", |_| true, |x| format!("{x:.3}"))
            .display()
            .to_string();
    let sparse =
        crate::common::calibration_derived(d, "sparse.csv", |i| i % 1000 == 0, |x| format!("{x}"))
            .display()
            .to_string();
    let args = |json: bool| {
        let mut a = vec![
            "compare".to_string(),
            "--train".into(),
            sample("calibration.csv"),
            "--test".into(),
            coarse.clone(),
            sparse.clone(),
            sample("validation.csv"),
            "--models".into(),
            "poly-t".into(),
        ];
        if json {
            a.push("--json".into());
        }
        a
    };
    let text = ok(&args(false).iter().map(String::as_str).collect::<Vec<_>>());
    let heading = |name: &str| {
        text.lines()
            .find(|l| l.contains(name) && l.contains(" ("))
            .unwrap_or_else(|| panic!("no heading of {name}: {text}"))
            .to_string()
    };
    let c = heading("coarse.csv");
    assert!(
        c.contains("cannot tell if it is the training log")
            && c.contains("0.001")
            && !c.contains("(held out)"),
        "{c}"
    );
    let s = heading("sparse.csv");
    assert!(
        s.contains("cannot tell if it is the training log") && !s.contains("(held out)"),
        "{s}"
    );
    assert!(heading("validation.csv").contains("(held out)"), "{text}");

    let json: serde_json::Value = serde_json::from_str(&ok(&args(true)
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()))
    .unwrap();
    let logs = json["models"][0]["logs"].as_array().unwrap();
    let told: Vec<(bool, bool)> = logs
        .iter()
        .map(|l| {
            (
                l["held_out"].as_bool().unwrap(),
                l["cannot_tell"].is_string(),
            )
        })
        .collect();
    assert_eq!(
        told,
        [(false, false), (false, true), (false, true), (true, false)],
        "{json}"
    );
    assert!(logs[0]["cannot_tell"].is_null() && logs[3]["cannot_tell"].is_null());
}

/// The report tags a log its calibration's sketch cannot tell apart from its own as such, with
/// why, never "held out"; another run is held out.
#[test]
fn the_report_says_cannot_tell_of_such_a_log() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let coarse =
        crate::common::calibration_derived(d, "coarse.csv", |_| true, |x| format!("{x:.3}"))
            .display()
            .to_string();
    let cal = d.join("cal.json").display().to_string();
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let out = d.join("report");
    let text = ok(&[
        "report",
        &cal,
        &coarse,
        &sample("validation.csv"),
        "--out",
        &out.display().to_string(),
    ]);
    assert!(text.contains("coarse.csv (cannot tell)"), "{text}");
    assert!(text.contains("validation.csv (held out)"), "{text}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("cannot tell if held out")
            && html.contains(
                "cannot tell whether this is that log (its rates are written in steps of 0.001"
            )
            && html.contains(r#"data-set="cannot-tell""#),
        "the report's page does not say so"
    );
}
