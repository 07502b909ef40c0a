//! The flight controllers' forms and their scripts' fits on the command line: `compare`
//! names the reference rows as such in its tables and JSON, `calibrate --model px4` writes a
//! calibration that reads back, and an order no polynomial model takes is refused by name.

use crate::common::run::{fails, ok, sample};

#[test]
fn compare_marks_the_scripts_rows_as_references() {
    let models = "px4,ardupilot,poly-t5,px4-script,ardupilot-script";
    let json = ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--test",
        &sample("validation.csv"),
        "--models",
        models,
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let rows: Vec<(String, bool)> = v["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            assert!(m["error"].is_null(), "{m}");
            (
                m["model"].as_str().unwrap().to_string(),
                m["reference"].as_bool().unwrap(),
            )
        })
        .collect();
    let want: Vec<(String, bool)> = models
        .split(',')
        .map(|m| (m.to_string(), m.ends_with("-script")))
        .collect();
    assert_eq!(rows, want);
    let text = ok(&[
        "compare",
        "--train",
        &sample("calibration.csv"),
        "--models",
        "px4,px4-script",
    ]);
    assert!(
        text.lines()
            .any(|l| l.trim_start().starts_with("px4-script*")),
        "{text}"
    );
    assert!(text.contains("* reference: the fit the flight controller's own script makes"));
    assert!(!text.lines().any(|l| l.trim_start().starts_with("px4*")));
}

#[test]
fn a_px4_calibration_reads_back_and_an_order_past_nine_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("px4.json");
    let cal = cal.to_str().unwrap();
    ok(&[
        "calibrate",
        "--model",
        "px4",
        "--out",
        cal,
        &sample("calibration.csv"),
    ]);
    let text = std::fs::read_to_string(cal).unwrap();
    assert!(
        text.contains("\"t_ref_c\"") && text.contains("(T-Tref)^3"),
        "{text}"
    );
    ok(&["evaluate", cal, &sample("validation.csv")]);
    let e = fails(&[
        "calibrate",
        "--model",
        "poly-t10",
        "--out",
        cal,
        &sample("calibration.csv"),
    ]);
    assert!(e.contains("poly-t10") && e.contains("1 to 9"), "{e}");
}
