//! The Allan page: the octave Allan deviation of the raw rate and of the rate corrected by
//! the current Vakhrameev calibration, on one log-log plot with their confidence intervals,
//! and the gyro read-outs (ARW, bias instability, RRW) of both.
//!
//! The deviations come from [`crate::judge::allan::allan`] on a worker
//! ([`super::jobs::Jobs::allan`]); this view asks for them when the calibration or the log
//! shown changes, and draws what came back.

use super::action::Action;
use super::jobs::AllanView as AllanData;
use super::plot_items::{Palette, num};
use super::state::AppState;
use crate::judge::allan::{AllanDeviation, Readout};
use eframe::egui::{self, Color32, Grid, Panel, RichText, Ui};
use egui_plot::{Corner, FilledArea, GridInput, GridMark, Legend, Line, Plot, PlotPoints, Points};
use std::ops::RangeInclusive;

/// View state of the Allan page.
#[derive(Debug, Default)]
pub struct AllanPage {
    /// Show the validation log rather than the calibration log.
    pub validation: bool,
}

impl AllanPage {
    /// What the page needs computed now: `(fit generation, validation)`, when a calibration
    /// exists for the log chosen.
    pub fn wanted(&mut self, state: &AppState) -> Option<(u64, bool)> {
        let fit = state.shown.fit.as_ref()?;
        if fit.outcome.held_out.is_none() {
            self.validation = false;
        }
        Some((fit.generation, self.validation))
    }

    /// The page.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, running: bool) -> Vec<Action> {
        let mut out = Vec::new();
        let has_val = state
            .shown
            .fit
            .as_ref()
            .is_some_and(|f| f.outcome.held_out.is_some());
        let data = state.shown.allan.clone();
        Panel::right("allan_readouts")
            .default_size(400.0)
            .size_range(320.0..=640.0)
            .show(ui, |ui| {
                ui.set_min_width(ui.available_width());
                readouts(ui, data.as_deref())
            });
        egui::CentralPanel::default().show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.strong(match state.active_axis_name() {
                    Some(axis) => format!("Allan deviation of axis {axis}, raw and corrected"),
                    None => "Allan deviation, raw and corrected".to_string(),
                })
                .on_hover_text(
                    "Octave τ, overlapping estimator, 68.3 % confidence intervals (shaded); \
                     the corrected rate is the calibration log's (or the validation log's) \
                     rate corrected by the calibration of the Calibration page",
                );
                ui.separator();
                ui.radio_value(&mut self.validation, false, "calibration log")
                    .on_hover_text("The log the calibration was fitted on");
                ui.add_enabled_ui(has_val, |ui| {
                    ui.radio_value(&mut self.validation, true, "validation log")
                        .on_hover_text("The held-out log, corrected with the same calibration");
                });
                if !has_val
                    && ui
                        .add_enabled(
                            state.shown.log.is_some(),
                            egui::Button::new("Open validation log…"),
                        )
                        .clicked()
                {
                    out.push(Action::OpenValidation);
                }
                if running {
                    ui.spinner().on_hover_text("Computing on a worker thread");
                }
            });
            match (&state.shown.fit, &data) {
                (None, _) => {
                    ui.weak("The Allan deviations appear once the log is calibrated.");
                }
                (Some(_), None) => {
                    ui.horizontal(|ui| {
                        ui.spinner();
                        ui.label("computing…");
                    });
                }
                (Some(_), Some(d)) => plot(ui, d),
            }
        });
        out
    }
}

/// The log-log plot: log10 of τ and σ on the axes, labelled in decades.
fn plot(ui: &mut Ui, d: &AllanData) {
    let pal = Palette::of(ui);
    let series: [(&str, &Result<AllanDeviation, String>, Color32); 2] = [
        (
            "raw",
            &d.raw,
            if ui.visuals().dark_mode {
                Color32::from_gray(200)
            } else {
                Color32::from_gray(80)
            },
        ),
        ("corrected", &d.corrected, pal.corrected),
    ];
    for (name, r, _) in &series {
        if let Err(e) = r {
            ui.colored_label(ui.visuals().error_fg_color, format!("{name}: {e}"));
        }
    }
    Plot::new("allan_plot")
        .height(ui.available_height().max(160.0))
        .legend(
            // Bottom left: the curves start high at short τ, so that corner stays clear.
            Legend::default()
                .position(Corner::LeftBottom)
                .follow_insertion_order(true)
                .color_conflict_handling(egui_plot::ColorConflictHandling::PickLast),
        )
        .x_axis_label("τ, s")
        .y_axis_label("σ(τ), °/h")
        .y_axis_min_width(72.0)
        .x_grid_spacer(decades)
        .y_grid_spacer(decades)
        .x_axis_formatter(decade_label)
        .y_axis_formatter(decade_label)
        .label_formatter(|pos| {
            let p = match pos {
                egui_plot::HoverPosition::NearDataPoint { position, .. }
                | egui_plot::HoverPosition::Elsewhere { position } => *position,
            };
            Some(format!(
                "τ = {} s\nσ = {} °/h",
                num(10f64.powf(p.x)),
                num(10f64.powf(p.y))
            ))
        })
        .show(ui, |pui| {
            for (name, r, color) in series {
                let Ok(dev) = r else {
                    continue;
                };
                let pts: Vec<[f64; 2]> = dev
                    .points
                    .iter()
                    .filter(|p| p.adev > 0.0 && p.tau_s > 0.0)
                    .map(|p| [p.tau_s.log10(), p.adev.log10()])
                    .collect();
                let (mut xs, mut lo, mut hi) = (Vec::new(), Vec::new(), Vec::new());
                for p in &dev.points {
                    if let (Some(a), Some(b)) = (p.adev_min, p.adev_max)
                        && a > 0.0
                        && b > 0.0
                        && p.tau_s > 0.0
                    {
                        xs.push(p.tau_s.log10());
                        lo.push(a.log10());
                        hi.push(b.log10());
                    }
                }
                if xs.len() >= 2 {
                    pui.add(
                        FilledArea::new(name, &xs, &lo, &hi)
                            .fill_color(color.gamma_multiply(0.22))
                            .allow_hover(false),
                    );
                }
                pui.line(
                    Line::new(name, PlotPoints::from(pts.clone()))
                        .color(color)
                        .width(1.8),
                );
                pui.add(
                    Points::new(name, PlotPoints::from(pts))
                        .color(color)
                        .radius(2.5),
                );
            }
        });
}

/// Grid lines at every decade (thick), at 2 and 5 times each decade (medium) and at the other
/// multiples (thin), on an axis of log10 values.
fn decades(input: GridInput) -> Vec<GridMark> {
    let (a, b) = input.bounds;
    if !(a.is_finite() && b.is_finite()) || b - a > 60.0 {
        return Vec::new();
    }
    let mut marks = Vec::new();
    let wide = b - a > 6.0;
    let mut d = a.floor();
    while d <= b.ceil() {
        marks.push(GridMark {
            value: d,
            step_size: 1.0,
        });
        if !wide {
            for k in 2..=9 {
                marks.push(GridMark {
                    value: d + f64::from(k).log10(),
                    step_size: if k == 2 || k == 5 { 0.5 } else { 0.1 },
                });
            }
        }
        d += 1.0;
    }
    marks
}

/// Decades labelled as plain numbers (1, 10, 0.01, 1e5); 2 and 5 times a decade too when the
/// axis spans under three decades; the other marks unlabelled.
fn decade_label(mark: GridMark, range: &RangeInclusive<f64>) -> String {
    let span = range.end() - range.start();
    if mark.step_size < 0.5 || (mark.step_size < 1.0 && span > 3.0) {
        return String::new();
    }
    // A label whose tick is at an end of the axis would be cut in half by the plot's edge.
    if !crate::gui::plot_items::label_fits(mark.value, range, 0.04) {
        return String::new();
    }
    let d = mark.value.floor() as i32;
    let k = 10f64.powf(mark.value - f64::from(d)).round();
    if (-4..=4).contains(&d) {
        let v = k * 10f64.powi(d);
        if d >= 0 {
            format!("{v:.0}")
        } else {
            format!("{v:.*}", (-d) as usize)
        }
    } else {
        format!("{k:.0}e{d}")
    }
}

fn readouts(ui: &mut Ui, d: Option<&AllanData>) {
    ui.heading("Read-outs");
    let Some(d) = d else {
        ui.weak("ARW, bias instability and RRW, raw and corrected, appear here.");
        return;
    };
    let name = crate::gui::widgets::file_name(std::path::Path::new(&d.source));
    ui.weak(format!(
        "{name}: samples from {} on (the correction's warm-up left out of both curves); \
         computed in {:.0} ms",
        d.from_sample,
        d.seconds * 1000.0
    ));
    ui.add_space(4.0);
    let get = |r: &Result<AllanDeviation, String>, k: usize| -> Option<Readout> {
        let o = &r.as_ref().ok()?.readouts;
        match k {
            0 => o.arw.clone(),
            1 => o.bias_instability.clone(),
            _ => o.rrw.clone(),
        }
    };
    Grid::new("allan_readouts_grid")
        .striped(true)
        .num_columns(3)
        .spacing([14.0, 4.0])
        .show(ui, |ui| {
            ui.label("");
            ui.label(RichText::new("raw").strong());
            ui.label(RichText::new("corrected").strong());
            ui.end_row();
            for (k, (name, unit, tip, missing)) in [
                (
                    "ARW",
                    "°/√h",
                    "Angle random walk: σ at τ = 1 s on the −1/2 line, ÷ 60",
                    "— no −1/2 slope",
                ),
                (
                    "bias instability",
                    "°/h",
                    "Minimum of the curve ÷ 0.664, when the curve rises again after it",
                    "— no minimum",
                ),
                (
                    "RRW",
                    "°/h/√h",
                    "Rate random walk: 60 × σ at τ = 3 s on the +1/2 line",
                    "— no +1/2 slope",
                ),
            ]
            .into_iter()
            .enumerate()
            {
                ui.label(name).on_hover_text(tip);
                for r in [&d.raw, &d.corrected] {
                    match get(r, k) {
                        Some(ro) => {
                            let mark = if ro.extrapolated { " *" } else { "" };
                            ui.monospace(format!("{} {unit}{mark}", num(ro.value)))
                                .on_hover_text(&ro.method);
                        }
                        None => {
                            ui.weak(missing).on_hover_text(
                                "The curve shows no such region over the τ it covers: the \
                                 figure cannot be read off it (a longer log may show it)",
                            );
                        }
                    }
                }
                ui.end_row();
            }
        });
    ui.add_space(4.0);
    ui.weak("* read off a line outside the τ range it was fitted on. Hover a value for how it was read.");
    ui.weak("The thermal drift a calibration removes sits at long τ: compare the right-hand end of the two curves.");
}
