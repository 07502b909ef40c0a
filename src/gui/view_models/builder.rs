//! The custom model's builder: the terms an engineer ticks, the delay τd and the lag of T, and
//! the [`RegressionSpec`] they make.

use super::ModelsView;
use super::{accessible, plain};
use crate::gui::state::AppState;
use crate::models::regression::{
    DELAY_SEARCH_MAX_S, DelaySpec, FitSamples, LAG_SEARCH_MAX_S, LagSpec, RegressionSpec, Term,
};
use eframe::egui::{self, Grid, RichText, Ui};

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
    /// Which samples the coefficients are fitted on.
    pub samples: FitSamples,
}

impl Default for CustomBuilder {
    fn default() -> Self {
        CustomBuilder {
            enabled: false,
            name: "custom".into(),
            terms: vec![Term::One, Term::T, Term::Tdot, Term::TTdot],
            delay: DelayChoice::None,
            delay_s: 300.0,
            delay_max_s: DELAY_SEARCH_MAX_S,
            bands: 3,
            lag: LagChoice::None,
            lag_s: 600.0,
            lag_max_s: LAG_SEARCH_MAX_S,
            lag_with_temperature: true,
            samples: FitSamples::All,
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
        s.samples = self.samples;
        s.validate()?;
        Ok(s)
    }
}

impl ModelsView {
    pub(super) fn builder(&mut self, ui: &mut Ui, state: &AppState) {
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
                .shown
                .log
                .as_ref()
                .map(|l| l.log.extra.iter().map(|c| c.name.clone()).collect())
                .unwrap_or_default();
            ui.label("Terms").on_hover_text(
                "One coefficient each, fitted by least squares on the samples \"Fit on\" chooses",
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
                            DelayChoice::Fixed => seconds(ui, &mut b.delay_s, "", "τd, s"),
                            DelayChoice::Search => {
                                seconds(ui, &mut b.delay_max_s, "up to ", "Longest delay tried, s");
                            }
                            DelayChoice::Bands => {
                                ui.add(
                                    egui::DragValue::new(&mut b.bands)
                                        .range(1..=20)
                                        .suffix(" bands"),
                                )
                                .on_hover_text("Equal-width temperature bands");
                                seconds(ui, &mut b.delay_max_s, "up to ", "Longest delay tried, s");
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
                            LagChoice::Fixed => seconds(ui, &mut b.lag_s, "", "Time constant, s"),
                            LagChoice::Search => {
                                seconds(
                                    ui,
                                    &mut b.lag_max_s,
                                    "up to ",
                                    "Longest time constant tried, s",
                                );
                                ui.checkbox(&mut b.lag_with_temperature, "with T")
                                    .on_hover_text(
                                        "Also search how the time constant shrinks as the gyro \
                                         warms: τ20 / (1 + β·(T − 20 °C))",
                                    );
                            }
                        }
                    });
                    ui.end_row();
                    ui.label("Fit on").on_hover_text(
                        "Which samples the coefficients are fitted on (searches are judged on \
                         every sample)",
                    );
                    let r = egui::ComboBox::from_id_salt("custom_fit")
                        .width(90.0)
                        .selected_text(fit_name(b.samples))
                        .show_ui(ui, |ui| {
                            ui.selectable_value(&mut b.samples, FitSamples::All, "all samples")
                                .on_hover_text("Every sample with a full rate history");
                            ui.selectable_value(&mut b.samples, FitSamples::Plateaus, "plateaus")
                                .on_hover_text(
                                    "The temperature plateaus only: for a model of the static \
                                     bias",
                                );
                            ui.selectable_value(&mut b.samples, FitSamples::Staged, "staged")
                                .on_hover_text(
                                    "Static terms on the plateaus, then the rate terms on what \
                                     they leave, as Vakhrameev calibrates",
                                );
                        })
                        .response;
                    accessible(&r, "Fit on", fit_name(b.samples));
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
}

fn delay_name(d: DelayChoice) -> &'static str {
    match d {
        DelayChoice::None => "none",
        DelayChoice::Fixed => "fixed",
        DelayChoice::Search => "search",
        DelayChoice::Bands => "bands",
    }
}

fn fit_name(f: FitSamples) -> &'static str {
    match f {
        FitSamples::All => "all samples",
        FitSamples::Plateaus => "plateaus",
        FitSamples::Staged => "staged",
    }
}

fn lag_name(l: LagChoice) -> &'static str {
    match l {
        LagChoice::None => "none",
        LagChoice::Fixed => "fixed",
        LagChoice::Search => "search",
    }
}

/// A duration field of up to a day: a given value (from 0 s) or, with a prefix such as
/// "up to ", the longest one a search tries (from 1 s).
fn seconds(ui: &mut Ui, v: &mut f64, prefix: &str, hover: &str) {
    let min = if prefix.is_empty() { 0.0 } else { 1.0 };
    ui.add(
        egui::DragValue::new(v)
            .range(min..=86_400.0)
            .prefix(prefix)
            .suffix(" s"),
    )
    .on_hover_text(hover);
}
