//! The plateaus that define K0(T): a table (times typed in, statistics of each, delete), the
//! detector's suggestion, and whether the detector chooses them.

use super::{ControlsView, PlateauFocus};
use crate::gui::action::{Action, Edit};
use crate::gui::plot_items::num;
use crate::gui::state::AppState;
use crate::signal::plateau::{DetectOptions, PlateauRange, PlateauStats};
use eframe::egui::{self, RichText, Ui};

/// The plateau table's column widths the controls panel is started for, points: #, delete,
/// start, end, T, Ω, ΔT, °C/min, std, samples, each just wide enough for the sample logs'
/// numbers (the units are in the header tips), so that the whole table fits the controls
/// panel of a 1280-wide window. The table itself takes each column's width from what it holds
/// ([`column_widths`], the same for every row, so the × buttons line up).
const W: [f32; 10] = [20.0, 18.0, 54.0, 54.0, 38.0, 48.0, 36.0, 40.0, 44.0, 34.0];
/// The table's headers, with their tips (the units are there).
const HEADERS: [(&str, &str); 10] = [
    (
        "#",
        "Click to select the plateau in the time plots; ! marks one outside \
     the detector's limits (hover it for why)",
    ),
    ("", ""),
    (
        "start, s",
        "Start time, s: drag the number or click and type",
    ),
    ("end, s", "End time, s"),
    ("T, °C", "Mean temperature on the plateau"),
    ("Ω, °/h", "Mean gyro output: the K0 point"),
    (
        "ΔT",
        "ΔT, °C: the spread of the temperature on the plateau, max − min (large: not stable)",
    ),
    (
        "°C/min",
        "How fast T moves over the plateau on average, °C/min: ΔT over its length (the \
     detector holds a plateau under its max rate)",
    ),
    ("std", "Standard deviation of the raw Ω on the plateau, °/h"),
    ("n", "Samples on the plateau"),
];

/// The gap between two columns, points.
const GAP: f32 = 2.0;
/// The controls panel's width that shows the whole table, points: its columns and gaps, the
/// collapsing header's indent (18), the panel's margins (2 × 8), and 28 points more: the
/// rows come out that much wider than their columns' sum (measured at 1280×720), and the
/// controls' scroll bar floats over the panel's right edge.
pub const CONTROLS_W_FOR_TABLE: f32 = {
    let mut w = 9.0 * GAP + 18.0 + 16.0 + 28.0;
    let mut k = 0;
    while k < W.len() {
        w += W[k];
        k += 1;
    }
    w
};

impl ControlsView {
    /// The plateau table with its buttons.
    pub(super) fn plateau_table(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        focus: PlateauFocus,
        out: &mut Vec<Action>,
    ) {
        let Some(loaded) = state.shown.log.clone() else {
            ui.weak("No log loaded.");
            return;
        };
        let log = &loaded.log;
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Suggest plateaus")
                .on_hover_text(
                    "Fill the table with the plateaus the engine's detector finds (|dT/dt| below \
                     0.05 °C/min for 20 min, settled half kept); they can then be edited",
                )
                .clicked()
            {
                out.push(Action::SuggestPlateaus);
            }
            if ui
                .button("Add")
                .on_hover_text("Add a plateau in the middle of the visible time range (then type its times or drag its edges)")
                .clicked()
            {
                let (a, b) = focus
                    .visible_s
                    .unwrap_or((log.time_s[0], log.time_s[log.len() - 1]));
                let c = 0.5 * (a + b);
                let w = 0.05 * (b - a);
                out.push(Action::AddPlateau(PlateauRange {
                    start_s: c - w,
                    end_s: c + w,
                }));
            }
            let mut auto = state.plateaus_auto();
            if ui
                .checkbox(&mut auto, "Automatic")
                .on_hover_text(
                    "On: the detector chooses the plateaus every time the filters change. \
                     Off: the plateaus are the ones in the table, kept as they are.",
                )
                .changed()
            {
                out.push(Action::Edit(if auto {
                    Edit::AutoPlateaus
                } else {
                    Edit::Plateaus(state.ranges())
                }));
            }
        });
        let ranges = state.ranges();
        let stats = state.plateau_stats();
        ui.weak(format!(
            "{} plateau{} {}",
            ranges.len(),
            if ranges.len() == 1 { "" } else { "s" },
            if state.plateaus_auto() {
                "found by the detector"
            } else {
                "set by hand"
            }
        ));
        let mut edited: Option<Vec<PlateauRange>> = None;

        // Hand-set plateaus are held to the limits of the detector they replace.
        let detector = match &state.recipe().plateaus {
            crate::models::recipe::PlateauChoice::Auto(opts) => *opts,
            crate::models::recipe::PlateauChoice::Manual { .. } => Default::default(),
        };
        let step = (log.nominal_dt_s() * 10.0).max(1e-3);
        // The table scrolls sideways in a narrow panel. The delete button comes second, so
        // that it stays in reach when it does.
        let row_h = ui.spacing().interact_size.y;
        let w = column_widths(ui, &HEADERS, &ranges, &stats);
        let cell = |ui: &mut Ui, k: usize, text: RichText| {
            ui.add_sized([w[k], row_h], egui::Label::new(text).truncate())
        };
        let (first_s, last_s) = (log.time_s[0], log.time_s[log.len() - 1]);
        egui::ScrollArea::horizontal()
            .id_salt("plateau_table_x")
            .auto_shrink([false, true])
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.spacing_mut().item_spacing.x = GAP;
                    for (k, (h, tip)) in HEADERS.into_iter().enumerate() {
                        cell(ui, k, RichText::new(h).strong()).on_hover_text(tip);
                    }
                });
                // Only the visible rows are laid out: a tiled ten-million-sample log has
                // hundreds.
                egui::ScrollArea::vertical()
                    .id_salt("plateau_table")
                    .max_height(8.0 * (row_h + ui.spacing().item_spacing.y))
                    .auto_shrink([false, true])
                    .show_rows(ui, row_h, ranges.len(), |ui, rows| {
                        for k in rows {
                            let r = ranges[k];
                            ui.horizontal(|ui| {
                                ui.spacing_mut().item_spacing.x = GAP;
                                self.plateau_row(
                                    ui,
                                    (k, r, &ranges),
                                    (&stats, &detector),
                                    (focus, step, (first_s, last_s), log),
                                    (&w, row_h),
                                    (out, &mut edited),
                                );
                            });
                        }
                    });
            });
        if let Some(note) = &self.plateau_note {
            ui.horizontal(|ui| {
                ui.add(
                    egui::Label::new(RichText::new(note).color(ui.visuals().warn_fg_color)).wrap(),
                );
            });
            if ui
                .small_button("OK")
                .on_hover_text("Hide this note")
                .clicked()
            {
                self.plateau_note = None;
            }
        }
        if let Some(r) = edited {
            out.push(Action::Edit(Edit::Plateaus(r)));
        }
    }

    /// One row of the plateau table: `k`, its range and every range; the fit's statistics and
    /// the detector's limits; what is focused, the drag step, the log's span and the log;
    /// the column widths and the row height; the actions and the table's edit.
    #[allow(clippy::type_complexity)]
    fn plateau_row(
        &mut self,
        ui: &mut Ui,
        (k, r, ranges): (usize, PlateauRange, &[PlateauRange]),
        (stats, detector): (&[PlateauStats], &DetectOptions),
        (focus, step, (first_s, last_s), log): (PlateauFocus, f64, (f64, f64), &crate::log::Log),
        (w, row_h): (&[f32; 10], f32),
        (out, edited): (&mut Vec<Action>, &mut Option<Vec<PlateauRange>>),
    ) {
        let cell = |ui: &mut Ui, c: usize, text: RichText| {
            ui.add_sized([w[c], row_h], egui::Label::new(text).truncate())
        };
        let sel = focus.selected == Some(k);
        let found = stats.iter().find(|s| s.range == r);
        // What keeps it from being a plateau the detector would have found (the engine's
        // words).
        let outside = found.map_or(Vec::new(), |s| {
            crate::signal::plateau::outside_detector(s, detector)
        });
        let warn = ui.visuals().warn_fg_color;
        let why = if outside.is_empty() {
            String::new()
        } else {
            format!("Outside the detector's limits: {}.\n", outside.join("; "))
        };
        // A campaign's plateau belongs to its run: its number in the run's colour (the K0
        // points' and the run strip's), the run named in the tip.
        let run = (log.runs().len() > 1)
            .then(|| crate::models::campaign::run_of_each(log, std::slice::from_ref(&r))[0]);
        let label = if outside.is_empty() {
            let text = RichText::new(format!("{}", k + 1));
            match run {
                Some(Some(j)) => text
                    .color(crate::gui::view_runs::run_color(j, ui.visuals().dark_mode))
                    .strong(),
                _ => text,
            }
        } else {
            RichText::new(format!("!{}", k + 1)).color(warn).strong()
        };
        let of_run = match run {
            Some(Some(j)) => format!("Run {}: {}.\n", j + 1, log.runs()[j].name),
            Some(None) => "Across the end of a run: a plateau of neither run, its samples \
                           from both; move it within one run.\n"
                .to_string(),
            None => String::new(),
        };
        if ui
            .add_sized([w[0], row_h], egui::Button::selectable(sel, label))
            .on_hover_text(format!(
                "{of_run}{why}Select this plateau (Delete removes it)"
            ))
            .clicked()
        {
            out.push(Action::SelectPlateau(if sel { None } else { Some(k) }));
        }
        if ui
            .add_sized([w[1], row_h], egui::Button::new("×"))
            .on_hover_text("Delete this plateau")
            .clicked()
        {
            let mut all = ranges.to_vec();
            all.remove(k);
            *edited = Some(all);
            out.push(Action::SelectPlateau(None));
        }
        let (mut a, mut b) = (r.start_s, r.end_s);
        let ca = ui
            .add_sized(
                [w[2], row_h],
                egui::DragValue::new(&mut a)
                    .speed(step)
                    .max_decimals(1)
                    .custom_formatter(|n, _| time_text(n))
                    .custom_parser(unedited_or_typed(r.start_s))
                    .update_while_editing(false),
            )
            .on_hover_text("Start, s: drag, or click and type a time");
        let cb = ui
            .add_sized(
                [w[3], row_h],
                egui::DragValue::new(&mut b)
                    .speed(step)
                    .max_decimals(1)
                    .custom_formatter(|n, _| time_text(n))
                    .custom_parser(unedited_or_typed(r.end_s))
                    .update_while_editing(false),
            )
            .on_hover_text("End, s: drag, or click and type a time");
        if ca.changed() || cb.changed() {
            match typed_range(k, a, b, (first_s, last_s), log) {
                Ok((range, note)) => {
                    let mut all = ranges.to_vec();
                    all[k] = range;
                    *edited = Some(all);
                    self.plateau_note = note;
                }
                Err(why) => {
                    out.push(Action::Warn(why.clone()));
                    self.plateau_note = Some(why);
                }
            }
        }
        match found {
            Some(s) => {
                let marked = |t: RichText| if outside.is_empty() { t } else { t.color(warn) };
                let [t, omega, spread, rate, std, n] = stat_cells(s);
                cell(ui, 4, RichText::new(t));
                cell(ui, 5, RichText::new(omega)).on_hover_text(match s.omega_sem_dph {
                    Some(sem) => format!("standard error of the mean {} °/h", num(sem)),
                    None => "one sample: its spread is unknown".to_string(),
                });
                let length_s = s.range.end_s - s.range.start_s;
                let quality = format!(
                    "{why}{} °C between the coldest and the warmest sample over its {} s",
                    crate::number::fixed(s.temp_spread_c, 3),
                    num(length_s),
                );
                cell(ui, 6, marked(RichText::new(spread))).on_hover_text(&quality);
                cell(ui, 7, marked(RichText::new(rate))).on_hover_text(&quality);
                cell(ui, 8, RichText::new(std)).on_hover_text(if s.omega_std_dph.is_some() {
                    "Standard deviation of the raw Ω on the plateau, °/h"
                } else {
                    "n/a: one sample has no spread"
                });
                cell(ui, 9, RichText::new(n));
            }
            None => {
                for c in 4..10 {
                    cell(ui, c, RichText::new("…").weak());
                }
            }
        }
    }
}

/// Plateau `k` typed as `a`..`b` s on a log spanning `span` s: the range to take, with what
/// to tell about it (it reaches past the log), or why it is not taken (it ends before it
/// starts, or holds no sample of the log), each in the engine's words.
fn typed_range(
    k: usize,
    a: f64,
    b: f64,
    span: (f64, f64),
    log: &crate::log::Log,
) -> Result<(PlateauRange, Option<String>), String> {
    let not_changed = |why: String| format!("Plateau {} not changed: {why}", k + 1);
    let text = format!(
        "{}:{}",
        crate::number::readable(a),
        crate::number::readable(b)
    );
    let range: PlateauRange = text.parse().map_err(|e| not_changed(format!("{e}")))?;
    if range.end_s < span.0 || range.start_s > span.1 {
        let words = crate::signal::plateau::too_few_samples(&[range], &[]);
        return Err(not_changed(words.join("; ")));
    }
    let recipe = crate::models::recipe::Recipe {
        plateaus: crate::models::recipe::PlateauChoice::Manual {
            ranges: vec![range],
        },
        ..Default::default()
    };
    let beyond: Vec<String> = recipe
        .plateaus_beyond(log)
        .into_iter()
        .map(|i| i.to_string())
        .collect();
    Ok((
        range,
        (!beyond.is_empty()).then(|| format!("Plateau {}: {}", k + 1, beyond.join("; "))),
    ))
}

/// The texts of a plateau's statistics cells: T, Ω, ΔT, °C/min, std, n.
fn stat_cells(s: &PlateauStats) -> [String; 6] {
    [
        crate::number::fixed(s.temp_c, 2),
        num(s.omega_dph),
        crate::number::fixed(s.temp_spread_c, 3),
        s.mean_rate_c_per_min().map_or("n/a".to_string(), rate_text),
        s.omega_std_dph.map_or("n/a".to_string(), num),
        s.samples.to_string(),
    ]
}

/// The columns' widths, points: each as wide as the widest of its header and its cells (the
/// numbers are never cut to "…": imu3's sample counts were), the buttons' and fields' with
/// their padding; the delete button's as [`W`] has it.
fn column_widths(
    ui: &Ui,
    headers: &[(&str, &str); 10],
    ranges: &[PlateauRange],
    stats: &[PlateauStats],
) -> [f32; 10] {
    let font = egui::TextStyle::Body.resolve(ui.style());
    let pad = 2.0 * ui.spacing().button_padding.x;
    let mut w = [0.0f32; 10];
    ui.fonts_mut(|f| {
        let mut wide = |k: usize, text: String, extra: f32| {
            let g = f.layout_no_wrap(text, font.clone(), egui::Color32::WHITE);
            w[k] = w[k].max(g.size().x + extra);
        };
        for (k, (h, _)) in headers.iter().enumerate() {
            wide(k, h.to_string(), 0.0);
        }
        wide(0, format!("!{}", ranges.len()), pad);
        for r in ranges {
            wide(2, time_text(r.start_s), pad);
            wide(3, time_text(r.end_s), pad);
        }
        for s in stats {
            for (k, text) in stat_cells(s).into_iter().enumerate() {
                wide(4 + k, text, 0.0);
            }
        }
    });
    w[1] = W[1];
    // (whole points: a text as wide as its cell is never elided)
    w.map(f32::ceil)
}

/// A time in a start or end cell: at most one decimal (`3708.6`, `40200`).
fn time_text(t: f64) -> String {
    eframe::egui::emath::format_with_decimals_in_range(t, 0..=1)
}

/// The parser of a start or end cell showing `t`: the text as shown (the cell committed
/// without an edit) is `t` itself, not its one-decimal display; anything else is read as
/// typed.
fn unedited_or_typed(t: f64) -> impl Fn(&str) -> Option<f64> {
    let shown = time_text(t);
    move |text: &str| {
        let text = text.trim();
        if text == shown {
            Some(t)
        } else {
            text.parse::<f64>().ok()
        }
    }
}

/// A rate of T for a narrow cell: two significant digits (`2.7e-4`, `0.052`, `1.3`).
fn rate_text(v: f64) -> String {
    if v != 0.0 && v.abs() < 0.01 {
        format!("{v:.1e}")
    } else {
        crate::number::significant(v, 2)
    }
}
