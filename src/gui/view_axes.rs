//! The gyro axes of a unit, above the Calibration page: one button per axis, with the axis's
//! figures at a glance (in-sample and, with a validation log, held-out peak-to-peak and std
//! ratios of raw over corrected, worse than raw marked as the figures panel marks it).
//! Clicking an axis shows it (Alt+1…9, or `[` and `]`). Shown for a log of several axes, or
//! of accelerometer axes beside its gyro axis or axes ([`AppState::has_axis_strip`]).
//!
//! A unit whose log has accelerometer columns lists them after the gyro axes, with the switch
//! that calibrates them (on by default) and each one's figures in m/s², the axis that carries
//! gravity marked; clicking one shows it ([`super::view_accel`]). A log of one gyro axis with
//! them is a unit of that axis and them, as `calibrate --accel` makes it: its axis's button
//! goes back to it.

use super::action::{Action, shortcuts};
use super::plot_items::{num, ratio};
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
        self.strip(ui, state, form, false)
    }

    /// The strip in the menu bar, in `room` points: as [`AxesView::ui`] draws it compact, or
    /// with the ratios' names left out (in the hover) when that is wider than `room`, so that
    /// the menu bar keeps its right-hand end in the window (at 1024 points it did not).
    pub fn ui_in(&mut self, ui: &mut Ui, state: &AppState, room: f32) -> Vec<Action> {
        if !state.has_axis_strip() {
            return Vec::new();
        }
        let pad = 2.0 * ui.spacing().button_padding.x + ui.spacing().item_spacing.x;
        // The strip's width in `form`: every gyro axis's button, the label, the accelerometers.
        let width = |ui: &Ui, form: Form| -> f32 {
            (0..state.axis_count())
                .filter_map(|k| state.axis(k))
                .map(|a| {
                    let job = axis_text(ui, &a, k_selected(state, a.name), form);
                    ui.fonts_mut(|f| f.layout_job(job).size().x) + pad
                })
                .sum::<f32>()
                + 48.0
                + accel_width(ui, state, form, pad)
        };
        let wide = width(ui, Form::Compact);
        let narrow = width(ui, Form::Narrow);
        // Narrower still, the accelerometer axes fold into a menu of their own.
        let (form, fold) = if wide <= room {
            (Form::Compact, false)
        } else {
            (Form::Narrow, narrow > room)
        };
        self.strip(ui, state, form, fold)
    }

    fn strip(&mut self, ui: &mut Ui, state: &AppState, form: Form, fold: bool) -> Vec<Action> {
        let compact = form != Form::Full;
        let mut out = Vec::new();
        if !state.has_axis_strip() {
            return out;
        }
        let ctx = ui.ctx().clone();
        ui.horizontal_wrapped(|ui| {
            let axis_label = if compact { "Axis:" } else { "Axis" };
            ui.label(RichText::new(axis_label).strong()).on_hover_text(
                "The unit's gyro axes: each keeps its own approximations, knots and \
                 dead-bands; the plateaus and the T settings are shared (they come from T)",
            );
            for k in 0..state.axis_count() {
                let Some(axis) = state.axis(k) else {
                    continue;
                };
                let selected = k == state.active_axis() && state.accel_shown().is_none();
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
                        gyro_name(&axis)
                    ));
                if r.clicked() {
                    out.push(Action::SelectAxis(k));
                }
            }
            if state.accel.is_some() {
                ui.separator();
                if fold {
                    ui.menu_button(switch_label(form), |ui| {
                        out.extend(accel_strip(ui, state, Form::Compact));
                    })
                    .response
                    .on_hover_text("The accelerometer axes: the switch, and each axis's figures");
                } else {
                    out.extend(accel_strip(ui, state, form));
                }
            }
        });
        out
    }
}

/// The accelerometer axes after the gyro axes: the switch that calibrates them, then a button
/// per axis ([`accel_buttons`]).
fn accel_strip(ui: &mut Ui, state: &AppState, form: Form) -> Vec<Action> {
    let mut out = Vec::new();
    let Some(accel) = &state.accel else {
        return out;
    };
    let unit = crate::log::AxisKind::Accel.unit();
    let on = state.accel_on();
    let mut ticked = on;
    if ui
        .checkbox(&mut ticked, switch_label(form))
        .on_hover_text(format!(
            "The log's accelerometer axes, calibrated beside the gyro axes as `driftlab \
             calibrate --accel` calibrates them: each a cubic in T fitted about its mean on \
             the calibration log, which its correction keeps (the axis along g still reads g); \
             figures in {unit}. Written with the unit into the calibration, the corrected log, \
             the flight files and the report. Untick to leave them out."
        ))
        .changed()
    {
        out.push(Action::AccelOn(ticked));
    }
    if !on {
        return out;
    }
    let bad = ui.visuals().error_fg_color;
    if let Some(e) = &accel.read_error {
        ui.colored_label(bad, "cannot be read").on_hover_text(e);
        return out;
    }
    if let Some(Err(e)) = accel.fit.as_ref().map(|f| &f.result) {
        ui.colored_label(bad, "calibration failed").on_hover_text(e);
        return out;
    }
    for (k, (job, hover)) in accel_buttons(ui, state, form).into_iter().enumerate() {
        let selected = state.accel_shown() == Some(k);
        if ui
            .add(egui::Button::selectable(selected, job))
            .on_hover_text(hover)
            .clicked()
        {
            out.push(Action::SelectAccel(k));
        }
    }
    out
}

/// The switch's label: the unit the accelerometers' figures are in is said on it where their
/// buttons leave it out.
fn switch_label(form: Form) -> String {
    match form {
        Form::Full => "Accelerometers".into(),
        _ => format!("Acc., {}", crate::log::AxisKind::Accel.unit()),
    }
}

/// Each accelerometer axis's button text and hover, as `form` says: in full its name (`g`
/// after the axis that carries gravity), its corrected peak-to-peak in m/s² and raw ÷
/// corrected; compact, the peak-to-peak alone (the switch says the unit); narrow, the name
/// alone (the figures in the hover).
fn accel_buttons(ui: &Ui, state: &AppState, form: Form) -> Vec<(LayoutJob, String)> {
    let Some(accel) = &state.accel else {
        return Vec::new();
    };
    let unit = crate::log::AxisKind::Accel.unit();
    let exact = state.accel_current();
    let fit = accel.fit.as_ref().and_then(|f| f.result.as_ref().ok());
    let gravity = fit.and_then(|f| f.gravity.as_ref());
    let six = |v: f64| crate::number::fixed(v, 6);
    let bad = ui.visuals().error_fg_color;
    accel
        .names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let selected = state.accel_shown() == Some(k);
            let (normal, weak) = strip_colors(ui, selected);
            let font = FontId::proportional(13.0);
            let mono = FontId::monospace(12.5);
            let mut job = LayoutJob::default();
            let mut push = |text: &str, font: &FontId, color: Color32, italics: bool| {
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
            push(name, &FontId::proportional(15.0), normal, false);
            let carries = gravity.is_some_and(|g| g.axis == *name);
            if carries {
                push(" g", &font, weak, false);
            }
            let axis = fit.and_then(|f| f.axes.iter().find(|a| a.fitted.name == *name));
            let color = if exact { normal } else { weak };
            let mut hover = format!("accelerometer axis {name}");
            match axis {
                Some(a) => {
                    let c = &a.fitted.calibrated.in_sample.comparison;
                    let (raw, cor) = (c.raw.p2p_dph, c.corrected.p2p_dph);
                    if form == Form::Full {
                        push("  p2p ", &font, weak, false);
                    } else if form == Form::Compact {
                        push(" ", &font, weak, false);
                    }
                    if form != Form::Narrow {
                        push(&six(cor), &mono, color, !exact);
                    }
                    if form == Form::Full {
                        push(&format!(" {unit} "), &font, weak, false);
                        let ratio_color = if c.p2p_ratio < 1.0 && exact {
                            bad
                        } else {
                            color
                        };
                        push(&ratio(c.p2p_ratio), &mono, ratio_color, !exact);
                    }
                    // Held out on the validation log, as a gyro axis's button gives it.
                    let held = a.held_out.as_ref().and_then(|h| h.as_ref().ok());
                    if let Some(h) = held
                        && form == Form::Full
                    {
                        let r = h.evaluation.comparison.p2p_ratio;
                        push(" · held out ", &font, weak, false);
                        let color = if r < 1.0 && exact { bad } else { color };
                        push(&ratio(r), &mono, color, !exact);
                    }
                    if let Some(m) = a.fitted.kept_mean {
                        hover += &format!("; mean {} {unit}, kept by its correction", num(m));
                    }
                    if carries {
                        hover += "; carries gravity";
                    }
                    hover += &format!(
                        "\np2p: peak-to-peak of its filtered change about that mean, \
                         in-sample, {} {unit} raw, {} {unit} corrected ({} better)",
                        six(raw),
                        six(cor),
                        ratio(c.p2p_ratio)
                    );
                    match &a.held_out {
                        Some(Ok(h)) => {
                            let c = &h.evaluation.comparison;
                            hover += &format!(
                                "; {} on the validation log, {} {unit} raw, {} {unit} \
                                 corrected ({} better)",
                                h.label,
                                six(c.raw.p2p_dph),
                                six(c.corrected.p2p_dph),
                                ratio(c.p2p_ratio)
                            );
                        }
                        Some(Err(why)) => hover += &format!("; not judged held out: {why}"),
                        None => {}
                    }
                }
                None => push(
                    if form == Form::Narrow {
                        "…"
                    } else {
                        "  calibrating…"
                    },
                    &font,
                    weak,
                    false,
                ),
            }
            hover += "\nclick to show it";
            (job, hover)
        })
        .collect()
}

/// The width the accelerometer axes take in the strip drawn as `form` (`pad` about each
/// button), with their switch; 0 for a log without them.
fn accel_width(ui: &Ui, state: &AppState, form: Form, pad: f32) -> f32 {
    if state.accel.is_none() {
        return 0.0;
    }
    let switch = {
        let font = FontId::proportional(13.0);
        let text = switch_label(form);
        ui.fonts_mut(|f| f.layout_no_wrap(text, font, Color32::WHITE).size().x)
            + ui.spacing().icon_width
            + ui.spacing().icon_spacing
            + pad
            + 12.0
    };
    accel_buttons(ui, state, form)
        .into_iter()
        .map(|(job, _)| ui.fonts_mut(|f| f.layout_job(job).size().x) + pad)
        .sum::<f32>()
        + switch
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

/// The name of a gyro axis as the strip shows it: the unit's, or for a log of one gyro axis
/// (no unit of gyro axes), the log's.
fn gyro_name<'a>(axis: &super::state::AxisRef<'a>) -> &'a str {
    match (axis.name, axis.log) {
        ("", Some(l)) => l.log.axis.as_str(),
        (name, _) => name,
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
        gyro_name(axis),
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
