//! The corrected log as CSV: `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`, the
//! output of `driftlab apply` and of the workbench's export. A unit of several axes writes
//! `time_s`, then `<axis>_raw_dph,<axis>_pred_dph,<axis>_cor_dph` for each axis in the
//! calibration's order, then `temp_c` ([`write_unit_streamed`]).
//!
//! Numbers are written in their shortest form that reads back to the same f64 (zmij), so a
//! corrected log loses nothing. Three stages overlap, each a batch apart: the prediction of
//! `apply` (sequential, its rates being one causal pass), the formatting of blocks of rows in
//! parallel, and the writing in order ([`crate::files::atomic::write_big_with`]).

use crate::log::Log;
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

/// Writes the corrected log atomically as `predictor` predicts it, batch after batch: the
/// prediction of one batch overlaps the formatting of the one before, and no column of it is
/// held. The predictor should start at the log's first sample; the corrected rate is
/// `Ω − pred`.
pub fn write_streamed(
    path: &Path,
    log: &Log,
    predictor: &mut Predictor<'_>,
    progress: &dyn Fn(f64),
) -> std::io::Result<()> {
    let source = Source::Stream(vec![predictor]);
    write_rows(
        path,
        log,
        HEADER,
        &[&log.omega_dph],
        log.len(),
        source,
        progress,
    )
}

/// The header of a unit's corrected log.
pub fn unit_header(axes: &[&str]) -> String {
    let mut h = String::from("time_s");
    for a in axes {
        h.push_str(&format!(",{a}_raw_dph,{a}_pred_dph,{a}_cor_dph"));
    }
    h.push_str(",temp_c");
    h
}

/// Writes the corrected log of a unit atomically: for each axis, its name, its rate (°/h,
/// aligned with the log) and its predictor, which should start at the log's first sample.
///
/// # Errors
/// An axis whose rate is not as long as the log, or the write's error.
pub fn write_unit_streamed(
    path: &Path,
    log: &Log,
    axes: Vec<(&str, &[f64], &mut Predictor<'_>)>,
    progress: &dyn Fn(f64),
) -> std::io::Result<()> {
    if let Some((name, ..)) = axes.iter().find(|(_, rate, _)| rate.len() != log.len()) {
        return Err(std::io::Error::other(format!(
            "axis {name} does not have a rate for every sample of the log"
        )));
    }
    let names: Vec<&str> = axes.iter().map(|(n, ..)| *n).collect();
    let rates: Vec<&[f64]> = axes.iter().map(|(_, r, _)| *r).collect();
    let predictors = axes.into_iter().map(|(_, _, p)| p).collect();
    let header = unit_header(&names);
    let source = Source::Stream(predictors);
    write_rows(path, log, &header, &rates, log.len(), source, progress)
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
