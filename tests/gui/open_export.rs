//! The workbench driven headless, as an engineer would use it: open the sample log, suggest
//! plateaus, change an approximation and see the figures change, export files the engine
//! reads back, save and reopen a session, survive a bad file, import semicolons.

use driftlab::gui::{Action, ScriptedDialogs, Workbench};
use driftlab::models::recipe::PlateauChoice;
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
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
    let e = &outcome(&h).in_sample.evaluation;
    assert!(
        e.comparison.p2p_ratio > 3.0,
        "in-sample ratio {}",
        e.comparison.p2p_ratio
    );
    // The figures on screen are the engine's.
    h.get_by_label(&driftlab::gui::plot_items::ratio(e.comparison.p2p_ratio));
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
    assert_eq!(*ranges, s.shown.fit.as_ref().unwrap().outcome.ranges);
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
    let fit = h.state().state.shown.fit.clone().unwrap();
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
    let fitted = outcome(&h).calibration.clone();
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
            .shown
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
    h.get_by_label_contains("Export corrected calibration log")
        .click();
    settle(&mut h);
    let text = std::fs::read_to_string(&out).expect("written");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c")
    );
    assert_eq!(
        lines.count(),
        h.state().state.shown.log.as_ref().unwrap().log.len()
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
    open_validation(&mut h, &dialogs, &sample("validation.csv"));
    assert!(h.state().state.shown.validation.is_some());
    h.get_by_label_contains("Held out · validation.csv");
    h.state_mut().state.view.show_validation = false;
    assert!(h.state().state.dirty());
    dialogs.answer(Some(path.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    assert!(!h.state().state.dirty(), "saved");
    let choices = h.state().state.shown.choices.clone();

    // A fresh workbench on another log opens the session.
    let mut other = harness(Workbench::new_for_test(&sample("validation.csv")));
    settle(&mut other);
    let ctx = other.ctx.clone();
    other.state_mut().act(&ctx, Action::OpenSessionPath(path));
    settle(&mut other);
    let s = &other.state().state;
    assert_eq!(s.shown.choices, choices);
    assert!(
        s.shown
            .log
            .as_ref()
            .unwrap()
            .path
            .ends_with("calibration.csv")
    );
    assert!(!s.dirty(), "a reopened session has nothing unsaved");
    assert!(
        s.shown
            .validation
            .as_ref()
            .unwrap()
            .path
            .ends_with("validation.csv")
    );
    assert!(
        !s.view.show_validation,
        "the result plot shows what it showed"
    );
    let fit = s.shown.fit.as_ref().unwrap();
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
    let choices = h.state().state.shown.choices.clone();
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
    assert!(
        s.shown
            .log
            .as_ref()
            .unwrap()
            .path
            .ends_with("calibration.csv")
    );
    assert_eq!(s.shown.choices, choices);
    assert!(s.shown.fit.is_some());
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
    let l = h.state().state.shown.log.as_ref().unwrap();
    assert!(l.path.ends_with("stand.csv"));
    assert_eq!(l.log.omega_dph[3], 0.3);
    assert_eq!(l.log.temp_c[0], 20.5);
}

/// The sample log copied into a folder of its own as `run7.csv`, open and calibrated, with
/// every file dialog answered "no system dialog here".
fn in_a_folder(dialogs: usize) -> (tempfile::TempDir, Harness<'static, Workbench>) {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("run7.csv");
    std::fs::copy(sample("calibration.csv"), &log).unwrap();
    let mut wb = Workbench::new_for_test(&log);
    let script = with_dialogs(&mut wb);
    for _ in 0..dialogs {
        script.answer_in_window();
    }
    let mut h = harness(wb);
    settle(&mut h);
    (dir, h)
}

#[test]
fn the_windows_own_dialog_writes_the_calibration_and_the_session_beside_the_log() {
    let (dir, mut h) = in_a_folder(3);
    let folder = std::fs::canonicalize(dir.path()).unwrap();

    // Ctrl+E: the dialog opens on the log's folder with a name beside the log; Enter writes.
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    h.run_ok();
    let text = h
        .state_mut()
        .file_dialog()
        .expect("the window's own dialog")
        .text()
        .to_string();
    assert_eq!(
        Path::new(&text),
        folder.join("run7-calibration.json"),
        "prefilled beside the log"
    );
    h.get_by_label("Export calibration");
    h.key_press(Key::Enter);
    settle(&mut h);
    assert!(h.state_mut().file_dialog().is_none(), "Enter closed it");
    let cal = folder.join("run7-calibration.json");
    let read =
        driftlab::files::calibration::load(&cal).expect("the engine reads the calibration written");
    assert_eq!(read.source.name, "run7.csv");
    h.get_by_label_contains(&format!("Calibration written: {}", cal.display()));

    // Ctrl+S: the session, beside the log too.
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run_ok();
    h.key_press(Key::Enter);
    settle(&mut h);
    let session = folder.join("run7-session.json");
    let s = driftlab::files::session::load(&session).expect("the session reads back");
    assert_eq!(
        std::fs::canonicalize(s.log.unwrap().path).unwrap(),
        folder.join("run7.csv")
    );
    assert!(!h.state().state.dirty(), "saved");
    h.get_by_label_contains(&format!("Session saved: {}", session.display()));

    // Escape cancels, and the status says nothing was written.
    h.key_press_modifiers(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
    h.run_ok();
    assert!(h.state_mut().file_dialog().is_some());
    h.key_press(Key::Escape);
    settle(&mut h);
    assert!(h.state_mut().file_dialog().is_none());
    assert!(!folder.join("run7-corrected.csv").exists());
    h.get_by_label_contains("Corrected log not exported: no file was chosen, nothing was written");
}

#[test]
fn the_windows_own_dialog_completes_a_name_and_opens_the_log_through_the_import_view() {
    let (dir, mut h) = in_a_folder(1);
    std::fs::write(dir.path().join("notes.json"), "not a log\n").unwrap();
    std::fs::create_dir(dir.path().join("older runs")).unwrap();
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run_ok();
    let d = h
        .state_mut()
        .file_dialog()
        .expect("the window's own dialog");
    assert!(
        d.text().ends_with(std::path::MAIN_SEPARATOR),
        "opens on a folder"
    );
    // The listing: folders and logs; the typed start of a name completes with Tab.
    h.get_by_label_contains("older runs");
    assert!(
        h.query_all_by_label("notes.json").next().is_none(),
        "logs only"
    );
    h.event(eframe::egui::Event::Text("run7.c".into()));
    h.run_ok();
    h.run_ok();
    h.key_press(Key::Tab);
    h.run_ok();
    let text = h.state_mut().file_dialog().unwrap().text().to_string();
    assert_eq!(Path::new(&text).file_name().unwrap(), "run7.csv", "{text}");
    h.key_press(Key::Enter);
    h.run_ok();
    assert!(h.state_mut().file_dialog().is_none());
    let import = h
        .state_mut()
        .import_view()
        .expect("the import view shows next");
    assert_eq!(import.path.file_name().unwrap(), "run7.csv");
}

#[test]
fn a_log_whose_columns_need_a_look_opens_on_the_import_view_from_the_command_line() {
    // Two temperature sensors on the gyro: which is the calibration temperature?
    let mut wb = Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    wb.open_log(sample("laser-gyro.csv"), Default::default(), true);
    let view = wb.import_view().expect("the import view shows first");
    assert!(
        view.concerns()
            .iter()
            .any(|c| c.message.contains("temp_housing_c")),
        "{:?}",
        view.concerns()
    );
    assert!(
        wb.state.shown.log.is_none(),
        "nothing is read before the engineer looks"
    );
    // A plain log is read at once; the options given are the ones it is read with.
    let mut wb = Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    let read = driftlab::log::ingest::ReadOptions {
        temp_col: Some(driftlab::log::ingest::ColumnRef::Name(
            "temp_chamber_c".into(),
        )),
        ..Default::default()
    };
    wb.open_log(
        sample("calibration.csv"),
        driftlab::gui::jobs::LoadOptions::read(read.clone()),
        true,
    );
    if let Some(v) = wb.import_view() {
        panic!("no look needed, yet: {:?}", v.concerns());
    }
    wb.wait_for_jobs();
    let l = wb.state.shown.log.as_ref().expect("read");
    assert_eq!(l.options.read, read);
    assert_eq!(l.log.temp_c[100], {
        let plain =
            driftlab::log::ingest::read_path(&sample("calibration.csv"), &Default::default())
                .unwrap();
        plain
            .extra
            .iter()
            .find(|c| c.name == "temp_chamber_c")
            .unwrap()
            .values[100]
    });
}

#[test]
fn column_mapping_reopens_the_import_view_on_the_loaded_log() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    // The Data section's button (the File menu has the same entry).
    h.get_by_label("Column mapping…").click();
    h.run_ok();
    let view = h.state_mut().import_view().expect("the import view");
    assert_eq!(view.path.file_name().unwrap(), "calibration.csv");
}

#[test]
fn a_register_read_as_the_temperature_reopens_the_import_view_naming_the_better_column() {
    // A raw temperature register (T = counts / 340 + 36.53 °C) beside the temperature in °C,
    // the register chosen by hand: read, then said, with the column to take instead.
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("imu.csv");
    let mut text = String::from("time_s,omega_dph,temp_raw_int16,temp_C_est\n");
    for i in 0..600 {
        let t_c = 20.0 + 10.0 * i as f64 / 600.0;
        let counts = ((t_c - 36.53) * 340.0).round();
        text.push_str(&format!(
            "{i},{},{counts},{t_c:.3}\n",
            0.01 * (i % 5) as f64
        ));
    }
    std::fs::write(&log, text).unwrap();
    let read = driftlab::log::ingest::ReadOptions {
        temp_col: Some(driftlab::log::ingest::ColumnRef::Name(
            "temp_raw_int16".into(),
        )),
        ..Default::default()
    };
    let mut wb = Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    wb.open_log(
        log.clone(),
        driftlab::gui::jobs::LoadOptions::read(read.clone()),
        true,
    );
    assert!(
        wb.import_view().is_some(),
        "a temperature of thousands of °C needs a look before the read"
    );
    let mut h = harness(wb);
    h.run_ok();
    h.get_by_label("Load").click();
    settle(&mut h);
    assert!(
        h.state().state.shown.log.is_some(),
        "the log is read as asked, and shown"
    );
    let view = h
        .state_mut()
        .import_view()
        .expect("the import view opens again after the read");
    let doubt = view
        .warnings()
        .iter()
        .find(|w| w.about_columns)
        .unwrap_or_else(|| panic!("{:?}", view.warnings()))
        .text
        .clone();
    assert!(
        doubt.contains("\"temp_raw_int16\"") && doubt.contains("Temperature column \"temp_C_est\""),
        "{doubt}"
    );
    // On screen, first.
    h.get_by_label_contains("its columns did not hold what they were read as");
    h.get_by_label(&format!("• {doubt}"));
    // Mapping the better column: the warning was about the old mapping, and goes.
    let view = h.state_mut().import_view().unwrap();
    view.read.temp_col = Some(driftlab::log::ingest::ColumnRef::Name("temp_C_est".into()));
    assert!(view.warnings().is_empty());
    h.run_ok();
    h.get_by_label("Load").click();
    settle(&mut h);
    assert!(h.state_mut().import_view().is_none());
    let l = h.state().state.shown.log.as_ref().unwrap();
    assert!((l.log.temp_c[0] - 20.0).abs() < 1e-9, "{}", l.log.temp_c[0]);
}

#[test]
fn a_sessions_windows_of_the_figures_of_merit_are_the_ones_shown() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("w.session.json");
    let recipe = driftlab::models::Recipe::default();
    let s = driftlab::files::session::Session {
        log: Some(driftlab::files::session::LogRef {
            path: sample("calibration.csv"),
            ..Default::default()
        }),
        merit: driftlab::judge::metrics::MeritOptions {
            filter_s: recipe.filter_s,
            window_s: 900.0,
        },
        recipe,
        ..Default::default()
    };
    driftlab::files::session::save(&path, &s).unwrap();
    let mut h = harness(Workbench::new_for_test(&sample("validation.csv")));
    settle(&mut h);
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, Action::OpenSessionPath(path));
    settle(&mut h);
    h.get_by_label("15-min RMS");
    let st = &h.state().state;
    assert_eq!(st.merit().window_s, 900.0);
    let fit = st.shown.fit.as_ref().unwrap();
    let shown = fit.outcome.in_sample.evaluation.comparison.raw.windows;
    // What the engine counts over 900-s windows of the same correction, not over 600-s ones.
    let log = &st.shown.log.as_ref().unwrap().log;
    let c = fit.outcome.calibration.correct(log);
    let of = |window_s| {
        let merit = driftlab::judge::metrics::MeritOptions {
            filter_s: fit.outcome.calibration.recipe.filter_s,
            window_s,
        };
        driftlab::Evaluation::of_correction(log, &c, &merit)
            .comparison
            .raw
            .windows
    };
    assert_eq!(shown, of(900.0));
    assert_ne!(shown, of(600.0));
    // Saved again, the window stays.
    assert_eq!(st.session().merit.window_s, 900.0);
}

#[test]
fn the_corrected_validation_log_is_exported_from_the_window() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("held-out.csv");
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    open_validation(&mut h, &dialogs, &sample("validation.csv"));
    assert!(
        h.state().state.view.show_validation,
        "the drift plot shows it"
    );
    // Ctrl+Shift+E writes the log the drift plot shows, named after it.
    dialogs.answer(Some(out.clone()));
    h.key_press_modifiers(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
    settle(&mut h);
    let asked = dialogs.suggested();
    assert_eq!(asked.last().unwrap().1, "validation-corrected.csv");
    let written = std::fs::read(&out).expect("written");
    // What the engine's writer makes of the validation log with the calibration shown.
    let st = &h.state().state;
    let cal = st.shown.fit.as_ref().unwrap().outcome.calibration.clone();
    let validation = &st.shown.validation.as_ref().unwrap().log;
    let want = dir.path().join("want.csv");
    let unit = driftlab::UnitCalibration::single(driftlab::DriftModel::Vakhrameev(Box::new(cal)));
    driftlab::files::corrected_csv::correct_and_write(&want, validation, &unit, &|_| {}).unwrap();
    assert_eq!(written, std::fs::read(&want).unwrap());
    assert_eq!(
        String::from_utf8_lossy(&written).lines().count(),
        validation.len() + 1
    );
    // From the menu, the calibration log's, named after it (no word twice).
    dialogs.answer(Some(dir.path().join("cal.csv")));
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label("Export corrected calibration log…").click();
    settle(&mut h);
    assert_eq!(
        dialogs.suggested().last().unwrap().1,
        "calibration-corrected.csv"
    );
    let text = std::fs::read_to_string(dir.path().join("cal.csv")).unwrap();
    assert_eq!(
        text.lines().count(),
        h.state().state.shown.log.as_ref().unwrap().log.len() + 1
    );
    // The calibration file beside calibration.csv is not `calibration-calibration.json`.
    dialogs.answer(None);
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    assert_eq!(dialogs.suggested().last().unwrap().1, "calibration.json");
}

/// Opens `validation` as the validation log of the workbench on `calibration`, settled.
fn with_validation(calibration: &str, validation: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample(calibration));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    open_validation(&mut h, &dialogs, validation);
    h
}

/// Opens `path` as the validation log through the dialog and the import view, as an engineer
/// does (the button in the Data panel; the result plot's header has one too), settled.
fn open_validation(h: &mut Harness<'static, Workbench>, dialogs: &ScriptedDialogs, path: &Path) {
    dialogs.answer(Some(path.to_path_buf()));
    h.get_all_by_label("Open validation log…")
        .next()
        .unwrap()
        .click();
    h.run_ok();
    h.get_by_label("Load").click();
    settle(h);
}

#[test]
fn a_one_axis_calibration_is_judged_only_on_the_same_axis_of_a_log_of_several() {
    // calibration.csv's axis is omega (column omega_dph); imu3-validation.csv holds gx, gy, gz: none of
    // them is the calibrated gyro, so none is judged on (it used to take gx, unsaid).
    let h = with_validation("calibration.csv", &sample("imu3-validation.csv"));
    let st = &h.state().state;
    assert!(st.shown.validation.is_none());
    let (_, message) = st.status.clone().unwrap();
    assert!(
        message.contains("3 gyro axes (gx, gy, gz)")
            && message.contains("none is the calibrated axis omega (column omega_dph)"),
        "{message}"
    );

    // The axis of the calibration log's name is found among several: a log of gx, gy and
    // omega_dph made from imu3-validation.csv's gy, judged on that column.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("validation.csv")).unwrap();
    let mut out = String::new();
    for (k, line) in text.lines().enumerate() {
        if line.starts_with('#') {
            out.push_str(line);
        } else if k > 0 && line.starts_with("time_s") {
            out.push_str("time_s,gx_dph,omega_dph,gz_dph,temp_c,temp_chamber_c");
        } else {
            let cells: Vec<&str> = line.split(',').collect();
            let doubled = |x: &str| (x.parse::<f64>().unwrap() * 2.0).to_string();
            out.push_str(&format!(
                "{},{},{},{},{},{}",
                cells[0],
                doubled(cells[1]),
                cells[1],
                doubled(cells[1]),
                cells[2],
                cells[3]
            ));
        }
        out.push('\n');
    }
    let three = dir.path().join("three.csv");
    std::fs::write(&three, out).unwrap();
    let h = with_validation("calibration.csv", &three);
    let st = &h.state().state;
    let judged = st.shown.validation.as_ref().expect("judged on omega_dph");
    assert_eq!(judged.log.axis, "omega");
    let plain = driftlab::read_path(&sample("validation.csv"), &Default::default()).unwrap();
    assert_eq!(judged.log.omega_dph, plain.omega_dph);
}

#[test]
fn the_calibration_log_is_not_opened_as_its_own_validation_log() {
    let h = with_validation("calibration.csv", &sample("calibration.csv"));
    let st = &h.state().state;
    assert!(st.shown.validation.is_none(), "in-sample shown as held out");
    let (_, message) = st.status.clone().unwrap();
    assert!(
        message.contains("is the calibration log itself"),
        "{message}"
    );
    // Nor is a copy of it with other bytes (CRLF line endings, no comment line) under
    // another name: it holds the same run.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let copy: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\r\n"))
        .collect();
    let path = dir.path().join("rerun.csv");
    std::fs::write(&path, copy).unwrap();
    let h = with_validation("calibration.csv", &path);
    let st = &h.state().state;
    assert!(st.shown.validation.is_none(), "a copy shown as held out");
}

#[test]
fn a_file_name_with_line_breaks_and_bidi_overrides_is_shown_escaped() {
    // A name that would split a heading over lines, or reorder the text around it.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run\nx\u{202e}.csv");
    std::fs::copy(sample("calibration.csv"), &path).unwrap();
    let mut h = harness(Workbench::new_for_test(&path));
    settle(&mut h);
    h.get_by_label_contains("In-sample · run\\u000ax\\u202e.csv");
    let raw: Vec<String> = h
        .query_all_by_label_contains("run\nx")
        .map(|n| format!("{n:?}").chars().take(300).collect())
        .collect();
    assert!(raw.is_empty(), "the raw name is shown: {raw:?}");
}
