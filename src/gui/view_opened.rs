//! The calibration opened beside the current fit, in a strip above the figures: its name and
//! what it is, its recipe (the kinds and knots of the axis shown; their ranges on hover), how
//! it fares on each open log (in-sample or held out, as `driftlab evaluate` says it, and every
//! axis's peak-to-peak ratio), the axes the engineer places where the files do not say, and
//! Close. Its figures sit in the figures' tables and its drift on the drift plot.

use super::action::{Action, OpenLog};
use super::jobs::{AxisVerdict, VerifiedLog};
use super::opened::{self, Column, Opened};
use super::plot_items::{Palette, ratio};
use super::state::AppState;
use crate::number::readable;
use eframe::egui::{self, RichText, Ui};

/// The strip (no state of its own).
#[derive(Debug, Default)]
pub struct OpenedView;

impl OpenedView {
    /// The strip; nothing with no calibration opened. `narrow`: in the controls panel of a
    /// short window, where the recipe folds under a heading.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, narrow: bool) -> Vec<Action> {
        let mut out = Vec::new();
        let Some(o) = state.opened.as_ref() else {
            return out;
        };
        let color = Palette::of(ui).opened;
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new("Opened calibration").strong().color(color))
                .on_hover_text(
                    "A calibration file opened to compare with the current fit: its figures are \
                     in the figures' tables, its corrected drift on the drift plot",
                );
            ui.label(RichText::new(o.name()).strong())
                .on_hover_text(o.path.display().to_string());
            ui.label(format!("· {}", o.what()));
            if state.shown.log.is_none() {
                ui.weak("· open a log to judge it on");
            } else if !opened::current(state) {
                ui.weak("· judging…");
            }
            // Judged with the workbench's filter, as the current fit is: said when it is not the
            // one the calibration was made with (`evaluate` without --filter takes that one).
            let filter = state.merit().filter_s;
            let own: Vec<f64> = o
                .unit
                .axes
                .iter()
                .map(|a| crate::judge::verify::merit_options(&a.model, None, None).filter_s)
                .filter(|f| *f != filter)
                .collect();
            if let Some(f) = own.first() {
                ui.weak(format!("· judged with a {} s filter", readable(filter)))
                    .on_hover_text(format!(
                        "Both calibrations are judged with the workbench's Ω filter, {} s; the \
                         opened one was made with {} s, which `driftlab evaluate` takes unless \
                         --filter is given",
                        readable(filter),
                        readable(*f)
                    ));
            }
            if ui
                .small_button("Close")
                .on_hover_text("Put the opened calibration away (the current fit stays)")
                .clicked()
            {
                out.push(Action::CloseCalibration);
            }
        });
        if narrow {
            egui::CollapsingHeader::new("Its recipe")
                .id_salt("opened_recipe")
                .default_open(false)
                .show(ui, |ui| recipe(ui, o, state));
        } else {
            recipe(ui, o, state);
        }
        if let Some(v) = &o.verified {
            if let Some(why) = &v.failed {
                ui.colored_label(ui.visuals().error_fg_color, why);
            }
            for l in &v.logs {
                // One axis on a log of one: the figures' tables say it all.
                if o.unit.is_unit() || l.log_axes.len() > 1 {
                    judged_on(ui, o, l);
                }
                out.extend(placements(ui, o, l));
            }
        }
        out
    }
}

/// The recipe of the calibration's axis judged on the axis shown (the first axis until one
/// is): each line's text, its detail on hover.
fn recipe(ui: &mut Ui, o: &Opened, state: &AppState) {
    let axis = match opened::column(state, OpenLog::Calibration) {
        Some(Column::Judged { axis, .. }) => axis.to_string(),
        _ => o
            .summaries
            .first()
            .map(|(n, _)| n.clone())
            .unwrap_or_default(),
    };
    let Some((name, lines)) = o.summaries.iter().find(|(n, _)| *n == axis) else {
        return;
    };
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 4.0;
        if !name.is_empty() {
            ui.label(RichText::new(format!("axis {name}:")).strong());
        }
        for (k, l) in lines.iter().enumerate() {
            if k > 0 {
                ui.weak("·");
            }
            ui.weak(format!("{}:", l.what));
            let r = ui.label(&l.text);
            if let Some(d) = &l.detail {
                r.on_hover_text(d.as_str());
            }
        }
    });
}

/// How the calibration fares on one open log: the in-sample or held-out label (once when the
/// axes agree) and each judged axis's peak-to-peak ratio raw ÷ corrected.
fn judged_on(ui: &mut Ui, o: &Opened, l: &VerifiedLog) {
    let judged: Vec<_> = l
        .axes
        .iter()
        .enumerate()
        .filter_map(|(k, v)| match v {
            AxisVerdict::Judged(j) => Some((k, j)),
            _ => None,
        })
        .collect();
    if judged.is_empty() {
        return;
    }
    let one_label = judged.windows(2).all(|w| w[0].1.label == w[1].1.label);
    ui.horizontal_wrapped(|ui| {
        ui.spacing_mut().item_spacing.x = 4.0;
        let which = match l.which {
            OpenLog::Calibration => "calibration log",
            OpenLog::Validation => "validation log",
        };
        let head = if one_label {
            format!("On {} ({}):", l.name, judged[0].1.label)
        } else {
            format!("On {}:", l.name)
        };
        ui.label(head).on_hover_text(format!(
            "The {which}; peak-to-peak of the filtered drift, raw ÷ corrected by the opened \
             calibration, per axis"
        ));
        for (k, j) in &judged {
            let name = o.unit.axes.get(*k).map_or("", |a| a.name.as_str());
            let c = &j.evaluation.comparison;
            let axis = if name.is_empty() || *name == j.log_axis {
                j.log_axis.clone()
            } else {
                format!("{name} on {}", j.log_axis)
            };
            let text = format!("{axis} {}", ratio(c.p2p_ratio));
            let color = if c.p2p_ratio >= 1.0 {
                ui.visuals().text_color()
            } else {
                ui.visuals().error_fg_color
            };
            let mut tip = format!(
                "peak-to-peak of the filtered drift, raw ÷ corrected by the opened \
                 calibration; {}",
                j.label
            );
            if j.by_hand {
                tip.push_str("; axis chosen by hand");
            }
            if let Some(t) = &j.told {
                tip.push_str(&format!("; {t}"));
            }
            ui.label(RichText::new(text).color(color))
                .on_hover_text(tip);
            if !one_label {
                ui.weak(format!("({})", j.label));
            }
        }
    });
}

/// The axes of the calibration the files do not place on log `l` (or placed by hand): what
/// is wrong, and the choice of the log's axis.
fn placements(ui: &mut Ui, o: &Opened, l: &VerifiedLog) -> Vec<Action> {
    let mut out = Vec::new();
    for (k, v) in l.axes.iter().enumerate() {
        let (why, chosen) = match v {
            AxisVerdict::Unplaced(why) => (Some(why.as_str()), None),
            AxisVerdict::Judged(j) if j.by_hand => (None, Some(j.log_axis.clone())),
            AxisVerdict::Failed { why, log_axis } => {
                ui.colored_label(ui.visuals().error_fg_color, why);
                if !o.chosen.contains_key(&(l.which, k)) {
                    continue;
                }
                (None, Some(log_axis.clone()))
            }
            _ => continue,
        };
        ui.horizontal_wrapped(|ui| {
            if let Some(why) = why {
                ui.colored_label(ui.visuals().warn_fg_color, why);
            }
            let name = o.unit.axes.get(k).map_or("", |a| a.name.as_str());
            let label = if name.is_empty() {
                format!("Axis it corrects in {}:", l.name)
            } else {
                format!("Axis {name} in {}:", l.name)
            };
            ui.label(&label);
            let mut pick = chosen.clone();
            let shown = pick.clone().unwrap_or_else(|| "choose…".into());
            let r = egui::ComboBox::from_id_salt(("opened_axis", l.which, k))
                .selected_text(shown.as_str())
                .show_ui(ui, |ui| {
                    for a in &l.log_axes {
                        ui.selectable_value(&mut pick, Some(a.clone()), a);
                    }
                    ui.selectable_value(&mut pick, None, "none");
                })
                .response;
            let name = label.trim_end_matches(':').to_string();
            r.widget_info(|| {
                let mut info =
                    egui::WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, &name);
                info.current_text_value = Some(shown.clone());
                info
            });
            if pick != chosen {
                out.push(Action::ChooseOpenedAxis(l.which, k, pick));
            }
        });
    }
    out
}
