//! K1± and K2±: the pointwise coefficients against dT/dt and d²T/dt² (+ and − in two colours,
//! thinned for drawing), the excluded dead-band shaded, the fitted curves, the approximation
//! of each of the four with its statistics, and spline/piecewise-linear knots placed by hand
//! (`knots.rs`).

use super::knots::{draw_knots, shown};
use super::{CoeffView, K1_SLOT, K2_SLOT};
use crate::files::session::Coefficient;
use crate::gui::action::{Action, Edit};
use crate::gui::plot_items::{
    CloudItem, EdgeMarksItem, Palette, ShadeItem, ShadeSpan, cloud_scale, num,
};
use crate::gui::state::AppState;
use crate::gui::widgets::{approx_controls, save_plot_entry};
use eframe::egui::{self, Color32, RichText, Stroke, Ui};
use egui_plot::{Line, Plot, PlotBounds, PlotPoints};

/// Which pair a plot shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Pair {
    /// K1+ and K1− against dT/dt.
    K1,
    /// K2+ and K2− against d²T/dt².
    K2,
}

impl Pair {
    fn coefs(self) -> [Coefficient; 2] {
        match self {
            Pair::K1 => [Coefficient::K1Plus, Coefficient::K1Minus],
            Pair::K2 => [Coefficient::K2Plus, Coefficient::K2Minus],
        }
    }
    fn scatter_index(self) -> usize {
        match self {
            Pair::K1 => 0,
            Pair::K2 => 2,
        }
    }
    fn id(self) -> &'static str {
        match self {
            Pair::K1 => "k1",
            Pair::K2 => "k2",
        }
    }
}

impl CoeffView {
    /// One pair's controls and plot.
    pub(super) fn pair(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        pair: Pair,
        height: f32,
        out: &mut Vec<Action>,
    ) {
        let pal = Palette::of(ui);
        let slot = if pair == Pair::K1 { K1_SLOT } else { K2_SLOT };
        let (title, x_label, y_label, tip) = match pair {
            Pair::K1 => (
                "K1±(dT/dt)",
                "dT/dt, °C/s",
                "K1, (°/h)/(°C/s)",
                "Pointwise K1 = (Ω − K0(T)) / (dT/dt) on the + set (orange) and − set (blue), outside plateaus and the dead-band",
            ),
            Pair::K2 => (
                "K2±(d²T/dt²)",
                "d²T/dt², °C/s²",
                "K2, (°/h)/(°C/s²)",
                "Pointwise K2 = what K0 and the fitted K1 leave, over d²T/dt², on the + and − sets",
            ),
        };
        let fit = state.shown.fit.clone();
        // The view the plot is scaled to (the bulk of the points, the curves and the
        // dead-band; every point with "all points") and how many points it leaves out,
        // read from the clouds' sorted y (built once per fit): cheap every frame.
        let scaled = fit.as_ref().and_then(|f| {
            let cal = &f.outcome.calibration;
            let db = match pair {
                Pair::K1 => cal.resolved.deadband_tdot,
                Pair::K2 => cal.resolved.deadband_tddot,
            };
            let i = pair.scatter_index();
            let clouds = [&*f.lods.scatter[i], &*f.lods.scatter[i + 1]];
            let curves_y = pair
                .coefs()
                .into_iter()
                .filter_map(|c| {
                    curve_points(&c.spec(&state.shown.choices.recipe).preview(c.approx(cal)))
                })
                .flatten()
                .map(|p| p[1])
                .filter(|v| v.is_finite())
                .fold(None, |r: Option<(f64, f64)>, v| {
                    Some(r.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
                });
            let scale = cloud_scale(&clouds, curves_y, db, self.all_points[slot])?;
            let beyond: usize = clouds
                .iter()
                .map(|c| {
                    let (lo, hi) = c.count_beyond_y(scale[2], scale[3]);
                    lo + hi
                })
                .sum();
            Some((scale, beyond))
        });
        let mut rescale = false;
        ui.horizontal_wrapped(|ui| {
            ui.strong(title).on_hover_text(tip);
            if ui
                .small_button("PNG")
                .on_hover_text("Save this plot as PNG")
                .clicked()
            {
                out.push(Action::SavePlotNamed(pair.id().into()));
            }
            rescale = ui
                .toggle_value(&mut self.all_points[slot], "all points")
                .on_hover_text(
                    "Scale the plot to every point. Off: to the bulk of the points (its 1st to 99th \
                     percentile or quartiles ∓ 3 IQR, widened a little), the fitted curves and the dead-band, the \
                     points beyond drawn as ▲/▼ marks at the plot's edge. Double-click the plot \
                     to go back to its scale after zooming.",
                )
                .changed();
            if let Some((_, n)) = scaled
                && n > 0
            {
                // One piece of text: moved whole to the next row, never broken inside.
                ui.add(
                    egui::Label::new(
                        RichText::new(format!("{n} points beyond the scale")).weak(),
                    )
                    .extend(),
                )
                .on_hover_text(
                    "Drawn as ▲/▼ marks at the plot's top and bottom edge. Tick \"all points\" or \
                     zoom out (Ctrl+wheel) to see them.",
                );
            }
        });
        for (c, color) in pair.coefs().into_iter().zip([pal.plus, pal.minus]) {
            ui.horizontal_wrapped(|ui| {
                ui.label(RichText::new(c.label()).color(color).strong())
                    .on_hover_text(if matches!(c, Coefficient::K1Plus | Coefficient::K2Plus) {
                        "+ set: thermal acceleration, dT/dt·d²T/dt² > 0"
                    } else {
                        "− set: thermal deceleration, dT/dt·d²T/dt² < 0"
                    });
                let now = c.spec(&state.shown.choices.recipe);
                let edited = now.hand_knots();
                let mut spec = now.clone();
                let asks = approx_controls(ui, c.key(), c.label(), &mut spec);
                if spec != *now {
                    out.push(Action::Edit(Edit::Approx(c, spec)));
                }
                if asks.reset {
                    out.push(Action::Edit(Edit::Approx(c, now.without_hand_knots())));
                }
                if asks.table {
                    self.open_knot_table(c);
                }
                if let Some(f) = &fit {
                    let s = c.approx(&f.outcome.calibration).stats();
                    // R² only (n on hover), never broken across rows beside a selector.
                    ui.add(
                        egui::Label::new(
                            RichText::new(format!(
                                "R² {}",
                                crate::number::or_na(s.computed_r2(), |v| {
                                    crate::number::fixed(v, 3)
                                })
                            ))
                            .weak(),
                        )
                        .extend(),
                    )
                    .on_hover_text(format!(
                        "{} points fitted; RMSE {} ; R² {}{}",
                        s.n,
                        crate::number::or_na(s.computed_rmse(), num),
                        crate::number::or_na(s.computed_r2(), |v| crate::number::fixed(v, 4)),
                        if edited {
                            "; knots placed or set by hand"
                        } else {
                            ""
                        }
                    ));
                }
            });
        }

        // The knots as this frame's drag leaves them (the edit is carried out at the end of
        // the frame).
        let pending = self.drag_knot(ui, state, slot, &pair.coefs(), out);
        let dragging = self.drag.is_some();
        let rule = self.bounds_rule(slot, &pair.coefs());
        let resp = ui.scope(|ui| {
            Plot::new(("coeff_plot", pair.id()))
                .height(height)
                .x_axis_label(x_label)
                .y_axis_label(crate::gui::plot_items::axis_label(
                    ui.ctx(),
                    y_label,
                    height,
                ))
                .y_axis_min_width(60.0)
                .x_axis_formatter(crate::gui::plot_items::tick_x)
                .y_axis_formatter(crate::gui::plot_items::tick_y)
                .x_grid_spacer(egui_plot::uniform_grid_spacer(
                    crate::gui::plot_items::nice_steps,
                ))
                .y_grid_spacer(egui_plot::uniform_grid_spacer(
                    crate::gui::plot_items::nice_steps,
                ))
                .allow_drag(!dragging)
                .allow_boxed_zoom(!dragging)
                // The wheel scrolls the panel (Ctrl+wheel zooms the plot).
                .allow_scroll(false)
                .show(ui, |pui| {
                    let auto = rule.apply(pui);
                    let Some(f) = &fit else {
                        return auto;
                    };
                    let cal = &f.outcome.calibration;
                    let db = match pair {
                        Pair::K1 => cal.resolved.deadband_tdot,
                        Pair::K2 => cal.resolved.deadband_tddot,
                    };
                    pui.add(ShadeItem::new(
                        "dead-band",
                        vec![ShadeSpan {
                            x0: -db,
                            x1: db,
                            fill: Palette::shade(pal.deadband, 0.35),
                            edge: Stroke::new(1.0, Palette::shade(pal.deadband, 0.8)),
                        }],
                    ));
                    if rescale {
                        pui.set_auto_bounds(true);
                    }
                    let rect = pui.response().rect;
                    let b = pui.plot_bounds();
                    let Some((scale, _)) = scaled else {
                        return auto;
                    };
                    for (k, (c, color)) in pair
                        .coefs()
                        .into_iter()
                        .zip([pal.plus, pal.minus])
                        .enumerate()
                    {
                        let lod = &f.lods.scatter[pair.scatter_index() + k];
                        if lod.is_empty() {
                            continue;
                        }
                        let view = if b.is_valid() && b.width() > 0.0 && b.height() > 0.0 {
                            [b.min()[0], b.max()[0], b.min()[1], b.max()[1]]
                        } else {
                            scale
                        };
                        let pts = lod.visible(view, [rect.width(), rect.height()], 2.5, 4000);
                        let bounds =
                            PlotBounds::from_min_max([scale[0], scale[2]], [scale[1], scale[3]]);
                        pui.add(
                            CloudItem::new(&format!("{} points", c.label()), pts, bounds)
                                .color(Palette::shade(color, 0.55)),
                        );
                        pui.add(EdgeMarksItem::new(
                            &format!("{} points beyond the scale", c.label()),
                            lod.beyond(view, rect.width(), 3.0),
                            Palette::shade(color, 0.9),
                        ));
                    }
                    for (c, color) in pair.coefs().into_iter().zip([pal.plus, pal.minus]) {
                        let Some(a) = shown(state, c, pending.as_ref()) else {
                            continue;
                        };
                        if let Some(curve) = curve_points(&a) {
                            pui.line(
                                Line::new(format!("{} fit", c.label()), PlotPoints::new(curve))
                                    .color(darker(color))
                                    .width(2.5),
                            );
                        }
                        let spec = match &pending {
                            Some((p, spec)) if *p == c => spec,
                            _ => c.spec(&state.shown.choices.recipe),
                        };
                        draw_knots(pui, c.label(), &a, spec, darker(color));
                    }
                    auto
                })
        });
        self.note_auto(slot, rule, resp.inner.inner);
        let tf = resp.inner.transform;
        self.transforms[slot] = Some(tf);
        self.hovered[slot] = resp.inner.response.hovered();
        self.knot_clicks(ui, state, slot, &pair.coefs(), &resp.inner.response, out);
        resp.inner.response.context_menu(|ui| {
            self.knot_menu(ui, state, &pair.coefs(), out);
            if save_plot_entry(ui) {
                out.push(Action::SavePlotNamed(pair.id().into()));
            }
        });
        out.push(Action::PlotRect(pair.id().into(), resp.response.rect));
    }
}

/// The fitted curve over its x-range, 201 points (none for a curve without a range).
fn curve_points(a: &crate::models::approx::Approx) -> Option<Vec<[f64; 2]>> {
    let (lo, hi) = (a.x_min(), a.x_max());
    (hi > lo).then(|| {
        (0..=200)
            .map(|j| {
                let x = lo + (hi - lo) * j as f64 / 200.0;
                [x, a.eval(x)]
            })
            .collect()
    })
}

fn darker(c: Color32) -> Color32 {
    let [r, g, b, _] = c.to_array();
    Color32::from_rgb(
        (r as f32 * 0.8) as u8,
        (g as f32 * 0.8) as u8,
        (b as f32 * 0.8) as u8,
    )
}
