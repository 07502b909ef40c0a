//! The workbench driven headless: plateaus edited by mouse and keyboard, a plateau edge and a
//! spline knot dragged, and the figures following.

use driftlab::gui::Workbench;
use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use crate::common;
use common::gui::*;

#[test]
fn plateaus_are_edited_by_mouse_and_undone_by_keyboard() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let ranges = |h: &Harness<'_, Workbench>| h.state().state.ranges();
    let before = ranges(&h);
    let rect = h
        .state()
        .plot_rect("time_temp")
        .expect("the T plot is drawn");
    let log_end = *h
        .state()
        .state
        .shown
        .log
        .as_ref()
        .unwrap()
        .log
        .time_s
        .last()
        .unwrap();

    // Shift+drag across the plot marks a new plateau.
    let y = rect.center().y;
    let (x0, x1) = (
        rect.left() + 0.45 * rect.width(),
        rect.left() + 0.52 * rect.width(),
    );
    drag(&mut h, Pos2::new(x0, y), Pos2::new(x1, y), Modifiers::SHIFT);
    settle(&mut h);
    let after = ranges(&h);
    assert_eq!(after.len(), before.len() + 1, "{after:?}");
    let new = after.iter().find(|r| !before.contains(r)).unwrap();
    assert!(new.end_s > new.start_s && new.start_s > 0.0 && new.end_s < log_end);

    // Delete removes the selected (new) plateau; Ctrl+Z brings it back, Ctrl+Y removes it again.
    h.key_press(Key::Delete);
    settle(&mut h);
    assert_eq!(ranges(&h), before);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    settle(&mut h);
    assert_eq!(ranges(&h), after);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    settle(&mut h);
    assert_eq!(ranges(&h), before);
}

/// A primary-button drag with `modifiers` held, in a few moves.
fn drag(h: &mut Harness<'_, Workbench>, from: Pos2, to: Pos2, modifiers: Modifiers) {
    h.event(Event::ModifiersChanged(modifiers));
    h.event(Event::PointerMoved(from));
    h.run_ok();
    h.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers,
    });
    h.step();
    for k in 1..=5 {
        let p = from + (to - from) * (k as f32 / 5.0);
        h.event(Event::PointerMoved(p));
        h.step();
    }
    h.event(Event::PointerButton {
        pos: to,
        button: PointerButton::Primary,
        pressed: false,
        modifiers,
    });
    h.step();
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_ok();
}

#[test]
fn a_plateau_edge_is_dragged() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let before = h.state().state.ranges();
    let rect = h.state().plot_rect("time_temp").unwrap();
    let px = |h: &Harness<'_, Workbench>, t: f64| h.state().time_plot_x(t).unwrap();
    let start = before[1].start_s;
    let y = rect.center().y;
    let x = px(&h, start);
    drag(
        &mut h,
        Pos2::new(x, y),
        Pos2::new(x - 15.0, y),
        Modifiers::NONE,
    );
    settle(&mut h);
    let after = h.state().state.ranges();
    assert_eq!(after.len(), before.len());
    assert!(
        after[1].start_s < start - 100.0,
        "start moved earlier: {} → {}",
        start,
        after[1].start_s
    );
    assert_eq!(after[1].end_s, before[1].end_s);
}

#[test]
fn a_spline_knot_is_dragged_and_the_figures_follow() {
    use driftlab::files::session::Coefficient;
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.state_mut().state.recipe_mut().k1_plus = driftlab::models::approx::ApproxSpec {
        kind: driftlab::models::approx::ApproxKind::Spline,
        knots: 5,
        extrapolate: false,
        ..Default::default()
    };
    settle(&mut h);
    let fitted = outcome(&h).calibration.k1_plus.clone();
    let before = p2p_corrected(&h);
    let p = h
        .state()
        .knot_screen_pos(Coefficient::K1Plus, 2)
        .expect("knot 2 drawn");
    drag(&mut h, p, p - egui::vec2(0.0, 30.0), Modifiers::NONE);
    settle(&mut h);
    let s = &h.state().state;
    let edited = s
        .shown
        .choices
        .recipe
        .k1_plus
        .values
        .as_ref()
        .expect("knot values set by hand");
    assert!(
        edited[2] > fitted.knots().1[2],
        "dragged up: {} → {}",
        fitted.knots().1[2],
        edited[2]
    );
    assert_eq!(edited[0], fitted.knots().1[0], "the other knots stay");
    let cal = &s.shown.fit.as_ref().unwrap().outcome.calibration;
    assert_eq!(cal.k1_plus.knots().1, &edited[..]);
    assert_ne!(p2p_corrected(&h), before);
    // "reset knots" goes back to the fitted curve.
    reset_knots(&h).click();
    settle(&mut h);
    assert!(!h.state().state.shown.choices.recipe.k1_plus.hand_knots());
    assert_eq!(p2p_corrected(&h), before);
}

/// The "reset knots" button of the coefficient whose knots are set by hand (the others are
/// greyed).
fn reset_knots<'h>(h: &'h Harness<'_, Workbench>) -> egui_kittest::Node<'h> {
    use egui_kittest::kittest::NodeT;
    h.get_all_by_label("reset knots")
        .find(|n| !n.accesskit_node().is_disabled())
        .expect("an enabled reset knots")
}

/// A spline K1+ with 5 knots, on a window of `size`.
fn spline_harness(size: egui::Vec2) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    wb.state.recipe_mut().k1_plus = driftlab::models::approx::ApproxSpec {
        kind: driftlab::models::approx::ApproxKind::Spline,
        knots: 5,
        extrapolate: false,
        ..Default::default()
    };
    let mut h = Harness::builder()
        .with_size(size)
        .build_ui_state(|ui, wb: &mut Workbench| wb.ui(ui), wb);
    settle(&mut h);
    h
}

/// A knot drag as a hand does it: the pointer moves every frame, the worker answers when it
/// can (no waiting between frames).
fn drag_knot_live(
    h: &mut Harness<'_, Workbench>,
    from: Pos2,
    dy: f32,
    mut each: impl FnMut(&mut Harness<'_, Workbench>),
) {
    h.event(Event::PointerMoved(from));
    h.run_ok();
    h.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    h.step();
    for k in 1..=12 {
        h.event(Event::PointerMoved(
            from + egui::vec2(0.0, dy * k as f32 / 12.0),
        ));
        h.step();
        each(h);
    }
    h.event(Event::PointerButton {
        pos: from + egui::vec2(0.0, dy),
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.step();
    settle(h);
}

#[test]
fn a_knot_drag_keeps_the_panels_and_the_plots_in_place() {
    use driftlab::files::session::Coefficient;
    for size in [egui::vec2(1600.0, 1000.0), egui::vec2(1280.0, 800.0)] {
        let mut h = spline_harness(size);
        let rects = |h: &Harness<'_, Workbench>| {
            let wb = h.state();
            let panels: Vec<egui::Rect> = ["controls", "coefficients", "central"]
                .iter()
                .map(|n| wb.panel_rect(n).expect("panel drawn"))
                .collect();
            let plots: Vec<egui::Rect> = [
                "time_omega",
                "time_temp",
                "time_tdot",
                "time_tddot",
                "result",
            ]
            .iter()
            .map(|n| wb.plot_rect(n).expect("plot drawn"))
            .collect();
            (panels, plots)
        };
        let (panels, plots) = rects(&h);
        let (controls, coeffs) = (panels[0], panels[1]);
        // Every central plot lies between the side panels, whole.
        for p in &plots {
            assert!(
                p.left() >= controls.right() - 0.5 && p.right() <= coeffs.left() + 0.5,
                "{size:?}: a plot {p:?} reaches under a side panel ({controls:?}, {coeffs:?})"
            );
        }
        let p = h
            .state()
            .knot_screen_pos(Coefficient::K1Plus, 2)
            .expect("knot 2 drawn");
        drag_knot_live(&mut h, p, -30.0, |_| {});
        assert!(
            h.state()
                .state
                .shown
                .choices
                .recipe
                .k1_plus
                .values
                .as_ref()
                .is_some()
        );
        let (panels2, plots2) = rects(&h);
        for (a, b) in panels.iter().zip(&panels2) {
            assert!(
                (a.width() - b.width()).abs() < 0.5,
                "{size:?}: a panel changed width during the knot drag: {a:?} → {b:?}"
            );
        }
        for (a, b) in plots.iter().zip(&plots2) {
            assert!(
                (a.width() - b.width()).abs() < 0.5 && (a.left() - b.left()).abs() < 0.5,
                "{size:?}: a plot moved or changed width: {a:?} → {b:?}"
            );
        }
        // "reset knots" goes back to the fitted knots; nothing moves either.
        reset_knots(&h).click();
        settle(&mut h);
        assert!(!h.state().state.shown.choices.recipe.k1_plus.hand_knots());
        let (panels3, plots3) = rects(&h);
        assert_eq!(panels3, panels2);
        assert_eq!(plots3, plots2);

        // Dragging the separator of the right panel resizes it; the time axis does not pan.
        let before = h.state().visible_time_s().unwrap();
        let edge = egui::pos2(coeffs.left() + 1.0, coeffs.center().y);
        drag(&mut h, edge, edge - egui::vec2(40.0, 0.0), Modifiers::NONE);
        settle(&mut h);
        let after = h.state().visible_time_s().unwrap();
        assert_eq!(
            before, after,
            "{size:?}: the separator drag panned the time plots"
        );
        let coeffs4 = h.state().panel_rect("coefficients").unwrap();
        assert!(
            coeffs4.width() > coeffs.width() + 20.0,
            "{coeffs:?} → {coeffs4:?}"
        );
        let (_, plots4) = rects(&h);
        for p in &plots4 {
            assert!(
                p.right() <= coeffs4.left() + 0.5,
                "{size:?}: {p:?} under {coeffs4:?}"
            );
        }
    }
}

#[test]
fn figures_after_a_knot_drag_are_those_of_a_fresh_calibration() {
    use driftlab::files::session::Coefficient;
    use driftlab::judge::metrics::Evaluation;
    let mut h = spline_harness(egui::vec2(1600.0, 1000.0));
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 3).unwrap();
    let fresh = |wb: &Workbench| {
        let req = wb.state.request().unwrap();
        driftlab::refit::Pipeline::new().run(&req).unwrap()
    };
    let mut provisional_seen = 0;
    drag_knot_live(&mut h, p, 40.0, |h| {
        // During the drag: exact, or marked as provisional. A frame with no new input first:
        // then what was drawn is what the state says (the knots of a frame's pointer move
        // change after that frame's figures are drawn).
        h.step();
        if h.state().state.fit_current() {
            let shown = h.state().state.shown.fit.as_ref().unwrap();
            let f = fresh(h.state());
            assert_eq!(
                shown.outcome.in_sample.evaluation, f.in_sample.evaluation,
                "figures shown as exact are a fresh calibration's"
            );
        } else {
            provisional_seen += 1;
            assert!(
                h.query_by_label("provisional").is_some(),
                "figures of other knots are marked provisional"
            );
        }
    });
    let wb = h.state();
    assert!(
        wb.state.fit_current(),
        "after release the fit answers the knots"
    );
    assert!(h.query_by_label("provisional").is_none());
    let edited = wb
        .state
        .shown
        .choices
        .recipe
        .k1_plus
        .values
        .as_ref()
        .expect("moved by hand");
    let shown = wb.state.shown.fit.as_ref().unwrap();
    assert_eq!(shown.outcome.calibration.k1_plus.knots().1, &edited[..]);
    // A fresh calibration with the same knots gives the same figures…
    let f = fresh(wb);
    assert_eq!(shown.outcome.in_sample.evaluation, f.in_sample.evaluation);
    // …and so does the engine's batch correction of that calibration.
    let log = &wb.state.shown.log.as_ref().unwrap().log;
    let c = shown
        .outcome
        .calibration
        .correct_with(log, &shown.outcome.prepared.deriv);
    assert_eq!(
        shown.outcome.in_sample.evaluation,
        Evaluation::of_correction(log, &c, &wb.state.merit())
    );
    eprintln!("{provisional_seen} of 12 drag frames showed provisional figures");
}

#[test]
fn the_detectors_suggestion_is_forgotten_once_the_plateaus_are_edited() {
    use egui_kittest::kittest::Queryable;
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    h.get_by_label_contains("The detector suggests 4 plateaus");
    // Delete one by hand: the status no longer speaks of the detector's four.
    h.get_all_by_label("×")
        .next()
        .expect("a delete button")
        .click();
    settle(&mut h);
    assert_eq!(h.state().state.ranges().len(), 3);
    assert!(h.query_by_label_contains("The detector suggests").is_none());
}

/// A dead-band set by hand reads as the automatic one does (`8.190e-7`, not `0.000000819`),
/// and a number typed in scientific form is taken.
#[test]
fn a_manual_deadband_reads_in_the_form_of_the_automatic_one() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.state_mut().state.recipe_mut().deadband_tddot = Some(8.19e-7);
    settle(&mut h);
    let shown = |text: &str| {
        h.query_all(egui_kittest::kittest::By::new().value(text))
            .count()
    };
    assert_eq!(
        shown("8.190e-7"),
        1,
        "the dead-band as the automatic one reads"
    );
    assert_eq!(shown("0.000000819"), 0);
    assert_eq!(
        h.state()
            .state
            .shown
            .fit
            .as_ref()
            .unwrap()
            .outcome
            .calibration
            .resolved
            .deadband_tddot,
        8.19e-7
    );
}

/// A plateau set by hand across a ramp is marked in the table (! before its number) and a
/// detected one is not.
#[test]
fn a_plateau_outside_the_detectors_limits_is_marked_in_the_table() {
    use driftlab::signal::plateau::PlateauRange;
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let marked = |h: &Harness<'_, Workbench>| {
        (1..=h.state().state.ranges().len())
            .filter(|k| h.query_by_label(&format!("!{k}")).is_some())
            .count()
    };
    assert_eq!(marked(&h), 0, "detected plateaus are within limits");
    let mut ranges = h.state().state.ranges();
    // On the 20 → 60 °C ramp of the sample log, between two detected plateaus.
    ranges.push(PlateauRange {
        start_s: 8000.0,
        end_s: 9000.0,
    });
    h.state_mut().state.set_ranges(ranges);
    settle(&mut h);
    let n = h.state().state.ranges().len();
    let k = h
        .state()
        .state
        .ranges()
        .iter()
        .position(|r| r.start_s == 8000.0)
        .unwrap();
    h.get_by_label(&format!("!{}", k + 1));
    assert_eq!(marked(&h), 1, "one of {n}");
}
