//! The table of the comparison: every model's figures of merit on each log, its ratios to raw,
//! and the choice of the model shown and exported.

use super::ModelsView;
use super::{hollow_swatch, model_color, plain, short, swatch};
use crate::gui::jobs::Compared;
use crate::gui::plot_items::{num, ratio};
use crate::judge::compare::Outcome;
use eframe::egui::{self, Grid, RichText, Ui};

/// What a reference row is.
const REFERENCE: &str = "the fit the flight controller's own script makes, with its filtering \
    and binning, shown beside driftlab's models and never recommended";

/// What the "outside" column means.
pub(super) const OUTSIDE: &str = "the share of the log's samples whose inputs (T, dT/dt, d²T/dt², the \
    channels) lay beyond the ranges the model was fitted on; there the model holds its edge \
    values instead of extrapolating";

impl ModelsView {
    pub(super) fn table(&mut self, ui: &mut Ui, c: &Compared) {
        let dark = ui.visuals().dark_mode;
        let bad = ui.visuals().error_fg_color;
        let window = crate::judge::options::window_label(c.window_s);
        let mean_label = format!("|{window} mean|");
        let rms_label = format!("{window} RMS");
        Grid::new("models_table")
            .striped(true)
            .num_columns(10)
            .spacing([10.0, 3.0])
            .show(ui, |ui| {
                // Two header rows: the four ratios are headed "raw ÷ corrected" above their
                // figure's name.
                let small = |ui: &mut Ui, s: &str| {
                    ui.label(RichText::new(s).small().weak());
                };
                for _ in 0..4 {
                    small(ui, "");
                }
                for _ in 0..4 {
                    small(ui, "raw ÷ corrected");
                }
                small(ui, "");
                ui.end_row();
                for (h, tip) in [
                    (
                        "model",
                        "Click a model to see what it found and to export it (right)",
                    ),
                    (
                        "log",
                        "In-sample: the log it was fitted on; held out: the validation log",
                    ),
                    ("p2p raw", "Peak-to-peak of the raw filtered drift, °/h"),
                    (
                        "p2p cor.",
                        "Peak-to-peak of the corrected filtered drift, °/h",
                    ),
                    (
                        "p2p",
                        "Peak-to-peak, raw ÷ corrected (above 1: the model helps)",
                    ),
                    ("std", "Standard deviation, raw ÷ corrected"),
                    (
                        &mean_label,
                        "Largest |mean| over the consecutive windows, raw ÷ corrected",
                    ),
                    (
                        &rms_label,
                        "Mean RMS within the consecutive windows, raw ÷ corrected",
                    ),
                    ("outside", OUTSIDE),
                ] {
                    ui.label(RichText::new(h).strong()).on_hover_text(tip);
                }
                ui.end_row();
                for (k, r) in c.reports.iter().enumerate() {
                    let color = model_color(k, dark);
                    let name = |ui: &mut Ui, this: &mut ModelsView| {
                        let sel = this.selected.as_deref() == Some(r.model.as_str());
                        ui.horizontal(|ui| {
                            // A reference row's swatch is hollow: a firmware script's fit,
                            // set beside and never recommended (said in the tip).
                            let tip = if r.reference {
                                format!("{} (reference: {REFERENCE})", plain(&r.description))
                            } else {
                                plain(&r.description)
                            };
                            if r.reference {
                                hollow_swatch(ui, color);
                            } else {
                                swatch(ui, color);
                            }
                            if ui
                                .selectable_label(sel, RichText::new(&r.model))
                                .on_hover_text(tip)
                                .clicked()
                            {
                                this.selected = Some(r.model.clone());
                            }
                        });
                    };
                    if let Some(e) = &r.error {
                        name(ui, self);
                        // The reason in the tip and in full under the table: written in a
                        // figure's column, it widened that column past the window.
                        ui.colored_label(bad, "not fitted").on_hover_text(e);
                        ui.end_row();
                        continue;
                    }
                    for (j, judged) in r.logs.iter().enumerate() {
                        if j == 0 {
                            name(ui, self);
                        } else {
                            ui.label("");
                        }
                        let hover = match &judged.cannot_tell {
                            Some(why) => format!(
                                "{}: cannot tell if it is the calibration log: {why}",
                                judged.log
                            ),
                            None => judged.log.clone(),
                        };
                        ui.label(judged.kind()).on_hover_text(hover);
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
                                    // Coloured by the value itself, shown to three digits:
                                    // a red ratio never reads 1.00×.
                                    let text = RichText::new(ratio(v)).monospace();
                                    ui.label(if v >= 1.0 { text } else { text.color(bad) })
                                        .on_hover_text(format!("raw ÷ corrected = {v}"));
                                }
                                ui.monospace(format!(
                                    "{}%",
                                    crate::number::percent(e.outside_fraction)
                                ))
                                .on_hover_text(OUTSIDE);
                            }
                            Outcome::Error(msg) => {
                                ui.colored_label(bad, "cannot apply").on_hover_text(msg);
                                ui.add(egui::Label::new(RichText::new(short(msg, 24)).color(bad)))
                                    .on_hover_text(msg);
                            }
                        }
                        ui.end_row();
                    }
                    if let Some(l) = &r.leave_one_run_out {
                        runs_left_out_rows(ui, l, bad);
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
}

/// A campaign's leave-one-run-out under a model's rows: the mean over the runs (the ratio of
/// the mean figures) and the worst run, in the peak-to-peak columns; each run's figures in the
/// tip.
fn runs_left_out_rows(
    ui: &mut Ui,
    l: &crate::judge::runs_left_out::LeaveOneRunOut,
    bad: egui::Color32,
) {
    let figure = |v: Option<f64>| v.map_or_else(|| "n/a".to_string(), num);
    let every: String = l
        .runs
        .iter()
        .map(|r| match &r.error {
            Some(e) => format!("{}: {e}", r.run),
            None => format!(
                "{}: raw {} → corrected {} °/h, {}",
                r.run,
                figure(r.raw_p2p_dph),
                figure(r.corrected_p2p_dph),
                r.p2p_ratio.map_or_else(|| "n/a".to_string(), ratio)
            ),
        })
        .collect::<Vec<_>>()
        .join("\n");
    let tip = format!(
        "Fitted on every run but one and judged on the one left out, for each run of the \
         campaign (peak-to-peak of the filtered drift):\n{every}"
    );
    let worst = l
        .runs
        .iter()
        .filter(|r| r.p2p_ratio.is_some_and(f64::is_finite))
        .min_by(|a, b| {
            a.p2p_ratio
                .unwrap_or(0.0)
                .total_cmp(&b.p2p_ratio.unwrap_or(0.0))
        });
    let rows = [
        (
            "runs left out, mean",
            l.mean_raw_p2p_dph,
            l.mean_corrected_p2p_dph,
            l.mean_p2p_ratio,
        ),
        (
            "runs left out, worst",
            worst.and_then(|r| r.raw_p2p_dph),
            worst.and_then(|r| r.corrected_p2p_dph),
            l.worst_p2p_ratio,
        ),
    ];
    for (label, raw, cor, r) in rows {
        ui.label("");
        ui.label(label).on_hover_text(&tip);
        ui.monospace(figure(raw));
        ui.monospace(figure(cor));
        match r {
            Some(v) => {
                let text = RichText::new(ratio(v)).monospace();
                ui.label(if v >= 1.0 { text } else { text.color(bad) })
                    .on_hover_text(&tip);
            }
            None => {
                ui.label(RichText::new("n/a").monospace())
                    .on_hover_text(&tip);
            }
        }
        ui.end_row();
    }
}
