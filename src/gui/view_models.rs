//! The Models page: the models of the papers and one built term by term, fitted on the
//! calibration log and judged on it and on the validation log (what `driftlab compare`
//! prints), their corrected drifts overlaid on one plot, what a regression model found
//! (coefficients, λ, τd, lag and the cost curves of its searches), and which model to export.
//!
//! The view holds the choices and what is selected; the comparison runs on a worker
//! ([`super::jobs::Jobs::compare`]) and comes back as [`Compared`] in the application data.

use super::app::Action;
use super::jobs::{CompareHandle, Compared};
use super::plot_items::{BandItem, Palette, TimeScale, num, ratio};
use super::state::AppState;
use crate::compare::{ModelReport, Outcome};
use crate::drift_model::DriftModel;
use crate::log::Log;
use crate::presets::{ModelChoice, Preset};
use crate::regression::{DelaySpec, LagSpec, RegressionModel, RegressionSpec, Term};
use eframe::egui::{self, Color32, Grid, Panel, RichText, ScrollArea, Ui, Vec2b};
use egui_plot::{Corner, Legend, Line, Plot, PlotPoints, Points, VLine};

/// How the builder's delay τd is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DelayChoice {
    /// No delay.
    None,
    /// A given delay.
    Fixed,
    /// One delay searched.
    Search,
    /// One delay per temperature band.
    Bands,
}

/// How the builder's lag of T is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LagChoice {
    /// T as measured.
    None,
    /// A given time constant.
    Fixed,
    /// Searched.
    Search,
}

/// The custom model as the engineer composes it.
#[derive(Debug, Clone, PartialEq)]
pub struct CustomBuilder {
    /// Compare it too.
    pub enabled: bool,
    /// Its name in tables and files.
    pub name: String,
    /// The terms ticked.
    pub terms: Vec<Term>,
    /// How τd is chosen.
    pub delay: DelayChoice,
    /// τd when fixed, s.
    pub delay_s: f64,
    /// Longest τd tried when searched, s.
    pub delay_max_s: f64,
    /// Temperature bands when τd is found per band.
    pub bands: usize,
    /// How the lag is chosen.
    pub lag: LagChoice,
    /// The lag when fixed, s.
    pub lag_s: f64,
    /// Longest lag tried when searched, s.
    pub lag_max_s: f64,
    /// Whether the search also finds how the lag changes with temperature.
    pub lag_with_temperature: bool,
}

impl Default for CustomBuilder {
    fn default() -> Self {
        CustomBuilder {
            enabled: false,
            name: "custom".into(),
            terms: vec![Term::One, Term::T, Term::Tdot, Term::TTdot],
            delay: DelayChoice::None,
            delay_s: 300.0,
            delay_max_s: 1800.0,
            bands: 3,
            lag: LagChoice::None,
            lag_s: 600.0,
            lag_max_s: 3600.0,
            lag_with_temperature: true,
        }
    }
}

impl CustomBuilder {
    /// The spec the builder describes, checked by the engine.
    ///
    /// # Errors
    /// No terms, no name, or what [`RegressionSpec::validate`] finds.
    pub fn spec(&self) -> Result<RegressionSpec, String> {
        let name = self.name.trim();
        if name.is_empty() {
            return Err("the custom model needs a name".into());
        }
        let mut s = RegressionSpec::new(name, self.terms.clone());
        s.delay = match self.delay {
            DelayChoice::None => DelaySpec::None,
            DelayChoice::Fixed => DelaySpec::Fixed {
                seconds: self.delay_s,
            },
            DelayChoice::Search => DelaySpec::Search {
                max_s: self.delay_max_s,
            },
            DelayChoice::Bands => DelaySpec::Bands {
                bands: self.bands,
                max_s: self.delay_max_s,
            },
        };
        s.lag = match self.lag {
            LagChoice::None => LagSpec::None,
            LagChoice::Fixed => LagSpec::Fixed {
                seconds: self.lag_s,
                per_c: 0.0,
            },
            LagChoice::Search => LagSpec::Search {
                max_s: self.lag_max_s,
                with_temperature: self.lag_with_temperature,
            },
        };
        s.validate()?;
        Ok(s)
    }
}

/// View state of the Models page.
pub struct ModelsView {
    /// Which presets are compared, in [`Preset::ALL`] order.
    pub presets: [bool; Preset::ALL.len()],
    /// The custom model.
    pub custom: CustomBuilder,
    /// The model whose details are shown (by name).
    pub selected: Option<String>,
    /// The model to export (by name).
    pub export: Option<String>,
    /// Which log of the comparison the plot shows (0: the calibration log).
    pub log_index: usize,
}

impl Default for ModelsView {
    fn default() -> Self {
        ModelsView {
            presets: [true; Preset::ALL.len()],
            custom: CustomBuilder::default(),
            selected: None,
            export: None,
            log_index: 0,
        }
    }
}

/// Colours of the models, by their place in the comparison: distinct from each other and
/// from the grey of the raw drift, on light and dark backgrounds.
pub fn model_color(k: usize, dark: bool) -> Color32 {
    const LIGHT: [Color32; 9] = [
        Color32::from_rgb(31, 119, 180),
        Color32::from_rgb(230, 110, 0),
        Color32::from_rgb(40, 150, 40),
        Color32::from_rgb(214, 39, 40),
        Color32::from_rgb(148, 103, 189),
        Color32::from_rgb(140, 86, 75),
        Color32::from_rgb(210, 90, 180),
        Color32::from_rgb(150, 150, 20),
        Color32::from_rgb(20, 170, 190),
    ];
    const DARK: [Color32; 9] = [
        Color32::from_rgb(90, 170, 255),
        Color32::from_rgb(255, 160, 60),
        Color32::from_rgb(100, 210, 100),
        Color32::from_rgb(255, 100, 100),
        Color32::from_rgb(190, 150, 255),
        Color32::from_rgb(205, 150, 120),
        Color32::from_rgb(255, 140, 220),
        Color32::from_rgb(215, 215, 70),
        Color32::from_rgb(70, 220, 235),
    ];
    if dark {
        DARK[k % DARK.len()]
    } else {
        LIGHT[k % LIGHT.len()]
    }
}

impl ModelsView {
    /// The models ticked, in table order (presets, then the custom model).
    ///
    /// # Errors
    /// Nothing ticked, or a custom model the engine would refuse.
    pub fn choices(&self) -> Result<Vec<ModelChoice>, String> {
        let mut out: Vec<ModelChoice> = Preset::ALL
            .iter()
            .zip(self.presets)
            .filter(|(_, on)| *on)
            .map(|(p, _)| ModelChoice::Preset(*p))
            .collect();
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

    /// Keeps the selection and the export choice on models of the newest comparison.
    pub fn adopt(&mut self, c: &Compared) {
        let fitted = |n: &Option<String>| {
            n.as_ref().is_some_and(|n| {
                c.reports
                    .iter()
                    .any(|r| &r.model == n && r.fitted.is_some())
            })
        };
        let first_regression = c
            .reports
            .iter()
            .find(|r| matches!(r.fitted, Some(DriftModel::Regression(_))))
            .or_else(|| c.reports.iter().find(|r| r.fitted.is_some()))
            .map(|r| r.model.clone());
        let listed = |n: &Option<String>| {
            n.as_ref()
                .is_some_and(|n| c.reports.iter().any(|r| &r.model == n))
        };
        if !listed(&self.selected) {
            self.selected = first_regression.clone();
        }
        if !fitted(&self.export) {
            self.export = first_regression;
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
        out: &mut Vec<Action>,
    ) {
        Panel::left("models_choose")
            .default_size(300.0)
            .size_range(260.0..=460.0)
            .show(ui, |ui| {
                ScrollArea::vertical()
                    .id_salt("models_choose_scroll")
                    .show(ui, |ui| self.choose(ui, state, running, out));
            });
        Panel::right("models_detail")
            .default_size(440.0)
            .size_range(320.0..=720.0)
            .show(ui, |ui| {
                ScrollArea::vertical()
                    .id_salt("models_detail_scroll")
                    .show(ui, |ui| self.detail(ui, state, out));
            });
        egui::CentralPanel::default().show(ui, |ui| {
            let Some(c) = state.models.clone() else {
                ui.add_space(12.0);
                match running {
                    Some(h) => progress(ui, h),
                    None => {
                        if let Some(e) = &state.models_error {
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
            let rows = 2 + c
                .reports
                .iter()
                .map(|r| r.logs.len().max(1) + usize::from(r.error.is_some()))
                .sum::<usize>();
            let table_h = (rows as f32 * row_h).clamp(120.0, ui.available_height() * 0.55);
            ScrollArea::both()
                .id_salt("models_table_scroll")
                .max_height(table_h)
                .auto_shrink([false, true])
                .show(ui, |ui| self.table(ui, &c));
            ui.separator();
            self.plot(ui, &c);
        });
    }

    fn choose(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        running: Option<&CompareHandle>,
        out: &mut Vec<Action>,
    ) {
        ui.heading("Models");
        ui.label("Fitted on the calibration log, judged on it and on the validation log.");
        ui.add_space(4.0);
        ui.strong("Presets");
        for (k, p) in Preset::ALL.iter().enumerate() {
            ui.checkbox(&mut self.presets[k], p.name())
                .on_hover_text(plain(p.describe()));
        }
        ui.horizontal(|ui| {
            if ui.small_button("all").clicked() {
                self.presets = [true; Preset::ALL.len()];
            }
            if ui.small_button("none").clicked() {
                self.presets = [false; Preset::ALL.len()];
            }
        });
        ui.separator();
        self.builder(ui, state);
        ui.separator();
        let choices = self.choices();
        let can = state.log.is_some() && choices.is_ok() && running.is_none();
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
                ui.spinner();
                ui.label(format!("{} of {} fitted", h.done(), h.total));
            }
        });
        if let Err(e) = &choices {
            ui.colored_label(ui.visuals().warn_fg_color, e);
        }
        let name = |l: &Option<super::jobs::Loaded>| {
            l.as_ref()
                .and_then(|l| l.path.file_name())
                .map(|s| s.to_string_lossy().into_owned())
        };
        match name(&state.log) {
            Some(n) => ui.weak(format!("Fitted on: {n}")),
            None => ui.weak("Open a log first."),
        };
        match name(&state.validation) {
            Some(n) => {
                ui.weak(format!("Held out: {n}"));
            }
            None => {
                ui.horizontal(|ui| {
                    ui.weak("Held out: none");
                    if ui
                        .add_enabled(state.log.is_some(), egui::Button::new("Open…").small())
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
        ui.weak(format!(
            "The Vakhrameev model uses the recipe of the Calibration page (knots moved by hand \
             are not part of it); the figures filter the drift over {} s.",
            num(state.recipe().filter_s)
        ));
    }

    fn builder(&mut self, ui: &mut Ui, state: &AppState) {
        let b = &mut self.custom;
        ui.checkbox(&mut b.enabled, RichText::new("Custom model").strong())
            .on_hover_text("Compose a model term by term and compare it with the presets");
        ui.add_enabled_ui(b.enabled, |ui| {
            ui.horizontal(|ui| {
                ui.label("Name");
                ui.add(
                    egui::TextEdit::singleline(&mut b.name)
                        .desired_width(150.0)
                        .hint_text("custom"),
                )
                .on_hover_text("The model's name in the table and in its calibration file");
            });
            let channels: Vec<String> = state
                .log
                .as_ref()
                .map(|l| l.log.extra.iter().map(|c| c.name.clone()).collect())
                .unwrap_or_default();
            ui.label("Terms").on_hover_text(
                "One coefficient each, fitted by least squares over every usable sample",
            );
            let (base, chans): (Vec<Term>, Vec<Term>) = Term::catalogue(&channels)
                .into_iter()
                .partition(|t| !matches!(t, Term::Channel { .. }));
            let mut tick = |ui: &mut Ui, term: Term| {
                let mut on = b.terms.contains(&term);
                if ui
                    .checkbox(&mut on, term.to_string())
                    .on_hover_text(plain(&term.describe()))
                    .changed()
                {
                    if on {
                        b.terms.push(term);
                    } else {
                        b.terms.retain(|t| *t != term);
                    }
                }
            };
            Grid::new("custom_terms")
                .num_columns(2)
                .spacing([10.0, 2.0])
                .show(ui, |ui| {
                    for (k, term) in base.into_iter().enumerate() {
                        tick(ui, term);
                        if k % 2 == 1 {
                            ui.end_row();
                        }
                    }
                });
            // A channel's name is long: its terms get a line each.
            for term in chans {
                tick(ui, term);
            }
            Grid::new("custom_params")
                .num_columns(2)
                .spacing([8.0, 4.0])
                .show(ui, |ui| {
                    ui.label("Delay τd").on_hover_text(
                        "Delay of T and dT/dt behind the gyro's response (Yan 2019)",
                    );
                    ui.horizontal(|ui| {
                        let r = egui::ComboBox::from_id_salt("custom_delay")
                            .width(90.0)
                            .selected_text(delay_name(b.delay))
                            .show_ui(ui, |ui| {
                                ui.selectable_value(&mut b.delay, DelayChoice::None, "none");
                                ui.selectable_value(&mut b.delay, DelayChoice::Fixed, "fixed")
                                    .on_hover_text("A given delay");
                                ui.selectable_value(&mut b.delay, DelayChoice::Search, "search")
                                    .on_hover_text("One delay for the whole log, searched");
                                ui.selectable_value(&mut b.delay, DelayChoice::Bands, "bands")
                                    .on_hover_text(
                                        "One delay per temperature band, searched, then τd(T)",
                                    );
                            })
                            .response;
                        accessible(&r, "Delay τd", delay_name(b.delay));
                        match b.delay {
                            DelayChoice::None => {}
                            DelayChoice::Fixed => {
                                ui.add(
                                    egui::DragValue::new(&mut b.delay_s)
                                        .range(0.0..=86_400.0)
                                        .suffix(" s"),
                                )
                                .on_hover_text("τd, s");
                            }
                            DelayChoice::Search => {
                                ui.add(
                                    egui::DragValue::new(&mut b.delay_max_s)
                                        .range(1.0..=86_400.0)
                                        .prefix("up to ")
                                        .suffix(" s"),
                                )
                                .on_hover_text("Longest delay tried, s");
                            }
                            DelayChoice::Bands => {
                                ui.add(
                                    egui::DragValue::new(&mut b.bands)
                                        .range(1..=20)
                                        .suffix(" bands"),
                                )
                                .on_hover_text("Equal-width temperature bands");
                                ui.add(
                                    egui::DragValue::new(&mut b.delay_max_s)
                                        .range(1.0..=86_400.0)
                                        .prefix("up to ")
                                        .suffix(" s"),
                                )
                                .on_hover_text("Longest delay tried, s");
                            }
                        }
                    });
                    ui.end_row();
                    ui.label("Lag of T").on_hover_text(
                        "T read through a first-order lag: the temperature inside the gyro \
                         estimated from a sensor on its housing",
                    );
                    ui.horizontal(|ui| {
                        let r = egui::ComboBox::from_id_salt("custom_lag")
                            .width(90.0)
                            .selected_text(lag_name(b.lag))
                            .show_ui(ui, |ui| {
                                ui.selectable_value(&mut b.lag, LagChoice::None, "none");
                                ui.selectable_value(&mut b.lag, LagChoice::Fixed, "fixed")
                                    .on_hover_text("A given time constant");
                                ui.selectable_value(&mut b.lag, LagChoice::Search, "search")
                                    .on_hover_text("The time constant searched");
                            })
                            .response;
                        accessible(&r, "Lag of T", lag_name(b.lag));
                        match b.lag {
                            LagChoice::None => {}
                            LagChoice::Fixed => {
                                ui.add(
                                    egui::DragValue::new(&mut b.lag_s)
                                        .range(0.0..=86_400.0)
                                        .suffix(" s"),
                                )
                                .on_hover_text("Time constant, s");
                            }
                            LagChoice::Search => {
                                ui.add(
                                    egui::DragValue::new(&mut b.lag_max_s)
                                        .range(1.0..=86_400.0)
                                        .prefix("up to ")
                                        .suffix(" s"),
                                )
                                .on_hover_text("Longest time constant tried, s");
                                ui.checkbox(&mut b.lag_with_temperature, "with T")
                                    .on_hover_text(
                                        "Also search how the time constant shrinks as the gyro \
                                         warms: τ20 / (1 + β·(T − 20 °C))",
                                    );
                            }
                        }
                    });
                    ui.end_row();
                });
            if b.enabled {
                let terms = b
                    .terms
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(" + ");
                ui.weak(if terms.is_empty() {
                    "no terms ticked".to_string()
                } else {
                    format!("Ω = {terms}")
                });
            }
        });
    }

    fn stale_note(
        &self,
        ui: &mut Ui,
        state: &AppState,
        c: &Compared,
        running: Option<&CompareHandle>,
    ) {
        ui.horizontal(|ui| {
            ui.strong("Figures of the filtered drift, °/h")
                .on_hover_text(
                    "As `driftlab compare` prints them: ratio = raw ÷ corrected, above 1 is \
                     better; 10-min mean: largest |mean| over consecutive 10-minute windows; \
                     RMS: mean RMS within those windows; outside: share of samples beyond the \
                     ranges the model was fitted on",
                );
            ui.weak(format!(
                "{} model(s) in {:.1} s",
                c.reports.len(),
                c.seconds
            ));
            if let Some(h) = running {
                ui.separator();
                progress(ui, h);
            } else {
                let same_log = state
                    .log
                    .as_ref()
                    .is_some_and(|l| std::sync::Arc::ptr_eq(&l.log, &c.logs[0].log));
                let held: Vec<_> = c.logs.iter().skip(1).map(|l| &l.log).collect();
                let same_held = match &state.validation {
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
            if let Some(e) = &state.models_error {
                ui.colored_label(ui.visuals().error_fg_color, e);
            }
        });
    }

    fn table(&mut self, ui: &mut Ui, c: &Compared) {
        let dark = ui.visuals().dark_mode;
        let bad = ui.visuals().error_fg_color;
        Grid::new("models_table")
            .striped(true)
            .num_columns(10)
            .spacing([14.0, 3.0])
            .show(ui, |ui| {
                for (h, tip) in [
                    ("model", "Click a model to see what it found (right)"),
                    (
                        "log",
                        "In-sample: the log it was fitted on; held out: the validation log",
                    ),
                    ("p2p raw", "Peak-to-peak of the raw filtered drift, °/h"),
                    (
                        "p2p cor",
                        "Peak-to-peak of the corrected filtered drift, °/h",
                    ),
                    ("p2p", "Peak-to-peak ratio, raw ÷ corrected"),
                    ("std", "Standard-deviation ratio"),
                    ("10-min", "Ratio of the largest |10-minute mean|"),
                    ("RMS", "Ratio of the mean 10-minute RMS"),
                    ("outside", "Share of samples beyond the fitted input ranges"),
                ] {
                    ui.label(RichText::new(h).strong()).on_hover_text(tip);
                }
                ui.end_row();
                for (k, r) in c.reports.iter().enumerate() {
                    let color = model_color(k, dark);
                    let name = |ui: &mut Ui, this: &mut ModelsView| {
                        let sel = this.selected.as_deref() == Some(r.model.as_str());
                        ui.horizontal(|ui| {
                            swatch(ui, color);
                            if ui
                                .selectable_label(sel, RichText::new(&r.model).monospace())
                                .on_hover_text(plain(&r.description))
                                .clicked()
                            {
                                this.selected = Some(r.model.clone());
                            }
                        });
                    };
                    if let Some(e) = &r.error {
                        name(ui, self);
                        ui.colored_label(bad, "not fitted").on_hover_text(e);
                        ui.add(egui::Label::new(RichText::new(short(e, 70)).color(bad)))
                            .on_hover_text(e);
                        ui.end_row();
                        continue;
                    }
                    for (j, judged) in r.logs.iter().enumerate() {
                        if j == 0 {
                            name(ui, self);
                        } else {
                            ui.label("");
                        }
                        ui.label(if judged.held_out {
                            "held out"
                        } else {
                            "in-sample"
                        })
                        .on_hover_text(&judged.log);
                        match &judged.result {
                            Outcome::Evaluation(e) => {
                                let cmp = &e.comparison;
                                ui.monospace(num(cmp.raw.p2p_dph));
                                ui.monospace(num(cmp.corrected.p2p_dph));
                                for v in [
                                    cmp.p2p_ratio,
                                    cmp.std_ratio,
                                    cmp.win_mean_ratio,
                                    cmp.win_rms_ratio,
                                ] {
                                    let text = RichText::new(ratio(v)).monospace();
                                    ui.label(if v >= 1.0 { text } else { text.color(bad) });
                                }
                                ui.monospace(format!("{:.1}%", 100.0 * e.outside_fraction));
                            }
                            Outcome::Error(msg) => {
                                ui.colored_label(bad, "cannot apply").on_hover_text(msg);
                                ui.add(egui::Label::new(RichText::new(short(msg, 70)).color(bad)))
                                    .on_hover_text(msg);
                            }
                        }
                        ui.end_row();
                    }
                }
            });
        for r in c.reports.iter().filter(|r| r.error.is_some()) {
            ui.colored_label(
                bad,
                format!(
                    "{} not fitted: {}",
                    r.model,
                    r.error.as_deref().unwrap_or("")
                ),
            );
        }
    }

    fn plot(&mut self, ui: &mut Ui, c: &Compared) {
        let pal = Palette::of(ui);
        let dark = ui.visuals().dark_mode;
        ui.horizontal(|ui| {
            ui.strong("Corrected drift of each model").on_hover_text(
                "Ω filtered as for the figures: raw (grey) and corrected by each fitted model; \
                     click a name in the legend to hide it",
            );
            ui.separator();
            for (j, l) in c.logs.iter().enumerate() {
                let label = if l.held_out {
                    "validation log"
                } else {
                    "calibration log"
                };
                ui.radio_value(&mut self.log_index, j, label)
                    .on_hover_text(&l.log.source);
            }
        });
        let Some(cl) = c.logs.get(self.log_index) else {
            return;
        };
        let log = &cl.log;
        let n = log.len();
        if n == 0 || cl.raw_filtered_dph.len() != n {
            return;
        }
        let scale = TimeScale::for_duration(log.duration_s());
        let t_full = (log.time_s[0], log.time_s[n - 1]);
        let li = self.log_index;
        Plot::new("models_drift")
            .height(ui.available_height().max(120.0))
            .legend(
                Legend::default()
                    .position(Corner::LeftTop)
                    .follow_insertion_order(true),
            )
            .x_axis_label(format!("time, {}", scale.unit))
            .y_axis_label("drift, °/h")
            .y_axis_min_width(64.0)
            .y_axis_formatter(super::plot_items::tick)
            .x_grid_spacer(egui_plot::uniform_grid_spacer(
                super::plot_items::nice_steps_x,
            ))
            .y_grid_spacer(egui_plot::uniform_grid_spacer(
                super::plot_items::nice_steps,
            ))
            .allow_zoom(Vec2b::new(true, false))
            .allow_drag(Vec2b::new(true, false))
            .allow_scroll(Vec2b::new(true, false))
            .show(ui, |pui| {
                let b = pui.plot_bounds();
                let (x0, x1) = if b.is_valid_x() && b.width() > 0.0 {
                    (b.min()[0] * scale.div, b.max()[0] * scale.div)
                } else {
                    t_full
                };
                let cols = pui.response().rect.width().max(50.0) as usize;
                let raw = crate::lod::reduce(
                    &log.time_s,
                    &cl.raw_filtered_dph,
                    &cl.raw_lod,
                    x0,
                    x1,
                    cols,
                );
                pui.add(
                    BandItem::new("raw", raw, scale.div, t_full)
                        .color(pal.raw)
                        .width(1.6),
                );
                for (k, r) in c.reports.iter().enumerate() {
                    let Some(Some(s)) = c.series.get(k).and_then(|v| v.get(li)) else {
                        continue;
                    };
                    if s.cor_filtered_dph.len() != n {
                        continue;
                    }
                    let band =
                        crate::lod::reduce(&log.time_s, &s.cor_filtered_dph, &s.lod, x0, x1, cols);
                    pui.add(
                        BandItem::new(&r.model, band, scale.div, t_full)
                            .color(model_color(k, dark))
                            .width(1.4),
                    );
                }
            });
    }

    fn detail(&mut self, ui: &mut Ui, state: &AppState, out: &mut Vec<Action>) {
        let Some(c) = state.models.clone() else {
            ui.heading("Model");
            ui.weak("What each model found appears here after a comparison.");
            return;
        };
        let fitted: Vec<&ModelReport> = c.reports.iter().filter(|r| r.fitted.is_some()).collect();
        ui.horizontal(|ui| {
            ui.heading("Model");
            let shown = self.selected.clone().unwrap_or_else(|| "—".into());
            let r = egui::ComboBox::from_id_salt("models_selected")
                .selected_text(&shown)
                .show_ui(ui, |ui| {
                    for r in &c.reports {
                        ui.selectable_value(&mut self.selected, Some(r.model.clone()), &r.model);
                    }
                })
                .response;
            accessible(&r, "Model shown", &shown);
            r.on_hover_text("The model whose coefficients and searches are shown");
        });
        let report = self
            .selected
            .as_ref()
            .and_then(|n| c.reports.iter().find(|r| &r.model == n));
        match report {
            None => {
                ui.weak("Click a model in the table.");
            }
            Some(r) => {
                ui.label(plain(&r.description));
                match (&r.fitted, &r.error) {
                    (_, Some(e)) => {
                        ui.colored_label(ui.visuals().error_fg_color, format!("Not fitted: {e}"));
                    }
                    (Some(DriftModel::Regression(rc)), _) => regression_detail(ui, &rc.model),
                    (Some(DriftModel::Vakhrameev(cal)), _) => {
                        ui.label(format!(
                            "K0(T), K1±(dT/dt), K2±(d²T/dt²) fitted with the workbench's recipe on {} \
                             samples; the Calibration page shows and edits them.",
                            cal.source.samples
                        ));
                    }
                    (None, None) => {}
                }
            }
        }
        ui.separator();
        ui.heading("Export");
        if fitted.is_empty() {
            ui.weak("No model was fitted.");
            return;
        }
        ui.label("Model to write as a calibration file:");
        ui.horizontal_wrapped(|ui| {
            for r in &fitted {
                ui.radio_value(&mut self.export, Some(r.model.clone()), &r.model)
                    .on_hover_text(plain(&r.description));
            }
        });
        ui.add_space(4.0);
        if ui
            .add_enabled(self.export.is_some(), egui::Button::new("Export model…"))
            .on_hover_text(
                "Write the chosen model's calibration file (JSON), which `driftlab apply` and \
                 the gyro's processor read. File › Export calibration keeps writing the \
                 Vakhrameev calibration of the Calibration page.",
            )
            .clicked()
        {
            out.push(Action::ExportModel);
        }
    }
}

/// Coefficients with standard errors, the non-linear parameters found and the cost curves
/// of their searches.
fn regression_detail(ui: &mut Ui, m: &RegressionModel) {
    Grid::new("models_coefficients")
        .striped(true)
        .num_columns(3)
        .spacing([14.0, 2.0])
        .show(ui, |ui| {
            ui.label(RichText::new("term").strong());
            ui.label(RichText::new("coefficient").strong())
                .on_hover_text("°/h per unit of the term");
            ui.label(RichText::new("± std error").strong())
                .on_hover_text(
                    "White-noise assumption: correlated noise makes the real uncertainty larger",
                );
            ui.end_row();
            for (k, name) in m.names.iter().enumerate() {
                ui.monospace(name);
                ui.monospace(m.coefficients.get(k).copied().map(num).unwrap_or_default());
                ui.monospace(m.std_errors.get(k).copied().map(num).unwrap_or_default());
                ui.end_row();
            }
        });
    ui.add_space(4.0);
    Grid::new("models_found")
        .num_columns(2)
        .spacing([14.0, 2.0])
        .show(ui, |ui| {
            ui.label("λ (self-heating)");
            ui.monospace(m.lambda_s.map_or("—".into(), |v| format!("{} s", secs(v))));
            ui.end_row();
            ui.label("τd (delay)");
            ui.monospace(match m.delay.points.as_slice() {
                [] => "—".to_string(),
                [p] => format!("{} s", secs(p[1])),
                pts => pts
                    .iter()
                    .map(|p| format!("{} s at {:.1} °C", secs(p[1]), p[0]))
                    .collect::<Vec<_>>()
                    .join("\n"),
            });
            ui.end_row();
            ui.label("lag of T");
            ui.monospace(m.lag_s.map_or("—".into(), |v| format!("{} s", secs(v))));
            ui.end_row();
            if let Some(t2) = &m.temp2 {
                ui.label("second sensor");
                ui.monospace(t2);
                ui.end_row();
            }
            ui.label("fit").on_hover_text(
                "Samples, RMS residual of the raw rate (the gyro's noise is part of it), R²",
            );
            ui.monospace(format!(
                "{} samples, RMS {} °/h, R² {:.3}",
                m.stats.n,
                num(m.stats.rmse),
                m.stats.r2
            ));
            ui.end_row();
        });
    if m.searches.is_empty() {
        ui.weak("No parameter was searched.");
        return;
    }
    for s in m.searches.iter().filter(|s| s.at_edge) {
        let beyond = if s.best > 0.0 {
            ": the optimum may lie beyond it"
        } else {
            ""
        };
        ui.colored_label(
            ui.visuals().warn_fg_color,
            format!(
                "{}: the best value, {} s, is an end of the range searched{beyond}",
                s.parameter,
                secs(s.best)
            ),
        );
    }
    ui.add_space(4.0);
    ui.strong("Cost of the searches").on_hover_text(
        "RMS residual of the fit at each value tried; the dashed line marks the value chosen",
    );
    let dark = ui.visuals().dark_mode;
    // The key above the plot, not inside it: a cost curve may have its minimum anywhere.
    ui.horizontal_wrapped(|ui| {
        for (k, s) in m.searches.iter().enumerate() {
            swatch(ui, model_color(k, dark));
            ui.label(format!("{}: best {} s", s.parameter, secs(s.best)));
            ui.add_space(6.0);
        }
    });
    Plot::new("models_cost")
        .height(190.0)
        .x_axis_label("value tried, s")
        .y_axis_label("RMS, °/h")
        .y_axis_min_width(56.0)
        .y_axis_formatter(fixed_tick)
        .x_grid_spacer(egui_plot::uniform_grid_spacer(
            super::plot_items::nice_steps,
        ))
        .y_grid_spacer(egui_plot::uniform_grid_spacer(
            super::plot_items::nice_steps,
        ))
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .show(ui, |pui| {
            for (k, s) in m.searches.iter().enumerate() {
                let color = model_color(k, dark);
                let pts: Vec<[f64; 2]> = s.x.iter().zip(&s.rmse).map(|(&x, &y)| [x, y]).collect();
                pui.line(
                    Line::new(s.parameter.clone(), PlotPoints::from(pts.clone()))
                        .color(color)
                        .width(1.5),
                );
                pui.add(
                    Points::new(s.parameter.clone(), PlotPoints::from(pts))
                        .color(color)
                        .radius(2.0),
                );
                pui.add(
                    VLine::new(s.parameter.clone(), s.best)
                        .color(color)
                        .width(1.0)
                        .style(egui_plot::LineStyle::dashed_dense()),
                );
            }
        });
}

/// A tick label with as many decimals as the visible range needs, the same for every label,
/// never in scientific notation (the cost of a search often changes in its fourth digit only).
fn fixed_tick(mark: egui_plot::GridMark, range: &std::ops::RangeInclusive<f64>) -> String {
    let span = (range.end() - range.start()).abs() / 5.0;
    let decimals = if span > 0.0 && span.is_finite() {
        ((-span.log10().floor()).max(0.0) as usize).min(9)
    } else {
        4
    };
    format!("{:.decimals$}", mark.value)
}

/// Seconds as the details show them: 0 as "0", else about four significant digits.
fn secs(v: f64) -> String {
    if v == 0.0 { "0".into() } else { num(v) }
}

fn delay_name(d: DelayChoice) -> &'static str {
    match d {
        DelayChoice::None => "none",
        DelayChoice::Fixed => "fixed",
        DelayChoice::Search => "search",
        DelayChoice::Bands => "bands",
    }
}

fn lag_name(l: LagChoice) -> &'static str {
    match l {
        LagChoice::None => "none",
        LagChoice::Fixed => "fixed",
        LagChoice::Search => "search",
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

fn progress(ui: &mut Ui, h: &CompareHandle) {
    ui.horizontal(|ui| {
        ui.spinner();
        ui.label(format!(
            "fitting… {} of {} models done ({:.0} s)",
            h.done(),
            h.total,
            h.started.elapsed().as_secs_f64()
        ));
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
    let name = |l: &Log| {
        std::path::Path::new(&l.source)
            .file_name()
            .map_or(l.source.clone(), |s| s.to_string_lossy().into_owned())
    };
    let mut s = name(train);
    for t in tests {
        s.push_str(" (held out: ");
        s.push_str(&name(t));
        s.push(')');
    }
    s
}
