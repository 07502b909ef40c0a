//! The table of the comparison: every model's figures of merit on each log, its ratios to raw,
//! and the choice of the model shown and exported.

use super::ModelsView;
use super::{model_color, plain, short, swatch};
use crate::gui::jobs::Compared;
use crate::gui::plot_items::{num, ratio};
use crate::judge::compare::Outcome;
use eframe::egui::{self, Grid, RichText, Ui};

impl ModelsView {
    pub(super) fn table(&mut self, ui: &mut Ui, c: &Compared) {
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
}
