//! The Calibration page's left-hand panel: the log (and the validation log), the plateau
//! table (`plateaus`), the signal settings (Ω filter, T smoothing, step H, dead-bands) and the
//! fit settings.

mod plateaus;

pub use plateaus::CONTROLS_W_FOR_TABLE;

use super::action::{Action, Edit};
use super::jobs::Target;
use super::plot_items::num;
use super::state::AppState;
use crate::models::recipe::Weighting;
use eframe::egui::{self, Ui};

/// What the time plots show and select, for the plateau table.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlateauFocus {
    /// The time range shown, s.
    pub visible_s: Option<(f64, f64)>,
    /// The plateau selected.
    pub selected: Option<usize>,
}

/// The panel: what it shows is the recipe; its own state is what it last said about a range
/// typed into the plateau table.
#[derive(Debug, Default)]
pub struct ControlsView {
    /// Why the last range typed into the plateau table was not taken as typed (the engine's
    /// words), shown under the table until the next edit of it.
    pub plateau_note: Option<String>,
}

impl ControlsView {
    /// The panel; `focus` is what the time plots show and select.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, focus: PlateauFocus) -> Vec<Action> {
        let mut actions = Vec::new();
        // The controls edit a copy of the recipe; a change goes back as one edit, first, so
        // that a plateau edited in the same frame is not undone by it.
        let mut recipe = state.recipe().clone();
        egui::CollapsingHeader::new("Data")
            .default_open(true)
            .show(ui, |ui| {
                match &state.shown.log {
                    Some(l) => {
                        let log = &l.log;
                        let (tmin, tmax) = l
                            .lods
                            .temp
                            .range_min_max(&log.temp_c, 0, log.len())
                            .unwrap_or((f64::NAN, f64::NAN));
                        ui.label(format!(
                            "{} samples, {:.2} h, T {:.1} … {:.1} °C",
                            log.len(),
                            log.duration_s() / 3600.0,
                            tmin,
                            tmax
                        ))
                        .on_hover_text(l.path.display().to_string());
                        if let Some(note) = &l.resampled {
                            ui.weak(note.as_str())
                                .on_hover_text("How the log was averaged after the read (the import view's bins, or one sample per burst)");
                        }
                        if l.segments.len() > 1 {
                            let widest = l.segments.gaps().map(|(a, b)| b - a).fold(0.0, f64::max);
                            ui.weak(format!(
                                "{} segments between gaps (widest {}): no window or derivative crosses a gap",
                                l.segments.len(),
                                crate::gui::plot_items::duration(widest)
                            ))
                            .on_hover_text("The log stops and starts again: each stretch is filtered, differentiated and judged on its own, and the plots leave the gaps empty");
                        }
                        if ui
                            .small_button("Column mapping…")
                            .on_hover_text("Reopen the import view on this log: columns, units, separator, decimal comma")
                            .clicked()
                        {
                            actions.push(Action::ColumnMapping(Target::Calibration));
                        }
                        let problems = &log.info.problems;
                        if !problems.is_empty() {
                            let text: Vec<String> = problems
                                .iter()
                                .map(|p| {
                                    format!(
                                        "line {}: {} ({}×)",
                                        p.line,
                                        super::view_import::in_labels(&p.message),
                                        p.count
                                    )
                                })
                                .collect();
                            ui.colored_label(
                                ui.visuals().warn_fg_color,
                                format!("{} kind(s) of problems worked around", problems.len()),
                            )
                            .on_hover_text(text.join("\n"));
                        }
                    }
                    None => {
                        ui.weak("No log.");
                    }
                }
                ui.horizontal(|ui| match &state.shown.validation {
                    Some(v) => {
                        let name = v
                            .path
                            .file_name()
                            .map(|s| s.to_string_lossy().into_owned())
                            .unwrap_or_default();
                        ui.label(format!("Validation: {name}"))
                            .on_hover_text(v.path.display().to_string());
                        if ui
                            .small_button("mapping…")
                            .on_hover_text("Reopen the import view on the validation log")
                            .clicked()
                        {
                            actions.push(Action::ColumnMapping(Target::Validation));
                        }
                        if ui
                            .small_button("×")
                            .on_hover_text("Forget the validation log")
                            .clicked()
                        {
                            actions.push(Action::CloseValidation);
                        }
                    }
                    None => {
                        if ui
                            .add_enabled(
                                state.shown.log.is_some(),
                                egui::Button::new("Open validation log…"),
                            )
                            .on_hover_text(
                                "A second log of the same gyro, to judge the calibration held out",
                            )
                            .clicked()
                        {
                            actions.push(Action::OpenValidation);
                        }
                    }
                });
            });
        // The plateaus before the derivatives' settings, as the engineer's path goes (and so
        // that the table is in view in a short window, beside an opened calibration).
        egui::CollapsingHeader::new("Plateaus (K0 points)")
            .default_open(true)
            .show(ui, |ui| {
                self.plateau_table(ui, state, focus, &mut actions);
            });
        let dt = state
            .shown
            .log
            .as_ref()
            .map_or(1.0, |l| l.log.nominal_dt_s());
        // A window shorter than the log's step (100 s on a log of one sample per 2-min burst)
        // is left as the recipe has it: the engine takes one sample, and the recipe is not
        // changed (nor the work marked unsaved) by opening a log.
        egui::CollapsingHeader::new("Derivatives").default_open(true).show(ui, |ui| {
            let r = &mut recipe;
            egui::Grid::new("deriv_grid").num_columns(3).spacing([8.0, 4.0]).show(ui, |ui| {
                let samples = |s: f64| format!("{} samples", crate::signal::seconds_to_samples(s, dt));
                ui.label("Ω filter").on_hover_text("Centred moving average of Ω before the pointwise coefficients and in the figures");
                ui.add(egui::DragValue::new(&mut r.filter_s).range(dt..=100_000.0).speed(1.0).suffix(" s").clamp_existing_to_range(false))
                    .on_hover_text("Ω moving-average window, s (the paper: 100 recording intervals)");
                ui.weak(samples(r.filter_s));
                ui.end_row();
                ui.label("T smoothing").on_hover_text("Causal moving average of T before differentiating");
                ui.add(egui::DragValue::new(&mut r.temp_smoothing_s).range(dt..=100_000.0).speed(1.0).suffix(" s").clamp_existing_to_range(false))
                    .on_hover_text("T smoothing window, s: longer quietens dT/dt and d²T/dt² but delays them");
                ui.weak(samples(r.temp_smoothing_s));
                ui.end_row();
                ui.label("Step H").on_hover_text("Step of the 3-point backward derivative");
                ui.add(egui::DragValue::new(&mut r.step_h_s).range(dt..=10_000.0).speed(0.5).suffix(" s").clamp_existing_to_range(false))
                    .on_hover_text("Derivative step H, s: H = 1 sample makes d²T/dt² pure quantisation noise on a 1 Hz log");
                ui.weak(samples(r.step_h_s));
                ui.end_row();
            });
            let resolved = state.shown.fit.as_ref().map(|f| f.outcome.calibration.resolved);
            for (name, tip, is_tdot) in [
                ("K1 dead-band |dT/dt|", "Points with |dT/dt| below this are left out of the K1 fits, °C/s", true),
                ("K2 dead-band |d²T/dt²|", "Points with |d²T/dt²| below this are left out of the K2 fits, °C/s²", false),
            ] {
                ui.horizontal(|ui| {
                    let r = &mut recipe;
                    let slot = if is_tdot { &mut r.deadband_tdot } else { &mut r.deadband_tddot };
                    let used = resolved.map(|r| if is_tdot { r.deadband_tdot } else { r.deadband_tddot });
                    let mut auto = slot.is_none();
                    ui.label(name).on_hover_text(tip);
                    if ui
                        .checkbox(&mut auto, "auto")
                        .on_hover_text("Automatic: a fifth of the 95th percentile of the rate outside plateaus")
                        .changed()
                    {
                        *slot = if auto { None } else { Some(used.unwrap_or(0.0)) };
                    }
                    match slot {
                        Some(v) => {
                            let speed = (v.abs() * 0.01).max(1e-9);
                            // Shown as the automatic one is (`8.19e-7`, not `0.000000819`);
                            // typed in any form a number is written.
                            ui.add(
                                egui::DragValue::new(v)
                                    .range(0.0..=f64::MAX)
                                    .speed(speed)
                                    .custom_formatter(|n, _| num(n))
                                    .custom_parser(|t| t.trim().parse::<f64>().ok().filter(|x| x.is_finite())),
                            )
                            .on_hover_text(tip);
                        }
                        None => {
                            ui.weak(used.map(num).unwrap_or_default());
                        }
                    }
                });
            }
        });
        egui::CollapsingHeader::new("Fit").default_open(true).show(ui, |ui| {
            let r = &mut recipe;
            ui.horizontal(|ui| {
                ui.label("Gyro id");
                ui.add(egui::TextEdit::singleline(&mut r.gyro_id).desired_width(140.0).hint_text("serial number"))
                    .on_hover_text("Identifier of the gyro, written into the calibration file");
            });
            ui.horizontal(|ui| {
                ui.label("Weighting");
                egui::ComboBox::from_id_salt("weighting")
                    .selected_text(match r.weighting {
                        Weighting::Drift => "drift",
                        Weighting::Ratio => "ratio (paper)",
                    })
                    .show_ui(ui, |ui| {
                        ui.selectable_value(&mut r.weighting, Weighting::Drift, "drift")
                            .on_hover_text("Each ratio weighted by its denominator squared: minimises the error of the predicted drift");
                        ui.selectable_value(&mut r.weighting, Weighting::Ratio, "ratio (paper)")
                            .on_hover_text("Every pointwise ratio counts alike, as the paper fits them");
                    })
                    .response
                    .on_hover_text("How the pointwise K1/K2 values are weighed in their least-squares fits");
            });
            ui.horizontal(|ui| {
                ui.label("Refinements");
                ui.add(egui::DragValue::new(&mut r.refinements).range(0..=10).speed(0.05))
                    .on_hover_text("Extra passes refitting K1 with the K2 term removed, then K2 (0: the paper's single pass)");
            });
        });
        if recipe != *state.recipe() {
            actions.insert(0, Action::Edit(Edit::Recipe(Box::new(recipe))));
        }
        actions
    }
}
