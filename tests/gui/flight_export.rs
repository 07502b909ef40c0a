//! The workbench's File › Export entries for flight controllers: the file is the engine's
//! (`driftlab export --format ardupilot-parm|px4-params` of the same calibration), and what
//! cannot be written is said, with nothing written.

use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::gui::Workbench;
use driftlab::gui::state::Severity;
use driftlab::models::DriftModel;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
use common::gui::*;

fn answering(out: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(out.to_path_buf()));
    h
}

fn export_from_menu(h: &mut Harness<'static, Workbench>, entry: &str) {
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains(entry).click();
    settle(h);
}

#[test]
fn ardupilot_parameters_from_the_menu_are_the_engines() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tcal.parm");
    let mut h = answering(&out);
    export_from_menu(&mut h, "Export ArduPilot parameters");
    let text = std::fs::read_to_string(&out).expect("written");
    let wb = h.state();
    let log = wb.state.shown.log.as_ref().unwrap();
    let cal = driftlab::gui::export::stamped(
        &wb.state.shown.fit.as_ref().unwrap().outcome.calibration,
        log,
    )
    .unwrap();
    let model = DriftModel::Vakhrameev(Box::new(cal));
    let want = firmware::flight(&model, Format::ArdupilotParm, &ExportOptions::default()).unwrap();
    assert_eq!(text, want.text);
    // The rate terms left out are said on the status line.
    let (severity, message) = wb.state.status.clone().unwrap();
    assert_eq!(severity, Severity::Warning);
    assert!(
        message.contains("ardupilot-parm file written") && message.contains("rate terms"),
        "{message}"
    );
}

#[test]
fn px4_parameters_without_a_device_id_are_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tc.params");
    let mut h = answering(&out);
    export_from_menu(&mut h, "Export PX4 parameters");
    assert!(!out.exists());
    let (severity, message) = h.state().state.status.clone().unwrap();
    assert_eq!(severity, Severity::Error);
    assert!(
        message.contains("nothing was written") && message.contains("device_id"),
        "{message}"
    );
}
