//! The Models page: the models of the papers and one built term by term, fitted on the
//! calibration log and judged on it and on the validation log (what `driftlab compare`
//! prints), their corrected drifts overlaid on one plot, what a regression model found
//! (coefficients, λ, τd, lag and the cost curves of its searches), and which model to export.
//!
//! The view holds the choices and what is selected; the comparison runs on a worker
//! ([`super::jobs::Jobs::compare`]) and comes back as [`Compared`] in the application data.

//!
//! One file a panel: `builder` (the custom model), `table` (the figures of every model),
//! `plot` (the corrected drifts overlaid) and `detail` (what the selected model found, and
//! its export); this file holds the page's state and lays the panels out.

mod builder;
mod detail;
mod plot;
mod table;

pub use builder::{CustomBuilder, DelayChoice, LagChoice};
pub use plot::model_color;

use super::action::Action;
use super::jobs::{CompareHandle, Compared};
use super::state::AppState;
use crate::gui::plot_items::num;
use crate::log::Log;
use crate::models::presets::{ModelChoice, Preset, REFERENCES};
use eframe::egui::{self, Color32, Panel, RichText, ScrollArea, Ui};

/// View state of the Models page.
pub struct ModelsView {
    /// Which presets are compared, in [`Preset::COMPARED_BY_DEFAULT`] order.
    pub presets: [bool; Preset::COMPARED_BY_DEFAULT.len()],
    /// Which reference rows (the firmware scripts' own fits) are compared beside, in
    /// [`REFERENCES`] order: ticked at first, so that the recommendation is set beside what
    /// the flight controller's own script would have given.
    pub references: [bool; REFERENCES.len()],
    /// The custom model.
    pub custom: CustomBuilder,
    /// The model selected in the table (by name): its details are shown, and it is the one
    /// Export model… writes. Nothing is selected until the engineer picks a row.
    pub selected: Option<String>,
    /// Which log of the comparison the plot shows (0: the calibration log).
    pub log_index: usize,
    /// The models (by name, `raw` the raw drift) the engineer hid from the plot with its key.
    pub hidden: std::collections::BTreeSet<String>,
}

impl Default for ModelsView {
    fn default() -> Self {
        ModelsView {
            presets: [true; Preset::COMPARED_BY_DEFAULT.len()],
            references: [true; REFERENCES.len()],
            custom: CustomBuilder::default(),
            selected: None,
            log_index: 0,
            hidden: Default::default(),
        }
    }
}

impl ModelsView {
    /// The models ticked, in table order (presets, then the custom model).
    ///
    /// # Errors
    /// Nothing ticked, or a custom model the engine would refuse.
    pub fn choices(&self) -> Result<Vec<ModelChoice>, String> {
        let mut out: Vec<ModelChoice> = Preset::COMPARED_BY_DEFAULT
            .iter()
            .zip(self.presets)
            .filter(|(_, on)| *on)
            .map(|(p, _)| ModelChoice::Preset(*p))
            .collect();
        out.extend(
            REFERENCES
                .iter()
                .zip(self.references)
                .filter(|(_, on)| *on)
                .map(|(p, _)| ModelChoice::Preset(*p)),
        );
        if self.custom.enabled {
            let spec = self.custom.spec()?;
            if out.iter().any(|c| c.name() == spec.name) {
                return Err(format!(
                    "the custom model is named \"{}\" like a preset; give it another name",
                    spec.name
                ));
            }
            out.push(ModelChoice::Custom(spec));
        }
        if out.is_empty() {
            return Err("tick at least one model".into());
        }
        Ok(out)
    }

    /// Keeps the selection on a model of the newest comparison; nothing is chosen for the
    /// engineer.
    pub fn adopt(&mut self, c: &Compared) {
        let listed = |n: &Option<String>| {
            n.as_ref()
                .is_some_and(|n| c.reports.iter().any(|r| &r.model == n))
        };
        if !listed(&self.selected) {
            self.selected = None;
        }
        if self.log_index >= c.logs.len() {
            self.log_index = 0;
        }
    }

    /// The whole page: choices on the left, details and export on the right, the table and
    /// the plot in the middle.
    pub fn ui(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        running: Option<&CompareHandle>,
    ) -> Vec<Action> {
        let mut out = Vec::new();
        // The side panels start narrower in a narrower window, so that the figures table in
        // the middle keeps its columns whole at 1280 points (the detail panel is empty until a
        // model is picked); they can be dragged wider.
        let page_w = ui.available_width();
        Panel::left("models_choose")
            .default_size((0.2 * page_w).clamp(250.0, 300.0))
            .size_range(250.0..=460.0)
            .show(ui, |ui| {
                // Compare stays at the panel's foot whatever the window's height; the choices
                // scroll above it.
                Panel::bottom("models_compare")
                    .resizable(false)
                    .show(ui, |ui| self.compare_row(ui, state, running, &mut out));
                ScrollArea::vertical()
                    .id_salt("models_choose_scroll")
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        ui.set_min_width(ui.available_width());
                        self.choose(ui, state)
                    });
            });
        Panel::right("models_detail")
            .default_size((0.24 * page_w).clamp(250.0, 380.0))
            .size_range(250.0..=720.0)
            .show(ui, |ui| {
                ScrollArea::vertical()
                    .id_salt("models_detail_scroll")
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        ui.set_min_width(ui.available_width());
                        self.detail(ui, state, &mut out)
                    });
            });
        egui::CentralPanel::default().show(ui, |ui| {
            if let Some(h) = running {
                // While models are fitted: each one's progress, the last table below.
                ui.add_space(4.0);
                progress(ui, h);
                model_progress(ui, h);
                ui.separator();
            }
            let Some(c) = state.shown.models.clone() else {
                ui.add_space(12.0);
                match running {
                    Some(_) => {}
                    None => {
                        if let Some(e) = &state.shown.models_error {
                            ui.colored_label(ui.visuals().error_fg_color, e);
                        }
                        ui.weak(
                            "Tick the models on the left and press Compare (F5): each is fitted on \
                             the calibration log and judged on it and on the validation log.",
                        );
                    }
                }
                return;
            };
            self.stale_note(ui, state, &c, running);
            // The whole table when it fits in a little over half the height, the plot below.
            let row_h = ui.spacing().interact_size.y + 3.0;
            // Two header rows, the "outside" note and a message line besides the models' rows.
            let rows = 5 + c
                .reports
                .iter()
                .map(|r| r.logs.len().max(1) + usize::from(r.error.is_some()))
                .sum::<usize>();
            // On a short window a little less than half, so that the plot keeps a height to read.
            let share = if ui.available_height() < 480.0 {
                0.45
            } else {
                0.55
            };
            // And never so tall that the recommendation's lines and the plot (at least 160
            // points) fall below the window's foot.
            const BELOW_TABLE: f32 = 330.0;
            let room = (ui.available_height() - BELOW_TABLE).max(120.0);
            let table_h =
                (rows as f32 * row_h).clamp(120.0, (ui.available_height() * share).min(room));
            // On a narrow window the table scrolls sideways, with its scroll bar always shown
            // so that the columns off to the right are not missed.
            ScrollArea::both()
                .id_salt("models_table_scroll")
                .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
                .max_height(table_h)
                .auto_shrink([false, true])
                .show(ui, |ui| self.table(ui, &c));
            // Under the table rather than in its scroll area; one line, the whole on hover.
            ui.weak("outside: the share of samples beyond the fitted ranges (hover for more)")
                .on_hover_text(format!("outside: {}.", table::OUTSIDE));
            self.recommendation(ui, &c);
            ui.separator();
            self.plot(ui, &c);
        });
        out
    }

    fn choose(&mut self, ui: &mut Ui, state: &AppState) {
        match state.active_axis_name() {
            Some(axis) => ui.heading(format!("Models · axis {axis}")),
            None => ui.heading("Models"),
        };
        ui.label("Fitted on the calibration log, judged on it and on the validation log.");
        ui.add_space(4.0);
        ui.strong("Presets");
        for (k, p) in Preset::COMPARED_BY_DEFAULT.iter().enumerate() {
            ui.checkbox(&mut self.presets[k], p.name())
                .on_hover_text(plain(p.describe()));
        }
        ui.horizontal(|ui| {
            if ui.small_button("all").clicked() {
                self.presets = [true; Preset::COMPARED_BY_DEFAULT.len()];
            }
            if ui.small_button("none").clicked() {
                self.presets = [false; Preset::COMPARED_BY_DEFAULT.len()];
            }
        });
        ui.add_space(4.0);
        ui.strong("Firmware scripts (reference)").on_hover_text(
            "The fits PX4's and ArduPilot's own calibration scripts make, shown beside              driftlab's models and judged alike; never recommended",
        );
        for (k, p) in REFERENCES.iter().enumerate() {
            ui.checkbox(&mut self.references[k], p.name())
                .on_hover_text(plain(p.describe()));
        }
        ui.separator();
        self.builder(ui, state);
        ui.separator();
        ui.weak(format!(
            "The Vakhrameev model uses the recipe of the Calibration page (knots moved by hand \
             are not part of it); the figures filter the drift over {} s.",
            num(state.recipe().filter_s)
        ));
    }

    /// Compare (with the progress while it runs), what it fits on and holds out.
    fn compare_row(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        running: Option<&CompareHandle>,
        out: &mut Vec<Action>,
    ) {
        ui.add_space(4.0);
        let choices = self.choices();
        let can = state.shown.log.is_some() && choices.is_ok() && running.is_none();
        ui.horizontal(|ui| {
            let n = choices.as_ref().map_or(0, Vec::len);
            if ui
                .add_enabled(
                    can,
                    egui::Button::new(RichText::new("Compare").strong())
                        .min_size(egui::vec2(110.0, 26.0)),
                )
                .on_hover_text(format!(
                    "Fit the {n} ticked model(s) on the calibration log and judge them (F5); \
                     runs in the background"
                ))
                .clicked()
            {
                out.push(Action::CompareModels);
            }
            if let Some(h) = running {
                ui.label(format!("{} of {} fitted", h.done(), h.total));
                cancel_button(ui, h);
            }
        });
        if let Err(e) = &choices {
            ui.colored_label(ui.visuals().warn_fg_color, e);
        }
        let name = |l: &Option<super::jobs::Loaded>| l.as_ref().map(super::jobs::Loaded::name);
        match name(&state.shown.log) {
            Some(n) => ui.weak(format!("Fitted on: {n}")),
            None => ui.weak("Open a log first."),
        };
        match name(&state.shown.validation) {
            Some(n) => {
                ui.weak(format!("Held out: {n}"));
            }
            None => {
                ui.horizontal(|ui| {
                    ui.weak("Held out: none");
                    if ui
                        .add_enabled(
                            state.shown.log.is_some(),
                            egui::Button::new("Open…").small(),
                        )
                        .on_hover_text(
                            "Open a validation log: a second log of the same gyro to judge the \
                             models held out",
                        )
                        .clicked()
                    {
                        out.push(Action::OpenValidation);
                    }
                });
            }
        }
    }

    fn stale_note(
        &self,
        ui: &mut Ui,
        state: &AppState,
        c: &Compared,
        running: Option<&CompareHandle>,
    ) {
        ui.horizontal_wrapped(|ui| {
            ui.strong("Figures of the filtered drift, °/h")
                .on_hover_text(
                    "As `driftlab compare` prints them: ratio = raw ÷ corrected, above 1 is \
                     better; window mean: largest |mean| over consecutive windows (10 minutes \
                     unless the session gives others); RMS: mean RMS within those windows; outside: share of samples beyond the \
                     ranges the model was fitted on",
                );
            ui.weak(format!(
                "{} model(s) in {:.1} s",
                c.reports.len(),
                c.seconds
            ));
            if running.is_some() {
                ui.separator();
                ui.weak("the table below is the comparison before");
            } else {
                let same_log = state
                    .shown
                    .log
                    .as_ref()
                    .is_some_and(|l| std::sync::Arc::ptr_eq(&l.log, &c.logs[0].log));
                let held: Vec<_> = c.logs.iter().skip(1).map(|l| &l.log).collect();
                let same_held = match &state.shown.validation {
                    Some(v) => held.len() == 1 && std::sync::Arc::ptr_eq(held[0], &v.log),
                    None => held.is_empty(),
                };
                let same_choices = self.choices().is_ok_and(|ch| ch == c.choices);
                let changed = if !same_log {
                    Some("the log changed: press Compare again")
                } else if !same_held {
                    Some("the validation log changed: press Compare again")
                } else if !same_choices {
                    Some("the models ticked changed: press Compare again")
                } else {
                    None
                };
                if let Some(text) = changed {
                    ui.separator();
                    ui.colored_label(ui.visuals().warn_fg_color, text);
                }
            }
            if let Some(e) = &state.shown.models_error {
                ui.colored_label(ui.visuals().error_fg_color, e);
            }
        });
    }
}

impl ModelsView {
    /// The model `driftlab compare` would name, what it was judged on, and a button that
    /// selects it (the model Export model… writes).
    fn recommendation(&mut self, ui: &mut Ui, c: &Compared) {
        let Some(r) = &c.recommended else {
            ui.weak("Recommended: none: no model was judged on every part");
            return;
        };
        // The logs by file name, as the page names them.
        let judged = match &r.judged_on {
            crate::judge::recommend::JudgedOn::HeldOutLogs { logs } => format!(
                "held out on {}",
                logs.iter()
                    .map(|l| crate::gui::widgets::file_name(std::path::Path::new(l)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            other => other.describe(),
        };
        ui.horizontal_wrapped(|ui| {
            ui.strong(format!("Recommended: {}", r.model));
            ui.label(format!(
                "worst raw ÷ corrected peak-to-peak {}, judged {judged}",
                crate::gui::plot_axes::ratio(r.worst_p2p_ratio),
            ));
            let chosen = self.selected.as_deref() == Some(r.model.as_str());
            if ui
                .add_enabled(!chosen, egui::Button::new("Adopt").small())
                .on_hover_text("Select it: its details are shown, and Export model… writes it")
                .clicked()
            {
                self.selected = Some(r.model.clone());
            }
        });
        if let Some(caution) = &r.caution {
            ui.colored_label(ui.visuals().warn_fg_color, format!("caution: {caution}"));
        }
        if let Some(f) = r.flight_form.as_ref().filter(|f| **f != r.model) {
            ui.weak(format!(
                "For a flight controller that takes a polynomial in T only: {f}"
            ));
        }
        self.beside_references(ui, r);
    }

    /// The firmware scripts' fits judged alike, set beside the recommendation, and whether it
    /// is at least as good as each.
    fn beside_references(&self, ui: &mut Ui, r: &crate::judge::recommend::Recommendation) {
        if r.references.is_empty() {
            return;
        }
        let rows: Vec<String> = r
            .references
            .iter()
            .map(|s| match s.worst_p2p_ratio {
                Some(x) => format!("{} {}", s.model, crate::gui::plot_axes::ratio(x)),
                None => format!("{} not judged", s.model),
            })
            .collect();
        let why: Vec<String> = r
            .references
            .iter()
            .filter_map(|s| s.why.as_ref().map(|w| format!("{}: {w}", s.model)))
            .collect();
        ui.horizontal_wrapped(|ui| {
            ui.label(format!(
                "Beside it, the firmware scripts judged alike (worst): {}",
                rows.join(", ")
            ))
            .on_hover_text(if why.is_empty() {
                "The fits PX4's and ArduPilot's own scripts make (their filtering and binning),                  judged on the same parts as the recommendation"
                    .to_string()
            } else {
                why.join("; ")
            });
            if let Some(v) = &r.against_references {
                let text = format!("{} {}", r.model, v.describe());
                if v.is_worse() {
                    ui.colored_label(ui.visuals().error_fg_color, text);
                } else {
                    ui.strong(text);
                }
            }
        });
    }
}

/// Names a combo box for screen readers (and tests).
fn accessible(r: &egui::Response, name: &str, value: &str) {
    r.widget_info(|| {
        let mut info = egui::WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, name);
        info.current_text_value = Some(value.to_string());
        info
    });
}

fn swatch(ui: &mut Ui, color: Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, color);
}

/// A swatch drawn as an outline: a reference row's.
fn hollow_swatch(ui: &mut Ui, color: Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
    ui.painter().rect_stroke(
        rect.shrink(1.0),
        2.0,
        egui::Stroke::new(2.0, color),
        egui::StrokeKind::Inside,
    );
}

/// One line: how many models are done, and Cancel.
fn progress(ui: &mut Ui, h: &CompareHandle) {
    ui.horizontal(|ui| {
        ui.label(format!(
            "fitting… {} of {} models done ({:.0} s)",
            h.done(),
            h.total,
            h.started.elapsed().as_secs_f64()
        ));
        cancel_button(ui, h);
    });
}

fn cancel_button(ui: &mut Ui, h: &CompareHandle) {
    if h.cancelled() {
        ui.weak("cancelling…");
    } else if ui
        .button("Cancel")
        .on_hover_text("Stop the comparison: models being fitted stop at their next step")
        .clicked()
    {
        h.cancel();
    }
}

/// Each model of a running comparison: waiting, fitting (with the share of its searches
/// done), done or failed, with its time.
fn model_progress(ui: &mut Ui, h: &CompareHandle) {
    use super::jobs::ModelProgress;
    egui::Grid::new("models_progress")
        .num_columns(3)
        .spacing([12.0, 4.0])
        .show(ui, |ui| {
            for (k, name) in h.names.iter().enumerate() {
                ui.monospace(name);
                match h.model(k) {
                    ModelProgress::Waiting => {
                        ui.weak("waiting for a core");
                        ui.label("");
                    }
                    ModelProgress::Fitting(share, since) => {
                        ui.add(
                            egui::ProgressBar::new(share as f32)
                                .desired_width(200.0)
                                .show_percentage(),
                        );
                        ui.weak(format!("{:.1} s", since.elapsed().as_secs_f64()));
                    }
                    ModelProgress::Done(s) => {
                        ui.label("fitted and judged");
                        ui.weak(format!("{s:.1} s"));
                    }
                    ModelProgress::Failed(s) => {
                        ui.colored_label(ui.visuals().error_fg_color, "not fitted");
                        ui.weak(format!("{s:.1} s"));
                    }
                    ModelProgress::Cancelled => {
                        ui.weak("cancelled");
                        ui.label("");
                    }
                }
                ui.end_row();
            }
        });
}

/// The engine's text with Ṫ and T̈ written as dT/dt and d²T/dt² (the workbench's fonts have
/// no glyphs for the dotted letters).
pub fn plain(s: &str) -> String {
    s.replace("T\u{308}", "d²T/dt²")
        .replace('\u{1E6A}', "dT/dt")
        .replace("T\u{307}", "dT/dt")
}

/// A message cut to `n` characters for a table cell (the whole of it is in the tooltip).
fn short(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_string()
    } else {
        format!("{}…", s.chars().take(n).collect::<String>())
    }
}

/// The logs of a comparison by file name, for messages.
pub fn log_names(train: &Log, tests: &[std::sync::Arc<Log>]) -> String {
    let name = |l: &Log| crate::gui::widgets::file_name(std::path::Path::new(&l.source));
    let mut s = name(train);
    for t in tests {
        s.push_str(" (held out: ");
        s.push_str(&name(t));
        s.push(')');
    }
    s
}
