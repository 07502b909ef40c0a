//! Knots by hand on the coefficient plots, the same on K0, K1± and K2±: a knot under the
//! pointer is dragged along the direction the pointer first moves (sideways: its position, the
//! values fitted there; up or down: its value, set by hand), Ctrl+click on the plot adds a knot
//! to the nearest curve, and the plot's right-click menu removes the knot clicked or opens the
//! knot table. What each gesture does to the knots is the engine's [`ApproxSpec::edit_knot`];
//! here the pointer is read and the knots drawn.

use super::CoeffView;
use crate::files::session::Coefficient;
use crate::gui::action::{Action, Edit};
use crate::gui::state::AppState;
use crate::models::approx::{Approx, ApproxSpec, KnotEdit};
use eframe::egui::{self, Color32, CursorIcon, Pos2, Ui, Vec2b};
use egui_plot::{MarkerShape, PlotBounds, PlotPoint, PlotPoints, PlotTransform, PlotUi, Points};

/// How near the pointer must be to a knot to take it, points.
const KNOT_GRAB_PX: f32 = 9.0;

/// How far the pointer must go before a drag knows its direction, points.
const AXIS_LOCK_PX: f32 = 4.0;

/// A knot being dragged.
pub(super) struct KnotDrag {
    /// Its coefficient.
    pub(super) c: Coefficient,
    /// Its index.
    j: usize,
    /// Where the pointer was pressed.
    start: Pos2,
    /// Sideways (true) or up and down (false), once the pointer has gone far enough to tell.
    sideways: Option<bool>,
    /// The spec and the curve as they were when the drag started: every frame's edit is made
    /// from them, so that the clamp between the neighbours stays where it was.
    spec: ApproxSpec,
    origin: Approx,
    /// The plot's bounds when the drag started, held while it goes on: a plot that rescaled
    /// to the dragged curve would give the same pointer position a new value each frame, and
    /// a knot held still would run away.
    bounds: PlotBounds,
    /// Whether the plot was scaling itself to its contents before the drag (given back on
    /// release).
    auto: Vec2b,
}

/// What a knot plot does with its bounds this frame ([`CoeffView::bounds_rule`]).
#[derive(Clone, Copy)]
pub(super) enum BoundsRule {
    /// As egui_plot keeps them (scaled to the contents, or as zoomed).
    Free,
    /// A knot of the plot is being dragged: these bounds, whatever the curves do.
    Frozen(PlotBounds),
    /// A drag just ended: the scaling the plot had before it.
    Thaw(Vec2b),
}

impl BoundsRule {
    /// Applies the rule inside the plot; returns whether the plot scaled itself to its
    /// contents before this frame.
    pub(super) fn apply(self, pui: &mut PlotUi<'_>) -> Vec2b {
        let before = pui.auto_bounds();
        match self {
            BoundsRule::Free => {}
            BoundsRule::Frozen(b) => pui.set_plot_bounds(b),
            BoundsRule::Thaw(auto) => pui.set_auto_bounds(auto),
        }
        before
    }
}

/// The curve of `c` as drawn: the last fit with the knots the recipe places and sets by hand
/// (which the fit has not answered yet while a drag goes on), or with `pending`'s spec when
/// this frame's drag changed it.
pub(super) fn shown(
    state: &AppState,
    c: Coefficient,
    pending: Option<&(Coefficient, ApproxSpec)>,
) -> Option<Approx> {
    let f = state.shown.fit.as_ref()?;
    let spec = match pending {
        Some((p, spec)) if *p == c => spec,
        _ => c.spec(&state.shown.choices.recipe),
    };
    Some(spec.preview(c.approx(&f.outcome.calibration)))
}

/// Draws the knots of `a` (none for a curve without knots): circles where fitted, squares
/// where placed by hand, diamonds where their values are set by hand.
pub(super) fn draw_knots(
    pui: &mut PlotUi<'_>,
    name: &str,
    a: &Approx,
    spec: &ApproxSpec,
    color: Color32,
) {
    let (kx, ky) = a.knots();
    if kx.is_empty() {
        return;
    }
    let pts: Vec<[f64; 2]> = kx.iter().zip(ky).map(|(&x, &y)| [x, y]).collect();
    let shape = if spec.values.is_some() {
        MarkerShape::Diamond
    } else if spec.at.is_some() {
        MarkerShape::Square
    } else {
        MarkerShape::Circle
    };
    pui.points(
        Points::new(format!("{name} knots"), PlotPoints::new(pts))
            .shape(shape)
            .radius(5.5)
            .filled(true)
            .color(color),
    );
}

impl CoeffView {
    /// The knot of one of `coefs` nearest to `p` on the plot drawn with `tf`, within grabbing
    /// distance.
    pub(super) fn knot_at(
        &self,
        state: &AppState,
        coefs: &[Coefficient],
        tf: &PlotTransform,
        p: Pos2,
    ) -> Option<(Coefficient, usize)> {
        let mut best: Option<(f32, Coefficient, usize)> = None;
        for &c in coefs {
            let Some(a) = shown(state, c, None) else {
                continue;
            };
            let (kx, ky) = a.knots();
            for (j, (&x, &y)) in kx.iter().zip(ky).enumerate() {
                let d = tf.position_from_point(&PlotPoint::new(x, y)).distance(p);
                if d <= KNOT_GRAB_PX && best.is_none_or(|b| d < b.0) {
                    best = Some((d, c, j));
                }
            }
        }
        best.map(|(_, c, j)| (c, j))
    }

    /// Starts, follows and ends a knot drag on plot `slot` (read before the plot is drawn, with
    /// last frame's transform, so that the knots drawn follow the pointer this frame): the
    /// spec the drag leaves, which is also sent as an edit.
    pub(super) fn drag_knot(
        &mut self,
        ui: &Ui,
        state: &AppState,
        slot: usize,
        coefs: &[Coefficient],
        out: &mut Vec<Action>,
    ) -> Option<(Coefficient, ApproxSpec)> {
        let tf = self.transforms[slot]?;
        let (pressed, down, pos) = ui.input(|i| {
            (
                i.pointer.primary_pressed(),
                i.pointer.primary_down(),
                i.pointer.interact_pos(),
            )
        });
        if pressed
            && self.drag.is_none()
            && self.hovered[slot]
            && let Some(p) = pos
            && tf.frame().contains(p)
            && let Some((c, j)) = self.knot_at(state, coefs, &tf, p)
            && let Some(origin) = shown(state, c, None)
        {
            self.drag = Some(KnotDrag {
                c,
                j,
                start: p,
                sideways: None,
                spec: c.spec(&state.shown.choices.recipe).clone(),
                origin,
                bounds: *tf.bounds(),
                auto: self.auto[slot],
            });
        }
        let d = self.drag.as_mut().filter(|d| coefs.contains(&d.c))?;
        let mut edited = None;
        if let Some(p) = pos {
            let moved = p - d.start;
            if d.sideways.is_none() && moved.length() >= AXIS_LOCK_PX {
                d.sideways = Some(moved.x.abs() > moved.y.abs());
            }
            let at = tf.value_from_position(p);
            let edit = match d.sideways {
                Some(true) => Some(KnotEdit::Drag {
                    index: d.j,
                    x: at.x,
                }),
                Some(false) => Some(KnotEdit::Value {
                    index: d.j,
                    y: at.y,
                }),
                None => None,
            };
            // A drag pushed past what the engine takes (a value beyond any rate) stays where
            // it last was.
            if let Some(Ok(spec)) = edit.map(|e| d.spec.edit_knot(&d.origin, e))
                && spec != *c_spec(state, d.c)
            {
                out.push(Action::Edit(Edit::Approx(d.c, spec.clone())));
                edited = Some((d.c, spec));
            }
        }
        if !down && let Some(d) = self.drag.take() {
            self.thaw[slot] = Some(d.auto);
        }
        edited
    }

    /// What plot `slot` does with its bounds this frame: frozen while one of its knots is
    /// dragged, given back its own scaling the frame after.
    pub(super) fn bounds_rule(&mut self, slot: usize, coefs: &[Coefficient]) -> BoundsRule {
        match (&self.drag, self.thaw[slot].take()) {
            (Some(d), _) if coefs.contains(&d.c) => BoundsRule::Frozen(d.bounds),
            (_, Some(auto)) => BoundsRule::Thaw(auto),
            _ => BoundsRule::Free,
        }
    }

    /// Remembers how plot `slot` scaled itself before this frame (`auto`, from
    /// [`BoundsRule::apply`]), unless one of its knots is being dragged.
    pub(super) fn note_auto(&mut self, slot: usize, rule: BoundsRule, auto: Vec2b) {
        if matches!(rule, BoundsRule::Free) {
            self.auto[slot] = auto;
        }
    }

    /// After plot `slot` is drawn: Ctrl+click adds a knot to the curve of `coefs` nearest to
    /// the pointer, a right-click remembers the knot under it for the menu, and the cursor
    /// says what a press would do.
    pub(super) fn knot_clicks(
        &mut self,
        ui: &Ui,
        state: &AppState,
        slot: usize,
        coefs: &[Coefficient],
        response: &egui::Response,
        out: &mut Vec<Action>,
    ) {
        let Some(tf) = self.transforms[slot] else {
            return;
        };
        let pointer = ui.input(|i| i.pointer.interact_pos());
        let command = ui.input(|i| i.modifiers.command);
        if response.clicked()
            && command
            && let Some(p) = pointer
            && let Some((c, j)) = self.knot_at(state, coefs, &tf, p)
        {
            // A knot is added at the pointer's x: on a knot there is no room for one.
            out.push(Action::Warn(format!(
                "No knot added to {}: the pointer is on knot {} (Ctrl+click adds a knot at the                  pointer's x, so click beside the knots; drag a knot to move it)",
                c.label(),
                j + 1
            )));
        } else if response.clicked()
            && command
            && let Some(p) = pointer
        {
            let at = tf.value_from_position(p);
            if let Some((c, a)) = nearest_curve(state, coefs, &tf, p, at.x) {
                match c_spec(state, c).edit_knot(&a, KnotEdit::Insert { x: at.x }) {
                    Ok(spec) => out.push(Action::Edit(Edit::Approx(c, spec))),
                    Err(e) => {
                        out.push(Action::Warn(format!("No knot added to {}: {e}", c.label())))
                    }
                }
            } else {
                out.push(Action::Warn(
                    "Ctrl+click adds a knot to a pwl or spline curve: this plot has none".into(),
                ));
            }
        }
        if response.secondary_clicked() {
            self.menu_knot = pointer.and_then(|p| self.knot_at(state, coefs, &tf, p));
        }
        if let Some(p) = ui.input(|i| i.pointer.hover_pos())
            && tf.frame().contains(p)
        {
            let icon = match self.drag.as_ref().filter(|d| coefs.contains(&d.c)) {
                Some(d) => match d.sideways {
                    Some(true) => Some(CursorIcon::ResizeHorizontal),
                    Some(false) => Some(CursorIcon::ResizeVertical),
                    None => Some(CursorIcon::Move),
                },
                None => self.knot_at(state, coefs, &tf, p).map(|_| CursorIcon::Move),
            };
            if let Some(icon) = icon {
                ui.ctx().set_cursor_icon(icon);
            }
        }
        if self.drag.is_some() {
            ui.ctx().request_repaint();
        }
    }

    /// The entries of a plot's right-click menu about the knot it was opened on: remove it,
    /// or open the knot table.
    pub(super) fn knot_menu(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        coefs: &[Coefficient],
        out: &mut Vec<Action>,
    ) {
        let Some((c, j)) = self.menu_knot.filter(|(c, _)| coefs.contains(c)) else {
            return;
        };
        let spec = c_spec(state, c);
        let removed =
            shown(state, c, None).map(|a| spec.edit_knot(&a, KnotEdit::Remove { index: j }));
        let r = ui.add_enabled(
            matches!(removed, Some(Ok(_))),
            egui::Button::new(format!("Remove knot {} of {}", j + 1, c.label())),
        );
        let r = match &removed {
            Some(Err(e)) => r.on_disabled_hover_text(e.to_string()),
            _ => r.on_hover_text(
                "The other knots stay where they are; the values are fitted again unless set \
                 by hand",
            ),
        };
        if r.clicked()
            && let Some(Ok(spec)) = removed
        {
            out.push(Action::Edit(Edit::Approx(c, spec)));
            self.menu_knot = None;
            ui.close();
        }
        if ui
            .button(format!("Knots of {}…", c.label()))
            .on_hover_text("Type the knots' positions and values")
            .clicked()
        {
            self.open_knot_table(c);
            self.menu_knot = None;
            ui.close();
        }
        ui.separator();
    }
}

/// The recipe's spec of `c`.
fn c_spec(state: &AppState, c: Coefficient) -> &ApproxSpec {
    c.spec(&state.shown.choices.recipe)
}

/// The knot curve of `coefs` nearest to `p` on screen, at the pointer's `x`, with its curve.
fn nearest_curve(
    state: &AppState,
    coefs: &[Coefficient],
    tf: &PlotTransform,
    p: Pos2,
    x: f64,
) -> Option<(Coefficient, Approx)> {
    coefs
        .iter()
        .filter(|c| c_spec(state, **c).kind.has_knots())
        .filter_map(|&c| {
            let a = shown(state, c, None)?;
            let d = (tf.position_from_point(&PlotPoint::new(x, a.eval(x))).y - p.y).abs();
            Some((d, c, a))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c, a)| (c, a))
}
