//! A unit of several gyro axes in the workbench: every axis calibrated on opening, an axis
//! switch (buttons and Alt+1…9, [ and ]) that keeps each axis's own choices, plateaus shared,
//! and files that hold every axis: the unit calibration (equal to the engine's
//! `models::calibrate`), the unit's corrected CSV (equal to what `driftlab apply` writes) and the
//! session.

use driftlab::files::session::Coefficient;
use driftlab::gui::action::Edit;
use driftlab::gui::{Action, Target, Workbench};
use driftlab::judge::metrics::MeritOptions;
use driftlab::models::approx::ApproxKind;
use driftlab::models::recipe::PlateauChoice;
use driftlab::models::{AxisPlan, DriftModel, ModelChoice, Preset, UnitCalibration};
use driftlab::signal::plateau::PlateauRange;
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::sync::Arc;

use crate::common;
use common::gui::*;

const NAMES: [&str; 3] = ["gx", "gy", "gz"];

fn unit_harness() -> Harness<'static, Workbench> {
    let mut h = harness(Workbench::new_for_test(&sample("imu3-calibration.csv")));
    settle(&mut h);
    h
}

/// Runs an action as the menus do.
fn act(h: &mut Harness<'_, Workbench>, a: Action) {
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, a);
    h.run_ok();
}

/// The unit the workbench calibrated, as the engine fits it from the same log and choices.
fn engine_unit(h: &Harness<'_, Workbench>) -> Vec<driftlab::models::CalibratedAxis> {
    let s = &h.state().state;
    let mut log = (**s.unit.as_ref().unwrap().full_log.as_ref().unwrap()).clone();
    let plans: Vec<AxisPlan> = (0..3)
        .map(|k| {
            let a = s.axis(k).unwrap();
            AxisPlan {
                name: a.name.to_string(),
                choice: ModelChoice::Preset(Preset::Vakhrameev),
                recipe: a.choices.recipe.clone().checked().unwrap(),
            }
        })
        .collect();
    driftlab::models::calibrate(&mut log, &plans, &MeritOptions::default())
        .expect("the engine calibrates the unit")
}

#[test]
fn a_unit_opens_with_every_axis_calibrated_and_the_switch_is_instant() {
    let mut h = unit_harness();
    let s = &h.state().state;
    assert_eq!(s.axis_count(), 3);
    assert_eq!(s.unit.as_ref().unwrap().names, NAMES);
    assert!(!s.dirty(), "a log just opened has nothing unsaved");
    for (k, name) in NAMES.iter().enumerate() {
        let a = s.axis(k).unwrap();
        assert_eq!(a.name, *name);
        assert_eq!(
            a.log.unwrap().log.axis,
            *name,
            "each axis fits its own rate"
        );
        assert!(a.fit_current(), "axis {} calibrated on opening", a.name);
        let r = a
            .fit
            .unwrap()
            .outcome
            .in_sample
            .evaluation
            .comparison
            .p2p_ratio;
        assert!(r > 2.0, "axis {} in-sample p2p ratio {r}", a.name);
    }
    // The strip names every axis with its figures; the Models and Allan pages say the axis.
    h.get_by_label("Axis");
    for n in NAMES {
        h.get_by_label_contains(&format!("{n}  p2p "));
    }
    let fits: Vec<_> = (0..3)
        .map(|k| h.state().state.axis(k).unwrap().fit.unwrap().clone())
        .collect();

    h.key_press_modifiers(Modifiers::ALT, Key::Num2);
    h.run_ok();
    let s = &h.state().state;
    assert_eq!(s.active_axis(), 1);
    assert_eq!(s.shown.log.as_ref().unwrap().log.axis, "gy");
    assert!(
        !h.state().busy(),
        "switching axes refits nothing: each axis keeps its fit"
    );
    for (k, f) in fits.iter().enumerate() {
        assert!(Arc::ptr_eq(f, s.axis(k).unwrap().fit.unwrap()));
    }
    h.key_press(Key::CloseBracket);
    h.run_ok();
    assert_eq!(h.state().state.active_axis(), 2);
    h.key_press(Key::CloseBracket);
    h.run_ok();
    assert_eq!(h.state().state.active_axis(), 0, "] wraps round");
    h.key_press(Key::OpenBracket);
    h.run_ok();
    assert_eq!(h.state().state.active_axis(), 2);
    // Clicking an axis in the strip shows it.
    h.get_by_label_contains("gy  p2p ").click();
    h.run_ok();
    assert_eq!(h.state().state.active_axis(), 1);

    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    h.get_by_label("Models · axis gy");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num3);
    settle(&mut h);
    h.get_by_label_contains("Allan deviation of axis gy");
    let allan = h
        .state()
        .state
        .shown
        .allan
        .clone()
        .expect("the Allan curves of gy");
    assert_eq!(
        allan.key.0,
        h.state().state.shown.fit.as_ref().unwrap().generation,
        "of the axis shown"
    );
}

#[test]
fn each_axis_keeps_its_own_choices_and_the_plateaus_are_shared() {
    let mut h = unit_harness();
    // gy: K1+ as a spline; gz: K0's knots set by hand.
    act(&mut h, Action::SelectAxis(1));
    let mut spec = h.state().state.recipe().k1_plus.clone();
    spec.kind = ApproxKind::Spline;
    spec.knots = 4;
    act(
        &mut h,
        Action::Edit(Edit::Approx(Coefficient::K1Plus, spec)),
    );
    settle(&mut h);
    assert!(h.state().state.fit_current());
    let gx_fit = h.state().state.axis(0).unwrap().fit.unwrap().clone();
    act(&mut h, Action::SelectAxis(2));
    let mut k0 = h.state().state.recipe().k0.clone();
    k0.kind = ApproxKind::Pwl;
    k0.knots = 3;
    act(&mut h, Action::Edit(Edit::Approx(Coefficient::K0, k0)));
    settle(&mut h);
    let knots: Vec<f64> = {
        let f = h.state().state.shown.fit.as_ref().unwrap();
        f.outcome
            .calibration
            .k0
            .knots()
            .1
            .iter()
            .map(|v| v + 0.01)
            .collect()
    };
    act(
        &mut h,
        Action::Edit(Edit::Knots(Coefficient::K0, Some(knots.clone()))),
    );
    settle(&mut h);
    let s = &h.state().state;
    assert!(
        Arc::ptr_eq(&gx_fit, s.axis(0).unwrap().fit.unwrap()),
        "editing gy and gz refits neither gx"
    );
    let gy = s.axis(1).unwrap();
    let gz = s.axis(2).unwrap();
    assert_eq!(gy.choices.recipe.k1_plus.kind, ApproxKind::Spline);
    assert_eq!(gz.choices.recipe.k1_plus.kind, ApproxKind::Linear);
    assert_eq!(gz.choices.recipe.k0.values.as_ref(), Some(&knots));
    assert!(!gy.choices.recipe.k0.hand_knots());
    assert!(!s.axis(0).unwrap().choices.recipe.k0.hand_knots());
    assert_eq!(
        gz.fit.unwrap().outcome.calibration.k0.knots().1,
        knots.as_slice(),
        "gz's fit has its hand-set knots"
    );
    // Undo steps back through gz's own history only.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_ok();
    assert!(!h.state().state.shown.choices.recipe.k0.hand_knots());
    assert_eq!(
        h.state().state.axis(1).unwrap().choices.recipe.k1_plus.kind,
        ApproxKind::Spline
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run_ok();

    // A plateau set on gx is every axis's plateau (they come from T).
    act(&mut h, Action::SelectAxis(0));
    let mut ranges = h.state().state.ranges();
    ranges.truncate(3);
    ranges.push(PlateauRange {
        start_s: 38_700.0,
        end_s: 40_100.0,
    });
    act(&mut h, Action::Edit(Edit::Plateaus(ranges.clone())));
    settle(&mut h);
    let s = &h.state().state;
    for k in 0..3 {
        let a = s.axis(k).unwrap();
        assert_eq!(
            a.choices.recipe.plateaus,
            PlateauChoice::Manual {
                ranges: ranges.clone()
            },
            "axis {}",
            a.name
        );
        assert!(
            a.fit_current(),
            "axis {} refitted on the new plateaus",
            a.name
        );
        assert_eq!(a.fit.unwrap().outcome.ranges, ranges);
    }
    assert_eq!(
        s.axis(1).unwrap().choices.recipe.k1_plus.kind,
        ApproxKind::Spline,
        "the shared plateaus leave each axis's own choices"
    );
    assert_eq!(
        s.axis(2).unwrap().choices.recipe.k0.values.as_ref(),
        Some(&knots)
    );
}

#[test]
fn export_writes_the_unit_calibration_the_engine_makes_and_its_corrected_csv() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = unit_harness();
    let dialogs = with_dialogs(h.state_mut());
    // The gyro axes alone (the sample's accelerometers are tests/gui/accel.rs's).
    act(&mut h, Action::AccelOn(false));
    // Each axis its own approximations.
    act(&mut h, Action::SelectAxis(1));
    let mut spec = h.state().state.recipe().k1_minus.clone();
    spec.kind = ApproxKind::Spline;
    spec.knots = 4;
    act(
        &mut h,
        Action::Edit(Edit::Approx(Coefficient::K1Minus, spec)),
    );
    act(&mut h, Action::SelectAxis(2));
    let mut spec = h.state().state.recipe().k0.clone();
    spec.kind = ApproxKind::Parabolic;
    act(&mut h, Action::Edit(Edit::Approx(Coefficient::K0, spec)));
    settle(&mut h);

    let out = dir.path().join("unit.json");
    dialogs.answer(Some(out.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let unit: UnitCalibration =
        driftlab::files::calibration::load_unit(&out).expect("a unit file reads back");
    assert!(unit.is_unit());
    assert_eq!(unit.axis_names(), NAMES);
    let expected = engine_unit(&h);
    for (got, want) in unit.axes.iter().zip(&expected) {
        assert_eq!(got.name, want.name);
        assert_eq!(got.rate_column, want.rate_column);
        assert_eq!(got.rate_column, format!("{}_dps", got.name));
        let (DriftModel::Vakhrameev(g), DriftModel::Vakhrameev(w)) =
            (&got.model, &want.calibrated.model)
        else {
            panic!("axis {}: Vakhrameev models", got.name);
        };
        let mut w = (**w).clone();
        // What files stamp: the log's name and SHA-256, the time written.
        w.source = g.source.clone();
        w.created = g.created.clone();
        assert_eq!(**g, w, "axis {}: the engine's calibration", got.name);
    }
    let DriftModel::Vakhrameev(gy) = &unit.axes[1].model else {
        unreachable!()
    };
    assert_eq!(gy.recipe.k1_minus.kind, ApproxKind::Spline);

    // The corrected CSV: every axis side by side, as `driftlab apply` writes it.
    let csv = dir.path().join("corrected.csv");
    dialogs.answer(Some(csv.clone()));
    h.key_press_modifiers(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
    settle(&mut h);
    let text = std::fs::read_to_string(&csv).expect("the corrected CSV is written");
    assert_eq!(
        text.lines().next().unwrap(),
        "time_s,gx_raw_dph,gx_pred_dph,gx_cor_dph,gy_raw_dph,gy_pred_dph,gy_cor_dph,\
         gz_raw_dph,gz_pred_dph,gz_cor_dph,temp_c"
    );
    let log = h
        .state()
        .state
        .unit
        .as_ref()
        .unwrap()
        .full_log
        .clone()
        .unwrap();
    // Each axis's columns are its model's whole correction of the log (not the streamed
    // prediction the writer uses), bit for bit: the shortest round-trip numbers lose nothing.
    let corrections: Vec<_> = unit
        .axes
        .iter()
        .map(|a| {
            let mut axis_log = (*log).clone();
            assert!(axis_log.select_axis(&a.name), "axis {}", a.name);
            a.model.correct(&axis_log).unwrap()
        })
        .collect();
    let bits = |v: f64| if v.is_nan() { u64::MAX } else { v.to_bits() };
    let mut rows = 0;
    for (i, line) in text.lines().skip(1).enumerate() {
        let cells: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        assert_eq!(cells.len(), 2 + 3 * unit.axes.len(), "row {i}");
        assert_eq!(bits(cells[0]), bits(log.time_s[i]), "row {i}: time");
        assert_eq!(
            bits(cells[cells.len() - 1]),
            bits(log.temp_c[i]),
            "row {i}: T"
        );
        for (k, (a, c)) in unit.axes.iter().zip(&corrections).enumerate() {
            let raw = log.axis_rate(&a.name).unwrap()[i];
            let want = [raw, c.pred_dph[i], c.cor_dph[i]];
            for (j, w) in want.into_iter().enumerate() {
                assert_eq!(
                    bits(cells[1 + 3 * k + j]),
                    bits(w),
                    "row {i}, axis {}",
                    a.name
                );
            }
        }
        rows += 1;
    }
    assert_eq!(rows, log.len());

    // The flight file: the unit's three axes as the firmware's X, Y and Z, as `driftlab
    // export` writes them from the unit's file.
    use driftlab::export::firmware::{ExportOptions, Format, flight_unit};
    let params = dir.path().join("tcal.parm");
    dialogs.answer(Some(params.clone()));
    act(&mut h, Action::ExportFlight(Format::ArdupilotParm));
    settle(&mut h);
    let written = std::fs::read_to_string(&params).expect("the ArduPilot file is written");
    let want = flight_unit(&unit, Format::ArdupilotParm, &ExportOptions::default()).unwrap();
    let body = |t: &str| {
        t.lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(body(&written), body(&want.text));
    for axis in ["X", "Y", "Z"] {
        assert!(
            written.contains(&format!("INS_TCAL1_GYR1_{axis}")),
            "{written}"
        );
    }

    // The report: every axis, a summary of all and a section each.
    let report = dir.path().join("report");
    dialogs.answer(Some(report.clone()));
    act(&mut h, Action::ExportReport);
    settle(&mut h);
    let html = std::fs::read_to_string(report.join("report.html")).expect("the report is written");
    assert!(html.contains("Summary of every axis"));
    for axis in NAMES {
        assert!(report.join(axis).is_dir(), "axis {axis}'s figures");
    }
}

#[test]
fn a_unit_session_keeps_every_axis_and_a_validation_log_judges_each() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("imu3.session.json");
    let mut h = unit_harness();
    let dialogs = with_dialogs(h.state_mut());
    let ctx = h.ctx.clone();
    h.state_mut().act(
        &ctx,
        Action::ReadLog(
            sample("imu3-validation.csv"),
            Default::default(),
            Target::Validation,
        ),
    );
    settle(&mut h);
    for (k, name) in NAMES.iter().enumerate() {
        let a = h.state().state.axis(k).unwrap();
        assert_eq!(a.validation.unwrap().log.axis, *name);
        let held = a
            .fit
            .unwrap()
            .outcome
            .held_out
            .as_ref()
            .expect("judged held out");
        assert!(
            held.evaluation.comparison.p2p_ratio > 1.5,
            "axis {} held-out ratio {}",
            a.name,
            held.evaluation.comparison.p2p_ratio
        );
    }
    h.get_by_label_contains("gz  p2p ");
    assert_eq!(
        h.get_all_by_label_contains("· held out p2p ").count(),
        3,
        "every axis's held-out figures in the strip"
    );

    act(&mut h, Action::SelectAxis(2));
    let mut spec = h.state().state.recipe().k2_plus.clone();
    spec.kind = ApproxKind::Pwl;
    spec.knots = 3;
    act(
        &mut h,
        Action::Edit(Edit::Approx(Coefficient::K2Plus, spec)),
    );
    settle(&mut h);
    let knots: Vec<f64> = {
        let f = h.state().state.shown.fit.as_ref().unwrap();
        f.outcome
            .calibration
            .k2_plus
            .knots()
            .1
            .iter()
            .map(|v| v * 1.1)
            .collect()
    };
    act(
        &mut h,
        Action::Edit(Edit::Knots(Coefficient::K2Plus, Some(knots))),
    );
    settle(&mut h);
    act(&mut h, Action::SelectAxis(1));
    assert!(h.state().state.dirty());
    dialogs.answer(Some(path.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    assert!(!h.state().state.dirty(), "saved");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("\"version\": 2"),
        "a unit's session is version 2"
    );
    let choices: Vec<_> = (0..3)
        .map(|k| h.state().state.axis(k).unwrap().choices.clone())
        .collect();

    let mut other = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut other);
    let ctx = other.ctx.clone();
    other.state_mut().act(&ctx, Action::OpenSessionPath(path));
    settle(&mut other);
    let s = &other.state().state;
    assert_eq!(s.axis_count(), 3);
    assert_eq!(s.active_axis(), 1, "the axis shown when saved");
    for (k, c) in choices.iter().enumerate() {
        let a = s.axis(k).unwrap();
        assert_eq!(a.choices, c, "axis {}", a.name);
        assert!(a.fit_current());
        assert!(
            a.validation.is_some(),
            "axis {} has its validation view",
            a.name
        );
    }
    assert!(!s.dirty(), "a reopened session has nothing unsaved");

    // The same session whose gz is named gq: the log has no gq, and its choices are said to be
    // left unused rather than dropped unsaid.
    let renamed = dir.path().join("renamed.session.json");
    let text = text.replace("\"name\": \"gz\"", "\"name\": \"gq\"");
    assert!(text.contains("\"gq\""), "the session names its axes");
    std::fs::write(&renamed, text).unwrap();
    let mut third = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut third);
    let ctx = third.ctx.clone();
    third
        .state_mut()
        .act(&ctx, Action::OpenSessionPath(renamed));
    settle(&mut third);
    let s = &third.state().state;
    assert_eq!(s.axis_count(), 3);
    let (_, said) = s.status.clone().unwrap();
    assert!(
        said.contains("the choices kept for axis gq are not used")
            && said.contains("its axes: gx, gy, gz"),
        "{said}"
    );
}

#[test]
fn a_single_axis_log_shows_no_axis_switch_and_saves_a_version_1_session() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one.session.json");
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    let dialogs = with_dialogs(h.state_mut());
    settle(&mut h);
    assert!(h.state().state.unit.is_none());
    assert!(h.query_by_label("Axis").is_none());
    assert!(h.state().panel_rect("axes").is_none());
    h.key_press_modifiers(Modifiers::ALT, Key::Num2);
    h.run_ok();
    assert_eq!(h.state().state.active_axis(), 0);
    dialogs.answer(Some(path.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"version\": 1"), "{text}");
    assert!(!text.contains("\"axes\""));
}

#[test]
fn a_unit_left_unsaved_is_recovered_with_every_axis() {
    let dir = tempfile::tempdir().unwrap();
    let settings = dir.path().join("workbench.json");
    let mut wb =
        Workbench::new_for_test_in(&sample("imu3-calibration.csv"), Some(settings.clone()));
    // gz filtered otherwise, gy shown.
    assert!(wb.state.switch_axis(2));
    wb.state.recipe_mut().filter_s = 57.0;
    assert!(wb.state.switch_axis(1));
    assert!(wb.state.dirty());
    wb.autosave_now();
    drop(wb);

    let mut wb = Workbench::new(
        driftlab::gui::settings::Settings::default(),
        Some(settings),
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    wb.restore_autosave();
    wb.wait_for_jobs();
    let s = &wb.state;
    assert_eq!(s.axis_count(), 3, "{:?}", s.status);
    assert_eq!(s.active_axis(), 1, "the axis shown");
    let filters: Vec<f64> = (0..3)
        .map(|k| s.axis(k).unwrap().choices.recipe.filter_s)
        .collect();
    assert_eq!(filters, [100.0, 100.0, 57.0]);
    assert!(s.dirty(), "recovered work is not saved work");
    assert!(s.all_current(), "every axis calibrated");
}
