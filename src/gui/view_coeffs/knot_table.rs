//! The knot table of one coefficient: each knot's position and value, typed or dragged, a knot
//! removed by its ×, one added at a typed position, and the engine's reason when a typed number
//! is not taken (a position outside its neighbours). A small window over the page, opened by a
//! coefficient's "knots…" button or the plot's right-click menu.

use super::CoeffView;
use super::knots::shown;
use crate::files::session::Coefficient;
use crate::gui::action::{Action, Edit};
use crate::gui::plot_items::num;
use crate::gui::state::AppState;
use crate::models::approx::{ApproxSpec, KnotEdit};
use eframe::egui::{self, RichText};

/// The table's own state: which coefficient, the position being typed for a new knot, and why
/// the last typed number was not taken.
pub(super) struct KnotTable {
    c: Coefficient,
    new_x: String,
    note: Option<String>,
    /// Where the pointer was when the table opened: it opens beside it, over the plots rather
    /// than over the controls.
    near: Option<egui::Pos2>,
}

impl KnotTable {
    /// The table of `c`, empty of notes.
    pub(super) fn of(c: Coefficient) -> KnotTable {
        KnotTable {
            c,
            new_x: String::new(),
            note: None,
            near: None,
        }
    }
}

/// A typed number: finite, in any form Rust reads (`0.002`, `-3e-5`).
fn parse(text: &str) -> Option<f64> {
    text.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The parser of a field showing `value` as `num` writes it: the text as shown (the field
/// committed without an edit) is `value` itself, not its rounded display; anything else is
/// read as typed.
fn unedited_or_typed(value: f64) -> impl Fn(&str) -> Option<f64> {
    let shown = num(value);
    move |text: &str| {
        if text.trim() == shown.trim() {
            Some(value)
        } else {
            parse(text)
        }
    }
}

impl CoeffView {
    /// The open knot table, as a window over the page.
    pub(super) fn knot_table(
        &mut self,
        ctx: &egui::Context,
        state: &AppState,
        out: &mut Vec<Action>,
    ) {
        let Some(mut t) = self.table.take() else {
            return;
        };
        let c = t.c;
        let spec = c.spec(&state.shown.choices.recipe).clone();
        let mut open = true;
        let near = *t.near.get_or_insert_with(|| {
            ctx.input(|i| i.pointer.latest_pos())
                .unwrap_or(ctx.content_rect().right_top())
        });
        egui::Window::new(format!("Knots of {}", c.label()))
            .id(egui::Id::unique("knot_table"))
            .default_pos(near - egui::vec2(320.0, 0.0))
            .open(&mut open)
            .resizable(false)
            .collapsible(false)
            .default_width(260.0)
            .show(ctx, |ui| {
                let Some(a) = shown(state, c, None).filter(|_| spec.kind.has_knots()) else {
                    ui.weak(format!(
                        "{} is {}: choose pwl or spline to place knots.",
                        c.label(),
                        spec.kind
                    ));
                    return;
                };
                ui.label(RichText::new(c.knots_text(&spec)).weak());
                let (xs, ys) = a.knots();
                let span = (xs[xs.len() - 1] - xs[0]).abs();
                let yspan = ys.iter().fold(0.0f64, |m, y| m.max(y.abs()));
                let mut edit = None;
                egui::Grid::new("knot_table_grid")
                    .num_columns(4)
                    .spacing([8.0, 4.0])
                    .show(ui, |ui| {
                        ui.strong("#");
                        ui.strong("position");
                        ui.strong("value");
                        ui.label("");
                        ui.end_row();
                        for (j, (&x0, &y0)) in xs.iter().zip(ys).enumerate() {
                            ui.label(format!("{}", j + 1));
                            let (mut x, mut y) = (x0, y0);
                            let rx = ui
                                .add(
                                    egui::DragValue::new(&mut x)
                                        .speed((span * 1e-3).max(1e-12))
                                        .custom_formatter(|n, _| num(n))
                                        .custom_parser(unedited_or_typed(x0))
                                        .update_while_editing(false),
                                )
                                .on_hover_text(format!(
                                    "Position of knot {}: drag, or click and type; it stays \
                                     between its neighbours",
                                    j + 1
                                ));
                            let ry = ui
                                .add(
                                    egui::DragValue::new(&mut y)
                                        .speed((yspan * 1e-3).max(1e-12))
                                        .custom_formatter(|n, _| num(n))
                                        .custom_parser(unedited_or_typed(y0))
                                        .update_while_editing(false),
                                )
                                .on_hover_text(format!(
                                    "Value of knot {}: typed, it is set by hand (and so are the \
                                     others, as they stand)",
                                    j + 1
                                ));
                            if rx.changed() && x != x0 {
                                edit = Some(KnotEdit::Place { index: j, x });
                            }
                            if ry.changed() && y != y0 {
                                edit = Some(KnotEdit::Value { index: j, y });
                            }
                            if ui
                                .add_enabled(xs.len() > 2, egui::Button::new("×").small())
                                .on_hover_text(format!("Remove knot {}", j + 1))
                                .on_disabled_hover_text("A knot curve keeps at least 2 knots")
                                .clicked()
                            {
                                edit = Some(KnotEdit::Remove { index: j });
                            }
                            ui.end_row();
                        }
                    });
                ui.horizontal(|ui| {
                    ui.label("new knot at");
                    let r = ui.add(
                        egui::TextEdit::singleline(&mut t.new_x)
                            .desired_width(90.0)
                            .hint_text("position"),
                    );
                    let enter = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    if (ui.button("Add knot").clicked() || enter) && !t.new_x.trim().is_empty() {
                        match parse(&t.new_x) {
                            Some(x) => edit = Some(KnotEdit::Insert { x }),
                            None => {
                                t.note = Some(format!("\"{}\" is not a number", t.new_x.trim()));
                            }
                        }
                    }
                });
                if let Some(e) = edit {
                    match spec.edit_knot(&a, e) {
                        Ok(next) => {
                            t.note = None;
                            if matches!(e, KnotEdit::Insert { .. }) {
                                t.new_x.clear();
                            }
                            out.push(Action::Edit(Edit::Approx(c, next)));
                        }
                        Err(err) => {
                            let message = format!("{} not changed: {err}", c.label());
                            t.note = Some(message.clone());
                            out.push(Action::Warn(message));
                        }
                    }
                }
                if let Some(n) = &t.note {
                    ui.colored_label(ui.visuals().error_fg_color, n);
                }
                ui.horizontal(|ui| {
                    if ui
                        .add_enabled(spec.hand_knots(), egui::Button::new("reset knots"))
                        .on_hover_text("Equally spaced, fitted knots again")
                        .clicked()
                    {
                        out.push(Action::Edit(Edit::Approx(
                            c,
                            ApproxSpec::without_hand_knots(&spec),
                        )));
                    }
                });
            });
        if open {
            self.table = Some(t);
        }
    }
}
