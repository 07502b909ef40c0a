//! The figures of merit as the window shows them: each "—" with its reason.

use driftlab::gui::Workbench;
use egui_kittest::kittest::Queryable;

use crate::common;
use common::gui::*;

/// A figure the engine could not compute is shown as "—" with its reason under the table:
/// windows longer than the log hold no whole window.
#[test]
fn every_dash_in_the_figures_says_why() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    assert!(h.query_by_label_contains("window figures: n/a").is_none());
    // 100 000 s windows over an 11-hour log.
    h.state_mut().state.merit_window_s = Some(100_000.0);
    settle(&mut h);
    let e = &outcome(&h).in_sample.evaluation;
    assert!(
        e.comparison.raw.win_rms_mean_dph.is_nan(),
        "no whole window"
    );
    assert!(
        h.query_by_label_contains(
            "window figures: n/a (no stretch of the log holds a whole window)"
        )
        .is_some(),
        "the reason is shown"
    );
}
