//! The corrected log as CSV: `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`, the
//! output of `driftlab apply` and of the workbench's export. A unit of several axes writes
//! `time_s`, then `<axis>_raw_dph,<axis>_pred_dph,<axis>_cor_dph` for each axis in the
//! calibration's order, then `temp_c`; an accelerometer axis, which a unit lists after its
//! gyro axes, is written in m/s², `<axis>_raw_m_s2,<axis>_pred_m_s2,<axis>_cor_m_s2` (its
//! corrected reading keeps the mean it was fitted about: [`crate::models::accel`]). [`correct_and_write`] is the one way a face corrects
//! and writes a log, for one axis or a unit.
//!
//! The header goes through the `csv` crate as every record with names does
//! ([`crate::files::csv_cells`]); the rows are numbers alone, which never need quoting, and are
//! formatted here directly.
//!
//! Numbers are written in their shortest form that reads back to the same f64 (zmij), so a
//! corrected log loses nothing. Three stages overlap, each a batch apart: the prediction of
//! `apply` (sequential, its rates being one causal pass), the formatting of blocks of rows in
//! parallel, and the writing in order ([`crate::files::atomic::write_big_with`]).

use crate::log::Log;
use crate::models::UnitCalibration;
use crate::models::fitted::Predictor;
use rayon::prelude::*;
use std::path::Path;

/// The header line.
pub const HEADER: &str = "time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c";

const BLOCK: usize = 1 << 16;

/// Writes the corrected log atomically. `progress` gets the fraction written.
pub fn write(
    path: &Path,
    log: &Log,
    pred_dph: &[f64],
    cor_dph: &[f64],
    progress: &dyn Fn(f64),
) -> std::io::Result<()> {
    let n = log.len().min(pred_dph.len()).min(cor_dph.len());
    let source = Source::Columns {
        pred: pred_dph,
        cor: cor_dph,
    };
    write_rows(path, log, HEADER, &[&log.omega_dph], n, source, progress)
}

/// The header line of a unit's corrected log, without its line break, written as every CSV
/// record with text is ([`crate::files::csv_cells`]): an axis name with a comma, a quote or a
/// line break quoted, one a spreadsheet would take for a formula neutralised.
pub fn unit_header(axes: &[(&str, crate::log::AxisKind)]) -> String {
    let mut cells = vec!["time_s".to_string()];
    for (a, kind) in axes {
        let unit = kind.unit_suffix();
        cells.extend(crate::log::ingest::CORRECTED_LOG_RATES.map(|k| format!("{a}_{k}_{unit}")));
    }
    cells.push("temp_c".to_string());
    let mut h = crate::files::csv_cells::text_record(&cells);
    h.pop();
    h
}

/// Why a log could not be corrected and written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The log has no axis for an axis of the calibration.
    #[error("{log}: no axis {axis} (its axes: {})", log_axes.join(", "))]
    MissingAxis {
        /// The log's source.
        log: String,
        /// The calibration's axis.
        axis: String,
        /// The rate column that axis was read from on its own log (empty when not known).
        rate_column: String,
        /// The log's axes.
        log_axes: Vec<String>,
    },
    /// An axis's model cannot predict this log (a channel it reads is missing, say).
    #[error("{}{source}", axis_prefix(axis))]
    Predict {
        /// The calibration's axis, empty for the one axis of a single-axis calibration.
        axis: String,
        /// What the model said.
        source: crate::Error,
    },
    /// The file could not be written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
}

/// `axis gx: ` before a message about a named axis; nothing for an unnamed one.
fn axis_prefix(axis: &str) -> String {
    if axis.is_empty() {
        String::new()
    } else {
        format!("axis {axis}: ")
    }
}

/// The log's axis each axis of `unit` corrects, in the unit's order: the axis the log's rate
/// column holds for the one unnamed axis of a single-axis calibration (whatever that axis is
/// called); for a named axis, the log's axis of that name, or of the rate column it was read
/// from on its own log.
///
/// # Errors
/// [`WriteError::MissingAxis`] for the first axis of `unit` the log does not have.
pub fn log_axes(log: &Log, unit: &UnitCalibration) -> Result<Vec<String>, WriteError> {
    if !unit.is_unit() {
        return Ok(vec![log.axis.clone()]);
    }
    // The engine's one rule for where a unit's axes are in a log.
    unit.axes
        .iter()
        .zip(crate::judge::verify::find_axes(unit, log))
        .map(|(ax, found)| {
            found.ok_or_else(|| WriteError::MissingAxis {
                log: log.source.clone(),
                axis: ax.name.clone(),
                rate_column: ax.rate_column.clone(),
                log_axes: log.axis_names(),
            })
        })
        .collect()
}

/// Corrects `log` with every axis of `unit` and writes it atomically: a single-axis
/// calibration (one unnamed axis) as [`HEADER`], a unit of named axes as [`unit_header`] in
/// the calibration's order. Each axis reads the log's axis [`log_axes`] finds and is
/// predicted batch by batch as the rows are written (its corrected rate being `Ω − pred`), so
/// no column of the prediction is held. `progress` gets the fraction written. Returns, per
/// axis of `unit`, the share of samples outside the calibrated ranges of its model's inputs.
///
/// # Errors
/// An axis the log lacks, a model that cannot predict the log, the write's error.
pub fn correct_and_write(
    path: &Path,
    log: &Log,
    unit: &UnitCalibration,
    progress: &dyn Fn(f64),
) -> Result<Vec<f64>, WriteError> {
    let columns = log_axes(log, unit)?;
    let mut rates = Vec::with_capacity(columns.len());
    for (ax, column) in unit.axes.iter().zip(&columns) {
        let rate = log
            .axis_rate(column)
            .filter(|r| r.len() == log.len())
            .ok_or_else(|| WriteError::MissingAxis {
                log: log.source.clone(),
                axis: ax.name.clone(),
                rate_column: ax.rate_column.clone(),
                log_axes: log.axis_names(),
            })?;
        rates.push(rate);
    }
    let mut predictors = Vec::with_capacity(unit.axes.len());
    for ax in &unit.axes {
        predictors.push(
            ax.model
                .predictor(log)
                .map_err(|source| WriteError::Predict {
                    axis: ax.name.clone(),
                    source,
                })?,
        );
    }
    let header = if unit.is_unit() {
        let axes: Vec<(&str, crate::log::AxisKind)> = unit
            .axes
            .iter()
            .map(|a| (a.name.as_str(), a.kind))
            .collect();
        unit_header(&axes)
    } else {
        HEADER.to_string()
    };
    let source = Source::Stream(predictors.iter_mut().collect());
    write_rows(path, log, &header, &rates, log.len(), source, progress).map_err(|source| {
        WriteError::Io {
            path: path.to_path_buf(),
            source,
        }
    })?;
    Ok(predictors.iter().map(|p| p.outside_fraction()).collect())
}

/// Where the predicted (and perhaps corrected) rates come from.
enum Source<'a, 'p> {
    /// Columns over the whole log.
    Columns { pred: &'a [f64], cor: &'a [f64] },
    /// Predicted batch by batch, one predictor per axis.
    Stream(Vec<&'a mut Predictor<'p>>),
}

impl Source<'_, '_> {
    /// Fills `b` with the rates of rows `start..start + len`, in order from the first row.
    fn fill(&mut self, start: usize, len: usize, b: &mut Batch) {
        match self {
            Source::Columns { pred, cor } => {
                b.pred.resize_with(1, Vec::new);
                b.pred[0].clear();
                b.pred[0].extend_from_slice(&pred[start..start + len]);
                b.cor.clear();
                b.cor.extend_from_slice(&cor[start..start + len]);
            }
            Source::Stream(predictors) => {
                b.pred.resize_with(predictors.len(), Vec::new);
                for (p, out) in predictors.iter_mut().zip(&mut b.pred) {
                    out.resize(len, 0.0);
                    p.fill(out);
                }
                b.cor.clear();
            }
        }
    }
}

/// The rates of one batch of rows: the predicted drift of each axis, and the corrected rate
/// of a single axis, empty meaning `Ω − pred`.
#[derive(Default)]
struct Batch {
    pred: Vec<Vec<f64>>,
    cor: Vec<f64>,
}

/// The writer of all: rows `0..n` of `header`, the raw rate of each axis from `rates`.
fn write_rows(
    path: &Path,
    log: &Log,
    header: &str,
    rates: &[&[f64]],
    n: usize,
    mut source: Source<'_, '_>,
    progress: &dyn Fn(f64),
) -> std::io::Result<()> {
    crate::files::atomic::write_big_with(path, |w| {
        w.write_all(header.as_bytes())?;
        w.write_all(b"\n")?;
        // Three stages a batch apart: the rates of a batch are gathered (or predicted) on one
        // thread, its blocks formatted in parallel on others, and the batch before written
        // here; memory stays at a few batches.
        let batch = BLOCK * rayon::current_num_threads().max(1) * 2;
        std::thread::scope(|scope| {
            let (rates_tx, rates_rx) = std::sync::mpsc::sync_channel::<Batch>(1);
            let (rates_back, rates_free) = std::sync::mpsc::channel::<Batch>();
            scope.spawn(move || {
                for start in (0..n).step_by(batch) {
                    let mut b = rates_free.try_recv().unwrap_or_default();
                    source.fill(start, batch.min(n - start), &mut b);
                    if rates_tx.send(b).is_err() {
                        return;
                    }
                }
            });
            let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, Vec<Vec<u8>>)>(1);
            // Written blocks go back to the formatter: fresh buffers would each cost their
            // pages again (a tenth of the time of a big write went to page faults).
            let (back_tx, back_rx) = std::sync::mpsc::channel::<Vec<u8>>();
            scope.spawn(move || {
                for (start, batch_rates) in (0..n).step_by(batch).zip(rates_rx) {
                    let end = (start + batch).min(n);
                    let cor = (!batch_rates.cor.is_empty()).then_some(&batch_rates.cor[..]);
                    let mut jobs: Vec<(usize, Vec<u8>)> = (start..end)
                        .step_by(BLOCK)
                        .map(|b| (b, back_rx.try_recv().unwrap_or_default()))
                        .collect();
                    jobs.par_iter_mut().for_each(|(b, text)| {
                        let rows = *b..(*b + BLOCK).min(end);
                        let axes = Axes {
                            raw: rates,
                            pred: &batch_rates.pred,
                            cor,
                        };
                        format_rows(text, log, &axes, start, rows)
                    });
                    let _ = rates_back.send(batch_rates);
                    let texts = jobs.into_iter().map(|(_, t)| t).collect();
                    if tx.send((end, texts)).is_err() {
                        // The writer stopped (an error): nothing more to format.
                        return;
                    }
                }
            });
            let mut done = 0;
            for (end, texts) in rx {
                for t in texts {
                    w.write_all(&t)?;
                    // The formatter may have finished; a buffer it no longer wants is freed.
                    let _ = back_tx.send(t);
                }
                done = end;
                progress(end as f64 / n as f64);
            }
            if done < n {
                // Never a short file renamed into place as if it were whole.
                return Err(std::io::Error::other(
                    "the rows stopped coming before the end",
                ));
            }
            Ok(())
        })
    })
}

/// The rates of a batch's rows, axis by axis.
struct Axes<'a> {
    /// Each axis's raw rate over the whole log.
    raw: &'a [&'a [f64]],
    /// Each axis's predicted drift, from the batch's first row.
    pred: &'a [Vec<f64>],
    /// A single axis's corrected rate from the batch's first row; absent: `Ω − pred`.
    cor: Option<&'a [f64]>,
}

/// Formats rows `rows` into `out`, replacing what it held; the batch's rates start at row
/// `base`.
fn format_rows(
    out: &mut Vec<u8>,
    log: &Log,
    axes: &Axes<'_>,
    base: usize,
    rows: std::ops::Range<usize>,
) {
    out.clear();
    out.reserve(rows.len() * (16 + 48 * axes.raw.len()));
    let mut buf = zmij::Buffer::new();
    let mut num = |out: &mut Vec<u8>, v: f64, end: u8| {
        if v.is_finite() {
            let s = buf.format_finite(v);
            // zmij writes integers as "20.0"; drop the ".0" as the reader needs no point.
            out.extend_from_slice(s.strip_suffix(".0").unwrap_or(s).as_bytes());
        } else {
            out.extend_from_slice(b"NaN");
        }
        out.push(end);
    };
    for i in rows {
        num(out, log.time_s[i], b',');
        for (raw, pred) in axes.raw.iter().zip(axes.pred) {
            let (w, p) = (raw[i], pred[i - base]);
            num(out, w, b',');
            num(out, p, b',');
            let c = axes.cor.map_or_else(|| w - p, |c| c[i - base]);
            num(out, c, b',');
        }
        num(out, log.temp_c[i], b'\n');
    }
}
