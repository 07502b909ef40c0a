//! The gyro axes of a unit, above the Calibration page: one button per axis, with the axis's
//! figures at a glance (in-sample and, with a validation log, held-out peak-to-peak and std
//! ratios of raw over corrected, worse than raw marked as the figures panel marks it).
//! Clicking an axis shows it (Alt+1…9, or `[` and `]`). Shown only for a log of several axes.

use super::action::{Action, shortcuts};
use super::plot_items::ratio;
use super::state::AppState;
use crate::judge::metrics::Evaluation;
use eframe::egui::{self, Color32, FontId, RichText, TextFormat, Ui, text::LayoutJob};

/// The axes strip (no state of its own).
#[derive(Debug, Default)]
pub struct AxesView;

impl AxesView {
    /// The strip; nothing for a log of one axis. `compact` (a short window, the strip in the
    /// menu bar): each axis's name and peak-to-peak ratios only, the rest on hover.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, compact: bool) -> Vec<Action> {
        let form = if compact { Form::Compact } else { Form::Full };
        self.strip(ui, state, form)
    }

    /// The strip in the menu bar, in `room` points: as [`AxesView::ui`] draws it compact, or
    /// with the ratios' names left out (in the hover) when that is wider than `room`, so that
    /// the menu bar keeps its right-hand end in the window (at 1024 points it did not).
    pub fn ui_in(&mut self, ui: &mut Ui, state: &AppState, room: f32) -> Vec<Action> {
        let Some(unit) = &state.unit else {
            return Vec::new();
        };
        let pad = 2.0 * ui.spacing().button_padding.x + ui.spacing().item_spacing.x;
        let wide: f32 = (0..unit.names.len())
            .filter_map(|k| state.axis(k))
            .map(|a| {
                let job = axis_text(ui, &a, k_selected(state, a.name), Form::Compact);
                ui.fonts_mut(|f| f.layout_job(job).size().x) + pad
            })
            .sum::<f32>()
            + 48.0;
        let form = if wide > room {
            Form::Narrow
        } else {
            Form::Compact
        };
        self.strip(ui, state, form)
    }

    fn strip(&mut self, ui: &mut Ui, state: &AppState, form: Form) -> Vec<Action> {
        let compact = form != Form::Full;
        let mut out = Vec::new();
        let Some(unit) = &state.unit else {
            return out;
        };
        let ctx = ui.ctx().clone();
        ui.horizontal_wrapped(|ui| {
            let axis_label = if compact { "Axis:" } else { "Axis" };
            ui.label(RichText::new(axis_label).strong()).on_hover_text(
                "The unit's gyro axes: each keeps its own approximations, knots and \
                 dead-bands; the plateaus and the T settings are shared (they come from T)",
            );
            for k in 0..unit.names.len() {
                let Some(axis) = state.axis(k) else {
                    continue;
                };
                let selected = k == unit.active;
                let job = axis_text(ui, &axis, selected, form);
                let keys = shortcuts::axis(k)
                    .map(|s| format!("{} — ", ctx.format_shortcut(&s)))
                    .unwrap_or_default();
                let column = axis
                    .log
                    .and_then(|l| l.log.rate_column())
                    .map(|c| format!(" (column {c})"))
                    .unwrap_or_default();
                let r = ui
                    .add(egui::Button::selectable(selected, job))
                    .on_hover_text(format!(
                        "{keys}show axis {}{column} ([ and ]: previous, next)\n\
                         p2p and std: raw ÷ corrected peak-to-peak and standard deviation of \
                         the filtered drift, in-sample, then on the validation log; above 1 is \
                         better, red: worse than raw",
                        axis.name
                    ));
                if r.clicked() {
                    out.push(Action::SelectAxis(k));
                }
            }
        });
        out
    }
}

/// How much an axis's button says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Form {
    /// Its name, then its peak-to-peak and std ratios, in-sample and held out, named.
    Full,
    /// The peak-to-peak ratios only.
    Compact,
    /// The peak-to-peak ratios without their names (`gx 4.54× · 4.08×`).
    Narrow,
}

/// The text colours of a strip's button (an axis's, a run's): its words and its labels, which
/// stand on the selection colour when it is the one shown (not greyed there).
pub fn strip_colors(ui: &Ui, selected: bool) -> (Color32, Color32) {
    let v = ui.visuals();
    match selected {
        true => (v.strong_text_color(), v.text_color()),
        false => (v.text_color(), v.weak_text_color()),
    }
}

/// Whether the axis named `name` is the one shown.
fn k_selected(state: &AppState, name: &str) -> bool {
    state.active_axis_name() == Some(name)
}

/// One axis's button: its name, then its ratios (in-sample, held out), as `form` says.
fn axis_text(ui: &Ui, axis: &super::state::AxisRef<'_>, selected: bool, form: Form) -> LayoutJob {
    let compact = form != Form::Full;
    let v = ui.visuals();
    let font = FontId::proportional(13.0);
    let mono = FontId::monospace(12.5);
    let (normal, weak) = strip_colors(ui, selected);
    let bad = v.error_fg_color;
    let provisional = v.weak_text_color();
    let mut job = LayoutJob::default();
    let push = |job: &mut LayoutJob, text: &str, font: &FontId, color: Color32, italics| {
        job.append(
            text,
            0.0,
            TextFormat {
                font_id: font.clone(),
                color,
                italics,
                ..Default::default()
            },
        );
    };
    push(
        &mut job,
        axis.name,
        &FontId::proportional(15.0),
        normal,
        false,
    );
    let Some(fit) = axis.fit else {
        let what = if axis.fit_error.is_some() {
            "  calibration failed"
        } else {
            "  calibrating…"
        };
        push(
            &mut job,
            what,
            &font,
            if axis.fit_error.is_some() { bad } else { weak },
            false,
        );
        return job;
    };
    if axis.fit_error.is_some() {
        push(&mut job, "  failed", &font, bad, false);
    }
    // Figures of the choices a moment ago (a refit on its way) are greyed and slanted.
    let exact = axis.fit_current();
    let figures = |job: &mut LayoutJob, label: &str, e: &Evaluation| {
        push(job, label, &font, weak, false);
        let all = [
            ("p2p ", e.comparison.p2p_ratio),
            ("std ", e.comparison.std_ratio),
        ];
        for (name, r) in &all[..if compact { 1 } else { 2 }] {
            let r = *r;
            if form != Form::Narrow {
                push(job, name, &font, weak, false);
            }
            let color = match (exact, r >= 1.0) {
                (false, _) => provisional,
                (true, true) => normal,
                (true, false) => bad,
            };
            push(job, &format!("{} ", ratio(r)), &mono, color, !exact);
        }
    };
    figures(&mut job, "  ", &fit.outcome.in_sample.evaluation);
    if let Some(h) = &fit.outcome.held_out {
        figures(
            &mut job,
            if compact { "· " } else { "· held out " },
            &h.evaluation,
        );
    }
    job
}
