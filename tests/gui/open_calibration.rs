//! A calibration opened beside the current fit (File › Open calibration, Ctrl+Alt+O, a dropped
//! `.json`): judged on the open logs as `driftlab evaluate` judges it (the binary run on the same
//! files is the independent truth), shown in the figures' tables and on the drift plot, closed
//! again; a malformed or wrong-kind file leaves the work as it was and names where it is wrong.
//! Units and the axis choice are in `open_calibration_units.rs`.

use driftlab::gui::action::OpenLog;
use driftlab::gui::jobs::{AxisVerdict, JudgedAxis, LoadOptions};
use driftlab::gui::opened::{self, Column};
use driftlab::gui::plot_items::{num, ratio};
use driftlab::gui::{Action, FileKind, Target, Workbench};
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};

use crate::common;
use common::gui::*;

/// Runs `driftlab ARGS` and gives its standard output; the command must succeed.
pub fn driftlab(args: &[&std::ffi::OsStr]) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("the driftlab binary runs");
    assert!(
        out.status.success(),
        "driftlab {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `driftlab calibrate LOG --out OUT EXTRA…`.
pub fn calibrate(log: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec![
        std::ffi::OsStr::new("calibrate"),
        log.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    driftlab(&args);
}

/// What `driftlab evaluate --json CAL LOG EXTRA…` prints.
pub fn evaluate_json(cal: &Path, log: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        std::ffi::OsStr::new("evaluate"),
        "--json".as_ref(),
        cal.as_os_str(),
        log.as_os_str(),
    ];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    serde_json::from_str(&driftlab(&args)).expect("evaluate --json prints JSON")
}

/// Runs an action as the menus do.
pub fn act(h: &mut Harness<'_, Workbench>, a: Action) {
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, a);
    h.run_ok();
}

/// Axis `k` of the opened calibration as judged on log `which`; the test fails when it was not
/// judged there.
pub fn judged<'h>(h: &'h Harness<'_, Workbench>, which: OpenLog, k: usize) -> &'h JudgedAxis {
    let o = h.state().opened().expect("a calibration is opened");
    let v = o
        .verified
        .as_ref()
        .expect("the opened calibration is judged");
    let on = v
        .logs
        .iter()
        .find(|l| l.which == which)
        .unwrap_or_else(|| panic!("judged on the {which:?} log"));
    match &on.axes[k] {
        AxisVerdict::Judged(j) => j,
        AxisVerdict::Unplaced(why) => panic!("axis {k} not placed: {why}"),
        AxisVerdict::Failed { why, .. } => panic!("axis {k} failed: {why}"),
    }
}

/// The JSON of a value, as `evaluate --json` writes its own.
pub fn json<T: serde::Serialize>(v: &T) -> serde_json::Value {
    serde_json::to_value(v).unwrap()
}

/// The sample log's workbench with the validation log open, settled.
fn with_validation() -> Workbench {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    wb.start_load(
        sample("validation.csv"),
        LoadOptions::default(),
        Target::Validation,
    );
    wb.wait_for_jobs();
    wb
}

/// A calibration made by `driftlab calibrate` on the sample log with K0 a spline of 3 knots
/// (at the three temperatures of its plateaus), so that its figures are not the current fit's,
/// in `dir`.
fn spline_calibration(dir: &Path) -> PathBuf {
    let cal = dir.join("lastweek.json");
    calibrate(
        &sample("calibration.csv"),
        &cal,
        &["--k0", "spline", "--knots", "3"],
    );
    cal
}

#[test]
fn an_opened_calibration_shows_the_figures_evaluate_prints() {
    let dir = tempfile::tempdir().unwrap();
    let cal = spline_calibration(dir.path());
    let mut wb = with_validation();
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    let session_before = h.state().state.session();
    let dirty_before = h.state().state.dirty();
    dialogs.answer(Some(cal.clone()));
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains("Open calibration…").click();
    settle(&mut h);
    assert_eq!(dialogs.asked(), vec![FileKind::OpenCalibration]);

    for (which, log) in [
        (OpenLog::Calibration, "calibration.csv"),
        (OpenLog::Validation, "validation.csv"),
    ] {
        let cli = evaluate_json(&cal, &sample(log), &[]);
        let j = judged(&h, which, 0);
        assert_eq!(json(&j.evaluation), cli["evaluation"], "{log}");
        assert_eq!(json(&j.options), cli["options"], "{log}");
        assert_eq!(Some(j.in_sample), cli["in_sample"].as_bool(), "{log}");
        // The label `evaluate` prints of the log, under the table of that log.
        let text = driftlab(&[
            "evaluate".as_ref(),
            cal.as_os_str(),
            sample(log).as_os_str(),
        ]);
        let first = text.lines().next().unwrap();
        assert!(
            first.contains(&format!("({})", j.label)),
            "{first:?} / {}",
            j.label
        );
        h.get_by_label(&format!("opened lastweek.json: {}", j.label));
    }
    assert!(judged(&h, OpenLog::Calibration, 0).in_sample);
    assert!(!judged(&h, OpenLog::Validation, 0).in_sample);

    // Its figures in their own columns, beside the current fit's, which they are not.
    let opened = judged(&h, OpenLog::Calibration, 0).evaluation.comparison;
    let current = outcome(&h).in_sample.evaluation.comparison;
    assert_ne!(opened.corrected.p2p_dph, current.corrected.p2p_dph);
    // (one column pair in each table: in-sample and held out)
    assert_eq!(h.get_all_by_label("opened").count(), 2);
    assert_eq!(h.get_all_by_label("current").count(), 2);
    h.get_by_label(&num(opened.corrected.p2p_dph));
    h.get_by_label(&ratio(opened.p2p_ratio));
    // Its recipe, readable: K0 a spline of 3 knots.
    h.get_by_label("spline, 3 knots");
    // Judged with the filter it was made with: nothing to say about it.
    assert!(h.query_by_label_contains("judged with a").is_none());
    // Its corrected drift on the drift plot, on the calibration log and on the validation log.
    let s = &h.state().state;
    let fit = s.shown.fit.as_ref().unwrap();
    let line = opened::drift_line(s, &fit.outcome.in_sample.log).expect("drawn");
    assert_eq!(line.cor_filtered_dph.len(), fit.outcome.in_sample.log.len());
    let held = fit.outcome.held_out.as_ref().unwrap();
    assert!(opened::drift_line(s, &held.log).is_some());
    // Opening a file to look at is no work to save: the session holds nothing of it.
    assert_eq!(s.session(), session_before);
    assert_eq!(s.dirty(), dirty_before);

    h.get_by_label("Close").click();
    settle(&mut h);
    assert!(h.state().opened().is_none());
    assert!(h.query_by_label("opened").is_none());
    let s = &h.state().state;
    assert!(opened::drift_line(s, &s.shown.fit.as_ref().unwrap().outcome.in_sample.log).is_none());
}

/// The workbench's own filter judges both calibrations: changed, the opened one is judged
/// again, as `evaluate --filter` judges it.
#[test]
fn the_opened_calibration_follows_the_workbench_filter() {
    let dir = tempfile::tempdir().unwrap();
    let cal = spline_calibration(dir.path());
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    act(&mut h, Action::OpenCalibrationPath(cal.clone()));
    settle(&mut h);
    // A filter typed digit by digit: each asks for a judging while the one before runs; the
    // last one asked for is the one kept.
    for f in [3.0, 30.0, 300.0] {
        h.state_mut().state.recipe_mut().filter_s = f;
        h.step();
    }
    settle(&mut h);
    assert!(opened::current(&h.state().state));
    let cli = evaluate_json(&cal, &sample("calibration.csv"), &["--filter", "300"]);
    let j = judged(&h, OpenLog::Calibration, 0);
    assert_eq!(j.options.filter_s, 300.0);
    assert_eq!(json(&j.evaluation), cli["evaluation"]);
    // Said, since `evaluate` without --filter would take the calibration's own 100 s.
    h.get_by_label("· judged with a 300 s filter");
}

#[test]
fn a_malformed_calibration_keeps_the_work_and_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = spline_calibration(dir.path());
    let bad = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        "{\n  \"format\": \"driftlab-calibration\",\n  \"version\": 1,\n  oops\n}\n",
    )
    .unwrap();
    let session = dir.path().join("run7.json");
    std::fs::write(
        &session,
        r#"{ "format": "driftlab-session", "version": 1, "session": {} }"#,
    )
    .unwrap();
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    act(&mut h, Action::OpenCalibrationPath(good.clone()));
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let choices = h.state().state.shown.choices.clone();
    let p2p = judged(&h, OpenLog::Calibration, 0)
        .evaluation
        .comparison
        .p2p_ratio;

    for (file, want) in [
        (&bad, ["not a calibration file", "line 4 column 3"]),
        (&session, ["format is", "driftlab-session\\\", expected"]),
    ] {
        act(&mut h, Action::OpenCalibrationPath(file.clone()));
        settle(&mut h);
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let shown = h.get_by_label_contains("Could not open the calibration. Nothing was changed.");
        let text = format!("{shown:?}");
        assert!(
            text.contains(&name) && want.iter().all(|w| text.contains(w)),
            "{text}"
        );
        let s = &h.state().state;
        assert_eq!(s.shown.choices, choices, "{name}: the choices are kept");
        assert!(s.shown.fit.is_some());
        // The calibration opened before is still there, judged as it was.
        assert_eq!(h.state().opened().unwrap().path, good);
        assert_eq!(
            judged(&h, OpenLog::Calibration, 0)
                .evaluation
                .comparison
                .p2p_ratio,
            p2p
        );
        h.get_by_label("OK").click();
        h.run_ok();
        assert!(h.query_by_label_contains("Nothing was changed").is_none());
    }
}

/// A file dropped on the window, as the desktop hands it over.
#[derive(Debug)]
struct Dropped(PathBuf);

impl eframe::egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

#[test]
fn ctrl_alt_o_and_a_dropped_json_open_a_calibration() {
    let dir = tempfile::tempdir().unwrap();
    let cal = spline_calibration(dir.path());
    // Named like nothing in particular: what it says it is decides.
    let dropped = dir.path().join("from-the-stand.json");
    std::fs::copy(&cal, &dropped).unwrap();
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(cal.clone()));
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::ALT, Key::O);
    settle(&mut h);
    // Ctrl+Alt+O, not Ctrl+O: the calibration's dialog, and no import view.
    assert_eq!(dialogs.asked(), vec![FileKind::OpenCalibration]);
    assert!(h.state_mut().import_view().is_none());
    assert_eq!(h.state().opened().unwrap().path, cal);

    h.input_mut()
        .dropped_files
        .push(std::sync::Arc::new(Dropped(dropped.clone())));
    h.run_ok();
    settle(&mut h);
    assert_eq!(h.state().opened().unwrap().path, dropped);
    assert!(judged(&h, OpenLog::Calibration, 0).in_sample);
    h.get_by_label("from-the-stand.json");
    // The current work is still the sample log's.
    assert!(
        h.state()
            .state
            .shown
            .log
            .as_ref()
            .unwrap()
            .path
            .ends_with("calibration.csv")
    );
}

#[test]
fn the_opened_column_says_why_when_there_are_no_figures() {
    let dir = tempfile::tempdir().unwrap();
    let cal = spline_calibration(dir.path());
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    act(&mut h, Action::OpenCalibrationPath(cal));
    settle(&mut h);
    // No validation log: the held-out table is not there, nor an opened column for it.
    let s = &h.state().state;
    assert!(matches!(
        opened::column(s, OpenLog::Calibration),
        Some(Column::Judged { .. })
    ));
    assert!(matches!(
        opened::column(s, OpenLog::Validation),
        Some(Column::Not(_))
    ));
    assert_eq!(
        h.state()
            .opened()
            .unwrap()
            .verified
            .as_ref()
            .unwrap()
            .logs
            .len(),
        1
    );
}
