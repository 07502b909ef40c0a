//! Whether a validation log is the calibration log's run is told by the calibration log's
//! sketch, measured on the validation log (as `driftlab compare` and `evaluate` tell it): a
//! part or a thinned copy of the calibration log is refused as its own validation log, a log
//! the sketch cannot tell apart (its rates written coarser) is opened with its figures marked
//! as perhaps not held out, and another run is held out.

use driftlab::gui::Workbench;
use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::settings::Settings;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
use common::gui::*;

/// The workbench on calibration.csv with `validation` asked for as its validation log, settled.
fn asked(validation: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    wb.open_log(sample("calibration.csv"), Default::default(), false);
    wb.open_validation_after(validation.to_path_buf(), Default::default());
    let mut h = harness(wb);
    settle(&mut h);
    h
}

fn status(h: &Harness<'_, Workbench>) -> String {
    h.state().state.status.clone().unwrap().1
}

#[test]
fn a_part_or_a_thinned_copy_of_the_calibration_log_is_not_its_validation_log() {
    let dir = tempfile::tempdir().unwrap();
    let same = |x: f64| format!("{x}");
    for path in [
        common::calibration_derived(dir.path(), "every20.csv", |i| i % 20 == 0, same),
        common::calibration_derived(dir.path(), "part.csv", |i| (2000..10000).contains(&i), same),
    ] {
        let h = asked(&path);
        let st = &h.state().state;
        assert!(
            st.shown.validation.is_none(),
            "{} shown as held out: {}",
            path.display(),
            status(&h)
        );
        assert!(
            status(&h).contains("is the calibration log itself"),
            "{}",
            status(&h)
        );
    }
}

#[test]
fn a_log_the_sketch_cannot_tell_apart_is_opened_with_its_figures_marked() {
    let dir = tempfile::tempdir().unwrap();
    // The calibration log's rates written in steps of 0.001 °/h (its own: 0.0001).
    let coarse =
        common::calibration_derived(dir.path(), "coarse.csv", |_| true, |x| format!("{:.3}", x));
    let h = asked(&coarse);
    let st = &h.state().state;
    assert!(st.shown.validation.is_some(), "{}", status(&h));
    let why = st.validation_doubt.clone().expect("the doubt kept");
    assert!(why.contains("0.001"), "{why}");
    assert!(
        status(&h).contains("cannot be told whether it is the calibration log"),
        "{}",
        status(&h)
    );
    h.get_by_label_contains("Held out? · coarse.csv");
    h.get_by_label_contains("Cannot tell if this is the calibration log");

    // Another run of the gyro is held out, unmarked.
    let h = asked(&sample("validation.csv"));
    let st = &h.state().state;
    assert!(st.shown.validation.is_some(), "{}", status(&h));
    assert!(st.validation_doubt.is_none());
    h.get_by_label_contains("Held out · validation.csv");
    assert!(
        h.query_by_label_contains("Cannot tell if this is")
            .is_none(),
        "another run marked"
    );
}
