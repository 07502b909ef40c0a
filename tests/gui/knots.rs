//! Knots placed by hand in the workbench (issue 22, item 1): a knot dragged sideways (held
//! between its neighbours) and up or down, on K1± and on K0; a knot added with Ctrl+click and
//! removed from the plot's menu; a position typed in the knot table; and the calibration
//! exported with the positions in its recipe, which `driftlab calibrate --recipe` reproduces,
//! for a log of one axis and axis by axis for a unit.

use driftlab::files::session::Coefficient;
use driftlab::gui::action::Edit;
use driftlab::gui::{Action, Workbench};
use driftlab::judge::metrics::MeritOptions;
use driftlab::models::approx::{ApproxKind, ApproxSpec, KnotEdit};
use driftlab::models::{AxisPlan, DriftModel, ModelChoice, Preset, UnitCalibration};
use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use serde_json::Value;

use crate::common;
use common::gui::*;

/// The workbench on the sample log with K1+ a spline of 5 knots (and `k0` for K0), settled.
fn spline_k1(k0: Option<ApproxSpec>) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    wb.state.recipe_mut().k1_plus = ApproxSpec {
        knots: 5,
        ..ApproxSpec::of(ApproxKind::Spline)
    };
    if let Some(k0) = k0 {
        wb.state.recipe_mut().k0 = k0;
    }
    let mut h = harness(wb);
    settle(&mut h);
    h
}

fn k1p(h: &Harness<'_, Workbench>) -> ApproxSpec {
    h.state().state.recipe().k1_plus.clone()
}

fn fitted_knots(h: &Harness<'_, Workbench>, c: Coefficient) -> (Vec<f64>, Vec<f64>) {
    let (x, y) = c.approx(&outcome(h).calibration).knots();
    (x.to_vec(), y.to_vec())
}

/// A primary-button drag from `from` to `to` in a few moves.
fn drag(h: &mut Harness<'_, Workbench>, from: Pos2, to: Pos2) {
    h.event(Event::PointerMoved(from));
    h.run_ok();
    primary_button(h, from, true);
    for k in 1..=6 {
        h.event(Event::PointerMoved(from + (to - from) * (k as f32 / 6.0)));
        h.step();
    }
    primary_button(h, to, false);
    settle(h);
}

/// A click of `button` at `at` with `modifiers` held.
fn click(h: &mut Harness<'_, Workbench>, at: Pos2, button: PointerButton, modifiers: Modifiers) {
    h.event(Event::ModifiersChanged(modifiers));
    h.event(Event::PointerMoved(at));
    h.run_ok();
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos: at,
            button,
            pressed,
            modifiers,
        });
        h.step();
    }
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_ok();
}

#[test]
fn a_knot_dragged_sideways_moves_between_its_neighbours_and_the_fit_follows() {
    let mut h = spline_k1(None);
    let (x0, y0) = fitted_knots(&h, Coefficient::K1Plus);
    let k2_before = outcome(&h).calibration.k2_plus.clone();
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 2).unwrap();
    drag(&mut h, p, p + egui::vec2(30.0, 0.0));
    let spec = k1p(&h);
    let at = spec.at.clone().expect("knot positions placed by hand");
    assert!(
        at[2] > x0[2] && at[2] < x0[3],
        "moved right: {} → {}",
        x0[2],
        at[2]
    );
    for j in [0, 1, 3, 4] {
        assert_eq!(at[j], x0[j], "knot {j} stays");
    }
    assert_eq!(spec.values, None, "a sideways drag sets no value by hand");
    assert!(h.state().state.fit_current());
    let (x1, y1) = fitted_knots(&h, Coefficient::K1Plus);
    assert_eq!(x1, at, "the fit puts its knots there");
    assert_ne!(y1, y0, "the values are fitted at the new positions");
    assert_ne!(
        outcome(&h).calibration.k2_plus,
        k2_before,
        "K2+ follows the new K1+"
    );

    // Dragged past its right neighbour: it stops short of it.
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 2).unwrap();
    let beyond = h.state().knot_screen_pos(Coefficient::K1Plus, 3).unwrap();
    drag(&mut h, p, Pos2::new(beyond.x + 40.0, p.y));
    let at = k1p(&h).at.unwrap();
    assert!(at[2] < at[3] && at[2] > at[1], "{at:?}");
    assert!(at[2] > x0[2] + 0.8 * (x0[3] - x0[2]), "{at:?}");

    // Up and down instead: the value is set by hand, the positions kept.
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 1).unwrap();
    let y_before = fitted_knots(&h, Coefficient::K1Plus).1[1];
    drag(&mut h, p, p - egui::vec2(0.0, 25.0));
    let spec = k1p(&h);
    let values = spec.values.clone().expect("values set by hand");
    assert!(values[1] > y_before, "{y_before} → {}", values[1]);
    assert_eq!(
        spec.at.unwrap(),
        at,
        "an up-down drag moves no knot sideways"
    );
    assert_eq!(fitted_knots(&h, Coefficient::K1Plus).1, values);

    // Undo takes the value back, then the second sideways drag.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    settle(&mut h);
    assert_eq!(k1p(&h).values, None);
    assert_eq!(k1p(&h).at.unwrap(), at);
}

#[test]
fn k0s_knots_are_dragged_too() {
    let mut h = spline_k1(Some(ApproxSpec {
        knots: 3,
        ..ApproxSpec::of(ApproxKind::Pwl)
    }));
    let (x0, y0) = fitted_knots(&h, Coefficient::K0);
    assert_eq!(x0.len(), 3, "K0 fitted as a pwl of 3 knots");
    let p = h
        .state()
        .knot_screen_pos(Coefficient::K0, 1)
        .expect("K0's knots are drawn");
    drag(&mut h, p, p + egui::vec2(0.0, -20.0));
    let k0 = h.state().state.recipe().k0.clone();
    let values = k0.values.expect("K0's value set by hand");
    assert!(values[1] > y0[1], "{} → {}", y0[1], values[1]);
    assert_eq!((values[0], values[2]), (y0[0], y0[2]));
    let p = h.state().knot_screen_pos(Coefficient::K0, 1).unwrap();
    drag(&mut h, p, p + egui::vec2(-25.0, 0.0));
    let k0 = h.state().state.recipe().k0.clone();
    let at = k0.at.expect("K0's knot moved sideways");
    assert!(at[1] < x0[1] && at[1] > x0[0], "{} → {}", x0[1], at[1]);
    assert_eq!(outcome(&h).calibration.k0.knots().0, &at[..]);
    assert_eq!(
        outcome(&h).calibration.k0.knots().1,
        &values[..],
        "its hand-set values stay"
    );
}

#[test]
fn ctrl_click_adds_a_knot_and_the_menu_removes_one() {
    let mut h = spline_k1(None);
    let (x0, _) = fitted_knots(&h, Coefficient::K1Plus);
    // Ctrl+click on the K1+ curve between knots 2 and 3.
    let x = 0.5 * (x0[2] + x0[3]);
    let y = outcome(&h).calibration.k1_plus.eval(x);
    let at = h.state().coeff_plot_pos(Coefficient::K1Plus, x, y).unwrap();
    click(&mut h, at, PointerButton::Primary, Modifiers::COMMAND);
    settle(&mut h);
    let spec = k1p(&h);
    assert_eq!(spec.knots, 6, "a knot added");
    let placed = spec.at.expect("the knots are placed by hand now");
    assert_eq!(placed.len(), 6);
    assert!((placed[3] - x).abs() < 0.02 * (x0[3] - x0[2]), "{placed:?}");
    assert_eq!(
        [placed[0], placed[1], placed[2], placed[4], placed[5]],
        [x0[0], x0[1], x0[2], x0[3], x0[4]]
    );
    assert_eq!(fitted_knots(&h, Coefficient::K1Plus).0, placed);

    // Right-click on knot 2 (the third), then "Remove knot 3 of K1+".
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 2).unwrap();
    click(&mut h, p, PointerButton::Secondary, Modifiers::NONE);
    h.get_by_label("Remove knot 3 of K1+").click();
    settle(&mut h);
    let spec = k1p(&h);
    assert_eq!(spec.knots, 5);
    let at = spec.at.unwrap();
    assert_eq!(at, [placed[0], placed[1], placed[3], placed[4], placed[5]]);
    assert_eq!(fitted_knots(&h, Coefficient::K1Plus).0, at);

    // Never below two knots: the menu entry of a two-knot curve is greyed.
    let two = ApproxSpec {
        knots: 2,
        ..ApproxSpec::of(ApproxKind::Pwl)
    };
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, Action::Edit(Edit::Approx(Coefficient::K1Plus, two)));
    settle(&mut h);
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 0).unwrap();
    click(&mut h, p, PointerButton::Secondary, Modifiers::NONE);
    let entry = h.get_by_label("Remove knot 1 of K1+");
    assert!(entry.accesskit_node().is_disabled());
}

/// The knot table's number field holding `value`.
fn field<'h>(h: &'h Harness<'_, Workbench>, value: f64) -> egui_kittest::Node<'h> {
    h.get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|n| n.accesskit_node().numeric_value() == Some(value))
        .unwrap_or_else(|| panic!("no field holds {value}"))
}

#[test]
fn a_position_typed_in_the_knot_table_is_taken_or_refused_with_the_reason() {
    let mut h = spline_k1(None);
    let (x0, y0) = fitted_knots(&h, Coefficient::K1Plus);
    h.get_by_label("knots…").click();
    settle(&mut h);
    h.get_by_label("Knots of K1+");
    let typed = x0[1] + 0.3 * (x0[2] - x0[1]);
    field(&h, x0[1]).set_value_accesskit(typed);
    settle(&mut h);
    let at = k1p(&h).at.expect("placed by hand");
    assert_eq!(at[1], typed);
    assert_eq!(fitted_knots(&h, Coefficient::K1Plus).0, at);
    // Past its neighbour: refused, said in the table, the knots kept.
    field(&h, at[3]).set_value_accesskit(at[1]);
    settle(&mut h);
    assert_eq!(k1p(&h).at.unwrap(), at);
    h.get_all_by_label_contains("K1+ not changed: knot 4 goes strictly between its neighbours")
        .next()
        .expect("the reason is shown");
    // A value typed: set by hand.
    let (_, y) = fitted_knots(&h, Coefficient::K1Plus);
    field(&h, y[4]).set_value_accesskit(y0[4] + 100.0);
    settle(&mut h);
    assert_eq!(k1p(&h).values.unwrap()[4], y0[4] + 100.0);
}

#[test]
fn the_exported_calibration_holds_the_knots_and_calibrate_recipe_reproduces_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = spline_k1(None);
    let dialogs = with_dialogs(h.state_mut());
    // A knot moved sideways, one added, one value set by hand.
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 1).unwrap();
    drag(&mut h, p, p + egui::vec2(-20.0, 0.0));
    let (x, _) = fitted_knots(&h, Coefficient::K1Plus);
    let a = outcome(&h).calibration.k1_plus.clone();
    let spec = k1p(&h)
        .edit_knot(
            &a,
            KnotEdit::Insert {
                x: 0.5 * (x[3] + x[4]),
            },
        )
        .unwrap();
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, Action::Edit(Edit::Approx(Coefficient::K1Plus, spec)));
    settle(&mut h);
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 4).unwrap();
    drag(&mut h, p, p + egui::vec2(0.0, 20.0));
    let spec = k1p(&h);
    assert_eq!(spec.knots, 6);
    assert!(spec.at.is_some() && spec.values.is_some());

    let out = dir.path().join("hand.json");
    dialogs.answer(Some(out.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let text = std::fs::read_to_string(&out).expect("the calibration is written");
    let v: Value = serde_json::from_str(&text).unwrap();
    let r = &v["calibration"]["recipe"]["k1_plus"];
    let at: Vec<f64> = serde_json::from_value(r["at"].clone()).unwrap();
    let values: Vec<f64> = serde_json::from_value(r["values"].clone()).unwrap();
    assert_eq!(Some(at.clone()), spec.at, "the recipe holds the positions");
    assert_eq!(
        Some(values.clone()),
        spec.values,
        "and the values set by hand"
    );
    let curve = &v["calibration"]["k1_plus"]["curve"];
    assert_eq!(curve["knots_x"], serde_json::json!(at));
    assert_eq!(curve["knots_y"], serde_json::json!(values));

    // The command line, given the file as its recipe, makes the same calibration.
    let again = dir.path().join("again.json");
    let printed = common::run::ok(&[
        "calibrate",
        &common::run::sample("calibration.csv"),
        "--recipe",
        &out.display().to_string(),
        "--out",
        &again.display().to_string(),
    ]);
    let strip = |path: &std::path::Path| {
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        v["calibration"]["created"] = Value::Null;
        v
    };
    assert_eq!(
        strip(&again),
        strip(&out),
        "bit for bit but the time written"
    );
    assert!(
        printed.contains("K1+ 6 knots placed by hand at") && printed.contains("values set by hand"),
        "{printed}"
    );
}

#[test]
fn each_axis_of_a_unit_keeps_its_own_hand_knots_and_the_unit_file_holds_them() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(Workbench::new_for_test(&sample("imu3-calibration.csv")));
    settle(&mut h);
    let dialogs = with_dialogs(h.state_mut());
    let act = |h: &mut Harness<'_, Workbench>, a: Action| {
        let ctx = h.ctx.clone();
        h.state_mut().act(&ctx, a);
        h.run_ok();
        settle(h);
    };
    // Axis gy: K1+ a pwl of 4 knots, its knot 1 moved sideways; gz: K0 a pwl of 3, knot 1
    // given a value.
    act(&mut h, Action::SelectAxis(1));
    let spec = ApproxSpec {
        knots: 4,
        ..ApproxSpec::of(ApproxKind::Pwl)
    };
    act(
        &mut h,
        Action::Edit(Edit::Approx(Coefficient::K1Plus, spec.clone())),
    );
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 1).unwrap();
    drag(&mut h, p, p + egui::vec2(25.0, 0.0));
    let gy_at = k1p(&h).at.expect("gy's knot moved");
    act(&mut h, Action::SelectAxis(2));
    act(
        &mut h,
        Action::Edit(Edit::Approx(
            Coefficient::K0,
            ApproxSpec {
                knots: 3,
                ..ApproxSpec::of(ApproxKind::Pwl)
            },
        )),
    );
    let p = h.state().knot_screen_pos(Coefficient::K0, 1).unwrap();
    drag(&mut h, p, p + egui::vec2(0.0, 15.0));
    let gz_values = h
        .state()
        .state
        .recipe()
        .k0
        .values
        .clone()
        .expect("gz's K0 value set");
    // Back on gy: its knots as they were, gx's untouched.
    act(&mut h, Action::SelectAxis(1));
    assert_eq!(k1p(&h).at.as_ref(), Some(&gy_at));
    let s = &h.state().state;
    assert!(!s.axis(0).unwrap().choices.recipe.k1_plus.hand_knots());
    assert!(!s.axis(0).unwrap().choices.recipe.k0.hand_knots());

    let out = dir.path().join("unit.json");
    dialogs.answer(Some(out.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let unit: UnitCalibration = driftlab::files::calibration::load_unit(&out).unwrap();
    let recipe_of = |k: usize| match &unit.axes[k].model {
        DriftModel::Vakhrameev(c) => c.recipe.clone(),
        _ => panic!("a Vakhrameev axis"),
    };
    assert_eq!(recipe_of(1).k1_plus.at, Some(gy_at.clone()));
    assert_eq!(recipe_of(2).k0.values, Some(gz_values));
    assert!(!recipe_of(0).k1_plus.hand_knots() && !recipe_of(0).k0.hand_knots());
    // The engine, given each axis's recipe, makes the same unit.
    let s = &h.state().state;
    let mut log = (**s.unit.as_ref().unwrap().full_log.as_ref().unwrap()).clone();
    let plans: Vec<AxisPlan> = (0..3)
        .map(|k| AxisPlan {
            name: unit.axes[k].name.clone(),
            choice: ModelChoice::Preset(Preset::Vakhrameev),
            recipe: recipe_of(k).checked().unwrap(),
        })
        .collect();
    let engine = driftlab::models::calibrate(&mut log, &plans, &MeritOptions::default()).unwrap();
    for (got, want) in unit.axes.iter().zip(&engine) {
        let (DriftModel::Vakhrameev(g), DriftModel::Vakhrameev(w)) =
            (&got.model, &want.calibrated.model)
        else {
            panic!("Vakhrameev axes");
        };
        let mut w = (**w).clone();
        w.source = g.source.clone();
        w.created = g.created.clone();
        assert_eq!(**g, w, "axis {}", got.name);
    }
    let DriftModel::Vakhrameev(gy) = &unit.axes[1].model else {
        unreachable!()
    };
    assert_eq!(gy.k1_plus.knots().0, &gy_at[..]);

    // The command line, each axis's recipe taken from the unit's file, makes the same file
    // (the sample's accelerometer axes with it, as the window calibrates them).
    let again = dir.path().join("again.json");
    let u = out.display().to_string();
    let [gx, gy, gz] = ["gx", "gy", "gz"].map(|n| format!("{n}={u}"));
    common::run::ok(&[
        "calibrate",
        &common::run::sample("imu3-calibration.csv"),
        "--accel",
        "--axis-recipe",
        &gx,
        "--axis-recipe",
        &gy,
        "--axis-recipe",
        &gz,
        "--out",
        &again.display().to_string(),
    ]);
    let strip = |path: &std::path::Path| {
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        v["created"] = Value::Null;
        v
    };
    assert_eq!(
        strip(&again),
        strip(&out),
        "bit for bit but the time written"
    );
}

#[test]
fn the_models_page_fits_and_shows_the_hand_placed_knots() {
    use driftlab::gui::action::Page;
    use eframe::egui::accesskit::Role;
    let mut h = spline_k1(None);
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 3).unwrap();
    drag(&mut h, p, p - egui::vec2(20.0, 0.0));
    let at = k1p(&h).at.expect("placed by hand");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    assert_eq!(h.state().page(), Page::Models);
    h.get_by_role_and_label(Role::Button, "Compare").click();
    h.run_ok();
    settle(&mut h);
    let c = h.state().state.shown.models.clone().expect("compared");
    let report = c
        .reports
        .iter()
        .find(|r| r.model == "vakhrameev")
        .expect("the Vakhrameev model is compared");
    let Some(DriftModel::Vakhrameev(cal)) = &report.fitted else {
        panic!("fitted: {:?}", report.error)
    };
    assert_eq!(
        cal.k1_plus.knots().0,
        &at[..],
        "fitted with the knots placed"
    );
    h.get_by_role_and_label(Role::Button, "vakhrameev").click();
    h.run_ok();
    h.get_by_label_contains("5 knots placed by hand at");
}
