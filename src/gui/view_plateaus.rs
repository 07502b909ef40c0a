//! The plateaus that define K0(T): a table (times typed in, statistics of each, delete), the
//! detector's suggestion, and the K0 plot of the plateau points with the fitted curve.

use super::app::Action;
use super::plot_items::{Palette, num};
use super::state::AppState;
use super::view_coeffs::approx_controls;
use super::view_time::TimeView;
use crate::files::session::Coefficient;
use crate::signal::plateau::PlateauRange;
use eframe::egui::{self, RichText, Ui};
use egui_plot::{Line, LineStyle, MarkerShape, Plot, PlotPoints, Points};

/// View state of the plateau table and the K0 plot.
#[derive(Default)]
pub struct PlateauView;

impl PlateauView {
    /// The plateau table with its buttons.
    pub fn table(
        &mut self,
        ui: &mut Ui,
        state: &mut AppState,
        time: &mut TimeView,
        out: &mut Vec<Action>,
    ) {
        let Some(loaded) = state.log.clone() else {
            ui.weak("No log loaded.");
            return;
        };
        let log = &loaded.log;
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Suggest plateaus")
                .on_hover_text(
                    "Fill the table with the plateaus the engine's detector finds (|dT/dt| below \
                     0.05 °C/min for 20 min, settled half kept); they can then be edited",
                )
                .clicked()
            {
                out.push(Action::SuggestPlateaus);
            }
            if ui
                .button("Add")
                .on_hover_text("Add a plateau in the middle of the visible time range (then type its times or drag its edges)")
                .clicked()
            {
                let (a, b) = time
                    .visible_s
                    .unwrap_or((log.time_s[0], log.time_s[log.len() - 1]));
                let c = 0.5 * (a + b);
                let w = 0.05 * (b - a);
                let mut r = state.ranges();
                r.push(PlateauRange {
                    start_s: c - w,
                    end_s: c + w,
                });
                state.set_ranges(r);
                time.selected = state
                    .ranges()
                    .iter()
                    .position(|x| (x.start_s - (c - w)).abs() < 1e-9);
            }
            let mut auto = state.plateaus_auto();
            if ui
                .checkbox(&mut auto, "Automatic")
                .on_hover_text(
                    "On: the detector chooses the plateaus every time the filters change. \
                     Off: the plateaus are the ones in the table, kept as they are.",
                )
                .changed()
            {
                if auto {
                    state.recipe_mut().plateaus = crate::models::recipe::PlateauChoice::default();
                } else {
                    let r = state.ranges();
                    state.set_ranges(r);
                }
            }
        });
        let ranges = state.ranges();
        let stats = state
            .fit
            .as_ref()
            .map(|f| f.outcome.calibration.plateaus.clone())
            .unwrap_or_default();
        ui.weak(format!(
            "{} plateau{} {}",
            ranges.len(),
            if ranges.len() == 1 { "" } else { "s" },
            if state.plateaus_auto() {
                "found by the detector"
            } else {
                "set by hand"
            }
        ));
        let mut edited: Option<Vec<PlateauRange>> = None;
        let step = (log.nominal_dt_s() * 10.0).max(1e-3);
        // Column widths: the table fits the controls panel at its narrowest (320).
        const W: [f32; 7] = [20.0, 56.0, 56.0, 42.0, 50.0, 46.0, 18.0];
        let row_h = ui.spacing().interact_size.y;
        let cell = |ui: &mut Ui, k: usize, text: RichText| {
            ui.add_sized([W[k], row_h], egui::Label::new(text).truncate())
        };
        ui.horizontal(|ui| {
            ui.spacing_mut().item_spacing.x = 4.0;
            for (k, (h, tip)) in [
                (
                    "#",
                    "Click to select the plateau in the time plots; hover it for its samples",
                ),
                (
                    "start, s",
                    "Start time, s: drag the number or click and type",
                ),
                ("end, s", "End time, s"),
                ("T, °C", "Mean temperature on the plateau"),
                ("Ω, °/h", "Mean gyro output: the K0 point"),
                (
                    "ΔT, °C",
                    "Spread of the temperature on the plateau: max − min, °C (large: not stable)",
                ),
                ("", ""),
            ]
            .into_iter()
            .enumerate()
            {
                cell(ui, k, RichText::new(h).strong()).on_hover_text(tip);
            }
        });
        // Only the visible rows are laid out: a tiled ten-million-sample log has hundreds.
        egui::ScrollArea::vertical()
            .id_salt("plateau_table")
            .max_height(8.0 * (row_h + ui.spacing().item_spacing.y))
            .auto_shrink([false, true])
            .show_rows(ui, row_h, ranges.len(), |ui, rows| {
                for k in rows {
                    let r = ranges[k];
                    ui.horizontal(|ui| {
                        ui.spacing_mut().item_spacing.x = 4.0;
                        let sel = time.selected == Some(k);
                        let samples = stats
                            .iter()
                            .find(|s| s.range == r)
                            .map_or(String::new(), |s| format!("{} samples; ", s.samples));
                        if ui
                            .add_sized(
                                [W[0], row_h],
                                egui::Button::selectable(sel, format!("{}", k + 1)),
                            )
                            .on_hover_text(format!(
                                "{samples}select this plateau (Delete removes it)"
                            ))
                            .clicked()
                        {
                            time.selected = if sel { None } else { Some(k) };
                        }
                        let (mut a, mut b) = (r.start_s, r.end_s);
                        let ca = ui
                            .add_sized(
                                [W[1], row_h],
                                egui::DragValue::new(&mut a)
                                    .speed(step)
                                    .max_decimals(1)
                                    .update_while_editing(false),
                            )
                            .on_hover_text("Start, s: drag, or click and type a time");
                        let cb = ui
                            .add_sized(
                                [W[2], row_h],
                                egui::DragValue::new(&mut b)
                                    .speed(step)
                                    .max_decimals(1)
                                    .update_while_editing(false),
                            )
                            .on_hover_text("End, s: drag, or click and type a time");
                        if (ca.changed() || cb.changed()) && b > a {
                            let mut all = ranges.clone();
                            all[k] = PlateauRange {
                                start_s: a,
                                end_s: b,
                            };
                            edited = Some(all);
                        }
                        match stats.iter().find(|s| s.range == r) {
                            Some(s) => {
                                cell(ui, 3, RichText::new(crate::number::fixed(s.temp_c, 2)));
                                cell(ui, 4, RichText::new(num(s.omega_dph))).on_hover_text(
                                    format!(
                                        "std {} °/h, standard error {} °/h",
                                        num(s.omega_std_dph),
                                        num(s.omega_sem_dph)
                                    ),
                                );
                                cell(
                                    ui,
                                    5,
                                    RichText::new(crate::number::fixed(s.temp_spread_c, 3)),
                                )
                                .on_hover_text(format!(
                                    "{} °C between the coldest and the warmest sample",
                                    crate::number::fixed(s.temp_spread_c, 3)
                                ));
                            }
                            None => {
                                for c in 3..6 {
                                    cell(ui, c, RichText::new("…").weak());
                                }
                            }
                        }
                        if ui
                            .add_sized([W[6], row_h], egui::Button::new("×"))
                            .on_hover_text("Delete this plateau")
                            .clicked()
                        {
                            let mut all = ranges.clone();
                            all.remove(k);
                            edited = Some(all);
                            time.selected = None;
                        }
                    });
                }
            });
        if let Some(r) = edited {
            state.set_ranges(r);
        }
    }

    /// The K0(T) plot with its approximation controls.
    pub fn k0_plot(
        &mut self,
        ui: &mut Ui,
        state: &mut AppState,
        height: f32,
        out: &mut Vec<Action>,
    ) {
        let pal = Palette::of(ui);
        ui.horizontal_wrapped(|ui| {
            ui.strong("K0(T)")
                .on_hover_text("Static bias: mean output on each plateau against its temperature");
            let edited = state.choices.knots.get(Coefficient::K0).is_some();
            let mut spec = state.choices.recipe.k0;
            let reset = approx_controls(ui, "k0", "K0", &mut spec, edited);
            if spec != state.choices.recipe.k0 {
                state.choices.recipe.k0 = spec;
                state.choices.knots.retain_matching(&state.choices.recipe);
            }
            if reset {
                state.choices.knots.set(Coefficient::K0, None);
            }
            if ui
                .small_button("PNG")
                .on_hover_text("Save the K0 plot as PNG")
                .clicked()
            {
                out.push(Action::SavePlotNamed("k0".into()));
            }
        });
        let fit = state.fit.clone();
        let resp = ui.scope(|ui| {
            Plot::new("k0_plot")
                .height(height)
                .x_axis_label("T, °C")
                .y_axis_label("K0, °/h")
                .y_axis_min_width(56.0)
                .y_axis_formatter(super::plot_items::tick_y)
                .x_axis_formatter(super::plot_items::tick_x)
                .x_grid_spacer(egui_plot::uniform_grid_spacer(
                    super::plot_items::nice_steps,
                ))
                .y_grid_spacer(egui_plot::uniform_grid_spacer(
                    super::plot_items::nice_steps,
                ))
                .show(ui, |pui| {
                    let Some(f) = &fit else {
                        return;
                    };
                    let cal = &f.outcome.calibration;
                    let pts: Vec<[f64; 2]> = cal
                        .plateaus
                        .iter()
                        .map(|p| [p.temp_c, p.omega_dph])
                        .collect();
                    for p in &cal.plateaus {
                        pui.line(
                            Line::new(
                                "±1 std",
                                PlotPoints::new(vec![
                                    [p.temp_c, p.omega_dph - p.omega_std_dph],
                                    [p.temp_c, p.omega_dph + p.omega_std_dph],
                                ]),
                            )
                            .color(Palette::shade(pal.plateau, 0.6))
                            .width(1.0)
                            .allow_hover(false),
                        );
                    }
                    let k0 = &cal.k0;
                    let (lo, hi) = (k0.x_min(), k0.x_max());
                    let pad = ((hi - lo) * 0.15).max(2.0);
                    let curve = |a: f64, b: f64| -> Vec<[f64; 2]> {
                        (0..=100)
                            .map(|j| {
                                let x = a + (b - a) * j as f64 / 100.0;
                                [x, k0.eval(x)]
                            })
                            .collect()
                    };
                    pui.line(
                        Line::new(
                            format!("K0 ({})", k0.kind()),
                            PlotPoints::new(curve(lo, hi)),
                        )
                        .color(pal.curve)
                        .width(2.0),
                    );
                    for (a, b) in [(lo - pad, lo), (hi, hi + pad)] {
                        pui.line(
                            Line::new("held beyond the plateaus", PlotPoints::new(curve(a, b)))
                                .color(pal.curve)
                                .style(LineStyle::dashed_dense())
                                .width(1.0),
                        );
                    }
                    pui.points(
                        Points::new("plateaus", PlotPoints::new(pts))
                            .shape(MarkerShape::Circle)
                            .radius(5.0)
                            .filled(true)
                            .color(pal.plateau),
                    );
                })
        });
        out.push(Action::PlotRect("k0".into(), resp.response.rect));
        match fit {
            Some(f) => {
                let s = f.outcome.calibration.k0.stats();
                ui.weak(format!(
                    "{} plateaus · RMSE {} °/h · R² {}",
                    s.n,
                    num(s.rmse),
                    crate::number::fixed(s.r2, 4)
                ))
                .on_hover_text("Fit statistics of K0 over the plateau points");
            }
            None => {
                ui.weak("No fit yet.");
            }
        }
    }
}

/// Plateau ranges of the time plots' shared view, for other views.
pub fn fmt_range(r: &PlateauRange) -> String {
    format!(
        "{}–{} s",
        crate::number::fixed(r.start_s, 0),
        crate::number::fixed(r.end_s, 0)
    )
}
