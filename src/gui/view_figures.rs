//! The figures of merit below the Calibration page: peak-to-peak, standard deviation and the
//! 10-minute figures of the filtered drift, raw and corrected, with the reduction ratios,
//! in-sample and held out, and the last refit's time and warnings. With a calibration opened
//! to compare, each table has its figures in two more columns beside the current fit's.

use super::action::{Action, OpenLog};
use super::opened::{self, Column};
use super::plot_items::{num, ratio};
use super::state::AppState;
use crate::judge::metrics::Evaluation;
use crate::log::AxisKind;
use eframe::egui::{self, Grid, RichText, Ui};

/// The figures panel (no state of its own).
#[derive(Debug, Default)]
pub struct FiguresView;

impl FiguresView {
    /// The figures of merit, always visible: the in-sample and held-out tables side by side,
    /// or (`stacked`, in the controls panel of a short window) one above the other.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, stacked: bool) -> Vec<Action> {
        let Some(fit) = state.shown.fit.as_ref() else {
            ui.weak("Figures of merit appear once the log is calibrated.");
            return Vec::new();
        };
        // A unit's figures name the axis they are of.
        let axis = state
            .active_axis_name()
            .map(|a| format!(" · axis {a}"))
            .unwrap_or_default();
        let name = |l: &Option<super::jobs::Loaded>| {
            l.as_ref()
                .map(|l| format!("{}{axis}", l.name()))
                .unwrap_or_default()
        };
        // While a refit is on its way (a knot being dragged on a long log) the figures are those
        // of the choices a moment ago: shown greyed and marked, never passed off as the
        // current ones.
        let exact = state.fit_current();
        let window = crate::judge::options::window_label(state.merit().window_s);
        let opened_exact = opened::current(state);
        let opened_name = state.opened.as_ref().map(|o| o.name()).unwrap_or_default();
        let beside = |which| {
            opened::column(state, which).map(|column| Beside {
                column,
                exact: opened_exact,
                name: &opened_name,
            })
        };
        let body = |ui: &mut Ui| {
            table(
                ui,
                "fig_in",
                &format!("In-sample · {}", name(&state.shown.log)),
                &fit.outcome.in_sample.evaluation,
                exact,
                Scale::gyro(&window),
                beside(OpenLog::Calibration),
            );
            ui.separator();
            match &fit.outcome.held_out {
                Some(h) => {
                    // A log the calibration log's sketch cannot tell apart from it: its
                    // figures are shown, marked as perhaps not held out.
                    let title = match &state.validation_doubt {
                        Some(_) => format!("Held out? · {}", name(&state.shown.validation)),
                        None => format!("Held out · {}", name(&state.shown.validation)),
                    };
                    table(
                        ui,
                        "fig_out",
                        &title,
                        &h.evaluation,
                        exact,
                        Scale::gyro(&window),
                        beside(OpenLog::Validation),
                    );
                    if let Some(why) = &state.validation_doubt {
                        ui.add(
                            egui::Label::new(
                                RichText::new(format!(
                                    "Cannot tell if this is the calibration log: {why}"
                                ))
                                .color(ui.visuals().warn_fg_color),
                            )
                            .wrap(),
                        );
                    }
                }
                None => {
                    ui.vertical(|ui| {
                        ui.strong("Held out");
                        match state.validation_unmatched() {
                            // A validation log is open, but not of this axis: said, never
                            // judged on another axis.
                            Some(why) => {
                                ui.add(
                                    egui::Label::new(
                                        RichText::new(format!("Not judged: {why}"))
                                            .color(ui.visuals().warn_fg_color),
                                    )
                                    .wrap(),
                                );
                            }
                            None => {
                                ui.weak("Open a validation log (File › Open validation log…)\nto judge the calibration on a run it was not fitted on.");
                            }
                        }
                    });
                }
            }
            ui.separator();
            // Stacked, the refit time takes one line and the warnings are left to the banner.
            let refit = |ui: &mut Ui| {
                let t = fit.outcome.timings;
                ui.strong("Refit");
                ui.label(format!("{:.1} ms", t.total_ms)).on_hover_text(format!(
                    "Last refit on the worker thread: prepare {:.1} ms, plateaus {:.1} ms, K1/K2 {:.1} ms, \
                     correct {:.1} ms, figures {:.1} ms, validation {:.1} ms (0: reused)",
                    t.prepare_ms, t.plateaus_ms, t.fit_ms, t.correct_ms, t.evaluate_ms, t.validation_ms
                ));
            };
            if stacked {
                ui.horizontal(refit);
            } else {
                ui.vertical(|ui| {
                    refit(ui);
                    for w in fit.outcome.warnings.iter().take(3) {
                        ui.colored_label(ui.visuals().warn_fg_color, format!("! {w}"))
                            .on_hover_text(w.as_str());
                    }
                });
            }
        };
        if stacked {
            // Rows as tall as their text: the controls above keep the rest of the panel.
            ui.spacing_mut().interact_size.y = 14.0;
            ui.spacing_mut().item_spacing.y = 2.0;
            ui.vertical(body);
        } else {
            ui.horizontal_top(body);
        }
        Vec::new()
    }
}

/// A calibration opened to compare, as a table shows it beside the current fit.
struct Beside<'a> {
    /// Its figures on the table's log, or why there are none.
    column: Column<'a>,
    /// Whether they answer the logs and options shown (else a judging is on its way).
    exact: bool,
    /// Its file's name.
    name: &'a str,
}

/// What a table's figures are read over and in.
#[derive(Debug, Clone, Copy)]
pub struct Scale<'a> {
    /// The label of the figures' windows (`10-min`).
    pub window: &'a str,
    /// The kind of axis they are of: its unit heads the table, an accelerometer's figures
    /// to 10⁻⁶ m/s² as the command line prints them.
    pub kind: AxisKind,
}

impl<'a> Scale<'a> {
    /// A gyro axis's figures, in °/h.
    fn gyro(window: &'a str) -> Scale<'a> {
        Scale {
            window,
            kind: AxisKind::Gyro,
        }
    }

    /// A figure as the table writes it.
    fn number(&self, v: f64) -> String {
        match self.kind {
            AxisKind::Gyro => num(v),
            AxisKind::Accel => crate::number::fixed(v, 6),
        }
    }
}

/// One axis's figures on one log, titled `title`, as the figures panel draws them (the
/// accelerometer view's tables, in-sample and held out): raw, corrected and their ratio,
/// worse than raw in red; `exact` false greys them as provisional.
pub fn axis_table(ui: &mut Ui, id: &str, title: &str, e: &Evaluation, exact: bool, scale: Scale) {
    table(ui, id, title, e, exact, scale, None);
}

/// `scale`: the figures' windows and unit; `beside`: a calibration opened to compare, whose
/// figures take two more columns.
fn table(
    ui: &mut Ui,
    id: &str,
    title: &str,
    e: &Evaluation,
    exact: bool,
    scale: Scale,
    beside: Option<Beside<'_>>,
) {
    let window = scale.window;
    let unit = scale.kind.unit();
    let c = &e.comparison;
    let opened_eval = match &beside {
        Some(Beside {
            column: Column::Judged { judged, .. },
            ..
        }) => Some(&judged.evaluation),
        _ => None,
    };
    ui.vertical(|ui| {
        ui.horizontal(|ui| {
            ui.strong(title);
            if !exact {
                ui.label(
                    RichText::new("provisional")
                        .italics()
                        .color(ui.visuals().warn_fg_color),
                )
                .on_hover_text(
                    "These figures are those of the choices a moment ago: the refit for the \
                     current ones is on its way",
                );
            }
        })
        .response
        .on_hover_text(format!(
            "{} samples after {} warm-up samples; {} whole {window} windows; {}",
            c.raw.samples,
            e.warmup_samples,
            c.raw.windows,
            e.outside_text()
        ));
        // Stacked in a narrow panel with the opened calibration's two columns beside, the
        // figures are named short (their full names on hover).
        let narrow = ui.spacing().item_spacing.y <= 2.0 && beside.is_some();
        // Narrower still (a 1024-point window): the ratios leave their columns for the
        // corrected figures' hover, so that both calibrations' figures stay whole.
        let ratios = beside.is_none() || ui.available_width() >= RATIOS_MIN_W;
        let rms_label = format!("{window} RMS");
        let mean_label = if narrow {
            format!("|{window} mean|")
        } else {
            format!("max |{window} mean|")
        };
        Grid::new(id)
            .striped(true)
            // (stacked in a narrow panel, its rows tight: the columns closer too)
            .spacing([
                if ui.spacing().item_spacing.y <= 2.0 {
                    8.0
                } else {
                    14.0
                },
                2.0,
            ])
            .show(ui, |ui| {
                let heads: &[&str] = if beside.is_some() && !ratios {
                    &[unit, "raw", "current", "opened"]
                } else if beside.is_some() {
                    &[unit, "raw", "current", "ratio", "opened", "ratio"]
                } else {
                    &[unit, "raw", "corrected", "ratio"]
                };
                let opened_color = super::plot_items::Palette::of(ui).opened;
                for h in heads {
                    let text = RichText::new(*h).strong();
                    let r = if *h == "opened" {
                        ui.label(text.color(opened_color))
                    } else {
                        ui.label(text)
                    };
                    if *h == "opened"
                        && let Some(b) = &beside
                    {
                        r.on_hover_text(format!(
                        "Corrected by the opened calibration {}, judged with the same filter and \
                         windows as the current fit",
                        b.name
                    ));
                    }
                }
                ui.end_row();
                // Each figure of a comparison: raw, corrected and their ratio.
                type Pick = fn(&crate::judge::metrics::Comparison) -> (f64, f64, f64);
                let rows: [(&str, &str, Pick); 4] = [
                    (
                        if narrow { "p-p" } else { "peak-to-peak" },
                        "Peak-to-peak of the filtered drift",
                        |c| (c.raw.p2p_dph, c.corrected.p2p_dph, c.p2p_ratio),
                    ),
                    ("std", "Standard deviation of the filtered drift", |c| {
                        (c.raw.std_dph, c.corrected.std_dph, c.std_ratio)
                    }),
                    (
                        &rms_label,
                        "Mean over the consecutive windows of the RMS within each window",
                        |c| {
                            (
                                c.raw.win_rms_mean_dph,
                                c.corrected.win_rms_mean_dph,
                                c.win_rms_ratio,
                            )
                        },
                    ),
                    (
                        &mean_label,
                        "Largest |mean| over the consecutive windows",
                        |c| {
                            (
                                c.raw.win_mean_max_abs_dph,
                                c.corrected.win_mean_max_abs_dph,
                                c.win_mean_ratio,
                            )
                        },
                    ),
                ];
                let weak = ui.visuals().weak_text_color();
                for (name, tip, pick) in rows {
                    let (raw, cor, r) = pick(c);
                    ui.label(name).on_hover_text(tip);
                    ui.monospace(scale.number(raw));
                    let cor_text = RichText::new(scale.number(cor)).monospace();
                    let shown = ui.label(if exact {
                        cor_text
                    } else {
                        cor_text.italics().color(weak)
                    });
                    if !ratios {
                        shown.on_hover_text(format!("raw ÷ corrected: {}", ratio(r)));
                        if let Some(b) = &beside {
                            opened_cells(
                                ui,
                                b,
                                opened_eval.map(|o| pick(&o.comparison)),
                                raw,
                                false,
                            );
                        }
                        ui.end_row();
                        continue;
                    }
                    let good = r >= 1.0;
                    let color = match (exact, good) {
                        (false, _) => weak,
                        (true, true) => ui.visuals().text_color(),
                        (true, false) => ui.visuals().error_fg_color,
                    };
                    let text = RichText::new(ratio(r)).monospace().strong().color(color);
                    ui.label(if exact { text } else { text.italics() })
                        .on_hover_text("raw ÷ corrected: above 1 is better");
                    if let Some(b) = &beside {
                        opened_cells(ui, b, opened_eval.map(|o| pick(&o.comparison)), raw, true);
                    }
                    ui.end_row();
                }
            });
        // Each n/a with its reason, in the engine's words, as the command line prints them.
        for (what, why) in c.unavailable() {
            ui.label(
                RichText::new(format!("{what}: n/a ({})", why.describe()))
                    .small()
                    .color(ui.visuals().weak_text_color()),
            );
        }
        if let Some(b) = &beside {
            let text = match &b.column {
                Column::Judged { judged, .. } => format!("opened {}: {}", b.name, judged.label),
                Column::Not(why) => format!("opened {}: {why}", b.name),
            };
            ui.label(
                RichText::new(text)
                    .small()
                    .color(super::plot_items::Palette::of(ui).opened),
            )
            .on_hover_text(
                "In-sample or held out, as `driftlab evaluate` says it of the opened \
                     calibration on this log",
            );
        }
    });
}

/// The width below which a table with an opened calibration drops its ratio columns, points.
const RATIOS_MIN_W: f32 = 330.0;

/// The opened calibration's cells of one figure: its corrected value and (`with_ratio`) its
/// ratio (`figure` `None`: not judged on this log), greyed while a judging is on its way.
/// `raw`: the current fit's raw figure, to tell when the opened calibration's raw differs (its
/// warm-up leaves out other samples). Without its column, the ratio is on the value's hover.
fn opened_cells(
    ui: &mut Ui,
    b: &Beside<'_>,
    figure: Option<(f64, f64, f64)>,
    raw: f64,
    with_ratio: bool,
) {
    let weak = ui.visuals().weak_text_color();
    let Some((own_raw, cor, r)) = figure else {
        for _ in 0..(1 + usize::from(with_ratio)) {
            ui.label(RichText::new("—").color(weak));
        }
        return;
    };
    let cor_text = RichText::new(num(cor)).monospace();
    let shown = ui.label(if b.exact {
        cor_text
    } else {
        cor_text.italics().color(weak)
    });
    if !with_ratio {
        shown.on_hover_text(format!(
            "raw ÷ corrected by the opened calibration: {}",
            ratio(r)
        ));
        return;
    }
    let color = match (b.exact, r >= 1.0) {
        (false, _) => weak,
        (true, true) => ui.visuals().text_color(),
        (true, false) => ui.visuals().error_fg_color,
    };
    let text = RichText::new(ratio(r)).monospace().strong().color(color);
    let mut tip = "raw ÷ corrected by the opened calibration: above 1 is better".to_string();
    let same_raw =
        (own_raw - raw).abs() <= 1e-9 * raw.abs().max(1e-12) || (own_raw.is_nan() && raw.is_nan());
    if !same_raw {
        tip.push_str(&format!(
            "; raw over its own samples is {} °/h (its warm-up leaves out other samples \
             than the current fit's)",
            num(own_raw)
        ));
    }
    ui.label(if b.exact { text } else { text.italics() })
        .on_hover_text(tip);
}
