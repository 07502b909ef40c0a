//! The Calibration page's layout measured, not eyeballed (issue 22, item 5): at 1280×720 each
//! time plot keeps at least 120 points of height; at 1024×640 the drift plot lies whole inside
//! the window; at every size the plots linked in time (the four time plots and the drift plot)
//! share one y-axis width, so one time sits at one x in each. Checked on a log of one axis
//! and on a three-axis unit, each with its validation log open, as
//! `driftlab gui LOG --validation VAL` starts.

use driftlab::gui::Workbench;
use driftlab::gui::dialogs::ScriptedDialogs;
use driftlab::gui::settings::Settings;
use eframe::egui;
use egui_kittest::Harness;

use crate::common;
use common::gui::*;

const TIME_PLOTS: [&str; 4] = ["time_omega", "time_temp", "time_tdot", "time_tddot"];

/// The workbench on `log` with `validation` held out, in a window of `size`, settled.
fn opened(log: &str, validation: &str, size: egui::Vec2) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    // (read at once, as `--screenshot` reads it: the laser gyro's four temperatures would
    // otherwise ask for a look in the import view first)
    wb.open_log(sample(log), Default::default(), false);
    wb.open_validation_after(sample(validation), Default::default());
    let mut h = Harness::builder()
        .with_size(size)
        .build_ui_state(|ui, wb: &mut Workbench| wb.ui(ui), wb);
    settle(&mut h);
    // The shared y-axis width settles within a frame or two of the widest tick label.
    for _ in 0..3 {
        h.run_ok();
    }
    assert!(
        h.state().state.shown.validation.is_some(),
        "{log}: the validation log {validation} is not open: {:?}",
        h.state().state.status
    );
    h
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

#[test]
fn time_plots_keep_120_points_at_1280x720_and_the_drift_plot_stays_in_a_1024x640_window() {
    for (log, val) in [
        ("calibration.csv", "validation.csv"),
        ("imu3-calibration.csv", "imu3-validation.csv"),
        ("laser-gyro.csv", "laser-gyro-2.csv"),
    ] {
        let size = egui::vec2(1280.0, 720.0);
        let h = opened(log, val, size);
        let what = format!("{log} at 1280×720");
        let hs = heights(&h);
        eprintln!("{what}: {hs:?}");
        for (name, height) in &hs[..4] {
            assert!(
                *height >= 120.0,
                "{what}: {name} is {height} points tall: {hs:?}"
            );
        }
        let window = egui::Rect::from_min_size(egui::Pos2::ZERO, size);
        let drift = h.state().plot_rect("result").unwrap();
        assert!(window.contains_rect(drift), "{what}: {drift:?}");
        assert_linked_plots_aligned(&h, &what);

        let size = egui::vec2(1024.0, 640.0);
        let h = opened(log, val, size);
        let what = format!("{log} at 1024×640");
        eprintln!("{what}: {:?}", heights(&h));
        let window = egui::Rect::from_min_size(egui::Pos2::ZERO, size);
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
    }
}
