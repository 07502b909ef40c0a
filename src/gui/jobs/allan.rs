//! Allan deviation of the raw and corrected rate, on a worker.

use super::*;

/// Allan deviations of a log's raw rate and of the same rate corrected.
#[derive(Clone)]
pub struct AllanRequest {
    /// What the answer is for (the fit's generation, and which log), to tell stale answers.
    pub key: (u64, bool),
    /// The log.
    pub log: Arc<Log>,
    /// Its correction.
    pub corrected: Arc<crate::refit::Correction>,
}

/// The Allan deviations of one log, raw and corrected.
pub struct AllanView {
    /// The request's key.
    pub key: (u64, bool),
    /// The log's name.
    pub source: String,
    /// First sample used (the correction's warm-up is left out of both curves).
    pub from_sample: usize,
    /// Raw rate.
    pub raw: Result<AllanDeviation, String>,
    /// Corrected rate.
    pub corrected: Result<AllanDeviation, String>,
    /// Seconds the two took.
    pub seconds: f64,
}

/// Octave Allan deviations of the raw and the corrected rate over the same samples (after
/// the correction's warm-up).
pub(super) fn run_allan(req: &AllanRequest) -> AllanView {
    let t = Instant::now();
    let log = &req.log;
    let end = req.corrected.cor_dph.len().min(log.len());
    let from = req.corrected.ready_from.min(end);
    let opts = AllanOptions {
        tau0_s: log.nominal_dt_s(),
        ..AllanOptions::default()
    };
    let (raw, corrected) = rayon::join(
        || crate::judge::allan::allan(&log.omega_dph[from..end], &opts).map_err(|e| e.to_string()),
        || {
            crate::judge::allan::allan(&req.corrected.cor_dph[from..end], &opts)
                .map_err(|e| e.to_string())
        },
    );
    AllanView {
        key: req.key,
        source: log.source.clone(),
        from_sample: from,
        raw,
        corrected,
        seconds: t.elapsed().as_secs_f64(),
    }
}
