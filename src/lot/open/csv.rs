//! `lot.csv` read back: its header checked as the lot's, each row's cells made a [`Row`] (the
//! text cells less the quote that kept a spreadsheet from taking them for formulas, the
//! figures as numbers, the reasons, unavailable figures and outliers split as the lot joined
//! them), and each calibrated unit's runs taken from its record (`OUT/<unit>/unit.json`),
//! since the CSV does not list them.

use super::{Column, LOT_CSV, LotFileError, Row};
use crate::lot::Status;
use crate::lot::figures;
use std::path::Path;

/// The first fields of `lot.csv`'s header, and its last.
const CSV_HEAD: [&str; 4] = ["unit", "status", "reasons", "calibration"];
const CSV_TAIL: [&str; 2] = ["unavailable", "outliers"];

/// The table of `lot.csv`. It holds no runs: each unit's are taken from its record in its
/// folder (`unit.json`), when there.
pub(super) fn of_csv(file: &Path, text: &str) -> Result<(Vec<Column>, Vec<Row>), LotFileError> {
    let bad = |line: u64, column: u64, message: String| LotFileError::Malformed {
        path: file.to_path_buf(),
        line,
        column,
        message,
    };
    let mut reader = ::csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(false)
        .from_reader(text.as_bytes());
    let mut records = reader.records();
    let header = match records.next() {
        Some(Ok(h)) => h,
        Some(Err(e)) => return Err(csv_error(file, &e)),
        None => return Err(bad(1, 1, format!("empty: not a lot's table ({LOT_CSV})"))),
    };
    let names: Vec<&str> = header.iter().collect();
    let n = names.len();
    if n < CSV_HEAD.len() + CSV_TAIL.len()
        || names[..CSV_HEAD.len()] != CSV_HEAD
        || names[n - CSV_TAIL.len()..] != CSV_TAIL
    {
        return Err(bad(
            1,
            1,
            format!(
                "not a lot's table ({LOT_CSV}): its header starts {} and ends {}",
                CSV_HEAD.join(","),
                CSV_TAIL.join(",")
            ),
        ));
    }
    let columns: Vec<Column> = names[CSV_HEAD.len()..n - CSV_TAIL.len()]
        .iter()
        .map(|h| split_heading(h))
        .collect();
    let out = file.parent().unwrap_or(Path::new("."));
    let mut rows = Vec::new();
    for record in records {
        let record = record.map_err(|e| csv_error(file, &e))?;
        let line = record.position().map_or(0, |p| p.line());
        let text = |k: usize| as_text(record.get(k).unwrap_or_default()).to_string();
        let status = match record.get(1).unwrap_or_default() {
            "pass" => Status::Pass,
            "fail" => Status::Fail,
            "error" => Status::Error,
            other => {
                return Err(bad(
                    line,
                    2,
                    format!("status {other:?}: a unit's status is pass, fail or error"),
                ));
            }
        };
        let mut values = Vec::with_capacity(columns.len());
        for (k, c) in columns.iter().enumerate() {
            let field = CSV_HEAD.len() + k;
            let cell = record.get(field).unwrap_or_default();
            values.push(if cell.is_empty() {
                None
            } else {
                match cell.parse::<f64>() {
                    Ok(v) if v.is_finite() => Some(v),
                    _ => {
                        return Err(bad(
                            line,
                            field as u64 + 1,
                            format!("cannot read {cell:?} as a number ({})", c.heading()),
                        ));
                    }
                }
            });
        }
        let listed = |k: usize| -> Vec<(String, String)> {
            let cell = text(k);
            split_list(&cell)
                .into_iter()
                .filter_map(|item| {
                    let (head, rest) = item.split_once(": ")?;
                    Some((head.to_string(), rest.to_string()))
                })
                .collect()
        };
        let unavailable_cells = listed(n - 2);
        let unavailable = columns
            .iter()
            .map(|c| {
                let h = c.heading();
                unavailable_cells
                    .iter()
                    .find(|(head, _)| *head == h)
                    .map(|(_, why)| why.clone())
            })
            .collect();
        let outlier_cells: Vec<(String, f64)> = split_list(&text(n - 1))
            .into_iter()
            .filter_map(|item| {
                let (head, rest) = item.rsplit_once(" (")?;
                let sigmas = rest.strip_suffix(" sd)")?.parse::<f64>().ok()?;
                Some((head.to_string(), sigmas))
            })
            .collect();
        let outliers = columns
            .iter()
            .map(|c| {
                let h = c.heading();
                outlier_cells
                    .iter()
                    .find(|(head, _)| *head == h)
                    .map(|(_, s)| *s)
            })
            .collect();
        let calibration = Some(text(3)).filter(|c| !c.is_empty());
        let (runs, runs_at) = calibration
            .as_deref()
            .and_then(|c| Path::new(c).parent())
            .and_then(|folder| crate::lot::cache::recorded_runs(&out.join(folder)))
            .unwrap_or_default();
        rows.push(Row {
            unit: text(0),
            status,
            reasons: split_list(&text(2)),
            calibration,
            values,
            unavailable,
            outliers,
            runs,
            runs_at,
        });
    }
    Ok((columns, rows))
}

/// A CSV reader's error at its place in `file`.
fn csv_error(file: &Path, e: &::csv::Error) -> LotFileError {
    let line = e.position().map_or(0, |p| p.line());
    let message = match e.kind() {
        ::csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} fields where the header has {expected_len}"),
        ::csv::ErrorKind::Utf8 { .. } => "not UTF-8 text: not a lot's table".to_string(),
        _ => e.to_string(),
    };
    LotFileError::Malformed {
        path: file.to_path_buf(),
        line,
        column: 1,
        message,
    }
}

/// A text cell as the lot wrote it, less the quote that kept a spreadsheet from reading it as
/// a formula ([`crate::files::csv_cells::text_cell`]).
fn as_text(cell: &str) -> &str {
    match cell.strip_prefix('\'') {
        Some(rest) if rest.starts_with(['=', '+', '-', '@', '\t', '\r']) => rest,
        _ => cell,
    }
}

/// The items of a cell the lot joined with `; `.
fn split_list(cell: &str) -> Vec<String> {
    if cell.is_empty() {
        Vec::new()
    } else {
        cell.split("; ").map(String::from).collect()
    }
}

/// A figure's heading made its axis and figure: `gx.arw_deg_rt_h`, or a figure alone. The
/// figure is told by its name (a K0 at a reference temperature holds a `.`: `k0_at_0.5c_dph`),
/// so an axis may hold one too.
fn split_heading(h: &str) -> Column {
    let is_figure = |f: &str| {
        f.starts_with("k0_at_")
            || [
                figures::RAW_P2P,
                figures::CORRECTED_P2P,
                figures::P2P_RATIO,
                figures::CORRECTED_STD,
                figures::CORRECTED_WIN_MEAN,
                figures::OUTSIDE_FRACTION,
                figures::PLATEAUS,
                figures::ARW,
                figures::BIAS_INSTABILITY,
                figures::RRW,
                figures::K0_MIN,
                figures::K0_MAX,
                figures::K0_MAX_SLOPE,
                figures::TEMP_MIN,
                figures::TEMP_MAX,
            ]
            .contains(&f)
    };
    if is_figure(h) {
        return Column {
            axis: String::new(),
            figure: h.to_string(),
        };
    }
    match h
        .match_indices('.')
        .map(|(k, _)| k)
        .find(|&k| is_figure(&h[k + 1..]))
    {
        Some(k) => Column {
            axis: h[..k].to_string(),
            figure: h[k + 1..].to_string(),
        },
        None => Column {
            axis: String::new(),
            figure: h.to_string(),
        },
    }
}
