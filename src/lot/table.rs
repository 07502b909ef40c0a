//! The lot's table: `lot.csv`, one row per unit, and `lot.json`, the same with every unit's
//! warnings and the outliers, and the page of both, `lot.html` ([`super::page`]). The three are
//! put in place together ([`Batch`]): never a table of one lot beside the JSON of another.
//!
//! The CSV's columns are `unit`, `status`, `reasons`, `calibration`, then each figure of each
//! axis the lot's units have (`corrected_p2p_dph` for a single-axis unit, `gx.corrected_p2p_dph`
//! for axis gx of a unit of several), then `unavailable` (each empty figure's reason) and
//! `outliers` (the unit's figures far from the lot's median). Every text cell goes through the
//! project's one CSV writer ([`crate::files::csv_cells`]): quoted as needed, a cell a
//! spreadsheet would take for a formula neutralised. A figure that could not be computed is
//! an empty cell, never `NaN` or `0`, with its reason in `unavailable`.

use super::{LotOutcome, UnitOutcome};
use crate::files::atomic::Batch;
use crate::files::csv_cells::{Cell, record, text_record};
use std::collections::HashSet;
use std::path::Path;

/// Writes `OUT/lot.csv`, `OUT/lot.json` and `OUT/lot.html`, all or none.
///
/// # Errors
/// A write that fails; the previous files stay as they were.
pub fn write(out: &Path, lot: &LotOutcome) -> crate::Result<()> {
    let json = serde_json::to_string_pretty(lot)
        .map_err(|e| crate::Error::io(out.join("lot.json"), std::io::Error::other(e)))?
        + "\n";
    let mut batch = Batch::new();
    batch.stage_bytes(&out.join("lot.csv"), csv(lot).as_bytes())?;
    batch.stage_bytes(&out.join("lot.json"), json.as_bytes())?;
    batch.stage_bytes(&out.join("lot.html"), super::page::page(lot).as_bytes())?;
    batch.commit()
}

/// The column of each figure of each axis: (axis, figure), in the order first met over the
/// units. The columns met are kept in a set, so that listing them is linear in the figures
/// the units hold, however many columns there are.
pub fn columns(units: &[UnitOutcome]) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::new();
    let mut met: HashSet<(&str, &str)> = HashSet::new();
    for u in units {
        for a in &u.axes {
            for f in &a.figures {
                if met.insert((a.axis.as_str(), f.name.as_str())) {
                    out.push((a.axis.clone(), f.name.clone()));
                }
            }
        }
    }
    out
}

/// The header of a figure's column: `figure`, or `axis.figure` for a named axis.
pub fn column_name(axis: &str, figure: &str) -> String {
    if axis.is_empty() {
        figure.to_string()
    } else {
        format!("{axis}.{figure}")
    }
}

/// The text of `lot.csv`.
pub fn csv(lot: &LotOutcome) -> String {
    let columns = columns(&lot.units);
    let mut header = vec![
        "unit".to_string(),
        "status".into(),
        "reasons".into(),
        "calibration".into(),
    ];
    header.extend(columns.iter().map(|(a, f)| column_name(a, f)));
    header.extend(["unavailable".to_string(), "outliers".into()]);
    let mut text = text_record(&header);
    for u in &lot.units {
        let mut values: Vec<String> = Vec::with_capacity(columns.len());
        let mut unavailable = Vec::new();
        for (axis, name) in &columns {
            let figure = u
                .axes
                .iter()
                .find(|a| a.axis == *axis)
                .and_then(|a| a.get(name));
            values.push(match figure {
                Some(f) => match (f.value, &f.unavailable) {
                    (Some(v), _) => format!("{v}"),
                    (None, why) => {
                        unavailable.push(format!(
                            "{}: {}",
                            column_name(axis, name),
                            why.as_deref().unwrap_or("not computed")
                        ));
                        String::new()
                    }
                },
                None => String::new(),
            });
        }
        let outliers: Vec<String> = lot
            .outliers
            .iter()
            .filter(|o| o.unit == u.unit)
            .map(|o| format!("{} ({:+.1} sd)", column_name(&o.axis, &o.figure), o.sigmas))
            .collect();
        let reasons = u.reasons.join("; ");
        let unavailable = unavailable.join("; ");
        let outliers = outliers.join("; ");
        let calibration = u.calibration.clone().unwrap_or_default();
        let mut cells = vec![
            Cell::Text(&u.unit),
            Cell::Text(u.status.word()),
            Cell::Text(&reasons),
            Cell::Text(&calibration),
        ];
        cells.extend(values.iter().map(|v| Cell::Number(v)));
        cells.extend([Cell::Text(&unavailable), Cell::Text(&outliers)]);
        text.push_str(&record(&cells));
    }
    text
}
