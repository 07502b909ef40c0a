//! The import view's accelerometer row: which columns are read as accelerometer axes and in
//! what unit, as `--accel-col` and `--accel-unit` say it on the command line. The view only
//! holds the choice (the engine's [`AccelAsk`]) and shows what the engine makes of it: the
//! columns it would take of the preview ([`accel_axes::columns_taken`], the rule the read
//! applies, [`accel_axes::take`]), or its refusal in the window's words.

use super::{ImportView, auto_label};
use crate::log::accel_axes::{self, AccelAsk, AccelError, AccelUnit};
use crate::log::ingest::{ColumnRef, Preview};
use crate::log::{ColumnInfo, ColumnRole};
use eframe::egui::{self, ComboBox, Ui, WidgetInfo};

/// The accelerometer columns control's label, as the window names the setting.
pub const COLUMNS_LABEL: &str = "Accelerometer columns";
/// The accelerometer unit control's label.
pub const UNIT_LABEL: &str = "Accelerometer unit";

/// Why the engine could not make accelerometer axes of a log's columns, in the window's
/// words: the setting to change named by its control in the import view (File › Column
/// mapping…), as the command line names its flag.
pub fn accel_in_labels(e: &AccelError) -> String {
    let at = |label: &str| format!("{e} ({label} in File › Column mapping…)");
    match e {
        AccelError::NoAccelerometers { .. } => e.to_string().replace(
            "name them with the accelerometer columns option",
            &format!("choose them under {COLUMNS_LABEL} in File › Column mapping…"),
        ),
        AccelError::NoColumn { .. }
        | AccelError::NotAnAcceleration { .. }
        | AccelError::TakenColumn { .. } => at(COLUMNS_LABEL),
        AccelError::UnitUntold { .. }
        | AccelError::UnitContradicted { .. }
        | AccelError::NotGravity { .. } => at(UNIT_LABEL),
    }
}

/// What the engine would take of the preview's columns as accelerometer axes with `ask`:
/// those columns, none (a log that names none and asks for none), or its refusal.
pub(super) fn taken<'a>(
    p: &'a Preview,
    ask: &AccelAsk,
    source: &str,
) -> Result<Vec<&'a ColumnInfo>, AccelError> {
    match accel_axes::columns_taken(source, &p.columns, ask) {
        Err(AccelError::NoAccelerometers { .. }) if ask.is_default() => Ok(Vec::new()),
        other => other,
    }
}

/// The sentence under the mapping that says which columns will be accelerometer axes and in
/// what unit; `None` for a log with none.
pub(super) fn summary(p: &Preview, ask: &AccelAsk, source: &str) -> Option<Result<String, String>> {
    let columns = match taken(p, ask, source) {
        Ok(c) if c.is_empty() => return None,
        Ok(c) => c,
        Err(e) => return Some(Err(accel_in_labels(&e))),
    };
    let unit = |c: &ColumnInfo| match (AccelUnit::of_channel(&c.unit), ask.unit) {
        (Some(u), _) => format!(" [{u}]"),
        (None, Some(u)) => format!(" [{u}, as chosen]"),
        (None, None) => " [unit told by gravity once read]".to_string(),
    };
    let list: Vec<String> = columns
        .iter()
        .map(|c| format!("column {} \"{}\"{}", c.index, c.name, unit(c)))
        .collect();
    Some(Ok(format!(
        "accelerometer axes, in m/s² once read: {}",
        list.join(", ")
    )))
}

impl ImportView {
    /// The accelerometer columns (every column named as one, or those ticked) and the unit of
    /// those whose name states none.
    pub(super) fn accel_controls(&mut self, ui: &mut Ui, p: Option<&Preview>) {
        let names: Vec<String> = p.map(|p| p.names.clone()).unwrap_or_default();
        let source = self.path.display().to_string();
        let by_name: String = p
            .and_then(|p| taken(p, &AccelAsk::default(), &source).ok())
            .map(|c| {
                c.iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            })
            .unwrap_or_default();
        let auto = if by_name.is_empty() {
            "none named as one".to_string()
        } else {
            auto_label(&by_name)
        };
        ui.horizontal_wrapped(|ui| {
            ui.label("Accelerometers");
            let shown = if self.accel.columns.is_empty() {
                auto.clone()
            } else {
                self.accel
                    .columns
                    .iter()
                    .map(|c| match c {
                        ColumnRef::Index(i) => format!(
                            "{i}: {}",
                            names.get(i.wrapping_sub(1)).cloned().unwrap_or_default()
                        ),
                        ColumnRef::Name(n) => n.clone(),
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let value = shown.clone();
            let r = ComboBox::from_id_salt("imp_accel")
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    if ui
                        .selectable_label(self.accel.columns.is_empty(), auto.as_str())
                        .on_hover_text("Every column whose name reads as an accelerometer")
                        .clicked()
                    {
                        self.accel.columns.clear();
                    }
                    let roles = p.map(|p| p.columns.as_slice()).unwrap_or_default();
                    for (i, n) in names.iter().enumerate() {
                        // The columns the log reads as time, rate and temperature are not free.
                        let free = roles
                            .iter()
                            .find(|c| c.index == i + 1)
                            .is_none_or(|c| c.role == ColumnRole::Extra);
                        let r = ColumnRef::Index(i + 1);
                        let mut on = self.accel.columns.contains(&r);
                        if ui
                            .add_enabled(
                                free,
                                egui::Checkbox::new(&mut on, format!("{}: {n}", i + 1)),
                            )
                            .changed()
                        {
                            self.accel.columns.retain(|c| *c != r);
                            if on {
                                self.accel.columns.push(r);
                                self.accel.columns.sort_by_key(|c| match c {
                                    ColumnRef::Index(i) => *i,
                                    ColumnRef::Name(_) => usize::MAX,
                                });
                            }
                        }
                    }
                })
                .response;
            r.widget_info(|| {
                let mut info =
                    WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, COLUMNS_LABEL);
                info.current_text_value = Some(value.clone());
                info
            });
            r.on_hover_text(
                "The columns read as accelerometer axes, calibrated beside the gyro axes \
                 (auto: every column whose name reads as one: acc_x, ax_g, accel_x_m_s2)",
            );
            ui.label("unit");
            let unit_text = |u: Option<AccelUnit>| match u {
                None => "auto (stated, else by gravity)".to_string(),
                Some(AccelUnit::MetersPerSecond2) => "m/s²".to_string(),
                Some(u) => u.to_string(),
            };
            let value = unit_text(self.accel.unit);
            let r = ComboBox::from_id_salt("imp_accel_unit")
                .selected_text(value.clone())
                .show_ui(ui, |ui| {
                    for u in [
                        None,
                        Some(AccelUnit::G),
                        Some(AccelUnit::MilliG),
                        Some(AccelUnit::MetersPerSecond2),
                    ] {
                        ui.selectable_value(&mut self.accel.unit, u, unit_text(u));
                    }
                })
                .response;
            r.widget_info(|| {
                let mut info =
                    WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, UNIT_LABEL);
                info.current_text_value = Some(value.clone());
                info
            });
            r.on_hover_text(
                "The unit of accelerometer columns whose names state none (auto: the \
                 magnitude of gravity tells g, mg or m/s²); converted to m/s²",
            );
        });
    }
}
