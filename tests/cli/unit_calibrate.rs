//! `calibrate` and `apply` on a three-axis IMU log in a stand's dialect (ms, deg/s, `;` and a
//! decimal comma), with no mapping: one calibration file for the unit, and every axis's
//! corrected rate the very text a single-axis calibration of that column writes.

use crate::common;
use common::run::{fails, ok, p, sample};

/// The cells of a CSV by column name.
fn columns(path: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let mut cols = vec![Vec::new(); header.len()];
    for line in lines {
        for (k, cell) in line.split(',').enumerate() {
            cols[k].push(cell.to_string());
        }
    }
    (header, cols)
}

fn column<'a>(csv: &'a (Vec<String>, Vec<Vec<String>>), name: &str) -> &'a [String] {
    let k = csv.0.iter().position(|h| h == name).unwrap_or_else(|| {
        panic!("no column {name} in {:?}", csv.0);
    });
    &csv.1[k]
}

#[test]
fn a_stand_log_calibrates_every_axis_into_one_file_as_each_axis_alone() {
    let dir = tempfile::tempdir().unwrap();
    let unit = p(dir.path(), "unit.json");
    let out = ok(&["calibrate", &sample("imu3-calibration.csv"), "--out", &unit]);
    assert!(out.contains("Calibration of 3 axes (gx, gy, gz)"), "{out}");
    assert!(out.contains("Unit summary"), "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&unit).unwrap()).unwrap();
    assert_eq!(v["version"], 2);
    let names: Vec<&str> = v["axes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["gx", "gy", "gz"]);
    assert_eq!(v["axes"][1]["rate_column"], "gy_dps");

    let corrected = p(dir.path(), "unit.csv");
    ok(&[
        "apply",
        &unit,
        &sample("imu3-validation.csv"),
        "--out",
        &corrected,
    ]);
    let unit_csv = columns(&corrected);
    assert_eq!(
        unit_csv.0.join(","),
        "time_s,gx_raw_dph,gx_pred_dph,gx_cor_dph,gy_raw_dph,gy_pred_dph,gy_cor_dph,\
         gz_raw_dph,gz_pred_dph,gz_cor_dph,temp_c"
    );
    for axis in ["gx", "gy", "gz"] {
        let col = format!("{axis}_dps");
        let single = p(dir.path(), &format!("{axis}.json"));
        ok(&[
            "calibrate",
            &sample("imu3-calibration.csv"),
            "--rate-col",
            &col,
            "--out",
            &single,
        ]);
        let text = std::fs::read_to_string(&single).unwrap();
        assert!(
            text.contains("\"version\": 1"),
            "one axis: a version-1 file"
        );
        let single_csv = p(dir.path(), &format!("{axis}.csv"));
        ok(&[
            "apply",
            &single,
            &sample("imu3-validation.csv"),
            "--rate-col",
            &col,
            "--out",
            &single_csv,
        ]);
        let alone = columns(&single_csv);
        for (mine, theirs) in [
            ("raw", "omega_raw_dph"),
            ("pred", "omega_pred_dph"),
            ("cor", "omega_cor_dph"),
        ] {
            assert_eq!(
                column(&unit_csv, &format!("{axis}_{mine}_dph")),
                column(&alone, theirs),
                "axis {axis}: {mine}"
            );
        }
        assert_eq!(column(&unit_csv, "time_s"), column(&alone, "time_s"));
        assert_eq!(column(&unit_csv, "temp_c"), column(&alone, "temp_c"));
    }
}

#[test]
fn axes_are_chosen_by_name_column_or_letter_and_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let two = p(dir.path(), "xz.json");
    let out = ok(&[
        "calibrate",
        &sample("imu3-calibration.csv"),
        "--axes",
        "x,gz_dps",
        "--axis-model",
        "z=poly-t",
        "--out",
        &two,
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let axes = v["axes"].as_array().unwrap();
    assert_eq!(axes.len(), 2);
    assert_eq!(axes[0]["name"], "gx");
    assert_eq!(axes[0]["model_name"], "vakhrameev");
    assert_eq!(axes[1]["name"], "gz");
    assert_eq!(axes[1]["model_name"], "poly-t");
    assert!(
        axes[0]["in_sample"]["comparison"]["p2p_ratio"]
            .as_f64()
            .unwrap()
            > 3.0
    );

    let e = fails(&[
        "calibrate",
        &sample("imu3-calibration.csv"),
        "--axes",
        "x,q",
        "--out",
        &p(dir.path(), "no.json"),
    ]);
    assert!(e.contains("--axes q") && e.contains("gx, gy, gz"), "{e}");
    let e = fails(&[
        "calibrate",
        &sample("imu3-calibration.csv"),
        "--axis-model",
        "gq=poly-t",
        "--out",
        &p(dir.path(), "no.json"),
    ]);
    assert!(e.contains("--axis-model gq"), "{e}");
    // One axis named by --rate-col is a single-axis calibration, which takes no per-axis
    // option.
    let e = fails(&[
        "calibrate",
        &sample("imu3-calibration.csv"),
        "--rate-col",
        "gy_dps",
        "--axis-model",
        "gy=poly-t",
        "--out",
        &p(dir.path(), "no.json"),
    ]);
    assert!(e.contains("--axis-model") && e.contains("one axis"), "{e}");
    // A unit applied to a log without one of its axes names the axis and what the log has.
    let e = fails(&[
        "apply",
        &two,
        &sample("calibration.csv"),
        "--out",
        &p(dir.path(), "no.csv"),
    ]);
    assert!(
        e.contains("no gyro axis gx") && e.contains("the log's axes"),
        "{e}"
    );
}

#[test]
fn a_single_axis_log_writes_the_version_one_file_it_always_did() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    let out = ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    assert!(!out.contains("Axis"), "{out}");
    assert!(out.contains("Calibration written to"), "{out}");
    let text = std::fs::read_to_string(&cal).unwrap();
    assert!(text.contains("\"version\": 1") && !text.contains("\"axes\""));
    let corrected = p(dir.path(), "cor.csv");
    ok(&[
        "apply",
        &cal,
        &sample("validation.csv"),
        "--out",
        &corrected,
    ]);
    let header = std::fs::read_to_string(&corrected)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_string();
    assert_eq!(
        header,
        "time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c"
    );
}
