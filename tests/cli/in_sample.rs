//! One rule for in-sample: `evaluate`, `report` and `compare` call figures in-sample when the
//! log holds the calibration's own run, whatever its bytes (line endings, a comment removed, a
//! new name), and held out only on another run.

use crate::common::run::{ok, p, sample};

/// The calibration log with CRLF line endings, without its comment line, under a new name.
fn copies(dir: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let crlf: String = text.lines().map(|l| format!("{l}\r\n")).collect();
    let bare: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut out = Vec::new();
    for (name, body) in [
        ("crlf.csv", crlf),
        ("bare.csv", bare),
        ("renamed.csv", text),
    ] {
        std::fs::write(dir.join(name), body).unwrap();
        out.push(p(dir, name));
    }
    out
}

fn evaluate_in_sample(cal: &str, log: &str) -> bool {
    let json: serde_json::Value =
        serde_json::from_str(&ok(&["evaluate", cal, log, "--json"])).unwrap();
    json["in_sample"].as_bool().expect("in_sample")
}

#[test]
fn a_copy_of_the_calibration_log_with_other_bytes_is_in_sample() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let copies = copies(dir.path());
    for log in &copies {
        assert!(evaluate_in_sample(&cal, log), "{log} called held out");
    }
    assert!(!evaluate_in_sample(&cal, &sample("validation.csv")));

    // The report tags each log's section by the same rule.
    let out = p(dir.path(), "report");
    ok(&[
        "report",
        &cal,
        &copies[0],
        &sample("validation.csv"),
        "--out",
        &out,
    ]);
    let html = std::fs::read_to_string(dir.path().join("report/report.html")).unwrap();
    let crlf_at = html.find("crlf.csv").expect("the copy's section");
    let validation_at = html
        .find("validation.csv")
        .expect("the other run's section");
    let tag_after = |at: usize| {
        let rest = &html[at..];
        match (rest.find("in-sample"), rest.find("held out")) {
            (Some(i), Some(h)) => i < h,
            (Some(_), None) => true,
            _ => false,
        }
    };
    assert!(tag_after(crlf_at), "the copy is not tagged in-sample");
    assert!(
        !tag_after(validation_at),
        "the other run is not tagged held out"
    );

    // compare, which has both logs, says the same.
    let json: serde_json::Value = serde_json::from_str(&ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &copies[1],
        "--test",
        &sample("validation.csv"),
        "--models",
        "poly-t",
        "--json",
    ]))
    .unwrap();
    let logs = json["models"][0]["logs"].as_array().expect("logs");
    let held: Vec<bool> = logs
        .iter()
        .map(|l| l["held_out"].as_bool().unwrap())
        .collect();
    assert_eq!(held, [false, false, true]);
}

#[test]
fn an_old_calibration_without_the_run_fingerprint_is_judged_by_its_file_hash() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let source = json.pointer_mut("/calibration/source").expect("a source");
    assert!(source["run"].is_string(), "{source}");
    source.as_object_mut().unwrap().remove("run");
    let old = p(dir.path(), "old.json");
    std::fs::write(&old, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    assert!(evaluate_in_sample(&old, &sample("calibration.csv")));
    assert!(!evaluate_in_sample(&old, &sample("validation.csv")));
}
