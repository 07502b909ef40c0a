//! Files the workbench writes outside its views: the autosave (unsaved work offered back
//! after a crash, nothing left behind after a clean close) and the test report.

use driftlab::files::session;
use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::settings::Settings;
use driftlab::gui::{Action, Workbench};
use std::path::{Path, PathBuf};

fn sample() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv")
}

#[test]
fn unsaved_work_survives_a_crash_and_a_clean_close_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let settings = dir.path().join("workbench.json");

    // A workbench with work that is not saved anywhere.
    let mut wb = Workbench::new_for_test_in(&sample(), Some(settings.clone()));
    let autosave = wb.autosave_path().unwrap().to_path_buf();
    assert!(wb.recovery().is_none());
    wb.state.recipe_mut().filter_s = 57.0;
    assert!(wb.state.dirty());
    wb.autosave_now();
    let saved = session::load(&autosave).expect("the autosave is a session");
    assert_eq!(saved.recipe.filter_s, 57.0);

    // The process dies: nothing closes cleanly.
    drop(wb);

    // The next workbench offers the work back and restores it, still unsaved.
    let mut wb = Workbench::new(
        Settings::default(),
        Some(settings.clone()),
        Box::new(ScriptedDialogs::new()),
    );
    let left = wb.recovery().expect("the left work is offered").clone();
    assert_eq!(
        std::fs::canonicalize(left.log.unwrap()).unwrap(),
        std::fs::canonicalize(sample()).unwrap()
    );
    wb.restore_autosave();
    wb.wait_for_jobs();
    assert!(wb.state.shown.log.is_some(), "{:?}", wb.state.status);
    assert_eq!(wb.state.shown.choices.recipe.filter_s, 57.0);
    assert!(wb.state.dirty(), "recovered work is not saved work");
    assert!(wb.state.session_path.is_none());

    // Saved or not, a clean close leaves nothing to recover.
    wb.close_cleanly();
    assert!(!autosave.exists());
    let wb = Workbench::new(
        Settings::default(),
        Some(settings),
        Box::new(ScriptedDialogs::new()),
    );
    assert!(wb.recovery().is_none());
}

#[test]
fn work_with_nothing_unsaved_writes_no_autosave() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = Workbench::new_for_test_in(&sample(), Some(dir.path().join("workbench.json")));
    wb.autosave_now();
    assert!(!wb.autosave_path().unwrap().exists());
}

#[test]
fn the_workbench_exports_the_test_report_into_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = Workbench::new_for_test(&sample());
    let dialogs = ScriptedDialogs::new();
    // A name typed with an extension still means a folder.
    dialogs.answer(Some(dir.path().join("gyro7-report.html")));
    wb.set_dialogs(Box::new(dialogs.clone()));
    wb.act(&eframe::egui::Context::default(), Action::ExportReport);
    wb.wait_for_jobs();
    let html = dir.path().join("gyro7-report").join("report.html");
    let text = std::fs::read_to_string(&html).expect("the report page");
    assert!(text.contains("calibration.csv"), "names the log");
    assert!(text.contains("Allan deviation"), "has the Allan figure");
    assert!(
        dir.path()
            .join("gyro7-report/drift-calibration.png")
            .is_file()
    );
}
