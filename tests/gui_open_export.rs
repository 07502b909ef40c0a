//! The workbench driven headless, as an engineer would use it: open the sample log, suggest
//! plateaus, change an approximation and see the figures change, export files the engine
//! reads back, save and reopen a session, survive a bad file, import semicolons.

use driftlab::gui::{Action, Workbench};
use driftlab::models::recipe::PlateauChoice;
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;

mod common;
use common::gui::*;

/// The workbench on the sample log, settled, whose next file dialog answers `out`.
fn answering(out: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(out.to_path_buf()));
    h
}

#[test]
fn the_sample_log_opens_calibrated_with_its_figures() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("peak-to-peak");
    h.get_by_label_contains("4 plateaus found by the detector");
    let e = &h
        .state()
        .state
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .in_sample
        .evaluation;
    assert!(
        e.comparison.p2p_ratio > 3.0,
        "in-sample ratio {}",
        e.comparison.p2p_ratio
    );
    // The figures on screen are the engine's.
    h.get_by_label(&format!("{:.2}×", e.comparison.p2p_ratio));
}

#[test]
fn suggest_plateaus_fills_the_table_from_the_detector() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let s = &h.state().state;
    let PlateauChoice::Manual { ranges } = &s.recipe().plateaus else {
        panic!("suggested plateaus are editable ranges");
    };
    assert_eq!(ranges.len(), 4);
    assert_eq!(*ranges, s.fit.as_ref().unwrap().outcome.ranges);
    h.get_by_label_contains("4 plateaus set by hand");
}

#[test]
fn changing_an_approximation_changes_the_figures() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    let before = p2p_corrected(&h);
    h.get_by_label("K1+ approximation").click();
    h.run_ok();
    let options = h.get_all_by_label("spline").collect::<Vec<_>>();
    options
        .last()
        .expect("the spline choice in the open list")
        .click();
    settle(&mut h);
    assert_eq!(
        h.state().state.recipe().k1_plus.kind,
        driftlab::models::approx::ApproxKind::Spline
    );
    let fit = h.state().state.fit.clone().unwrap();
    assert_eq!(
        fit.outcome.calibration.k1_plus.kind(),
        driftlab::models::approx::ApproxKind::Spline
    );
    let after = p2p_corrected(&h);
    assert_ne!(before, after, "the figures follow the new K1+");
    // And undo brings the linear K1+ (and its figures) back.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    settle(&mut h);
    assert_eq!(
        h.state().state.recipe().k1_plus.kind,
        driftlab::models::approx::ApproxKind::Linear
    );
    assert_eq!(p2p_corrected(&h), before);
}

#[test]
fn export_writes_a_calibration_the_engine_loads() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gyro7.json");
    let mut h = answering(&out);
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let cal = driftlab::files::calibration::load(&out).expect("the engine reads the exported file");
    let fitted = h
        .state()
        .state
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .calibration
        .clone();
    assert_eq!(cal.k0, fitted.k0);
    assert_eq!(cal.k1_plus, fitted.k1_plus);
    assert_eq!(cal.k2_minus, fitted.k2_minus);
    assert_eq!(cal.source.name, "calibration.csv");
    assert_eq!(
        cal.source.sha256,
        driftlab::files::calibration::sha256_file(&sample("calibration.csv")).unwrap()
    );
    // It corrects a log as the workbench showed it.
    let log =
        driftlab::log::ingest::read_path(&sample("calibration.csv"), &Default::default()).unwrap();
    let c = cal.correct(&log);
    assert_eq!(
        c.cor_dph,
        h.state()
            .state
            .fit
            .as_ref()
            .unwrap()
            .outcome
            .in_sample
            .corrected
            .cor_dph
    );
}

#[test]
fn export_corrected_log_from_the_menu() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("corrected.csv");
    let mut h = answering(&out);
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains("Export corrected log").click();
    settle(&mut h);
    let text = std::fs::read_to_string(&out).expect("written");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c")
    );
    assert_eq!(
        lines.count(),
        h.state().state.log.as_ref().unwrap().log.len()
    );
}

#[test]
fn a_saved_session_reopens_as_it_was_left() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.session.json");
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    h.state_mut().state.recipe_mut().filter_s = 150.0;
    settle(&mut h);
    // A held-out log, through the import view.
    dialogs.answer(Some(sample("validation.csv")));
    // (the button in the Data panel; the result plot's header has one too)
    h.get_all_by_label("Open validation log…")
        .next()
        .unwrap()
        .click();
    h.run_ok();
    h.get_by_label("Load").click();
    settle(&mut h);
    assert!(h.state().state.validation.is_some());
    h.get_by_label_contains("Held out · validation.csv");
    h.state_mut().state.view.show_validation = false;
    assert!(h.state().state.dirty());
    dialogs.answer(Some(path.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    assert!(!h.state().state.dirty(), "saved");
    let choices = h.state().state.choices.clone();

    // A fresh workbench on another log opens the session.
    let mut other = harness(Workbench::new_for_test(&sample("validation.csv")));
    settle(&mut other);
    let ctx = other.ctx.clone();
    other.state_mut().act(&ctx, Action::OpenSessionPath(path));
    settle(&mut other);
    let s = &other.state().state;
    assert_eq!(s.choices, choices);
    assert!(s.log.as_ref().unwrap().path.ends_with("calibration.csv"));
    assert!(!s.dirty(), "a reopened session has nothing unsaved");
    assert!(
        s.validation
            .as_ref()
            .unwrap()
            .path
            .ends_with("validation.csv")
    );
    assert!(
        !s.view.show_validation,
        "the result plot shows what it showed"
    );
    let fit = s.fit.as_ref().unwrap();
    assert_eq!(fit.outcome.calibration.recipe.filter_s, 150.0);
    assert!(fit.outcome.held_out.is_some());
}

#[test]
fn a_bad_file_leaves_the_work_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..200 {
        if i == 120 {
            text.push_str("120,0.1x,20.0\n");
        } else {
            text.push_str(&format!("{i},0.1,20.0\n"));
        }
    }
    std::fs::write(&bad, text).unwrap();
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let choices = h.state().state.choices.clone();
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, Action::OpenLogPath(bad.clone()));
    h.run_ok();
    // Unsaved plateaus: asked first.
    h.get_by_label("Unsaved work");
    h.get_by_label("Discard").click();
    h.run_ok();
    // The import view previews the first rows; the bad cell is further down.
    assert!(h.state_mut().import_view().is_some());
    h.get_by_label("Load").click();
    settle(&mut h);
    h.get_by_label_contains("bad.csv:122:2");
    let s = &h.state().state;
    assert!(s.log.as_ref().unwrap().path.ends_with("calibration.csv"));
    assert_eq!(s.choices, choices);
    assert!(s.fit.is_some());
    h.get_by_label("OK").click();
    h.run_ok();
    assert!(h.query_by_label_contains("bad.csv:122:2").is_none());
}

#[test]
fn the_import_view_reads_semicolons_and_decimal_commas() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("stand.csv");
    let mut text = String::from("Zeit [s];Drift [deg/h];Temp [°C]\n");
    for i in 0..2000 {
        text.push_str(&format!("{i};0,{};20,5\n", i % 7));
    }
    std::fs::write(&log, text).unwrap();
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(log.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run_ok();
    {
        let view = h
            .state_mut()
            .import_view()
            .expect("Ctrl+O opens the import view");
        let p = view.preview().unwrap();
        assert_eq!(p.delimiter, ';');
        assert!(p.decimal_comma);
        assert_eq!(p.rows[0], vec!["0", "0,0", "20,5"]);
    }
    h.get_by_label("Load").click();
    settle(&mut h);
    let l = h.state().state.log.as_ref().unwrap();
    assert!(l.path.ends_with("stand.csv"));
    assert_eq!(l.log.omega_dph[3], 0.3);
    assert_eq!(l.log.temp_c[0], 20.5);
}
