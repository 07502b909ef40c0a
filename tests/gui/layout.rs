//! The Calibration page's layout measured, not eyeballed (issue 22, item 5, and "a layout
//! that holds"): at 1600×1000 and 1280×720 every time plot and the drift plot keep at least
//! 120 points of height and the plateau table shows all its columns; at 1024×640 the drift
//! plot lies whole inside the window; at every size the plots linked in time (the four time
//! plots and the drift plot) share one y-axis width, so one time sits at one x in each, their
//! y-axis labels lie on one line along their plots, and the drift plot's header and legend do
//! not overlap. Checked on a log of one axis, on a three-axis unit and on a laser gyro's log,
//! each with its validation log open, as `driftlab gui LOG --validation VAL` starts.

use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::plot_items::{axis_label_size, label_width};
use driftlab::gui::settings::Settings;
use driftlab::gui::{Action, Page, Workbench};
use eframe::egui;
use eframe::egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use crate::common;
use common::gui::*;

const TIME_PLOTS: [&str; 4] = ["time_omega", "time_temp", "time_tdot", "time_tddot"];

/// The workbench on `log` with `validation` held out, in a window of `size`, settled.
pub(crate) fn opened(log: &str, validation: &str, size: egui::Vec2) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    // (read at once, as `--screenshot` reads it: the laser gyro's four temperatures would
    // otherwise ask for a look in the import view first)
    wb.open_log(sample(log), Default::default(), false);
    wb.open_validation_after(sample(validation), Default::default());
    let h = drawn(wb, size);
    assert!(
        h.state().state.shown.validation.is_some(),
        "{log}: the validation log {validation} is not open: {:?}",
        h.state().state.status
    );
    h
}

/// `wb` in a window of `size`, its work done and drawn. egui_kittest draws the app 8 points
/// inside its window: the window is that much larger, so that the workbench has the whole
/// area of a real window of `size`.
pub(crate) fn drawn(wb: Workbench, size: egui::Vec2) -> Harness<'static, Workbench> {
    let mut h = Harness::builder()
        .with_size(size + egui::vec2(16.0, 16.0))
        .build_ui_state(|ui, wb: &mut Workbench| wb.ui(ui), wb);
    settle(&mut h);
    // The shared y-axis width settles within a frame or two of the widest tick label.
    for _ in 0..3 {
        h.run_ok();
    }
    h
}

/// Where the workbench's window of `size` lies in the harness (see [`opened`]).
pub(crate) fn window_rect(size: egui::Vec2) -> egui::Rect {
    egui::Rect::from_min_size(egui::pos2(8.0, 8.0), size)
}

/// The frames' left and right edges of every linked plot agree to half a point.
fn assert_linked_plots_aligned(h: &Harness<'_, Workbench>, what: &str) {
    let wb = h.state();
    let frames: Vec<(&str, egui::Rect)> = TIME_PLOTS
        .iter()
        .chain(&["result"])
        .map(|n| {
            (
                *n,
                wb.plot_frame(n)
                    .unwrap_or_else(|| panic!("{what}: {n} drawn")),
            )
        })
        .collect();
    let rects: Vec<egui::Rect> = TIME_PLOTS
        .iter()
        .chain(&["result"])
        .map(|n| wb.plot_rect(n).unwrap())
        .collect();
    let (first, f0) = frames[0];
    for ((name, f), r) in frames.iter().zip(&rects) {
        let axis_w = f.left() - r.left();
        let axis_w0 = f0.left() - rects[0].left();
        assert!(
            (axis_w - axis_w0).abs() <= 0.5,
            "{what}: the y-axis of {name} is {axis_w} wide, that of {first} {axis_w0}"
        );
        assert!(
            (f.left() - f0.left()).abs() <= 0.5 && (f.right() - f0.right()).abs() <= 0.5,
            "{what}: {name}'s frame {f:?} is not under {first}'s {f0:?}: one time would sit at \
             two x"
        );
    }
}

fn heights(h: &Harness<'_, Workbench>) -> Vec<(&'static str, f32)> {
    TIME_PLOTS
        .iter()
        .chain(&["result"])
        .map(|n| (*n, h.state().plot_rect(n).unwrap().height()))
        .collect()
}

/// The drift plot's legend: its entries (egui_plot makes each a check box) inside the plot,
/// grown by the legend frame's margins (8 × 4 points).
fn drift_legend(h: &Harness<'_, Workbench>, what: &str) -> egui::Rect {
    let drift = h.state().plot_rect("result").unwrap();
    ["raw", "corrected"]
        .into_iter()
        .flat_map(|l| {
            h.query_all_by_role_and_label(Role::CheckBox, l)
                .map(|n| n.rect())
                .collect::<Vec<_>>()
        })
        .filter(|r| drift.contains_rect(*r))
        .reduce(|a, b| a.union(b))
        .unwrap_or_else(|| panic!("{what}: no legend in the drift plot {drift:?}"))
        .expand2(egui::vec2(8.0, 4.0))
}

/// The drift plot's header (which log, PNG) is drawn clear of its legend.
fn assert_header_clear_of_legend(h: &Harness<'_, Workbench>, what: &str) {
    let header = h
        .state()
        .plot_rect("result.header")
        .unwrap_or_else(|| panic!("{what}: the drift plot's header not drawn"));
    let legend = drift_legend(h, what);
    assert!(
        !header.intersects(legend),
        "{what}: the drift plot's header {header:?} is drawn over its legend {legend:?}"
    );
}

/// Each time plot's y-axis label lies along its plot on one line, at a readable size.
fn assert_axis_labels_fit(h: &Harness<'_, Workbench>, what: &str) {
    // The height each label is fitted to: a plot's own (the last one's less its time axis).
    let each = TIME_PLOTS[..3]
        .iter()
        .map(|n| h.state().plot_rect(n).unwrap().height())
        .fold(f32::INFINITY, f32::min);
    for (_, label) in driftlab::gui::view_time::TIME_PLOTS {
        assert!(!label.contains('\n'), "{what}: {label:?} on two lines");
        let size = axis_label_size(&h.ctx, label, each);
        let long = label_width(&h.ctx, label, size);
        assert!(
            long <= each,
            "{what}: the y-axis label {label:?} is {long} points long at {size} pt, its plot \
             {each} tall"
        );
    }
}

/// Every column of the plateau table, to its last (the samples, "n"), lies inside the
/// controls panel's content (the panel less its 8-point margins): none is scrolled to. (A
/// sample count is looked for in the panel's right half: the same number may be written
/// elsewhere.)
fn assert_plateau_table_whole(h: &Harness<'_, Workbench>, what: &str) {
    let panel = h.state().panel_rect("controls").unwrap();
    let content = panel.shrink2(egui::vec2(8.0, 0.0));
    // The header, and each plateau's sample count.
    let mut names = vec!["n".to_string()];
    names.extend(
        h.state()
            .state
            .plateau_stats()
            .iter()
            .map(|s| s.samples.to_string()),
    );
    let last: Vec<egui::Rect> = names
        .iter()
        .flat_map(|l| {
            h.query_all_by_label(l)
                .map(|n| n.rect())
                .collect::<Vec<_>>()
        })
        .filter(|r| r.left() > panel.center().x && r.left() < panel.right())
        .collect();
    assert!(!last.is_empty(), "{what}: no plateau table");
    for r in last {
        assert!(
            content.contains_rect(r),
            "{what}: the plateau table's last column {r:?} is outside its panel {content:?}"
        );
    }
}

#[test]
fn plots_keep_120_points_at_1600x1000_and_1280x720_and_the_drift_plot_stays_in_a_1024x640_window() {
    for (log, val) in [
        ("calibration.csv", "validation.csv"),
        ("imu3-calibration.csv", "imu3-validation.csv"),
        ("laser-gyro.csv", "laser-gyro-2.csv"),
    ] {
        for size in [egui::vec2(1600.0, 1000.0), egui::vec2(1280.0, 720.0)] {
            let h = opened(log, val, size);
            let what = format!("{log} at {}×{}", size.x, size.y);
            let hs = heights(&h);
            eprintln!("{what}: {hs:?}");
            for (name, height) in &hs {
                assert!(
                    *height >= 120.0,
                    "{what}: {name} is {height} points tall: {hs:?}"
                );
            }
            let window = window_rect(size);
            let drift = h.state().plot_rect("result").unwrap();
            assert!(window.contains_rect(drift), "{what}: {drift:?}");
            assert_linked_plots_aligned(&h, &what);
            assert_header_clear_of_legend(&h, &what);
            assert_axis_labels_fit(&h, &what);
            assert_plateau_table_whole(&h, &what);
        }

        let size = egui::vec2(1024.0, 640.0);
        let h = opened(log, val, size);
        let what = format!("{log} at 1024×640");
        eprintln!("{what}: {:?}", heights(&h));
        let window = window_rect(size);
        let drift = h.state().plot_rect("result").unwrap();
        assert!(
            window.contains_rect(drift) && drift.height() >= 100.0,
            "{what}: the drift plot {drift:?} is not whole in the window {window:?}"
        );
        for n in TIME_PLOTS {
            let r = h.state().plot_rect(n).unwrap();
            assert!(window.contains_rect(r), "{what}: {n} {r:?} cut");
        }
        assert_linked_plots_aligned(&h, &what);
        assert_header_clear_of_legend(&h, &what);
        assert_axis_labels_fit(&h, &what);
    }
}

/// The Models page's Compare button stays in the window at every size (its panel's foot).
#[test]
fn compare_is_in_the_window_on_the_models_page_at_every_size() {
    for size in [
        egui::vec2(1600.0, 1000.0),
        egui::vec2(1280.0, 720.0),
        egui::vec2(1024.0, 640.0),
    ] {
        let mut h = opened("calibration.csv", "validation.csv", size);
        let ctx = h.ctx.clone();
        h.state_mut().act(&ctx, Action::ShowPage(Page::Models));
        h.run_ok();
        h.run_ok();
        let window = window_rect(size);
        let compare = h.get_by_label("Compare").rect();
        assert!(
            window.contains_rect(compare),
            "at {}×{}: Compare {compare:?} is not in the window",
            size.x,
            size.y
        );
    }
}

/// At 1280×720 the Models page's figures table keeps its last column ("outside") clear of the
/// detail panel: the side panels start narrower in a narrower window (it scrolled sideways).
#[test]
fn the_models_figures_table_is_whole_at_1280x720() {
    let mut h = opened(
        "calibration.csv",
        "validation.csv",
        egui::vec2(1280.0, 720.0),
    );
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, Action::ShowPage(Page::Models));
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Compare").click();
    h.run_ok();
    settle(&mut h);
    assert!(h.state().state.shown.models.is_some(), "compared");
    h.run_ok();
    let last = h.get_by_label("outside").rect();
    let detail = h.get_by_label("Export model…").rect();
    assert!(
        last.max.x <= detail.min.x,
        "the table's last column {last:?} runs under the detail panel (its button {detail:?})"
    );
}

/// A campaign (its run strip in a short window at the head of the controls) keeps the same
/// room: every time plot and the drift plot 120 points tall at 1280×720, the drift plot whole.
#[test]
fn a_campaign_keeps_the_plots_at_1280x720() {
    let size = egui::vec2(1280.0, 720.0);
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    let options = driftlab::gui::jobs::LoadOptions {
        more_runs: vec![sample("yan-full-range.csv")],
        ..Default::default()
    };
    wb.open_log(sample("calibration.csv"), options, false);
    wb.open_validation_after(sample("validation.csv"), Default::default());
    let h = drawn(wb, size);
    let s = &h.state().state;
    assert_eq!(
        s.shown.log.as_ref().map(|l| l.log.runs().len()),
        Some(2),
        "{:?}",
        s.status
    );
    assert!(s.shown.validation.is_some(), "{:?}", s.status);
    let hs = heights(&h);
    for (name, height) in &hs {
        assert!(*height >= 120.0, "{name} is {height} points tall: {hs:?}");
    }
    let drift = h.state().plot_rect("result").unwrap();
    assert!(window_rect(size).contains_rect(drift), "{drift:?}");
    assert_linked_plots_aligned(&h, "a campaign at 1280×720");
}

/// With no validation log open, the drift plot's header stays one row and the plots keep
/// their 120 points at 1280×720 (its "Open validation log…" stands where the choice of the
/// validation log would be).
#[test]
fn without_a_validation_log_the_plots_keep_120_points_at_1280x720() {
    let size = egui::vec2(1280.0, 720.0);
    for log in ["calibration.csv", "imu3-calibration.csv"] {
        let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
        wb.open_log(sample(log), Default::default(), false);
        let h = drawn(wb, size);
        assert!(h.state().state.shown.validation.is_none());
        let hs = heights(&h);
        for (name, height) in &hs {
            assert!(
                *height >= 120.0,
                "{log}: {name} is {height} points tall: {hs:?}"
            );
        }
    }
}
