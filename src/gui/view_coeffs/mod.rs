//! The Calibration page's right-hand panel: the three coefficient plots stacked, `k0`
//! (K0(T) over the plateau points) and `pair` (K1± against dT/dt, K2± against d²T/dt²), each
//! with its approximation controls. The knots of a pwl or spline coefficient are placed by hand
//! on any of the three plots (`knots`: dragged sideways or up and down, added with Ctrl+click,
//! removed from the right-click menu) and typed in a small table (`knot_table`); every such
//! change is made by the engine (`ApproxSpec::edit_knot`), the panel only turns the pointer
//! and the keys into it.

mod k0;
mod knot_table;
mod knots;
mod pair;

use super::action::Action;
use super::state::AppState;
use crate::files::session::Coefficient;
use eframe::egui::{self, Ui};
use egui_plot::PlotTransform;
use knot_table::KnotTable;
use knots::KnotDrag;
use pair::Pair;

/// The least height of a coefficient plot, its axes included, points: shorter, the panel
/// scrolls (K2± was squashed to 55 points at 1280×720, and its axis cut at 1024×640).
const PLOT_LEAST_H: f32 = 130.0;

/// The plots' slots in the view's per-plot state: K1, K2, K0.
const K1_SLOT: usize = 0;
const K2_SLOT: usize = 1;
const K0_SLOT: usize = 2;

/// View state of the coefficient plots.
pub struct CoeffView {
    /// The knot being dragged.
    drag: Option<KnotDrag>,
    /// How the K1, K2 and K0 plots were drawn last frame.
    transforms: [Option<PlotTransform>; 3],
    /// Whether the pointer was over each plot last frame (not covered by a window).
    hovered: [bool; 3],
    /// "all points" of the K1 and K2 plots: scaled to every point rather than the bulk.
    all_points: [bool; 2],
    /// The knot the plot's menu was opened on (right-click), while the menu is open.
    menu_knot: Option<(Coefficient, usize)>,
    /// The knot table open, when one is.
    table: Option<KnotTable>,
    /// Height of the panel's rows other than its three plots, last frame.
    overhead: Option<f32>,
    /// Whether each plot scaled itself to its contents (x, y) when last drawn free of a
    /// knot drag.
    auto: [egui::Vec2b; 3],
    /// A plot whose knot drag just ended: the scaling to give it back.
    thaw: [Option<egui::Vec2b>; 3],
}

impl Default for CoeffView {
    fn default() -> Self {
        Self {
            drag: None,
            transforms: [None; 3],
            hovered: [false; 3],
            all_points: [false; 2],
            menu_knot: None,
            table: None,
            overhead: None,
            // egui_plot's own start: scaled to the contents.
            auto: [egui::Vec2b::TRUE; 3],
            thaw: [None; 3],
        }
    }
}

impl CoeffView {
    /// The panel: K0, K1 and K2, sharing the height their control rows leave, each at least
    /// [`PLOT_LEAST_H`] tall (the panel scrolls then: it is drawn in a scroll area).
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
        let plot_h = ((h - overhead) / 3.0).max(PLOT_LEAST_H).floor();
        self.k0(ui, state, plot_h, &mut out);
        ui.separator();
        self.pair(ui, state, Pair::K1, plot_h, &mut out);
        ui.separator();
        self.pair(ui, state, Pair::K2, plot_h, &mut out);
        let used = ui.cursor().top() - top;
        self.overhead = Some((used - 3.0 * plot_h).max(0.0));
        self.knot_table(ui.ctx(), state, &mut out);
        out
    }

    /// Where knot `j` of `c` is on screen (as drawn last frame).
    pub fn knot_pos(&self, state: &AppState, c: Coefficient, j: usize) -> Option<egui::Pos2> {
        let tf = self.transforms[slot_of(c)]?;
        let a = knots::shown(state, c, None)?;
        let (kx, ky) = a.knots();
        Some(tf.position_from_point(&egui_plot::PlotPoint::new(*kx.get(j)?, *ky.get(j)?)))
    }

    /// Where the point `(x, y)` of `c`'s plot is on screen (as drawn last frame).
    pub fn plot_pos(&self, c: Coefficient, x: f64, y: f64) -> Option<egui::Pos2> {
        let tf = self.transforms[slot_of(c)]?;
        Some(tf.position_from_point(&egui_plot::PlotPoint::new(x, y)))
    }

    /// Opens the knot table of `c` (as its "knots…" button does).
    pub fn open_knot_table(&mut self, c: Coefficient) {
        self.table = Some(KnotTable::of(c));
    }
}

/// The plot a coefficient is drawn on.
fn slot_of(c: Coefficient) -> usize {
    match c {
        Coefficient::K1Plus | Coefficient::K1Minus => K1_SLOT,
        Coefficient::K2Plus | Coefficient::K2Minus => K2_SLOT,
        Coefficient::K0 => K0_SLOT,
    }
}
