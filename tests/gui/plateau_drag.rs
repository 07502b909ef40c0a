//! A plateau edge dragged: while the button is held, the plateaus and K0 follow the edge
//! (the engine's preview) and nothing is refitted; on release every axis is refitted, and the
//! preview was the refit's K0 and plateaus to the bit.

use driftlab::gui::Workbench;
use eframe::egui::{Event, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::time::{Duration, Instant};

use crate::common;
use common::gui::*;

/// Frames until `done` holds (the worker answers between them), at most 20 s.
fn frames_until(h: &mut Harness<'_, Workbench>, done: impl Fn(&Workbench) -> bool) {
    let t = Instant::now();
    while !done(h.state()) {
        assert!(
            t.elapsed() < Duration::from_secs(20),
            "the worker never answered"
        );
        std::thread::sleep(Duration::from_millis(5));
        h.step();
    }
}

fn generation(wb: &Workbench) -> u64 {
    wb.state.shown.fit.as_ref().map_or(0, |f| f.generation)
}

#[test]
fn a_dragged_edge_previews_k0_and_the_release_refits_to_the_same() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let before = h.state().state.ranges();
    let fitted_k0 = outcome(&h).calibration.k0.clone();
    let fitted_at = generation(h.state());
    let rect = h.state().plot_rect("time_temp").unwrap();
    let from = Pos2::new(
        h.state().time_plot_x(before[1].start_s).unwrap(),
        rect.center().y,
    );
    let to = from - eframe::egui::vec2(25.0, 0.0);

    h.event(Event::PointerMoved(from));
    h.run_ok();
    primary_button(&mut h, from, true);
    for k in 1..=5 {
        h.event(Event::PointerMoved(from + (to - from) * (k as f32 / 5.0)));
        h.step();
    }
    // Held: the preview arrives, and the fit shown is still the one before the drag.
    frames_until(&mut h, |wb| {
        wb.state
            .shown
            .preview
            .as_ref()
            .is_some_and(|p| p.preview.ranges == wb.state.ranges())
    });
    let held = h.state().state.ranges();
    assert!(
        held[1].start_s < before[1].start_s - 100.0,
        "the edge moved: {held:?}"
    );
    let preview = h
        .state()
        .state
        .shown
        .preview
        .clone()
        .unwrap()
        .preview
        .clone();
    assert_eq!(preview.ranges, held);
    assert_eq!(
        generation(h.state()),
        fitted_at,
        "nothing refitted while the edge is held"
    );
    assert_ne!(preview.k0, fitted_k0, "K0 follows the edge");
    // The moved plateau's statistics are of its new range.
    let moved = preview
        .plateaus
        .iter()
        .find(|p| p.range == held[1])
        .expect("the dragged plateau's statistics");
    assert!(moved.samples > 0);
    assert!(
        h.query_by_label_contains("K1, K2 and the drift follow its release")
            .is_some(),
        "the K0 panel says what is previewed"
    );
    assert!(
        h.query_by_label_contains("Moving a plateau edge: its plateaus and K0 follow it")
            .is_some(),
        "the status line says the figures wait for the release (no refit runs)"
    );

    primary_button(&mut h, to, false);
    frames_until(&mut h, |wb| {
        wb.state.shown.preview.is_none() && generation(wb) > fitted_at
    });
    settle(&mut h);
    let refit = &outcome(&h).calibration;
    assert_eq!(refit.k0, preview.k0, "the release's K0 is the preview's");
    assert_eq!(refit.plateaus, preview.plateaus);
    assert_eq!(h.state().state.ranges(), held);
}
