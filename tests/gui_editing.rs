//! The workbench driven headless: plateaus edited by mouse and keyboard, a plateau edge and a
//! spline knot dragged, and the figures following.

use driftlab::gui::Workbench;
use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

mod common;
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
    };
    settle(&mut h);
    let fitted = h
        .state()
        .state
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .calibration
        .k1_plus
        .clone();
    let before = p2p_corrected(&h);
    let p = h
        .state()
        .knot_screen_pos(Coefficient::K1Plus, 2)
        .expect("knot 2 drawn");
    drag(&mut h, p, p - egui::vec2(0.0, 30.0), Modifiers::NONE);
    settle(&mut h);
    let s = &h.state().state;
    let edited = s
        .choices
        .knots
        .get(Coefficient::K1Plus)
        .expect("knot values set by hand");
    assert!(
        edited[2] > fitted.knots().1[2],
        "dragged up: {} → {}",
        fitted.knots().1[2],
        edited[2]
    );
    assert_eq!(edited[0], fitted.knots().1[0], "the other knots stay");
    let cal = &s.fit.as_ref().unwrap().outcome.calibration;
    assert_eq!(cal.k1_plus.knots().1, &edited[..]);
    assert_ne!(p2p_corrected(&h), before);
    // "reset knots" goes back to the fitted curve.
    h.get_by_label("reset knots").click();
    settle(&mut h);
    assert!(h.state().state.choices.knots.is_empty());
    assert_eq!(p2p_corrected(&h), before);
}
