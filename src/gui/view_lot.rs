//! The Lot page: a lot opened from its output folder (File › Open lot, `driftlab gui --lot
//! OUT`), as `lot.html` shows it: the counts, each figure's distribution over the lot as a
//! strip of dots (one per unit; outliers red, failed units orange, the median dashed), and the
//! table of units, sorted by a click on a column's heading. A click on a unit's name (or its
//! dot) opens the unit on the Calibration page: its log(s) and its calibration beside the fit.
//!
//! What the table holds, its order and its medians are the engine's
//! ([`crate::lot::open::LotTable`]); this view draws them.

use super::action::Action;
use super::plot_items::num;
use super::state::AppState;
use crate::lot::Status;
use crate::lot::open::{LotTable, SortBy};
use eframe::egui::{self, Align2, Color32, FontId, RichText, ScrollArea, Sense, Stroke, Ui};

/// The Lot page's view state: the order of the table.
#[derive(Debug, Default)]
pub struct LotView {
    /// The column the table is sorted by and whether descending; the lot's order when `None`.
    pub sort: Option<(SortBy, bool)>,
}

/// A strip's height, points.
const STRIP_H: f32 = 16.0;
/// A dot's radius, points.
const DOT_R: f32 = 3.5;
/// The width of the strips' labels, points.
const LABEL_W: f32 = 200.0;
/// The width of the strips' ranges at their right, points.
const RANGE_W: f32 = 130.0;

/// The colour of a unit's dot and status.
pub fn status_color(status: Status, outlier: bool, dark: bool) -> Color32 {
    match (outlier, status) {
        (true, _) => Color32::from_rgb(214, 39, 40),
        (false, Status::Fail) => Color32::from_rgb(255, 127, 14),
        (false, Status::Error) => Color32::from_rgb(140, 86, 75),
        (false, Status::Pass) if dark => Color32::from_rgb(120, 170, 220),
        (false, Status::Pass) => Color32::from_rgb(31, 119, 180),
    }
}

impl LotView {
    /// The page; what the engineer asked for.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState) -> Vec<Action> {
        let mut out = Vec::new();
        egui::CentralPanel::default().show(ui, |ui| {
            let Some(lot) = &state.lot else {
                ui.vertical_centered(|ui| {
                    ui.add_space(ui.available_height() * 0.3);
                    ui.heading("No lot open");
                    ui.label(
                        "A lot is the output folder of `driftlab lot`: its lot.json or lot.csv.",
                    );
                    if ui.button("Open lot…").clicked() {
                        out.push(Action::OpenLot);
                    }
                });
                return;
            };
            self.header(ui, lot, &mut out);
            ui.separator();
            // Whole strips in the space given (no strip cut at the foot), the bar always
            // shown when they do not all fit: a short window scrolls them.
            let row_h = STRIP_H + ui.spacing().item_spacing.y;
            let fit = ((ui.available_height() * 0.45) / row_h).floor().max(4.0);
            let strips_h = fit * row_h - ui.spacing().item_spacing.y;
            ScrollArea::vertical()
                .id_salt("lot_strips")
                .max_height(strips_h)
                .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
                .auto_shrink([false, true])
                .show(ui, |ui| self.strips(ui, lot, &mut out));
            ui.separator();
            self.table(ui, lot, &mut out);
        });
        out
    }

    fn header(&mut self, ui: &mut Ui, lot: &LotTable, out: &mut Vec<Action>) {
        let [pass, fail, error] = lot.counts();
        let outliers = lot.rows.iter().filter(|r| r.is_outlier()).count();
        ui.horizontal_wrapped(|ui| {
            ui.strong(lot.file.display().to_string());
            ui.label(format!(
                "{} units: {pass} pass, {fail} fail, {error} error; {outliers} with outliers",
                lot.rows.len()
            ));
            if ui
                .button("Close lot")
                .on_hover_text("Put the lot away (the work on the Calibration page stays)")
                .clicked()
            {
                out.push(Action::CloseLot);
            }
        });
        ui.weak(
            "Click a heading to sort by it (again: the other way); click a unit's name or dot \
             to open its log and calibration on the Calibration page.",
        );
    }

    /// Each figure's distribution over the lot: a strip of dots, the median dashed.
    fn strips(&mut self, ui: &mut Ui, lot: &LotTable, out: &mut Vec<Action>) {
        let dark = ui.visuals().dark_mode;
        let text = ui.visuals().text_color();
        for (c, column) in lot.columns.iter().enumerate() {
            let points: Vec<(usize, f64)> = lot
                .rows
                .iter()
                .enumerate()
                .filter_map(|(k, r)| Some((k, r.values.get(c).copied().flatten()?)))
                .collect();
            let w = ui.available_width();
            let (rect, _) = ui.allocate_exact_size(egui::vec2(w, STRIP_H), Sense::hover());
            let painter = ui.painter_at(rect);
            painter.text(
                rect.left_center(),
                Align2::LEFT_CENTER,
                column.heading(),
                FontId::monospace(11.0),
                text,
            );
            // The dots at the ends keep clear of the label and of the range.
            let strip = egui::Rect::from_min_max(
                egui::pos2(rect.left() + LABEL_W + 2.0 * DOT_R, rect.top()),
                egui::pos2(rect.right() - RANGE_W - 2.0 * DOT_R, rect.bottom()),
            );
            if points.is_empty() {
                painter.text(
                    egui::pos2(strip.left(), rect.center().y),
                    Align2::LEFT_CENTER,
                    "no unit has it (hover its column in the table for why)",
                    FontId::proportional(11.0),
                    ui.visuals().weak_text_color(),
                );
                continue;
            }
            if strip.width() < 20.0 {
                continue;
            }
            let lo = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
            let hi = points.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
            let x = |v: f64| {
                if hi > lo {
                    strip.left() + ((v - lo) / (hi - lo)) as f32 * strip.width()
                } else {
                    strip.center().x
                }
            };
            painter.line_segment(
                [strip.left_center(), strip.right_center()],
                Stroke::new(1.0, ui.visuals().weak_text_color()),
            );
            if let Some(m) = lot.median(c) {
                let mx = x(m);
                painter.add(egui::Shape::dashed_line(
                    &[egui::pos2(mx, strip.top()), egui::pos2(mx, strip.bottom())],
                    Stroke::new(1.0, text),
                    3.0,
                    2.0,
                ));
            }
            painter.text(
                egui::pos2(rect.right(), rect.center().y),
                Align2::RIGHT_CENTER,
                format!("{}…{}", num(lo), num(hi)),
                FontId::monospace(10.0),
                ui.visuals().weak_text_color(),
            );
            // Outliers drawn last, over the others.
            let mut drawn: Vec<(usize, f64)> = points;
            drawn.sort_by_key(|(k, _)| lot.rows[*k].outliers[c].is_some());
            for (k, v) in drawn {
                let row = &lot.rows[k];
                let outlier = row.outliers[c].is_some();
                let centre = egui::pos2(x(v), strip.center().y);
                let r = if outlier { DOT_R + 1.0 } else { DOT_R };
                painter.circle_filled(centre, r, status_color(row.status, outlier, dark));
                let id = ui.scope_id().with(("lot_dot", c, k));
                let hit = egui::Rect::from_center_size(
                    centre,
                    egui::vec2(2.0 * r, 2.0 * r) + egui::vec2(2.0, 2.0),
                );
                let resp = ui.interact(hit, id, Sense::click());
                let resp = resp.on_hover_text(format!(
                    "{}: {} = {}{}\nclick to open it on the Calibration page",
                    row.unit,
                    column.heading(),
                    num(v),
                    row.outliers[c]
                        .map(|s| format!(" (outlier, {s:+.1} sd)"))
                        .unwrap_or_default()
                ));
                if resp.clicked() {
                    out.push(Action::OpenLotUnit(k));
                }
            }
        }
    }

    /// The table of units: a row each, in the order chosen.
    fn table(&mut self, ui: &mut Ui, lot: &LotTable, out: &mut Vec<Action>) {
        let dark = ui.visuals().dark_mode;
        let order = match self.sort {
            Some((by, descending)) => lot.order(by, descending),
            None => (0..lot.rows.len()).collect(),
        };
        ScrollArea::both()
            .id_salt("lot_table")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                egui::Grid::new("lot_grid")
                    .striped(true)
                    .spacing(egui::vec2(12.0, 3.0))
                    .show(ui, |ui| {
                        let mut heading = |ui: &mut Ui, label: String, by: SortBy| {
                            let mark = match self.sort {
                                Some((b, false)) if b == by => " ^",
                                Some((b, true)) if b == by => " v",
                                _ => "",
                            };
                            if ui
                                .add(
                                    egui::Button::new(
                                        RichText::new(format!("{label}{mark}")).strong(),
                                    )
                                    .frame(false),
                                )
                                .on_hover_text(format!("Sort by {label}"))
                                .clicked()
                            {
                                self.sort = Some(match self.sort {
                                    Some((b, d)) if b == by => (by, !d),
                                    _ => (by, false),
                                });
                            }
                        };
                        heading(ui, "unit".into(), SortBy::Unit);
                        heading(ui, "status".into(), SortBy::Status);
                        heading(ui, "outliers".into(), SortBy::Outliers);
                        for (c, column) in lot.columns.iter().enumerate() {
                            heading(ui, column.heading(), SortBy::Figure(c));
                        }
                        heading(ui, "reasons".into(), SortBy::Reasons);
                        ui.end_row();
                        for &k in &order {
                            let row = &lot.rows[k];
                            if ui
                                .link(&row.unit)
                                .on_hover_text(
                                    "Open its log and calibration on the Calibration page",
                                )
                                .clicked()
                            {
                                out.push(Action::OpenLotUnit(k));
                            }
                            ui.colored_label(
                                status_color(row.status, false, dark),
                                row.status.word(),
                            );
                            let n = row.outliers.iter().flatten().count();
                            if n > 0 {
                                ui.colored_label(
                                    status_color(row.status, true, dark),
                                    format!("{n}"),
                                );
                            } else {
                                ui.label("");
                            }
                            for c in 0..lot.columns.len() {
                                let cell = match row.values[c] {
                                    Some(v) => RichText::new(num(v)).monospace(),
                                    None => RichText::new("—").weak(),
                                };
                                let cell = match row.outliers[c] {
                                    Some(_) => {
                                        cell.color(status_color(row.status, true, dark)).strong()
                                    }
                                    None => cell,
                                };
                                let r = ui.label(cell);
                                match (row.outliers[c], &row.unavailable[c]) {
                                    (Some(s), _) => {
                                        r.on_hover_text(format!(
                                            "outlier: {s:+.1} robust sd from the lot's median"
                                        ));
                                    }
                                    (None, Some(why)) => {
                                        r.on_hover_text(why);
                                    }
                                    _ => {}
                                }
                            }
                            let reasons = row.reasons.join("; ");
                            let short: String = reasons.chars().take(90).collect();
                            let r = ui.label(if short.len() < reasons.len() {
                                format!("{short}…")
                            } else {
                                short
                            });
                            if !reasons.is_empty() {
                                r.on_hover_text(reasons);
                            }
                            ui.end_row();
                        }
                    });
            });
    }
}
