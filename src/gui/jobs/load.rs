//! Reading a log off the UI thread, with progress and cancel, and the first views of it.

use super::*;

/// Pyramids of a log's raw columns, built once after reading.
#[derive(Debug, Default)]
pub struct LogLods {
    /// Raw Ω.
    pub omega: MinMaxPyramid,
    /// Raw T.
    pub temp: MinMaxPyramid,
}

/// A log read from a file.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The file.
    pub path: PathBuf,
    /// How it was read.
    pub read: ReadOptions,
    /// The columns.
    pub log: Arc<Log>,
    /// Pyramids of the raw columns.
    pub lods: Arc<LogLods>,
    /// SHA-256 of the file, for the calibration's source.
    pub sha256: Option<String>,
    /// Seconds the read took.
    pub seconds: f64,
}

/// A read in progress.
#[derive(Debug, Clone)]
pub struct LoadHandle {
    /// Which slot.
    pub target: Target,
    /// The file.
    pub path: PathBuf,
    /// Fraction done (f64 bits).
    pub(super) progress: Arc<AtomicU64>,
    /// Set to stop the read.
    pub(super) cancel: Arc<AtomicBool>,
    /// When it started.
    pub started: Instant,
}

impl LoadHandle {
    /// Fraction done, 0 to 1.
    pub fn progress(&self) -> f64 {
        f64::from_bits(self.progress.load(Ordering::Relaxed)).clamp(0.0, 1.0)
    }
}

pub(super) fn load_log(h: &LoadHandle, read: ReadOptions) -> JobResult {
    let t = Instant::now();
    let progress = h.progress.clone();
    let cancel = h.cancel.clone();
    let result = ingest::read_path_with_progress(&h.path, &read, &|f| {
        progress.store(f.to_bits(), Ordering::Relaxed);
        !cancel.load(Ordering::Relaxed)
    });
    match result {
        Ok(log) => {
            if log.len() < 16 {
                return JobResult::LoadFailed(
                    h.target,
                    h.path.clone(),
                    format!(
                        "{}: only {} samples, too few to work with",
                        h.path.display(),
                        log.len()
                    ),
                );
            }
            let path = h.path.clone();
            let ((omega, temp), sha256) = rayon::join(
                || {
                    rayon::join(
                        || MinMaxPyramid::new(&log.omega_dph),
                        || MinMaxPyramid::new(&log.temp_c),
                    )
                },
                || crate::files::calibration::sha256_file(&path).ok(),
            );
            JobResult::Loaded(
                h.target,
                Box::new(Loaded {
                    path: h.path.clone(),
                    read,
                    log: Arc::new(log),
                    lods: Arc::new(LogLods { omega, temp }),
                    sha256,
                    seconds: t.elapsed().as_secs_f64(),
                }),
            )
        }
        Err(_) if h.cancel.load(Ordering::Relaxed) => {
            JobResult::LoadCancelled(h.target, h.path.clone())
        }
        Err(e) => JobResult::LoadFailed(h.target, h.path.clone(), e.to_string()),
    }
}
