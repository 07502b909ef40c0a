//! Accelerometer axes judged held out: with a validation log open, each accelerometer axis's
//! figures on it beside the in-sample ones, as `driftlab evaluate --json` gives them for the
//! command line's calibration of the same log; a correction worse than raw there is marked
//! as the gyro figures mark it.

use super::accel::{driftlab, imu6};
use super::common::gui::{harness, settle};
use driftlab::gui::Workbench;
use driftlab::gui::jobs::LoadOptions;
use driftlab::log::AxisKind;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};

/// Another run of the simulated IMU (seed 2), its `acc_x` change with T turned over about its
/// mean (`2·mean − a`): a run on which the calibration of the first makes `acc_x` worse.
fn turned_over(dir: &Path) -> PathBuf {
    let seed2 = dir.join("imu6-seed2.csv");
    let os = std::ffi::OsStr::new;
    driftlab(&[
        os("simulate"),
        os("--profile"),
        os("mems-imu"),
        os("--seed"),
        os("2"),
        os("-o"),
        seed2.as_os_str(),
    ]);
    let text = std::fs::read_to_string(&seed2).unwrap();
    let rows: Vec<Vec<String>> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(rows[0][4], "acc_x_g");
    let values: Vec<f64> = rows[1..].iter().map(|r| r[4].parse().unwrap()).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mut out = rows[0].join(",") + "\n";
    for (row, v) in rows[1..].iter().zip(&values) {
        let mut row = row.clone();
        row[4] = format!("{:.6}", 2.0 * mean - v);
        out.push_str(&row.join(","));
        out.push('\n');
    }
    let path = dir.join("turned.csv");
    std::fs::write(&path, out).unwrap();
    path
}

/// The window on `log` with `validation` open beside it.
fn with_validation(log: &Path, validation: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new(
        driftlab::gui::settings::Settings::default(),
        None,
        Box::new(driftlab::gui::dialogs::ScriptedDialogs::new()),
    );
    wb.open_log(log.to_path_buf(), LoadOptions::default(), false);
    wb.open_validation_after(validation.to_path_buf(), LoadOptions::default());
    let mut h = harness(wb);
    settle(&mut h);
    settle(&mut h);
    h
}

#[test]
fn accelerometer_axes_are_judged_held_out_as_evaluate_judges_them() {
    let dir = tempfile::tempdir().unwrap();
    let log = imu6(dir.path());
    let validation = turned_over(dir.path());
    let cal = dir.path().join("cli.json");
    let os = std::ffi::OsStr::new;
    driftlab(&[
        os("calibrate"),
        log.as_os_str(),
        os("--accel"),
        os("--out"),
        cal.as_os_str(),
    ]);
    let cli: serde_json::Value = serde_json::from_str(&driftlab(&[
        os("evaluate"),
        os("--json"),
        cal.as_os_str(),
        validation.as_os_str(),
    ]))
    .unwrap();

    let mut h = with_validation(&log, &validation);
    let s = &h.state().state;
    assert!(s.accel_current(), "judged on the validation log");
    let fit = s.accel.as_ref().unwrap().fit.as_ref().unwrap();
    let fit = fit.result.as_ref().expect("calibrated");
    for axis in &fit.axes {
        let name = &axis.fitted.name;
        let want = cli["axes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["name"] == name.as_str())
            .expect("evaluate judges every axis");
        assert_eq!(want["kind"], "accelerometer", "{name}");
        let held = axis
            .held_out
            .as_ref()
            .expect("a validation log is open")
            .as_ref()
            .unwrap_or_else(|e| panic!("axis {name} not judged: {e}"));
        assert_eq!(
            held.in_sample,
            want["in_sample"].as_bool().unwrap(),
            "{name}"
        );
        assert!(!held.in_sample, "another run: held out");
        // The engine's figures, named in the axis's unit as the command names them.
        let mut got = serde_json::to_value(held.evaluation).unwrap();
        AxisKind::Accel.name_fields_in_unit(&mut got);
        assert_eq!(got, want["evaluation"], "axis {name}");
    }
    assert_eq!(fit.axes.len(), 3, "every accelerometer axis judged");

    // Shown beside the in-sample figures, the turned-over axis's ratios below 1.
    h.get_by_label_contains("acc_x  p2p ").click();
    h.run_ok();
    h.get_by_label("Held out · turned.csv · axis acc_x");
    h.get_by_label_contains("In-sample · imu6.csv · axis acc_x");
    let want = &cli["axes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["name"] == "acc_x")
        .unwrap()["evaluation"]["comparison"];
    let p2p = want["p2p_ratio"].as_f64().unwrap();
    assert!(p2p < 1.0, "the turned-over axis is made worse: {p2p}");
    for which in ["raw", "corrected"] {
        let v = want[which]["p2p_m_s2"].as_f64().unwrap();
        h.get_by_label(&driftlab::number::fixed(v, 6));
    }
    // The strip's button gives its held-out ratio too, as a gyro axis's does.
    h.get_by_label_contains(&format!(
        "· held out {}",
        driftlab::gui::plot_items::ratio(p2p)
    ));
}
