//! A knot dragged up or down and held still stays where the pointer is: the plot's bounds are
//! frozen while the knot is dragged (the plot does not rescale to the dragged curve, which
//! made the same pointer position mean a larger value each frame: a knot running from 60 to
//! 1000 with the mouse still), on every knot plot; after the release they may refit.

use driftlab::files::session::Coefficient;
use driftlab::gui::Workbench;
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use eframe::egui::{self, Event};
use egui_kittest::Harness;

use crate::common;
use common::gui::*;

/// The workbench on the sample log with every coefficient a curve with knots, settled.
fn every_curve_with_knots() -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let r = wb.state.recipe_mut();
    let spline = ApproxSpec {
        knots: 5,
        ..ApproxSpec::of(ApproxKind::Spline)
    };
    r.k1_plus = spline.clone();
    r.k1_minus = spline.clone();
    r.k2_plus = spline.clone();
    r.k2_minus = spline;
    r.k0 = ApproxSpec {
        knots: 3,
        ..ApproxSpec::of(ApproxKind::Pwl)
    };
    let mut h = harness(wb);
    settle(&mut h);
    h
}

/// The value of knot `j` of `c` in the recipe, once set by hand.
fn hand_value(h: &Harness<'_, Workbench>, c: Coefficient, j: usize) -> Option<f64> {
    c.spec(h.state().state.recipe())
        .values
        .as_ref()
        .map(|v| v[j])
}

#[test]
fn a_knot_held_still_while_dragged_keeps_its_value_on_every_plot() {
    let mut h = every_curve_with_knots();
    for (c, j) in [
        (Coefficient::K1Plus, 3),
        (Coefficient::K1Minus, 2),
        (Coefficient::K2Plus, 3),
        (Coefficient::K2Minus, 1),
        (Coefficient::K0, 1),
    ] {
        let from = h
            .state()
            .knot_screen_pos(c, j)
            .unwrap_or_else(|| panic!("{c:?}: knot {j} drawn"));
        let to = from - egui::vec2(0.0, 14.0);
        h.event(Event::PointerMoved(from));
        h.run_ok();
        primary_button(&mut h, from, true);
        for k in 1..=4 {
            h.event(Event::PointerMoved(from + (to - from) * (k as f32 / 4.0)));
            h.step();
        }
        let first = hand_value(&h, c, j).unwrap_or_else(|| panic!("{c:?}: a value set"));
        // Held still: frames go by, the refits answer, the pointer does not move.
        for _ in 0..12 {
            h.state_mut().wait_for_jobs();
            h.step();
        }
        let held = hand_value(&h, c, j).unwrap();
        assert_eq!(
            held, first,
            "{c:?}: knot {j} ran away with the mouse still ({first} → {held})"
        );
        let at = h.state().knot_screen_pos(c, j).unwrap();
        assert!(
            (at.y - to.y).abs() < 1.0,
            "{c:?}: the knot is drawn under the pointer ({} vs {})",
            at.y,
            to.y
        );
        primary_button(&mut h, to, false);
        settle(&mut h);
        assert_eq!(
            hand_value(&h, c, j),
            Some(held),
            "{c:?}: the release keeps the value the knot had"
        );
    }
}
