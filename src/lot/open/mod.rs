//! A lot read back for a face to show: `lot.json` or `lot.csv` of a lot's output folder made
//! one table ([`LotTable`]), a row per unit and a column per figure of each axis, with each
//! cell's outlier mark; its rows ordered by any column, each column's median, and the files a
//! unit was made of and calibrated into, found again.
//!
//! The workbench draws this table; it reads nothing itself. A file that is not a lot's table
//! is refused with the file, line and column where it stops being one, so that the face can
//! leave whatever it showed before as it was.

use super::table::{column_name, columns};
use super::{LotOutcome, Status};
use std::path::{Path, PathBuf};

mod csv;

/// The lot's JSON table in its output folder.
pub const LOT_JSON: &str = "lot.json";
/// The lot's CSV table in its output folder.
pub const LOT_CSV: &str = "lot.csv";

/// The largest table read: a 10,000-unit lot's `lot.json` is a few tens of megabytes.
const MAX_TABLE_BYTES: u64 = 1 << 30;

/// Why a lot's table cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum LotFileError {
    /// The file or folder cannot be read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The file is not a lot's table from this place on: for `lot.json` the line and the
    /// character of the line; for `lot.csv` the line and the field (1 for `unit`).
    #[error("{}:{line}:{column}: {message}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// Its line, from 1.
        line: u64,
        /// The character of the line (JSON) or the field of the record (CSV), from 1.
        column: u64,
        /// What is wrong there.
        message: String,
    },
    /// The path holds no lot's table.
    #[error("{}: {message}", path.display())]
    NotALot {
        /// The path given.
        path: PathBuf,
        /// Why not.
        message: String,
    },
}

/// One figure's column: the axis (empty for a single-axis unit) and the figure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Column {
    /// The axis.
    pub axis: String,
    /// The figure's name ([`figures`]' constants, or [`figures::k0_at`]).
    pub figure: String,
}

impl Column {
    /// Its heading, as `lot.csv` writes it (`corrected_p2p_dph`, `gx.arw_deg_rt_h`).
    pub fn heading(&self) -> String {
        column_name(&self.axis, &self.figure)
    }
}

/// One unit of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The unit's name.
    pub unit: String,
    /// Pass, fail or error.
    pub status: Status,
    /// Every limit it breaks, or why it could not be calibrated.
    pub reasons: Vec<String>,
    /// Its calibration file, relative to the output folder; none for an error.
    pub calibration: Option<String>,
    /// Each column's value; `None` when the unit has no such figure or it was not computed.
    pub values: Vec<Option<f64>>,
    /// Each column's reason when its figure could not be computed.
    pub unavailable: Vec<Option<String>>,
    /// Each column's distance from the lot's median in robust standard deviations, when the
    /// unit is an outlier on it.
    pub outliers: Vec<Option<f64>>,
    /// Its runs' files as the lot was given them (relative to where it was run).
    pub runs: Vec<String>,
    /// Its runs' files as absolute paths, when the table says them.
    pub runs_at: Vec<String>,
}

impl Row {
    /// Whether any figure of the unit is an outlier.
    pub fn is_outlier(&self) -> bool {
        self.outliers.iter().any(Option::is_some)
    }
}

/// What a row is ordered by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SortBy {
    /// The unit's name.
    Unit,
    /// Its status (error, fail, pass), then its name.
    Status,
    /// Its reasons, as text.
    Reasons,
    /// Its number of outlying figures, then the largest distance.
    Outliers,
    /// A figure's column; units without the figure last whichever the order.
    Figure(usize),
}

/// A lot's table as read.
#[derive(Debug, Clone, PartialEq)]
pub struct LotTable {
    /// The file read.
    pub file: PathBuf,
    /// The lot's output folder (the file's), which the calibrations' paths are relative to.
    pub out: PathBuf,
    /// Every figure's column, in the table's order.
    pub columns: Vec<Column>,
    /// Every unit, in the lot's order.
    pub rows: Vec<Row>,
}

/// The files of one unit, found again: its runs (in order) and its calibration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnitFiles {
    /// Its runs' files.
    pub runs: Vec<PathBuf>,
    /// Its calibration file; none for a unit that could not be calibrated.
    pub calibration: Option<PathBuf>,
}

/// Reads the lot at `path`: its output folder (its `lot.json`, else its `lot.csv`), or either
/// file.
///
/// # Errors
/// A path that cannot be read, holds no table, or a table that is not a lot's, named with its
/// line and column.
pub fn open(path: &Path) -> Result<LotTable, LotFileError> {
    let io = |source| LotFileError::Io {
        path: path.to_path_buf(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    let file = if meta.is_dir() {
        [LOT_JSON, LOT_CSV]
            .iter()
            .map(|n| path.join(n))
            .find(|p| p.is_file())
            .ok_or_else(|| LotFileError::NotALot {
                path: path.to_path_buf(),
                message: format!(
                    "holds neither {LOT_JSON} nor {LOT_CSV}: give a lot's output folder, or \
                     one of its tables"
                ),
            })?
    } else {
        path.to_path_buf()
    };
    let io = |source| LotFileError::Io {
        path: file.clone(),
        source,
    };
    if std::fs::metadata(&file).map_err(io)?.len() > MAX_TABLE_BYTES {
        return Err(LotFileError::NotALot {
            path: file,
            message: format!(
                "larger than {} MiB: no lot's table is",
                MAX_TABLE_BYTES >> 20
            ),
        });
    }
    let text = std::fs::read_to_string(&file).map_err(io)?;
    let out = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let json = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let (columns, rows) = if json {
        of_json(&file, &text)?
    } else {
        csv::of_csv(&file, &text)?
    };
    Ok(LotTable {
        file,
        out,
        columns,
        rows,
    })
}

/// The table of `lot.json`.
fn of_json(file: &Path, text: &str) -> Result<(Vec<Column>, Vec<Row>), LotFileError> {
    let lot: LotOutcome = serde_json::from_str(text).map_err(|e| LotFileError::Malformed {
        path: file.to_path_buf(),
        line: e.line() as u64,
        column: e.column() as u64,
        message: format!("not a lot's table ({LOT_JSON}): {e}"),
    })?;
    let columns: Vec<Column> = columns(&lot.units)
        .into_iter()
        .map(|(axis, figure)| Column { axis, figure })
        .collect();
    let rows = lot
        .units
        .iter()
        .map(|u| {
            let figure = |c: &Column| {
                u.axes
                    .iter()
                    .find(|a| a.axis == c.axis)
                    .and_then(|a| a.get(&c.figure))
            };
            Row {
                unit: u.unit.clone(),
                status: u.status,
                reasons: u.reasons.clone(),
                calibration: u.calibration.clone(),
                values: columns
                    .iter()
                    .map(|c| figure(c).and_then(|f| f.value))
                    .collect(),
                unavailable: columns
                    .iter()
                    .map(|c| figure(c).and_then(|f| f.unavailable.clone()))
                    .collect(),
                outliers: columns
                    .iter()
                    .map(|c| {
                        lot.outliers
                            .iter()
                            .find(|o| o.unit == u.unit && o.axis == c.axis && o.figure == c.figure)
                            .map(|o| o.sigmas)
                    })
                    .collect(),
                runs: u.runs.clone(),
                runs_at: u.runs_at.clone(),
            }
        })
        .collect();
    Ok((columns, rows))
}

impl LotTable {
    /// The units of each status: pass, fail, error.
    pub fn counts(&self) -> [usize; 3] {
        let n = |s: Status| self.rows.iter().filter(|r| r.status == s).count();
        [n(Status::Pass), n(Status::Fail), n(Status::Error)]
    }

    /// The rows' indices ordered by `by`, ascending or descending; ties keep the lot's order.
    /// A unit without the figure sorted by comes last either way.
    pub fn order(&self, by: SortBy, descending: bool) -> Vec<usize> {
        use std::cmp::Ordering;
        let mut order: Vec<usize> = (0..self.rows.len()).collect();
        let rank = |s: Status| match s {
            Status::Error => 0,
            Status::Fail => 1,
            Status::Pass => 2,
        };
        let flip = |o: Ordering| if descending { o.reverse() } else { o };
        order.sort_by(|&a, &b| {
            let (ra, rb) = (&self.rows[a], &self.rows[b]);
            match by {
                SortBy::Unit => flip(ra.unit.cmp(&rb.unit)),
                SortBy::Status => flip(rank(ra.status).cmp(&rank(rb.status))),
                SortBy::Reasons => flip(ra.reasons.join("; ").cmp(&rb.reasons.join("; "))),
                SortBy::Outliers => {
                    let key = |r: &Row| {
                        let n = r.outliers.iter().flatten().count();
                        let far = r
                            .outliers
                            .iter()
                            .flatten()
                            .fold(0.0f64, |m, s| m.max(s.abs()));
                        (n, far)
                    };
                    let (ka, kb) = (key(ra), key(rb));
                    flip(ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1)))
                }
                SortBy::Figure(c) => {
                    let (va, vb) = (
                        ra.values.get(c).copied().flatten(),
                        rb.values.get(c).copied().flatten(),
                    );
                    match (va, vb) {
                        (Some(x), Some(y)) => flip(x.total_cmp(&y)),
                        (Some(_), None) => Ordering::Less,
                        (None, Some(_)) => Ordering::Greater,
                        (None, None) => Ordering::Equal,
                    }
                }
            }
        });
        order
    }

    /// The lot's median of column `c` over the units that have it (the line a figure's
    /// distribution is drawn about); `None` when none has.
    pub fn median(&self, c: usize) -> Option<f64> {
        let mut v: Vec<f64> = self
            .rows
            .iter()
            .filter_map(|r| r.values.get(c).copied().flatten())
            .collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let m = v.len() / 2;
        Some(if v.len() % 2 == 1 {
            v[m]
        } else {
            0.5 * (v[m - 1] + v[m])
        })
    }

    /// The files of row `k`: its runs, each where the table says it was found (its absolute
    /// path), else as given when that is a file from here, else as given from the folder the
    /// output folder lies in (a lot run beside its output folder); and its calibration in the
    /// output folder.
    ///
    /// # Errors
    /// A unit whose runs are not said (a `lot.csv` without its units' records), or a run
    /// found nowhere, named.
    pub fn unit_files(&self, k: usize) -> Result<UnitFiles, String> {
        let row = self
            .rows
            .get(k)
            .ok_or_else(|| format!("the lot has no unit {}", k + 1))?;
        if row.runs.is_empty() {
            return Err(format!(
                "{}: {} does not say which files unit {} was made of (open the lot's {LOT_JSON})",
                self.file.display(),
                file_name(&self.file),
                row.unit
            ));
        }
        let base = std::path::absolute(&self.out)
            .ok()
            .and_then(|o| o.parent().map(Path::to_path_buf));
        let mut runs = Vec::with_capacity(row.runs.len());
        for (j, given) in row.runs.iter().enumerate() {
            let candidates = row
                .runs_at
                .get(j)
                .map(PathBuf::from)
                .into_iter()
                .chain([PathBuf::from(given)])
                .chain(base.as_ref().map(|b| b.join(given)));
            let mut candidates = candidates.collect::<Vec<_>>().into_iter();
            match candidates.find(|p| p.is_file()) {
                Some(p) => runs.push(p),
                None => {
                    return Err(format!(
                        "unit {}: its run {given} is not found (from here, nor beside the lot's \
                         folder {})",
                        row.unit,
                        self.out.display()
                    ));
                }
            }
        }
        Ok(UnitFiles {
            runs,
            calibration: row.calibration.as_ref().map(|c| self.out.join(c)),
        })
    }
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}
