//! The Calibration page's right-hand panel: the three coefficient plots stacked, `k0`
//! (K0(T) over the plateau points) and `pair` (K1± against dT/dt, K2± against d²T/dt²), each
//! with its approximation controls; knots are dragged by hand on the K1 and K2 plots.

mod k0;
mod pair;

use super::action::Action;
use super::state::AppState;
use crate::files::session::Coefficient;
use eframe::egui::{self, Ui};
use egui_plot::PlotTransform;
use pair::Pair;

/// View state of the coefficient plots.
#[derive(Default)]
pub struct CoeffView {
    /// The knot being dragged (coefficient, index).
    drag: Option<(Coefficient, usize)>,
    /// How the K1 and K2 plots were drawn last frame.
    transforms: [Option<PlotTransform>; 2],
    /// Whether the pointer was over each plot last frame (not covered by a window).
    hovered: [bool; 2],
    /// "all points" of the K1 and K2 plots: scaled to every point rather than the bulk.
    all_points: [bool; 2],
    /// Height of the panel's rows other than its three plots, last frame.
    overhead: Option<f32>,
}

impl CoeffView {
    /// The panel: K0, K1 and K2, sharing the height their control rows leave.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState) -> Vec<Action> {
        let mut out = Vec::new();
        if state.shown.log.is_none() {
            ui.weak("K0, K1± and K2± appear here once a log is loaded.");
            return out;
        }
        // The three plots share what their control rows leave, as measured last frame (rows
        // wrap when the panel is narrow, rather than widening it).
        let top = ui.cursor().top();
        let h = ui.available_height();
        let row = ui.spacing().interact_size.y + ui.spacing().item_spacing.y;
        let overhead = self.overhead.unwrap_or(11.0 * row + 30.0);
        let plot_h = ((h - overhead) / 3.0).max(90.0).floor();
        self.k0(ui, state, plot_h, &mut out);
        ui.separator();
        self.pair(ui, state, Pair::K1, plot_h, &mut out);
        ui.separator();
        self.pair(ui, state, Pair::K2, plot_h, &mut out);
        let used = ui.cursor().top() - top;
        self.overhead = Some((used - 3.0 * plot_h).max(0.0));
        out
    }

    /// Where knot `j` of `c` is on screen (as drawn last frame).
    pub fn knot_pos(&self, state: &AppState, c: Coefficient, j: usize) -> Option<egui::Pos2> {
        let slot = match c {
            Coefficient::K1Plus | Coefficient::K1Minus => 0,
            Coefficient::K2Plus | Coefficient::K2Minus => 1,
            Coefficient::K0 => return None,
        };
        let tf = self.transforms[slot]?;
        let f = state.shown.fit.as_ref()?;
        let a = crate::models::vakhrameev::knots::with_knots(
            c.approx(&f.outcome.calibration),
            state.shown.choices.knots.get(c),
        );
        let (kx, ky) = a.knots();
        Some(tf.position_from_point(&egui_plot::PlotPoint::new(*kx.get(j)?, *ky.get(j)?)))
    }
}
