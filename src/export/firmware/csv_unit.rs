//! A unit's lookup tables as one CSV file with an `axis` column.
//!
//! Why one file with an axis column rather than a file per axis: a firmware build step turns
//! the tables into one array (or one flash block) for the unit, and one file keeps the axes
//! together, of one version, from one export; the rows of an axis are the table a single-axis
//! export writes for it, with the axis's name before each row, so the loader of a single-axis
//! table reads an axis after filtering on the first column. Every axis's `#` comments come
//! first, each line starting with `# axis <name>:`, then one header line
//! `axis,<the single-axis table's columns>`, then every axis's rows in the calibration's order.
//!
//! The axes must have tables of the same columns (all Vakhrameev, in the same units, or all
//! regression): a unit mixing the two is refused with the axes named, each then exported alone
//! (`--axis`).

use super::csv_table;
use super::{ExportError, comment_text};
use crate::models::fitted::DriftModel;
use crate::models::unit::UnitCalibration;

/// The tables of every axis of `unit`, `points` rows per Vakhrameev coefficient.
///
/// # Errors
/// As the single-axis tables; axes whose tables have different columns.
pub fn csv_unit(unit: &UnitCalibration, points: usize) -> Result<String, ExportError> {
    unit.validate()?;
    let mut comments = String::new();
    let mut header: Option<(String, &str)> = None;
    let mut rows = String::new();
    for a in &unit.axes {
        let table = match &a.model {
            DriftModel::Vakhrameev(cal) => csv_table::csv_table(cal, points),
            DriftModel::Regression(r) => csv_table::regression(r),
        }
        .map_err(|e| ExportError::Calibration(format!("axis {}: {e}", a.name)))?;
        let axis = cell(&a.name);
        let mut lines = table.lines();
        let mut columns = None;
        for line in lines.by_ref() {
            match line.strip_prefix('#') {
                Some(c) => comments.push_str(&format!(
                    "# axis {}:{c}\n",
                    comment_text(&a.name).replace(':', ";")
                )),
                None => {
                    columns = Some(line.to_string());
                    break;
                }
            }
        }
        let Some(columns) = columns else {
            return Err(ExportError::Calibration(format!(
                "axis {}: a table without a header line",
                a.name
            )));
        };
        match &header {
            None => header = Some((columns, &a.name)),
            Some((first, first_axis)) if *first != columns => {
                return Err(ExportError::Calibration(format!(
                    "axes {first_axis} ({}) and {} ({}) have tables of different columns ({first} \
                     and {columns}): one file cannot hold both; export each axis alone with \
                     --axis",
                    model_of(unit, first_axis),
                    a.name,
                    a.model.tag()
                )));
            }
            Some(_) => {}
        }
        for line in lines {
            rows.push_str(&format!("{axis},{line}\n"));
        }
    }
    let Some((columns, _)) = header else {
        return Err(ExportError::Calibration("a unit without axes".into()));
    };
    Ok(format!(
        "# driftlab {version} lookup tables of a unit of {n} axes ({names}): the rows of each axis \
         are its table, as a single-axis export writes it, after its name in the first column\n\
         {comments}axis,{columns}\n{rows}",
        version = env!("CARGO_PKG_VERSION"),
        n = unit.axes.len(),
        names = comment_text(&unit.axis_names().join(", ")),
    ))
}

/// The model tag of the axis named `name`.
fn model_of(unit: &UnitCalibration, name: &str) -> &'static str {
    unit.axis(name).map_or("?", |a| a.model.tag())
}

/// An axis name as a CSV cell: as it is, or quoted when it holds a comma, a quote or a line
/// break.
fn cell(name: &str) -> String {
    if name.contains([',', '"', '\n', '\r']) {
        format!(
            "\"{}\"",
            name.replace('"', "\"\"").replace(['\n', '\r'], " ")
        )
    } else {
        name.to_string()
    }
}
