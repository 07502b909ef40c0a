//! The validation log kept beside a new calibration log only where it matches: each axis is
//! judged on the validation log's axis of the same name or rate column, as `driftlab
//! evaluate` finds a unit's axes (`Log::matching_axis`), never on the axis that happens to sit
//! at the same place. A validation log that matches no axis of the new log is put away, one
//! that matches some is kept for those, the others saying why where their held-out figures
//! would be, and the status line says which.

use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::settings::Settings;
use driftlab::gui::{Action, Workbench};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};

use crate::common;
use common::gui::*;

/// The workbench on `log` with `validation` open, settled.
fn with_validation(log: &Path, validation: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    wb.open_log(log.to_path_buf(), Default::default(), false);
    wb.open_validation_after(validation.to_path_buf(), Default::default());
    let mut h = harness(wb);
    settle(&mut h);
    assert!(
        h.state().state.shown.validation.is_some(),
        "{}",
        h.state().state.status.clone().unwrap().1
    );
    h
}

/// Opens `log` as the new calibration log, settled.
fn open_log(h: &mut Harness<'_, Workbench>, log: &Path) {
    h.state_mut()
        .open_log(log.to_path_buf(), Default::default(), false);
    settle(h);
}

/// The validation log's view each axis holds: the view's axis, `None` where it has none.
fn judged_on(h: &Harness<'_, Workbench>) -> Vec<Option<String>> {
    let s = &h.state().state;
    (0..s.axis_count())
        .map(|k| s.axis(k).unwrap().validation.map(|v| v.log.axis.clone()))
        .collect()
}

fn status(h: &Harness<'_, Workbench>) -> String {
    h.state().state.status.clone().unwrap().1
}

/// imu3-calibration.csv with its axis gz renamed `renamed` (its column `<renamed>_dps`).
fn imu3_renamed(dir: &Path, renamed: &str) -> PathBuf {
    let text = std::fs::read_to_string(sample("imu3-calibration.csv")).unwrap();
    let path = dir.join(format!("imu3-{renamed}.csv"));
    std::fs::write(&path, text.replacen("gz_dps", &format!("{renamed}_dps"), 1)).unwrap();
    path
}

#[test]
fn a_unit_opened_after_a_validation_log_of_another_gyro_is_not_judged_on_it() {
    let mut h = with_validation(&sample("calibration.csv"), &sample("validation.csv"));
    open_log(&mut h, &sample("imu3-calibration.csv"));
    assert_eq!(h.state().state.axis_count(), 3);
    assert_eq!(
        judged_on(&h),
        [None, None, None],
        "validation.csv has no axis gx, gy or gz: `driftlab evaluate` refuses it"
    );
    assert!(h.state().state.validation_file.is_none(), "put away");
    for k in 0..3 {
        let fit = h.state().state.axis(k).unwrap().fit.cloned().unwrap();
        assert!(
            fit.outcome.held_out.is_none(),
            "axis {k}: no held-out figures"
        );
    }
    let msg = status(&h);
    assert!(
        msg.contains("validation log validation.csv put away")
            && msg.contains("no axis gx, gy, gz"),
        "{msg}"
    );
    assert!(
        h.query_by_label_contains("Held out · validation.csv")
            .is_none()
    );
}

#[test]
fn axes_are_matched_by_name_not_by_place_when_another_unit_is_opened() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = with_validation(
        &sample("imu3-calibration.csv"),
        &sample("imu3-validation.csv"),
    );
    assert_eq!(
        judged_on(&h),
        [Some("gx".into()), Some("gy".into()), Some("gz".into())]
    );

    // A unit of gx, gy and gq: gq is on none of imu3-validation's axes; gx and gy keep theirs.
    let gq = imu3_renamed(dir.path(), "gq");
    open_log(&mut h, &gq);
    assert_eq!(
        h.state().state.unit.as_ref().unwrap().names,
        ["gx", "gy", "gq"]
    );
    assert_eq!(judged_on(&h), [Some("gx".into()), Some("gy".into()), None]);
    let msg = status(&h);
    assert!(
        msg.contains("validation log imu3-validation.csv kept") && msg.contains("no axis gq"),
        "{msg}"
    );
    // gq's held-out figures say why there are none.
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, Action::SelectAxis(2));
    h.run_ok();
    assert!(
        h.query_by_label_contains("imu3-validation.csv has no axis gq")
            .is_some(),
        "the reason where the held-out figures would be"
    );
    assert!(
        h.query_by_label_contains("Held out · imu3-validation.csv")
            .is_none()
    );

    // A log whose axes are none of them: the validation log is put away, not judged axis 0
    // on gx.
    let text = std::fs::read_to_string(sample("imu3-calibration.csv")).unwrap();
    let other = dir.path().join("other.csv");
    std::fs::write(
        &other,
        text.replacen("gx_dps;gy_dps;gz_dps", "wx_dps;wy_dps;wz_dps", 1),
    )
    .unwrap();
    open_log(&mut h, &other);
    assert_eq!(
        h.state().state.unit.as_ref().unwrap().names,
        ["wx", "wy", "wz"],
        "{}",
        status(&h)
    );
    assert_eq!(judged_on(&h), [None, None, None]);
    assert!(h.state().state.validation_file.is_none());
    assert!(
        status(&h).contains("validation log imu3-validation.csv put away"),
        "{}",
        status(&h)
    );
}

#[test]
fn a_validation_log_that_matches_is_kept_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = with_validation(&sample("calibration.csv"), &sample("validation.csv"));
    let copy = dir.path().join("run2.csv");
    std::fs::copy(sample("yan-steps-mid.csv"), &copy).unwrap();
    open_log(&mut h, &copy);
    assert_eq!(judged_on(&h).len(), 1);
    assert!(judged_on(&h)[0].is_some(), "{}", status(&h));
    assert!(
        status(&h).contains("validation log validation.csv kept"),
        "{}",
        status(&h)
    );
    // The validation log opened as the calibration log: not its own held-out log.
    open_log(&mut h, &sample("validation.csv"));
    assert_eq!(judged_on(&h), [None]);
    assert!(h.state().state.validation_file.is_none());
    assert!(
        status(&h).contains("is the calibration log itself"),
        "{}",
        status(&h)
    );
}
