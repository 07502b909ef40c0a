//! A freshly opened log is fitted with the K0 its plateaus support, so that no sample log opens
//! on a K0 warning: the papers' parabola where three set points or more were held, a line
//! where two were (the yan-steps runs, which warned before), said on the status line. A
//! session keeps its own K0, and a kind the engineer chose is never replaced.

use driftlab::files::session;
use driftlab::gui::jobs::LoadOptions;
use driftlab::gui::{Target, Workbench};
use driftlab::models::approx::ApproxKind;
use driftlab::models::recipe::Recipe;
use egui_kittest::kittest::Queryable;

use crate::common;
use common::gui::*;

fn k0_warnings(wb: &Workbench) -> Vec<String> {
    let fit = wb.state.shown.fit.as_ref().expect("calibrated");
    fit.outcome
        .warnings
        .iter()
        .filter(|w| w.starts_with("K0"))
        .cloned()
        .collect()
}

/// The set points of the fit's plateaus, counted here apart from the engine: sorted
/// temperatures, a new one after a gap of more than 1 °C.
fn set_points(wb: &Workbench) -> usize {
    let fit = wb.state.shown.fit.as_ref().expect("calibrated");
    let mut t: Vec<f64> = fit
        .outcome
        .calibration
        .plateaus
        .iter()
        .map(|p| p.temp_c)
        .collect();
    t.sort_by(f64::total_cmp);
    t.windows(2).filter(|w| w[1] - w[0] > 1.0).count() + usize::from(!t.is_empty())
}

fn open(wb: &mut Workbench, log: &str) {
    wb.start_load(sample(log), LoadOptions::default(), Target::Calibration);
    wb.wait_for_jobs();
    assert!(wb.state.fit_current(), "{log}: {:?}", wb.state.status);
}

#[test]
fn no_sample_log_opens_on_a_k0_warning() {
    for log in [
        "calibration.csv",
        "validation.csv",
        "yan-steps-low.csv",
        "yan-steps-mid.csv",
        "yan-steps-high.csv",
        "yan-full-range.csv",
        "laser-gyro.csv",
        "laser-gyro-2.csv",
        "imu3-calibration.csv",
    ] {
        let wb = Workbench::new_for_test(&sample(log));
        assert!(wb.state.fit_current(), "{log}");
        assert_eq!(k0_warnings(&wb), Vec::<String>::new(), "{log}");
        let (kind, said) = match set_points(&wb) {
            2 => (ApproxKind::Linear, true),
            n => {
                assert!(n >= 3, "{log}: {n} set points");
                (ApproxKind::Parabolic, false)
            }
        };
        assert_eq!(wb.state.recipe().k0.kind, kind, "{log}");
        // Every axis of a unit alike: they share the plateaus.
        for k in 0..wb.state.axis_count() {
            assert_eq!(
                wb.state.axis(k).unwrap().choices.recipe.k0.kind,
                kind,
                "{log} axis {k}"
            );
        }
        let (_, status) = wb.state.status.clone().unwrap();
        assert_eq!(status.contains("K0 linear"), said, "{log}: {status}");
        // Opening is no work to save, and the choice is no step to undo.
        assert!(!wb.state.dirty(), "{log}");
        assert!(!wb.state.shown.history.can_undo(), "{log}");
    }
}

#[test]
fn two_set_points_open_on_a_line_said_on_the_status_line() {
    let mut h = harness(Workbench::new_for_test(&sample("yan-steps-low.csv")));
    settle(&mut h);
    h.get_by_label_contains("K0 linear: the plateaus hold 2 temperatures (-45, -25 °C)");
    let fit = h.state().state.shown.fit.clone().unwrap();
    assert_eq!(fit.outcome.calibration.k0.kind(), ApproxKind::Linear);
    assert_eq!(fit.outcome.calibration.recipe.k0.kind, ApproxKind::Linear);
    // The K0 control shows it.
    let combo = h.get_by_label("K0 approximation");
    assert_eq!(combo.value().as_deref(), Some("linear"));

    // A log of three set points next: the workbench's own line gives way to the parabola.
    let wb = h.state_mut();
    open(wb, "yan-full-range.csv");
    assert_eq!(wb.state.recipe().k0, Recipe::default().k0);
    assert!(k0_warnings(wb).is_empty(), "{:?}", k0_warnings(wb));
    let (_, status) = wb.state.status.clone().unwrap();
    assert!(
        status.contains("K0 parabolic: the plateaus hold 3"),
        "{status}"
    );
}

#[test]
fn a_kind_the_engineer_chose_is_never_replaced() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    assert_eq!(h.state().state.recipe().k0.kind, ApproxKind::Parabolic);
    // The engineer picks the parabola over again: a choice, though the kind is the same
    // (linear first, then parabolic).
    for kind in ["linear", "parabolic"] {
        h.get_by_label("K0 approximation").click();
        h.run_ok();
        let options = h.get_all_by_label(kind).collect::<Vec<_>>();
        options.last().expect("the choice in the open list").click();
        settle(&mut h);
    }
    assert_eq!(h.state().state.recipe().k0.kind, ApproxKind::Parabolic);
    let wb = h.state_mut();
    open(wb, "yan-steps-mid.csv");
    assert_eq!(wb.state.recipe().k0.kind, ApproxKind::Parabolic);
    // What calibrate says of the papers' parabola through two set points, the window says.
    let w = k0_warnings(wb);
    assert!(
        w.len() == 1 && w[0].contains("at only 2 temperatures"),
        "{w:?}"
    );
}

#[test]
fn a_session_keeps_its_own_k0() {
    let dir = tempfile::tempdir().unwrap();
    // A session on a two-set-point log saved with the papers' parabola for K0.
    let mut wb = Workbench::new_for_test(&sample("yan-steps-high.csv"));
    assert_eq!(wb.state.recipe().k0.kind, ApproxKind::Linear);
    wb.state.recipe_mut().k0 = Recipe::default().k0;
    wb.wait_for_jobs();
    let path = dir.path().join("parabola.session.json");
    session::save(&path, &wb.state.session()).unwrap();

    // Opened in a workbench that has not been told anything about K0.
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, driftlab::gui::Action::OpenSessionPath(path));
    settle(&mut h);
    let s = &h.state().state;
    assert!(
        s.shown
            .log
            .as_ref()
            .unwrap()
            .path
            .ends_with("yan-steps-high.csv")
    );
    assert_eq!(s.recipe().k0, Recipe::default().k0);
    assert!(s.fit_current());
    assert_eq!(
        s.shown
            .fit
            .as_ref()
            .unwrap()
            .outcome
            .calibration
            .recipe
            .k0
            .kind,
        ApproxKind::Parabolic
    );
    assert!(!s.dirty());
}
