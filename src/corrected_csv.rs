//! The corrected log as CSV: `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`, the
//! output of `driftlab apply` and of the workbench's export.
//!
//! Numbers are written in their shortest form that reads back to the same f64 (zmij), so a
//! corrected log loses nothing; blocks of rows are formatted in parallel and written in order,
//! the writing of one batch overlapping the formatting of the next.

use crate::log::Log;
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
    write_rows(path, log, pred_dph, Some(cor_dph), progress)
}

/// Writes the corrected log atomically from the predicted drift alone, the corrected rate
/// being `Ω − pred` (as every model computes it): a caller need not hold a column of it.
pub fn write_predicted(
    path: &Path,
    log: &Log,
    pred_dph: &[f64],
    progress: &dyn Fn(f64),
) -> std::io::Result<()> {
    write_rows(path, log, pred_dph, None, progress)
}

/// The writer of both: `cor_dph` when given, else `Ω − pred` row by row.
fn write_rows(
    path: &Path,
    log: &Log,
    pred_dph: &[f64],
    cor_dph: Option<&[f64]>,
    progress: &dyn Fn(f64),
) -> std::io::Result<()> {
    let n = log
        .len()
        .min(pred_dph.len())
        .min(cor_dph.map_or(usize::MAX, <[f64]>::len));
    crate::atomic::write_with(path, |w| {
        w.write_all(HEADER.as_bytes())?;
        w.write_all(b"\n")?;
        // Batches of blocks are formatted in parallel on one side while the batch before is
        // written on the other; memory stays at a few batches.
        let batch = BLOCK * rayon::current_num_threads().max(1) * 2;
        std::thread::scope(|scope| {
            let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, Vec<Vec<u8>>)>(1);
            // Written blocks go back to the formatter: fresh buffers would each cost their
            // pages again (a tenth of the time of a big write went to page faults).
            let (back_tx, back_rx) = std::sync::mpsc::channel::<Vec<u8>>();
            scope.spawn(move || {
                let mut start = 0;
                while start < n {
                    let end = (start + batch).min(n);
                    let mut jobs: Vec<(usize, Vec<u8>)> = (start..end)
                        .step_by(BLOCK)
                        .map(|b| (b, back_rx.try_recv().unwrap_or_default()))
                        .collect();
                    jobs.par_iter_mut().for_each(|(b, text)| {
                        format_rows(text, log, pred_dph, cor_dph, *b, (*b + BLOCK).min(end))
                    });
                    let texts = jobs.into_iter().map(|(_, t)| t).collect();
                    if tx.send((end, texts)).is_err() {
                        // The writer stopped (an error): nothing more to format.
                        return;
                    }
                    start = end;
                }
            });
            for (end, texts) in rx {
                for t in texts {
                    w.write_all(&t)?;
                    // The formatter may have finished; a buffer it no longer wants is freed.
                    let _ = back_tx.send(t);
                }
                progress(end as f64 / n as f64);
            }
            Ok(())
        })
    })
}

/// Formats rows `from..to` into `out`, replacing what it held.
fn format_rows(
    out: &mut Vec<u8>,
    log: &Log,
    pred: &[f64],
    cor: Option<&[f64]>,
    from: usize,
    to: usize,
) {
    out.clear();
    out.reserve((to - from) * 64);
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
    for i in from..to {
        num(out, log.time_s[i], b',');
        num(out, log.omega_dph[i], b',');
        num(out, pred[i], b',');
        let c = cor.map_or_else(|| log.omega_dph[i] - pred[i], |c| c[i]);
        num(out, c, b',');
        num(out, log.temp_c[i], b'\n');
    }
}
