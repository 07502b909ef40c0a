//! The import view: what the reader would make of a file (its first rows, the column each
//! role would take, the units), what it said about the file when it last read it, and the
//! controls to correct the mapping, units, separator and decimal comma, the accelerometer
//! columns and their unit ([`accel`]), and to average the log into bins, before the (possibly
//! long) read starts.

mod accel;
pub use accel::{
    COLUMNS_LABEL as ACCEL_COLUMNS_LABEL, UNIT_LABEL as ACCEL_UNIT_LABEL, accel_in_labels,
};

use super::action::Action;
use super::jobs::{LoadOptions, Target};
use crate::log::ColumnRole;
use crate::log::accel_axes::AccelAsk;
use crate::log::ingest::{self, ColumnRef, Preview, RateUnit, ReadOptions, TimeUnit};
use crate::log::mapping_check::{self, Concern};
use eframe::egui::{self, Color32, ComboBox, Grid, RichText, ScrollArea, Ui};
use std::path::PathBuf;

/// The import view's state.
pub struct ImportView {
    /// The file.
    pub path: PathBuf,
    /// Which slot it goes into.
    pub target: Target,
    /// The options being edited.
    pub read: ReadOptions,
    /// Bins of this many seconds the log is averaged into after the read ("Average into bins
    /// of").
    pub bin_s: Option<f64>,
    /// The columns read as accelerometer axes and the unit of those whose name states none
    /// ("Accelerometers", "unit"): the engine's ask, `--accel-col` and `--accel-unit`.
    pub accel: AccelAsk,
    /// The gyro and temperature of a drone or robot log, kept as they were (the view maps a
    /// CSV's columns; File › Gyro of the log chooses these).
    instance: crate::log::read::InstanceChoice,
    /// A campaign's further runs, read with the mapping chosen here for the first (runs of
    /// one gyro are logged alike), kept as they were.
    more_runs: Vec<PathBuf>,
    /// What the reader said when it last read this file (problems it worked around, columns
    /// that do not hold what their role means, how the log was averaged), shown first while
    /// the options are the ones it was read with.
    warnings: Vec<ReadWarning>,
    /// The options the warnings are about.
    warned_for: ReadOptions,
    preview: Result<Preview, String>,
    previewed: ReadOptions,
    /// Where the window was last frame: while it moves or grows (a row wrapping once the
    /// width is known, the centring that follows a new size) the next frame is asked for, so
    /// the window settles without waiting for input.
    last_rect: Option<egui::Rect>,
    /// What to look at before loading (ambiguous or implausible columns).
    concerns: Vec<Concern>,
}

const PREVIEW_ROWS: usize = 25;

/// The read settings a reader's message may name, each with the label of its control in this
/// view (the column roles are one row of controls, "Time", "Rate", "Temperature"), and the
/// temperature source of a drone log by its place in File › Gyro of the log.
const SETTING_LABELS: [(&str, &str); 8] = [
    ("time_col", "Time column"),
    ("rate_col", "Rate column"),
    ("temp_col", "Temperature column"),
    ("rate_unit", "Rate unit"),
    ("time_unit", "Time unit"),
    ("sample_rate_hz", "Sample rate"),
    ("bin_s", "Average into bins of"),
    ("temp_from", "File › Gyro of the log › Temperature from"),
];

/// A message of the reader in the window's words: the settings it names are named by the
/// labels of this view's controls (`temp_col "temp_C"` → `Temperature column "temp_C"`).
pub fn in_labels(message: &str) -> String {
    crate::log::read::reworded(message, &SETTING_LABELS)
}

/// One thing the reader said about a file it read.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadWarning {
    /// True when it is about the columns chosen (values their role cannot have), which the
    /// view's mapping settles; false for rows and time steps the reader worked around.
    pub about_columns: bool,
    /// The sentence, with its line or column.
    pub text: String,
}

impl ImportView {
    /// Opens the view on `path` with starting options.
    pub fn new(path: PathBuf, target: Target, options: LoadOptions) -> ImportView {
        let LoadOptions {
            read,
            bin_s,
            instance,
            more_runs,
            accel,
        } = options;
        let preview =
            ingest::preview(&path, &read, PREVIEW_ROWS).map_err(|e| in_labels(&e.to_string()));
        let concerns = preview
            .as_ref()
            .map(|p| mapping_check::concerns_for(p, &read))
            .unwrap_or_default();
        ImportView {
            path,
            target,
            previewed: read.clone(),
            warned_for: read.clone(),
            read,
            bin_s,
            accel,
            instance,
            more_runs,
            warnings: Vec::new(),
            last_rect: None,
            preview,
            concerns,
        }
    }

    /// The view showing, first, what the reader said when it read the file with the view's
    /// starting options (the columns' doubts first).
    pub fn with_warnings(mut self, mut warnings: Vec<ReadWarning>) -> ImportView {
        warnings.sort_by_key(|w| !w.about_columns);
        self.warnings = warnings;
        self
    }

    /// What the reader said when it last read the file, while the options are the ones it
    /// read with (none once the engineer changes them).
    pub fn warnings(&self) -> &[ReadWarning] {
        if self.read == self.warned_for {
            &self.warnings
        } else {
            &[]
        }
    }

    /// The options the Load button reads with.
    pub fn options(&self) -> LoadOptions {
        LoadOptions {
            read: self.read.clone(),
            bin_s: self.bin_s,
            instance: self.instance,
            more_runs: self.more_runs.clone(),
            accel: self.accel.clone(),
        }
    }

    /// The preview as it stands (for tests).
    pub fn preview(&self) -> Result<&Preview, &str> {
        self.preview.as_ref().map_err(String::as_str)
    }

    /// What to look at before loading: ambiguous or implausible columns.
    pub fn concerns(&self) -> &[Concern] {
        &self.concerns
    }

    /// True when the file should not be read without the engineer seeing the preview: it
    /// cannot be previewed or mapped, or a column is ambiguous or implausible.
    pub fn needs_a_look(&self) -> bool {
        self.preview.is_err() || !self.concerns.is_empty()
    }

    /// Shows the view as a modal window; once the engineer decides, the read
    /// ([`Action::ReadLog`]) or [`Action::CloseImport`].
    pub fn ui(&mut self, ui: &mut Ui) -> Vec<Action> {
        let ctx = ui.ctx().clone();
        let mut decision = None;
        let modal = egui::Modal::new(egui::Id::unique("import_view")).show(&ctx, |ui| {
            ui.set_width((ctx.content_rect().width() * 0.8).clamp(480.0, 1200.0));
            decision = self.contents(ui);
        });
        let rect = modal.response.rect;
        if self.last_rect != Some(rect) {
            self.last_rect = Some(rect);
            ctx.request_repaint();
        }
        if modal.should_close() && decision.is_none() {
            decision = Some(Action::CloseImport);
        }
        if self.read != self.previewed {
            self.preview = ingest::preview(&self.path, &self.read, PREVIEW_ROWS)
                .map_err(|e| in_labels(&e.to_string()));
            self.concerns = self
                .preview
                .as_ref()
                .map(|p| mapping_check::concerns_for(p, &self.read))
                .unwrap_or_default();
            self.previewed = self.read.clone();
        }
        decision.into_iter().collect()
    }

    fn contents(&mut self, ui: &mut Ui) -> Option<Action> {
        let name = crate::gui::widgets::file_name(&self.path);
        ui.heading(match self.target {
            Target::Calibration => format!("Import {name}"),
            Target::Validation => format!("Import {name} as the validation log"),
        });
        ui.weak(self.path.display().to_string());
        ui.add_space(4.0);
        let warnings = self.warnings();
        if !warnings.is_empty() {
            ui.label(
                RichText::new(if warnings.iter().any(|w| w.about_columns) {
                    "When this file was read, its columns did not hold what they were read as:"
                } else {
                    "When this file was read:"
                })
                .strong(),
            );
            for w in warnings {
                let color = if w.about_columns {
                    ui.visuals().error_fg_color
                } else {
                    ui.visuals().warn_fg_color
                };
                ui.colored_label(color, format!("• {}", w.text));
            }
            ui.add_space(4.0);
        }
        let detected = self.preview.as_ref().ok().cloned();
        self.dialect_controls(ui, detected.as_ref());
        self.column_controls(ui, detected.as_ref());
        self.accel_controls(ui, detected.as_ref());
        self.bin_control(ui);
        ui.add_space(4.0);
        let mut ok = false;
        match &self.preview {
            Err(e) => {
                ui.colored_label(ui.visuals().error_fg_color, e.as_str());
            }
            Ok(p) => {
                if let Some(e) = &p.mapping_error {
                    ui.colored_label(
                        ui.visuals().error_fg_color,
                        format!("Cannot map the columns: {e}"),
                    );
                } else {
                    ok = true;
                    let role_of = |r: ColumnRole| p.columns.iter().find(|c| c.role == r);
                    let describe = |r: ColumnRole, what: &str| match role_of(r) {
                        Some(c) => format!(
                            "{what}: column {} \"{}\"{}",
                            c.index,
                            c.name,
                            if c.unit.is_empty() {
                                String::new()
                            } else {
                                format!(" [{}]", c.unit)
                            }
                        ),
                        None => format!("{what}: —"),
                    };
                    for c in self
                        .concerns
                        .iter()
                        .filter(|c| !c.message.starts_with("The columns cannot"))
                    {
                        ui.colored_label(
                            ui.visuals().warn_fg_color,
                            format!("Check: {}", c.message),
                        );
                    }
                    ui.label(format!(
                        "{} · {} · {}{}",
                        describe(ColumnRole::Time, "time"),
                        describe(ColumnRole::Rate, "rate"),
                        describe(ColumnRole::Temperature, "temperature"),
                        if p.time_from_sample_rate {
                            " · time from the sample rate"
                        } else {
                            ""
                        }
                    ));
                    // The accelerometer axes the engine would make of the columns, or why
                    // it cannot (columns asked for that are none of the kept ones).
                    match accel::summary(p, &self.accel, &self.path.display().to_string()) {
                        Some(Ok(s)) => {
                            ui.label(s);
                        }
                        Some(Err(e)) => {
                            ok = false;
                            ui.colored_label(ui.visuals().error_fg_color, e);
                        }
                        None => {}
                    }
                }
                let accels: Vec<usize> =
                    accel::taken(p, &self.accel, &self.path.display().to_string())
                        .map(|c| c.iter().map(|c| c.index).collect())
                        .unwrap_or_default();
                preview_table(ui, p, &accels);
            }
        }
        ui.separator();
        let mut decision = None;
        ui.horizontal(|ui| {
            if ui
                .add_enabled(ok, egui::Button::new(RichText::new("Load").strong()))
                .on_hover_text("Read the whole file with these settings (on a background thread; it can be cancelled)")
                .clicked()
            {
                decision = Some(Action::ReadLog(self.path.clone(), self.options(), self.target));
            }
            if ui.button("Cancel").on_hover_text("Close without reading; the current work stays as it is").clicked() {
                decision = Some(Action::CloseImport);
            }
            if ui
                .button("Reset")
                .on_hover_text("Back to what the reader guesses from the file")
                .clicked()
            {
                self.read = ReadOptions::default();
                self.bin_s = None;
                self.accel = AccelAsk::default();
            }
        });
        if ui.input(|i| i.key_pressed(egui::Key::Enter))
            && ok
            && !ui.ctx().egui_wants_keyboard_input()
        {
            decision = Some(Action::ReadLog(
                self.path.clone(),
                self.options(),
                self.target,
            ));
        }
        decision
    }

    fn dialect_controls(&mut self, ui: &mut Ui, p: Option<&Preview>) {
        ui.horizontal_wrapped(|ui| {
            let sep_name = |d: u8| match d {
                b',' => "comma".to_string(),
                b';' => "semicolon".to_string(),
                b'\t' => "tab".to_string(),
                b' ' => "spaces".to_string(),
                c => format!("'{}'", c as char),
            };
            let detected = p.map(|p| sep_name(p.delimiter as u8)).unwrap_or_default();
            ui.label("Separator");
            ComboBox::from_id_salt("imp_sep")
                .selected_text(match self.read.delimiter {
                    None => auto_label(&detected),
                    Some(d) => sep_name(d),
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.read.delimiter, None, auto_label(&detected));
                    for d in [b',', b';', b'\t', b' '] {
                        ui.selectable_value(&mut self.read.delimiter, Some(d), sep_name(d));
                    }
                })
                .response
                .on_hover_text("Field separator; 'spaces' means runs of blanks (aligned columns)");
            ui.label("Decimal");
            let dc = p
                .map(|p| if p.decimal_comma { "comma" } else { "point" })
                .unwrap_or("");
            ComboBox::from_id_salt("imp_dec")
                .selected_text(match self.read.decimal_comma {
                    None => auto_label(dc),
                    Some(true) => "comma (1,5)".into(),
                    Some(false) => "point (1.5)".into(),
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.read.decimal_comma, None, auto_label(dc));
                    ui.selectable_value(&mut self.read.decimal_comma, Some(false), "point (1.5)");
                    ui.selectable_value(&mut self.read.decimal_comma, Some(true), "comma (1,5)");
                })
                .response
                .on_hover_text("Whether numbers are written with a decimal comma");
            ui.label("Header");
            let hh = p
                .map(|p| if p.has_header { "yes" } else { "no" })
                .unwrap_or("");
            ComboBox::from_id_salt("imp_head")
                .selected_text(match self.read.has_header {
                    None => auto_label(hh),
                    Some(true) => "yes".into(),
                    Some(false) => "no".into(),
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.read.has_header, None, auto_label(hh));
                    ui.selectable_value(&mut self.read.has_header, Some(true), "yes");
                    ui.selectable_value(&mut self.read.has_header, Some(false), "no");
                })
                .response
                .on_hover_text("Whether the first non-comment line names the columns");
        });
    }

    fn column_controls(&mut self, ui: &mut Ui, p: Option<&Preview>) {
        let names: Vec<String> = p.map(|p| p.names.clone()).unwrap_or_default();
        let found = |r: ColumnRole| {
            p.and_then(|p| p.columns.iter().find(|c| c.role == r))
                .map(|c| format!("{}: {}", c.index, c.name))
                .unwrap_or_else(|| "none".into())
        };
        ui.horizontal_wrapped(|ui| {
            for (label, id, slot, role, tip) in [
                (
                    "Time",
                    "imp_time",
                    &mut self.read.time_col,
                    ColumnRole::Time,
                    "The time column (auto: found by name)",
                ),
                (
                    "Rate",
                    "imp_rate",
                    &mut self.read.rate_col,
                    ColumnRole::Rate,
                    "The gyro rate column",
                ),
                (
                    "Temperature",
                    "imp_temp",
                    &mut self.read.temp_col,
                    ColumnRole::Temperature,
                    "The calibration temperature (coil or frame sensor)",
                ),
            ] {
                ui.label(label);
                let shown = match slot {
                    None => auto_label(&found(role)),
                    Some(ColumnRef::Index(i)) => format!(
                        "{i}: {}",
                        names.get(i.wrapping_sub(1)).cloned().unwrap_or_default()
                    ),
                    Some(ColumnRef::Name(n)) => n.clone(),
                };
                ComboBox::from_id_salt(id)
                    .selected_text(shown)
                    .show_ui(ui, |ui| {
                        ui.selectable_value(slot, None, auto_label(&found(role)));
                        for (i, n) in names.iter().enumerate() {
                            ui.selectable_value(
                                slot,
                                Some(ColumnRef::Index(i + 1)),
                                format!("{}: {n}", i + 1),
                            );
                        }
                    })
                    .response
                    .on_hover_text(tip);
            }
        });
        ui.horizontal_wrapped(|ui| {
            let unit_of = |r: ColumnRole| {
                p.and_then(|p| p.columns.iter().find(|c| c.role == r))
                    .map(|c| if c.unit.is_empty() { "default".to_string() } else { c.unit.clone() })
                    .unwrap_or_default()
            };
            ui.label("Rate unit");
            let ru = unit_of(ColumnRole::Rate);
            ComboBox::from_id_salt("imp_ru")
                .selected_text(match self.read.rate_unit {
                    None => auto_label(&ru),
                    Some(u) => u.to_string(),
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.read.rate_unit, None, auto_label(&ru));
                    for u in [RateUnit::DegPerHour, RateUnit::DegPerSec, RateUnit::RadPerSec] {
                        ui.selectable_value(&mut self.read.rate_unit, Some(u), u.to_string());
                    }
                })
                .response
                .on_hover_text("Unit of the rate column (auto: from the header, else °/h); converted to °/h");
            ui.label("Time unit");
            let tu = unit_of(ColumnRole::Time);
            ComboBox::from_id_salt("imp_tu")
                .selected_text(match self.read.time_unit {
                    None => auto_label(&tu),
                    Some(u) => u.to_string(),
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.read.time_unit, None, auto_label(&tu));
                    for u in [
                        TimeUnit::Seconds,
                        TimeUnit::Millis,
                        TimeUnit::Minutes,
                        TimeUnit::Hours,
                        TimeUnit::Samples,
                    ] {
                        ui.selectable_value(&mut self.read.time_unit, Some(u), u.to_string());
                    }
                })
                .response
                .on_hover_text("Unit of the time column (auto: from the header, else s); 'samples' needs a sample rate");
            let mut has_rate = self.read.sample_rate_hz.is_some();
            if ui
                .checkbox(&mut has_rate, "Sample rate")
                .on_hover_text("Needed when time is a sample counter or the file has no time column")
                .changed()
            {
                self.read.sample_rate_hz = has_rate.then_some(1.0);
            }
            if let Some(hz) = &mut self.read.sample_rate_hz {
                ui.add(egui::DragValue::new(hz).range(1e-6..=1e6).speed(0.1).suffix(" Hz"))
                    .on_hover_text("Samples per second");
            }
        });
    }

    /// Average the log into bins of a few seconds once it is read.
    fn bin_control(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            let mut binned = self.bin_s.is_some();
            if ui
                .checkbox(&mut binned, "Average into bins of")
                .on_hover_text(
                    "Average the log into bins of this many seconds once it is read, before \
                     anything else: the usual first step with 100 Hz–2 kHz IMU logs, \
                     whose thermal drift lives at minutes",
                )
                .changed()
            {
                self.bin_s = binned.then_some(1.0);
            }
            match &mut self.bin_s {
                Some(s) => {
                    ui.add(
                        egui::DragValue::new(s)
                            .range(1e-3..=86_400.0)
                            .speed(0.1)
                            .suffix(" s"),
                    )
                    .on_hover_text("Bin length, s");
                }
                None => {
                    ui.weak("no: a log written in bursts is reduced to one sample per burst");
                }
            }
        });
    }
}

fn role_color(ui: &Ui, r: ColumnRole) -> Color32 {
    match r {
        ColumnRole::Time => ui.visuals().hyperlink_color,
        ColumnRole::Rate | ColumnRole::OtherAxis | ColumnRole::AccelAxis => {
            Color32::from_rgb(220, 120, 0)
        }
        ColumnRole::Temperature => Color32::from_rgb(200, 50, 40),
        ColumnRole::Extra => ui.visuals().text_color(),
        ColumnRole::Ignored => ui.visuals().weak_text_color(),
    }
}

/// The preview's columns, each with the role it would be read with (`accels`: the columns
/// that would be accelerometer axes, by their numbers).
fn preview_table(ui: &mut Ui, p: &Preview, accels: &[usize]) {
    // As tall as it will be from the first frame (a scroll area that needs scrolling would
    // otherwise grow by a row a frame, and the window with it).
    ScrollArea::both()
        .max_height(320.0)
        .min_scrolled_height(320.0)
        .auto_shrink([false, true])
        .show(ui, |ui| {
            Grid::new("import_preview")
                .striped(true)
                .spacing([12.0, 2.0])
                .show(ui, |ui| {
                    // Column names and cells on one line each: the grid widens, the view scrolls.
                    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
                    ui.label(RichText::new("line").weak());
                    for (i, n) in p.names.iter().enumerate() {
                        let info = p.columns.iter().find(|c| c.index == i + 1);
                        let (mut role, unit) = info
                            .map_or((ColumnRole::Ignored, String::new()), |c| {
                                (c.role, c.unit.clone())
                            });
                        if accels.contains(&(i + 1)) {
                            role = ColumnRole::AccelAxis;
                        }
                        let role_name = match role {
                            ColumnRole::Time => "time",
                            ColumnRole::Rate => "rate",
                            ColumnRole::OtherAxis => "other axis",
                            ColumnRole::AccelAxis => "accelerometer axis",
                            ColumnRole::Temperature => "temperature",
                            ColumnRole::Extra => "kept",
                            ColumnRole::Ignored => "ignored",
                        };
                        ui.vertical(|ui| {
                            ui.label(RichText::new(n).strong());
                            ui.label(
                                RichText::new(if unit.is_empty() {
                                    role_name.to_string()
                                } else {
                                    format!("{role_name} [{unit}]")
                                })
                                .small()
                                .color(role_color(ui, role)),
                            );
                        });
                    }
                    ui.end_row();
                    for (row, line) in p.rows.iter().zip(&p.row_lines) {
                        ui.label(RichText::new(line.to_string()).weak().monospace());
                        for cell in row {
                            ui.monospace(cell);
                        }
                        ui.end_row();
                    }
                });
        });
}

/// "auto" with what the reader found (`auto (deg/s)`), or alone when it found nothing to name.
fn auto_label(found: &str) -> String {
    if found.trim().is_empty() {
        "auto".to_string()
    } else {
        format!("auto ({found})")
    }
}
