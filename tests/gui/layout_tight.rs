//! The Calibration page in the tight spots a new user found (issue 22's bar: at 1600×1000 and
//! 1280×720 everything readable and the tables whole; at 1024×640 usable, the side panels
//! scrolling, the drift plot never pushed off), measured in windows of the real sizes:
//!
//! - at 1024×640 with a unit, its validation log and a calibration opened to compare, the
//!   controls keep a scrolling area of their own (the opened strip was drawn over the Data
//!   section and left the controls some 20 points), the strip and the figures stay clear of
//!   it, and the log's name in the menu bar stays clear of the theme button;
//! - the coefficients panel scrolls with the wheel over its plots (the plots took the wheel),
//!   to K2's x-axis (cut at the panel's foot);
//! - at 1280×720 and 1600×1000 each coefficient plot keeps 130 points (K2± was 55), the
//!   plateau table's cells are as wide as their numbers (imu3's sample counts were cut to
//!   "176…"), and with a calibration opened every plateau row is in view.

use driftlab::gui::{Action, Workbench};
use eframe::egui::{self, Event};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
use crate::layout::{opened, window_rect};
use crate::open_calibration::calibrate;
use common::gui::*;

/// The coefficient plots' least height at 1600×1000 and 1280×720, points (axes included).
const COEFF_PLOT_H: f32 = 130.0;

/// Opens `cal` beside the fit to compare, settled.
fn open_calibration(h: &mut Harness<'_, Workbench>, cal: &Path) {
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, Action::OpenCalibrationPath(cal.to_path_buf()));
    settle(h);
    for _ in 0..3 {
        h.run_ok();
    }
    assert!(h.state().state.opened.is_some(), "the calibration is open");
}

fn panel(h: &Harness<'_, Workbench>, name: &str, what: &str) -> egui::Rect {
    h.state()
        .panel_rect(name)
        .unwrap_or_else(|| panic!("{what}: no {name} drawn"))
}

/// The wheel turned over `at` (down: the content moves up), and the frames that scroll.
fn wheel_down(h: &mut Harness<'_, Workbench>, at: egui::Pos2, points: f32) {
    h.event(Event::PointerMoved(at));
    h.run_ok();
    h.event(Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, -points),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Wheel,
        modifiers: egui::Modifiers::NONE,
    });
    for _ in 0..30 {
        h.run_ok();
    }
}

#[test]
fn at_1024x640_the_controls_keep_room_and_the_menu_bar_its_theme_button() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("calibration.json");
    calibrate(&sample("calibration.csv"), &cal, &[]);
    for (log, val, size) in [
        (
            "calibration.csv",
            "validation.csv",
            egui::vec2(1280.0, 720.0),
        ),
        (
            "calibration.csv",
            "validation.csv",
            egui::vec2(1024.0, 640.0),
        ),
        (
            "imu3-calibration.csv",
            "imu3-validation.csv",
            egui::vec2(1280.0, 720.0),
        ),
    ] {
        let what = format!("{log} with a calibration opened at {}×{}", size.x, size.y);
        let mut h = opened(log, val, size);
        open_calibration(&mut h, &cal);
        let controls = panel(&h, "controls_scroll", &what);
        let (opened_r, figures) = (panel(&h, "opened", &what), panel(&h, "figures", &what));
        for (foot, r) in [("opened", opened_r), ("figures", figures)] {
            assert!(
                !r.intersects(controls.shrink(1.0)),
                "{what}: the {foot} strip {r:?} is drawn over the controls {controls:?}"
            );
        }
        assert!(
            !opened_r.intersects(figures.shrink(1.0)),
            "{what}: the opened strip {opened_r:?} is drawn over the figures {figures:?}"
        );
    }
    let size = egui::vec2(1024.0, 640.0);
    let what = "imu3 with a calibration opened at 1024×640";
    let mut h = opened("imu3-calibration.csv", "imu3-validation.csv", size);
    open_calibration(&mut h, &cal);
    let controls = panel(&h, "controls_scroll", what);
    assert!(
        controls.height() >= 120.0,
        "{what}: the controls' scrolling area is {} points tall",
        controls.height()
    );
    for foot in ["opened", "figures"] {
        let r = panel(&h, foot, what);
        assert!(
            !r.intersects(controls.shrink(1.0)),
            "{what}: the {foot} strip {r:?} is drawn over the controls {controls:?}"
        );
    }
    // The Data section's button is in the controls' area, not under the strip.
    let mapping = h.get_by_label("Column mapping…").rect();
    assert!(
        controls.contains_rect(mapping),
        "{what}: Column mapping… {mapping:?} outside the controls {controls:?}"
    );
    // The menu bar: the log's name clear of the theme button, which is in the window.
    let theme = h.get_by_label("Light theme").rect();
    assert!(window_rect(size).contains_rect(theme), "{what}: {theme:?}");
    for name in h
        .query_all_by_label_contains("imu3-calibration.csv")
        .map(|n| n.rect())
        .filter(|r| r.center().y < theme.bottom() + 4.0)
    {
        assert!(
            !name.intersects(theme),
            "{what}: the log's name {name:?} is drawn over the theme button {theme:?}"
        );
    }
    let drift = h.state().plot_rect("result").unwrap();
    assert!(window_rect(size).contains_rect(drift), "{what}: {drift:?}");
}

#[test]
fn the_coefficients_scroll_with_the_wheel_to_k2s_axis() {
    for size in [egui::vec2(1024.0, 640.0), egui::vec2(1280.0, 720.0)] {
        let what = format!("{}×{}", size.x, size.y);
        let mut h = opened("imu3-calibration.csv", "imu3-validation.csv", size);
        let coeffs = panel(&h, "coefficients", &what);
        let k1 = h.state().plot_rect("k1").unwrap();
        let k2 = h.state().plot_rect("k2").unwrap();
        eprintln!("{what}: K2 {k2:?} in the panel {coeffs:?} before the wheel");
        let bounds = h
            .state()
            .coeff_plot_pos(driftlab::files::session::Coefficient::K1Plus, 0.0, 40.0)
            .unwrap()
            - k1.min;
        wheel_down(&mut h, k1.center(), 2000.0);
        let k1_after = h.state().plot_rect("k1").unwrap();
        let k2_after = h.state().plot_rect("k2").unwrap();
        assert!(
            k1_after.top() < k1.top() - 20.0,
            "{what}: the wheel over K1 did not scroll the panel ({k1:?} → {k1_after:?})"
        );
        let same = h
            .state()
            .coeff_plot_pos(driftlab::files::session::Coefficient::K1Plus, 0.0, 40.0)
            .unwrap()
            - k1_after.min;
        assert!(
            (same - bounds).length() < 0.5,
            "{what}: the wheel panned the K1 plot as well"
        );
        assert!(
            k2_after.bottom() <= coeffs.bottom() + 0.5,
            "{what}: K2's axis {k2_after:?} still below the panel {coeffs:?}"
        );
    }
}

#[test]
fn coefficient_plots_and_the_plateau_table_are_readable_at_1280x720_and_1600x1000() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("calibration.json");
    calibrate(&sample("calibration.csv"), &cal, &[]);
    for (log, val) in [
        ("calibration.csv", "validation.csv"),
        ("imu3-calibration.csv", "imu3-validation.csv"),
        ("laser-gyro.csv", "laser-gyro-2.csv"),
    ] {
        for size in [egui::vec2(1600.0, 1000.0), egui::vec2(1280.0, 720.0)] {
            let what = format!("{log} at {}×{}", size.x, size.y);
            let mut h = opened(log, val, size);
            for plot in ["k0", "k1", "k2"] {
                let r = h.state().plot_rect(plot).unwrap();
                assert!(
                    r.height() >= COEFF_PLOT_H - 0.5,
                    "{what}: the {plot} plot is {} points tall",
                    r.height()
                );
            }
            assert_cells_whole(&h, &what);
            if log == "calibration.csv" {
                // With a calibration opened beside the fit, every plateau row is in view.
                open_calibration(&mut h, &cal);
                let controls = panel(&h, "controls_scroll", &what);
                for s in h.state().state.plateau_stats() {
                    let cell = h
                        .query_all_by_label(&s.samples.to_string())
                        .map(|n| n.rect())
                        .find(|r| r.left() > controls.center().x && r.right() < controls.right())
                        .unwrap_or_else(|| panic!("{what}: no row of {}", s.samples));
                    assert!(
                        controls.contains_rect(cell),
                        "{what}: the row of {} samples {cell:?} is out of view {controls:?}",
                        s.samples
                    );
                }
            }
        }
    }
}

/// Every number cell of the plateau table is as wide as its text (none cut to "…").
fn assert_cells_whole(h: &Harness<'_, Workbench>, what: &str) {
    let controls = h.state().panel_rect("controls").unwrap();
    let size = egui::TextStyle::Body.resolve(&h.ctx.global_style()).size;
    for s in h.state().state.plateau_stats() {
        let text = s.samples.to_string();
        let need = driftlab::gui::plot_items::label_width(&h.ctx, &text, size);
        let cell = h
            .query_all_by_label(&text)
            .map(|n| n.rect())
            .find(|r| controls.contains_rect(*r))
            .unwrap_or_else(|| panic!("{what}: no cell of {text}"));
        assert!(
            cell.width() + 0.5 >= need,
            "{what}: the cell of {text} is {} points wide, its text {need}",
            cell.width()
        );
    }
}
