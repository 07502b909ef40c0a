//! The small things around knots and the status line: a Ctrl+click on a knot says why it adds
//! none (it did nothing, unsaid); a knot-table or plateau-table field committed without an
//! edit leaves the number as it was (it wrote back its display: −0.0083491 → −0.0083); a refusal
//! leaves the status line once a later edit is taken; and the time plots' hover text goes
//! with the pointer when it leaves the window.

use driftlab::files::session::Coefficient;
use driftlab::gui::Workbench;
use driftlab::models::approx::{ApproxKind, ApproxSpec, KnotEdit};
use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};

use crate::common;
use common::gui::*;

/// The workbench on the sample log with K1+ a spline of 5 knots, settled.
fn spline_k1() -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    wb.state.recipe_mut().k1_plus = ApproxSpec {
        knots: 5,
        ..ApproxSpec::of(ApproxKind::Spline)
    };
    let mut h = harness(wb);
    settle(&mut h);
    h
}

fn k1p(h: &Harness<'_, Workbench>) -> ApproxSpec {
    h.state().state.recipe().k1_plus.clone()
}

fn status(h: &Harness<'_, Workbench>) -> Option<String> {
    h.state().state.status.clone().map(|(_, m)| m)
}

/// A click of the primary button at `at` with Ctrl held.
fn ctrl_click(h: &mut Harness<'_, Workbench>, at: Pos2) {
    h.event(Event::ModifiersChanged(Modifiers::COMMAND));
    h.event(Event::PointerMoved(at));
    h.run_ok();
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos: at,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::COMMAND,
        });
        h.step();
    }
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_ok();
}

#[test]
fn ctrl_click_on_a_knot_says_why_no_knot_is_added() {
    let mut h = spline_k1();
    let before = k1p(&h);
    let p = h.state().knot_screen_pos(Coefficient::K1Plus, 2).unwrap();
    ctrl_click(&mut h, p + egui::vec2(3.0, 2.0));
    settle(&mut h);
    assert_eq!(k1p(&h), before, "no knot added on a knot");
    let said = status(&h).unwrap_or_default();
    assert!(
        said.contains("No knot added to K1+") && said.contains("knot 3"),
        "the status line says why: {said:?}"
    );
}

#[test]
fn a_field_committed_unedited_keeps_its_number() {
    let mut h = spline_k1();
    h.get_by_label("knots…").click();
    settle(&mut h);
    let (x, y) = {
        let (x, y) = Coefficient::K1Plus.approx(&outcome(&h).calibration).knots();
        (x.to_vec(), y.to_vec())
    };
    for v in [x[1], y[2]] {
        let field = h
            .get_all_by_role(egui::accesskit::Role::SpinButton)
            .find(|n| n.accesskit_node().numeric_value() == Some(v))
            .unwrap_or_else(|| panic!("no field holds {v}"));
        field.click();
        h.run_ok();
        h.key_press(Key::Enter);
        settle(&mut h);
        let spec = k1p(&h);
        assert_eq!(
            (spec.at, spec.values),
            (None, None),
            "committing the field of {v} unedited changed nothing"
        );
    }
    // The plateau table's times alike (shown with one decimal).
    let mut ranges = h.state().state.ranges();
    ranges[0].start_s += 0.637;
    h.state_mut().state.set_ranges(ranges.clone());
    settle(&mut h);
    let field = h
        .get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|n| n.accesskit_node().numeric_value() == Some(ranges[0].start_s))
        .expect("the plateau's start field");
    field.click();
    h.run_ok();
    h.key_press(Key::Enter);
    settle(&mut h);
    assert_eq!(
        h.state().state.ranges(),
        ranges,
        "the start kept to the bit"
    );
}

#[test]
fn a_refusal_leaves_the_status_line_once_an_edit_is_taken() {
    let mut h = spline_k1();
    let a = outcome(&h).calibration.k1_plus.clone();
    let (x, _) = a.knots();
    let (x, x3) = (x.to_vec(), x[3]);
    // Typed past its neighbour in the knot table: refused, said.
    h.get_by_label("knots…").click();
    settle(&mut h);
    h.get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|n| n.accesskit_node().numeric_value() == Some(x[1]))
        .unwrap()
        .set_value_accesskit(x3);
    settle(&mut h);
    let said = status(&h).unwrap_or_default();
    assert!(said.contains("K1+ not changed"), "{said:?}");
    // A knot moved where it may go: taken, and the refusal is no longer on the status line.
    let spec = k1p(&h)
        .edit_knot(
            &a,
            KnotEdit::Place {
                index: 1,
                x: 0.5 * (x[1] + x[2]),
            },
        )
        .unwrap();
    h.get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|n| n.accesskit_node().numeric_value() == Some(x[1]))
        .unwrap()
        .set_value_accesskit(spec.at.as_ref().unwrap()[1]);
    settle(&mut h);
    assert_eq!(k1p(&h).at, spec.at, "taken");
    assert!(
        !status(&h).unwrap_or_default().contains("not changed"),
        "the refusal stays after the edit taken: {:?}",
        status(&h)
    );
}

#[test]
fn the_hover_text_goes_when_the_pointer_leaves_the_window() {
    let mut h = spline_k1();
    let r = h.state().plot_rect("time_temp").unwrap();
    h.event(Event::PointerMoved(r.center()));
    for _ in 0..3 {
        h.run_ok();
    }
    assert!(
        h.query_all_by_label_contains("Ω raw =").next().is_some(),
        "hovering a time plot shows its values"
    );
    h.event(Event::PointerGone);
    for _ in 0..3 {
        h.run_ok();
    }
    assert!(
        h.query_all_by_label_contains("Ω raw =").next().is_none(),
        "the hover text stays after the pointer left"
    );
}
