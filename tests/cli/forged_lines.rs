//! A line break or a tab inside a name (a log's file name, a calibration's source name) never
//! reaches the terminal raw: every line a command prints shows it escaped, so a crafted name
//! cannot print a line that reads as driftlab's own (`error: calibration REJECTED`).

use crate::common::run::{driftlab, ok, p, sample};

/// The line a crafted name would forge.
const FORGED: &str = "error: calibration REJECTED, do not use";

/// A log named to forge [`FORGED`] on a line of its own, with a tab too.
const NAME: &str = "run\nerror: calibration REJECTED, do not use\n\t.csv";

/// Asserts that `driftlab ARGS` exits with `code` and that neither of its outputs has a raw
/// tab or a line starting with the forged text; returns both outputs.
fn clean(args: &[&str], code: i32) -> String {
    let out = driftlab(args);
    let (o, e) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(code), "{args:?}: {e}");
    for text in [&o, &e] {
        assert!(
            !text.lines().any(|l| l.trim_start().starts_with(FORGED)),
            "{args:?}: a forged line in\n{text}"
        );
        assert!(!text.contains('\t'), "{args:?}: a raw tab in\n{text}");
    }
    format!("{o}{e}")
}

/// As [`clean`], and the name is shown escaped in what the command printed.
fn escaped(args: &[&str], code: i32) {
    let printed = clean(args, code);
    assert!(
        printed.contains("run\\u000aerror: calibration REJECTED, do not use\\u000a\\u0009."),
        "{args:?}: the name is not shown escaped:\n{printed}"
    );
}

#[test]
fn a_file_name_with_line_breaks_forges_no_line_in_any_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = d.join(NAME);
    std::fs::copy(sample("calibration.csv"), &log).unwrap();
    let log = log.display().to_string();
    let cal = p(d, "cal.json");
    escaped(&["calibrate", &log, "-o", &cal], 0);
    // The calibration's source name is the file's name: it reaches export, evaluate, report.
    escaped(
        &["export", &cal, "--format", "c-header", "-o", &p(d, "x.h")],
        0,
    );
    escaped(&["evaluate", &cal, &log], 0);
    clean(&["apply", &cal, &log, "-o", &p(d, "cor.csv")], 0);
    escaped(&["inspect", &log], 0);
    escaped(&["report", &cal, &log, "--out", &p(d, "rep")], 0);
    // As the output's name, and in an error naming it.
    let crafted_out = d.join(NAME.replace(".csv", ".out.csv"));
    escaped(
        &[
            "apply",
            &cal,
            &log,
            "-o",
            &crafted_out.display().to_string(),
        ],
        0,
    );
    let missing = d.join(format!("missing-{NAME}"));
    escaped(&["inspect", &missing.display().to_string()], 1);
    // More files than the command takes (a glob): clap's refusal shows the name escaped.
    escaped(&["inspect", &sample("calibration.csv"), &log], 2);
}

#[test]
fn a_source_name_edited_to_hold_line_breaks_forges_no_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    let log = sample("calibration.csv");
    ok(&["calibrate", &log, "-o", &cal]);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    json["calibration"]["source"]["name"] = serde_json::Value::from(NAME);
    std::fs::write(&cal, json.to_string()).unwrap();
    escaped(
        &["export", &cal, "--format", "c-header", "-o", &p(d, "x.h")],
        0,
    );
    clean(&["evaluate", &cal, &log], 0);
}
