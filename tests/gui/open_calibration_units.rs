//! A calibration opened beside a unit's fit: a three-axis calibration judged axis by axis on a
//! three-axis log as `driftlab evaluate` judges it, each axis's figures shown with the axis;
//! and where the files do not say which axis a calibration's axis corrects (a single-axis
//! calibration on a log of three, a unit on a log of one), the workbench says so and the
//! engineer chooses, never a guess.

use driftlab::gui::action::OpenLog;
use driftlab::gui::jobs::AxisVerdict;
use driftlab::gui::opened::{self, Column};
use driftlab::gui::plot_items::{num, ratio};
use driftlab::gui::{Action, Workbench};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use super::open_calibration::{act, calibrate, evaluate_json, json, judged};
use crate::common;
use common::gui::*;

const NAMES: [&str; 3] = ["gx", "gy", "gz"];

fn unit_harness() -> Harness<'static, Workbench> {
    let mut h = harness(Workbench::new_for_test(&sample("imu3-calibration.csv")));
    settle(&mut h);
    h
}

/// The verdicts of every axis of the opened calibration on log `which`.
fn verdicts<'h>(h: &'h Harness<'_, Workbench>, which: OpenLog) -> &'h [AxisVerdict] {
    let v = h.state().opened().unwrap().verified.as_ref().unwrap();
    &v.logs.iter().find(|l| l.which == which).unwrap().axes
}

#[test]
fn a_unit_calibration_is_judged_axis_by_axis_as_evaluate_judges_it() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("imu3.json");
    calibrate(
        &sample("imu3-calibration.csv"),
        &cal,
        &["--k0", "spline", "--knots", "4"],
    );
    let cli = evaluate_json(&cal, &sample("imu3-calibration.csv"), &[]);
    let mut h = unit_harness();
    act(&mut h, Action::OpenCalibrationPath(cal.clone()));
    settle(&mut h);
    h.get_by_label("· 3 axes: gx, gy, gz (vakhrameev)");
    for (k, name) in NAMES.iter().enumerate() {
        let axis = &cli["axes"][k];
        assert_eq!(axis["name"], *name);
        let j = judged(&h, OpenLog::Calibration, k);
        assert_eq!(j.log_axis, *name);
        assert_eq!(axis["log_axis"], j.log_axis.as_str());
        assert!(!j.by_hand, "found by its name");
        assert_eq!(json(&j.evaluation), axis["evaluation"], "axis {name}");
        assert_eq!(Some(j.in_sample), axis["in_sample"].as_bool());
        // Every axis's ratio in the strip.
        h.get_by_label(&format!(
            "{name} {}",
            ratio(j.evaluation.comparison.p2p_ratio)
        ));
    }
    // The figures' table follows the axis shown.
    for (k, name) in NAMES.iter().enumerate() {
        act(&mut h, Action::SelectAxis(k));
        settle(&mut h);
        let s = &h.state().state;
        let Some(Column::Judged { axis, judged }) = opened::column(s, OpenLog::Calibration) else {
            panic!("axis {name}: the opened calibration's figures");
        };
        assert_eq!(axis, *name);
        let p2p = judged.evaluation.comparison.corrected.p2p_dph;
        let fit = s.shown.fit.as_ref().unwrap();
        assert!(opened::drift_line(s, &fit.outcome.in_sample.log).is_some());
        assert_eq!(
            opened::drift_line(s, &fit.outcome.in_sample.log)
                .unwrap()
                .log_axis,
            *name
        );
        h.get_by_label(&num(p2p));
        h.get_by_label_contains(&format!("axis {name}:"));
    }
}

#[test]
fn a_single_axis_calibration_on_a_unit_log_asks_which_axis_it_corrects() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json");
    calibrate(&sample("calibration.csv"), &cal, &[]);
    let mut h = unit_harness();
    act(&mut h, Action::OpenCalibrationPath(cal.clone()));
    settle(&mut h);
    let AxisVerdict::Unplaced(why) = &verdicts(&h, OpenLog::Calibration)[0] else {
        panic!("a calibration of one axis is not placed on a log of three by a guess");
    };
    assert!(
        why.contains("gx, gy, gz") && why.contains("choose the axis it corrects"),
        "{why}"
    );
    h.get_by_label_contains("does not record the column it was fitted on");
    h.get_by_label("Axis it corrects in imu3-calibration.csv:");
    assert!(
        opened::drift_line(
            &h.state().state,
            &h.state()
                .state
                .shown
                .fit
                .as_ref()
                .unwrap()
                .outcome
                .in_sample
                .log
        )
        .is_none()
    );
    let s = &h.state().state;
    assert!(matches!(
        opened::column(s, OpenLog::Calibration),
        Some(Column::Not(_))
    ));

    // The engineer says gy: judged on gy as `evaluate --rate-col gy_dps` judges it.
    act(
        &mut h,
        Action::ChooseOpenedAxis(OpenLog::Calibration, 0, Some("gy".into())),
    );
    settle(&mut h);
    let j = judged(&h, OpenLog::Calibration, 0);
    assert_eq!(j.log_axis, "gy");
    assert!(j.by_hand);
    let cli = evaluate_json(
        &cal,
        &sample("imu3-calibration.csv"),
        &["--rate-col", "gy_dps"],
    );
    assert_eq!(json(&j.evaluation), cli["evaluation"]);
    // Shown with gy, and with no other axis.
    let Some(Column::Not(why)) = opened::column(&h.state().state, OpenLog::Calibration) else {
        panic!("gx is shown, and the calibration corrects gy");
    };
    assert!(why.contains("another axis than gx"), "{why}");
    act(&mut h, Action::SelectAxis(1));
    settle(&mut h);
    assert!(matches!(
        opened::column(&h.state().state, OpenLog::Calibration),
        Some(Column::Judged { .. })
    ));
    // And taken back: asked again.
    act(
        &mut h,
        Action::ChooseOpenedAxis(OpenLog::Calibration, 0, None),
    );
    settle(&mut h);
    assert!(matches!(
        verdicts(&h, OpenLog::Calibration)[0],
        AxisVerdict::Unplaced(_)
    ));
}

#[test]
fn a_unit_calibration_on_a_log_of_one_axis_names_the_axes_it_lacks() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("imu3.json");
    calibrate(&sample("imu3-calibration.csv"), &cal, &[]);
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    act(&mut h, Action::OpenCalibrationPath(cal));
    settle(&mut h);
    for (k, name) in NAMES.iter().enumerate() {
        let AxisVerdict::Unplaced(why) = &verdicts(&h, OpenLog::Calibration)[k] else {
            panic!("axis {name} is not on the log");
        };
        assert!(
            why.contains(&format!("has no axis {name}")) && why.contains("its axes: omega"),
            "{why}"
        );
        h.get_by_label(&format!("Axis {name} in calibration.csv:"));
    }
    // gz on the log's one axis, chosen: judged there, the others still asked for.
    act(
        &mut h,
        Action::ChooseOpenedAxis(OpenLog::Calibration, 2, Some("omega".into())),
    );
    settle(&mut h);
    let j = judged(&h, OpenLog::Calibration, 2);
    assert_eq!(j.log_axis, "omega");
    assert!(matches!(
        verdicts(&h, OpenLog::Calibration)[0],
        AxisVerdict::Unplaced(_)
    ));
    let Some(Column::Judged { axis, .. }) = opened::column(&h.state().state, OpenLog::Calibration)
    else {
        panic!("gz's figures beside the fit of the log's one axis");
    };
    assert_eq!(axis, "gz");
    // calibration.csv's rates are written in 0.0001 °/h, coarser than the unit's (8 decimals
    // of °/s): its samples' sketch cannot find the unit's values in it, whatever they were,
    // and says so rather than call it another run.
    h.get_by_label(
        "opened imu3.json: cannot tell if it is the calibration log: its rates are written in \
         steps of 0.0001 °/h, the calibration log's in steps of 0.000036 °/h",
    );
}
