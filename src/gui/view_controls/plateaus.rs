//! The plateaus that define K0(T): a table (times typed in, statistics of each, delete), the
//! detector's suggestion, and whether the detector chooses them.

use super::{ControlsView, PlateauFocus};
use crate::gui::action::{Action, Edit};
use crate::gui::plot_items::num;
use crate::gui::state::AppState;
use crate::signal::plateau::PlateauRange;
use eframe::egui::{self, RichText, Ui};

impl ControlsView {
    /// The plateau table with its buttons.
    pub(super) fn plateau_table(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        focus: PlateauFocus,
        out: &mut Vec<Action>,
    ) {
        let Some(loaded) = state.shown.log.clone() else {
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
                let (a, b) = focus
                    .visible_s
                    .unwrap_or((log.time_s[0], log.time_s[log.len() - 1]));
                let c = 0.5 * (a + b);
                let w = 0.05 * (b - a);
                out.push(Action::AddPlateau(PlateauRange {
                    start_s: c - w,
                    end_s: c + w,
                }));
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
                out.push(Action::Edit(if auto {
                    Edit::AutoPlateaus
                } else {
                    Edit::Plateaus(state.ranges())
                }));
            }
        });
        let ranges = state.ranges();
        let stats = state
            .shown
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
        // Hand-set plateaus are held to the limits of the detector they replace.
        let detector = match &state.recipe().plateaus {
            crate::models::recipe::PlateauChoice::Auto(opts) => *opts,
            crate::models::recipe::PlateauChoice::Manual { .. } => Default::default(),
        };
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
                        let sel = focus.selected == Some(k);
                        let found = stats.iter().find(|s| s.range == r);
                        // What keeps it from being a plateau the detector would have found.
                        let outside = found.map_or(Vec::new(), |s| {
                            crate::signal::plateau::outside_detector(s, &detector)
                        });
                        let samples = found.map_or(String::new(), |s| {
                            format!(
                                "{} samples, {} s; ",
                                s.samples,
                                num(s.range.end_s - s.range.start_s)
                            )
                        });
                        let warn = ui.visuals().warn_fg_color;
                        let (label, why) = if outside.is_empty() {
                            (RichText::new(format!("{}", k + 1)), String::new())
                        } else {
                            (
                                RichText::new(format!("!{}", k + 1)).color(warn),
                                format!("Outside the detector's limits: {}.\n", outside.join("; ")),
                            )
                        };
                        if ui
                            .add_sized([W[0], row_h], egui::Button::selectable(sel, label))
                            .on_hover_text(format!(
                                "{why}{samples}select this plateau (Delete removes it)"
                            ))
                            .clicked()
                        {
                            out.push(Action::SelectPlateau(if sel { None } else { Some(k) }));
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
                        if (ca.changed() || cb.changed()) && b <= a {
                            out.push(Action::Warn(format!(
                                "Plateau {} not changed: it would end ({} s) before it starts ({} \
                                 s); type a start before the end",
                                k + 1,
                                num(b),
                                num(a)
                            )));
                        }
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
                                cell(ui, 4, RichText::new(num(s.omega_dph))).on_hover_text(match (
                                    s.omega_std_dph,
                                    s.omega_sem_dph,
                                ) {
                                    (Some(std), Some(sem)) => format!(
                                        "std {} °/h, standard error {} °/h",
                                        num(std),
                                        num(sem)
                                    ),
                                    _ => "one sample: its spread is unknown".to_string(),
                                });
                                let spread =
                                    RichText::new(crate::number::fixed(s.temp_spread_c, 3));
                                let length_s = s.range.end_s - s.range.start_s;
                                cell(
                                    ui,
                                    5,
                                    if outside.is_empty() {
                                        spread
                                    } else {
                                        spread.color(warn)
                                    },
                                )
                                .on_hover_text(format!(
                                    "{} °C between the coldest and the warmest sample, {} °C/min \
                                     over its {} s; std of Ω {} °/h over {} samples",
                                    crate::number::fixed(s.temp_spread_c, 3),
                                    num(s.temp_spread_c / length_s * 60.0),
                                    num(length_s),
                                    s.omega_std_dph.map_or("n/a".to_string(), num),
                                    s.samples
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
                            out.push(Action::SelectPlateau(None));
                        }
                    });
                }
            });
        if let Some(r) = edited {
            out.push(Action::Edit(Edit::Plateaus(r)));
        }
    }
}
