//! The plateau table tells a plateau's quality and a typed range that cannot be (issue 22,
//! item 7): a range ending before it starts is explained in the window in the engine's words
//! and the plateau keeps its range; a range reaching past the log is taken and told; a hand
//! plateau across a ramp is marked, with the engine's reason on hover.

use driftlab::gui::Workbench;
use driftlab::gui::action::{Action, Edit};
use driftlab::signal::plateau::PlateauRange;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};

use crate::common;
use common::gui::*;

/// The table's number field holding `value` (a start or an end, s).
fn field<'h>(h: &'h Harness<'_, Workbench>, value: f64) -> egui_kittest::Node<'h> {
    h.get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|n| n.accesskit_node().numeric_value() == Some(value))
        .unwrap_or_else(|| panic!("no field holds {value}"))
}

use eframe::egui;

#[test]
fn a_typed_end_before_the_start_is_explained_and_the_plateau_kept() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    let before = h.state().state.ranges();
    let first = before[0];
    // Plateau 1's end typed before its start.
    field(&h, first.end_s).set_value_accesskit(first.start_s - 500.0);
    settle(&mut h);
    assert_eq!(h.state().state.ranges(), before, "the bad range was taken");
    // Under the table (and in the status line), naming the plateau.
    let notes: Vec<String> = h
        .get_all_by_label_contains("the start must come before the end")
        .filter_map(|n| n.accesskit_node().label().or(n.accesskit_node().value()))
        .collect();
    assert!(
        notes.len() >= 2 && notes.iter().all(|l| l.contains("Plateau 1 not changed")),
        "{notes:?}"
    );

    // An end past the log's end is taken, and said with what it covers.
    let end_of_log = *h
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
    field(&h, first.end_s).set_value_accesskit(end_of_log + 5000.0);
    settle(&mut h);
    let after = h.state().state.ranges();
    assert!(
        after.iter().any(|r| r.end_s > end_of_log),
        "the range reaching past the log was not taken: {after:?}"
    );
    assert!(
        h.get_all_by_label_contains("reaches past the log").count() >= 1,
        "the range past the log is not told"
    );
}

#[test]
fn a_hand_plateau_across_a_ramp_is_marked_with_the_engines_reason() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    let mut ranges = h.state().state.ranges();
    // 8000..12000 s: T climbs from 20 toward 60 °C there (not a hold).
    ranges.push(PlateauRange {
        start_s: 8000.0,
        end_s: 12000.0,
    });
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, Action::Edit(Edit::Plateaus(ranges.clone())));
    settle(&mut h);
    let ranges = h.state().state.ranges();
    let k = ranges
        .iter()
        .position(|r| r.start_s == 8000.0)
        .expect("the hand plateau is in the table");
    // The steady ones are not marked; the ramp is ("!" before its number).
    for j in 0..ranges.len() {
        let marked = h.query_by_label(&format!("!{}", j + 1)).is_some();
        assert_eq!(marked, j == k, "plateau {}: marked {marked}", j + 1);
    }
    // Its reason, on hover, is the engine's.
    let stats = h
        .state()
        .state
        .shown
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .calibration
        .plateaus
        .iter()
        .find(|s| s.range == ranges[k])
        .copied()
        .unwrap();
    let why = driftlab::signal::plateau::outside_detector(&stats, &Default::default());
    assert!(!why.is_empty() && why[0].contains("°C/min"), "{why:?}");
    h.get_by_label(&format!("!{}", k + 1)).hover();
    h.run_ok();
    h.get_by_label_contains(&why[0]);
}
