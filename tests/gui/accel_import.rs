//! Accelerometer columns mapped in the import view, as `--accel-col` and `--accel-unit` map
//! them on the command line: columns whose names say nothing of an accelerometer, ticked in
//! the view with their unit, calibrated as `driftlab calibrate --accel-col … --accel-unit …`
//! calibrates them; a choice the engine refuses is said in the view's words before the read.

use super::accel::{driftlab, imu6, without_dates};
use super::common::gui::{harness, sample, settle, with_dialogs};
use driftlab::gui::Workbench;
use driftlab::log::accel_axes::{AccelAsk, AccelUnit};
use driftlab::log::ingest::ColumnRef;
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};

/// The simulated six-axis IMU of `dir` rewritten with its accelerometer columns named `a1`,
/// `a2`, `a3` (no accelerometer's name, no unit) and written in mg; columns 5 to 7.
fn unnamed_accelerometers(dir: &Path) -> PathBuf {
    let src = imu6(dir);
    let text = std::fs::read_to_string(&src).unwrap();
    let mut out = String::new();
    let mut header = true;
    for line in text.lines() {
        if line.starts_with('#') {
            continue;
        }
        let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
        if header {
            assert_eq!(cells[4..7], ["acc_x_g", "acc_y_g", "acc_z_g"]);
            for (k, c) in cells[4..7].iter_mut().enumerate() {
                *c = format!("a{}", k + 1);
            }
            header = false;
        } else {
            for c in &mut cells[4..7] {
                let g: f64 = c.parse().unwrap();
                *c = format!("{:.3}", g * 1000.0);
            }
        }
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    let path = dir.join("stand.csv");
    std::fs::write(&path, out).unwrap();
    path
}

/// Clicks the control labelled `control`, then the entry `entry` of the list it opens.
fn choose(h: &mut Harness<'_, Workbench>, control: &str, entry: &str) {
    h.get_by_label(control).click();
    h.run_ok();
    h.get_by_label(entry).click();
    h.run_ok();
}

#[test]
fn accelerometer_columns_and_their_unit_mapped_in_the_import_view_are_calibrated_as_accel_col_calibrates_them()
 {
    let dir = tempfile::tempdir().unwrap();
    let log = unnamed_accelerometers(dir.path());
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(log.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run_ok();
    // Named as none, the columns are no accelerometers until the engineer says so.
    assert_eq!(
        h.get_by_label("Accelerometer columns").value().as_deref(),
        Some("none named as one")
    );
    assert_eq!(
        h.query_all_by_label_contains("accelerometer axes, in m/s²")
            .count(),
        0
    );
    for column in ["5: a1", "6: a2", "7: a3"] {
        choose(&mut h, "Accelerometer columns", column);
    }
    choose(&mut h, "Accelerometer unit", "mg");
    let view = h.state_mut().import_view().expect("the import view");
    assert_eq!(
        view.accel,
        AccelAsk {
            columns: (5..=7).map(ColumnRef::Index).collect(),
            unit: Some(AccelUnit::MilliG),
        }
    );
    h.run_ok();
    // The engine's reading of the choice, before the read.
    h.get_by_label_contains(
        "accelerometer axes, in m/s² once read: column 5 \"a1\" [mg, as chosen], column 6",
    );
    // A column the engine refuses is said in the view's words, and nothing is read.
    let view = h.state_mut().import_view().unwrap();
    view.accel.columns.push(ColumnRef::Name("a9".into()));
    h.run_ok();
    h.get_by_label_contains("no column a9 to read as an accelerometer axis");
    h.get_by_label_contains("(Accelerometer columns in File › Column mapping…)");
    h.get_by_label("Load").click();
    h.run_ok();
    assert!(h.state_mut().import_view().is_some(), "not read");
    h.state_mut().import_view().unwrap().accel.columns.pop();
    h.run_ok();
    h.get_by_label("Load").click();
    settle(&mut h);

    let s = &h.state().state;
    let l = s.shown.log.as_ref().unwrap();
    assert!(l.path.ends_with("stand.csv"));
    assert_eq!(l.options.accel.unit, Some(AccelUnit::MilliG));
    assert_eq!(s.accel.as_ref().unwrap().names, ["a1", "a2", "a3"]);
    assert!(s.accel_on() && s.accel_current());

    // The window's calibration is the command line's, coefficient for coefficient.
    let window = dir.path().join("window.json");
    dialogs.answer(Some(window.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let cli = dir.path().join("cli.json");
    let os = std::ffi::OsStr::new;
    let mut args = vec![os("calibrate"), log.as_os_str()];
    for c in ["5", "6", "7"] {
        args.extend([os("--accel-col"), os(c)]);
    }
    args.extend([os("--accel-unit"), os("mg"), os("--out"), cli.as_os_str()]);
    driftlab(&args);
    assert_eq!(without_dates(&window), without_dates(&cli));

    // The session keeps the mapping.
    let session = dir.path().join("stand.session.json");
    dialogs.answer(Some(session.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&session).unwrap()).unwrap();
    assert_eq!(
        saved["session"]["log"]["accelerometers"],
        serde_json::json!({"columns": [5, 6, 7], "unit": "mg"})
    );
}
