//! Work off the UI thread: reading logs (with progress and cancel), the live refit (newest
//! request wins) and long exports. Results come back through one channel; each sender asks
//! egui for a repaint so the UI shows them at once.
//!
//! One file a job: `load` (a log, with progress and cancel), `fit` (the live refit and its
//! plot levels of detail), `accel` (a unit's accelerometer axes), `compare` (the Models page), `allan` (the Allan page) and `opened`
//! (a calibration opened to compare: its file read and its judging on the open logs); this
//! file holds the workers' handle and the channel their results come back through.

mod accel;
mod allan;
mod compare;
mod fit;
mod load;
mod opened;

use accel::run_accel;
pub use accel::{
    AccelAxisView, AccelFit, AccelHeldOut, AccelKey, AccelRequest, AccelValidation, AccelView, Line,
};
use allan::run_allan;
pub use allan::{AllanRequest, AllanView};
use compare::run_compare;
pub use compare::{
    CompareHandle, CompareRequest, Compared, ComparedLog, ModelProgress, ModelSeries,
};
pub use fit::{FitLods, FitView, HeldLods};
use fit::{RefitKey, fit_worker};
use load::load_log;
pub use load::{LoadHandle, LoadOptions, Loaded, LogLods, Recorded};
pub use opened::{
    AxisVerdict, JudgedAxis, LogInput, Verified, VerifiedLog, VerifyKey, VerifyRequest,
};

use super::plot_items::Segments;
use crate::judge::allan::{AllanDeviation, AllanOptions};
use crate::judge::compare::ModelReport;
use crate::judge::metrics::MeritOptions;
use crate::log::Log;
use crate::log::ingest::ReadOptions;
use crate::models::presets::ModelChoice;
use crate::models::recipe::Recipe;
use crate::models::vakhrameev::{PointSet, Prepared};
use crate::refit::Same;
use crate::refit::{Outcome, Pipeline, Request};
use crate::signal::lod::{ClassLod, MinMaxPyramid, ScatterLod};
use eframe::egui;
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Which slot a log is loaded into.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// The log the calibration is fitted on.
    Calibration,
    /// The held-out log the calibration is judged on.
    Validation,
}

/// What comes back from the workers.
pub enum JobResult {
    /// A log was read.
    Loaded(Target, Box<Loaded>),
    /// A log could not be read (the engine's message, with file, line and column).
    LoadFailed(Target, PathBuf, String),
    /// The engineer cancelled a read.
    LoadCancelled(Target, PathBuf),
    /// A refit finished.
    Fitted(Arc<FitView>),
    /// A refit of an axis (0 for a log of one axis) failed: (axis, request number, message).
    FitFailed(usize, u64, String),
    /// A long export finished.
    Exported(String, Result<PathBuf, String>),
    /// A comparison of models finished, or stopped: by Cancel ([`crate::Error::Cancelled`]) or
    /// on a defect.
    Compared(u64, Result<Arc<Compared>, crate::Error>),
    /// Allan deviations finished.
    Allan(Arc<AllanView>),
    /// A calibration file opened to compare was read, or could not be (the loader's message,
    /// naming the file, line and column).
    CalibrationRead(PathBuf, Result<Arc<crate::models::UnitCalibration>, String>),
    /// The opened calibration was judged on the open logs.
    Verified(Arc<Verified>),
    /// The plateaus and K0 of a plateau edge drag in progress.
    Previewed(Arc<PreviewView>),
    /// A unit's accelerometer axes were calibrated, or refused.
    AccelFitted(Arc<AccelView>),
}

/// The plateaus and K0 of a plateau edge drag in progress, for the axis it was asked for.
#[derive(Debug)]
pub struct PreviewView {
    /// The gyro axis (0 for a log of one axis).
    pub axis: usize,
    /// The request number it answers (refits and previews are numbered alike, so the newer of
    /// a preview and a fit is the one to show).
    pub generation: u64,
    /// The engine's preview.
    pub preview: crate::refit::PlateauPreview,
}

/// What a preview was asked for: the axis, the log by identity, the ranges and K0's spec.
type PreviewKey = (
    usize,
    Same<Log>,
    Vec<crate::signal::plateau::PlateauRange>,
    crate::models::approx::ApproxSpec,
);

/// What a plateau edge drag shows is asked for with.
pub(super) struct PreviewAsk {
    log: Arc<Log>,
    ranges: Vec<crate::signal::plateau::PlateauRange>,
    recipe: Recipe,
}

enum FitMsg {
    /// Refit axis `.0` (0 for a log of one axis) as request number `.1`.
    Fit(usize, u64, Box<Request>),
    /// The plateaus and K0 of a drag in progress on axis `.0`, as request number `.1`.
    Preview(usize, u64, Box<PreviewAsk>),
    /// The log has this many axes: the worker forgets what it kept for any further one.
    Axes(usize),
}

type SharedCtx = Arc<Mutex<Option<egui::Context>>>;

fn repaint(ctx: &SharedCtx) {
    if let Ok(c) = ctx.lock()
        && let Some(c) = c.as_ref()
    {
        c.request_repaint();
    }
}

/// The workers and their channel.
pub struct Jobs {
    fit_tx: Option<Sender<FitMsg>>,
    worker: Option<std::thread::JoinHandle<()>>,
    tx: Sender<JobResult>,
    rx: Receiver<JobResult>,
    ctx: SharedCtx,
    /// The read in progress, if any.
    pub loading: Option<LoadHandle>,
    /// Number of the newest refit asked for, of any axis.
    pub requested: u64,
    /// Per axis, the number of its newest refit asked for.
    requested_by_axis: Vec<u64>,
    /// Per axis, the number of its newest refit answered (result or failure).
    answered_by_axis: Vec<u64>,
    /// Exports running.
    pub exports: usize,
    /// The comparison of models in progress, if any.
    pub comparing: Option<CompareHandle>,
    /// Number of the newest comparison asked for.
    compare_requested: u64,
    /// The Allan deviations in progress, if any.
    pub allan: Option<(u64, bool)>,
    /// Per axis, what its newest refit was asked for.
    sent: Vec<Option<RefitKey>>,
    /// What the newest preview was asked for (axis, log, ranges, K0's spec).
    preview_sent: Option<PreviewKey>,
    /// Calibration files being read.
    pub reading_calibration: usize,
    /// The number of the newest judging of the opened calibration asked for.
    pub verify_requested: u64,
    /// The judging of the opened calibration running, if any (its number).
    pub verifying: Option<u64>,
    /// What the newest judging was asked for.
    verify_sent: Option<VerifyKey>,
    /// The newest judging asked for while another ran, with its number.
    verify_waiting: Option<(u64, Box<VerifyRequest>)>,
    /// The number of the newest calibration of the accelerometer axes asked for, and of the
    /// newest answered.
    accel_numbers: (u64, u64),
    /// What the newest calibration of the accelerometer axes was asked with.
    accel_sent: Option<AccelKey>,
}

impl Default for Jobs {
    fn default() -> Self {
        Jobs::new()
    }
}

impl Jobs {
    /// Starts the refit worker.
    pub fn new() -> Jobs {
        let (tx, rx) = mpsc::channel();
        let (fit_tx, fit_rx) = mpsc::channel();
        let ctx: SharedCtx = Arc::default();
        let worker = {
            let (tx, ctx) = (tx.clone(), ctx.clone());
            std::thread::Builder::new()
                .name("driftlab-fit".into())
                .spawn(move || fit_worker(fit_rx, tx, ctx))
                .ok()
        };
        Jobs {
            fit_tx: Some(fit_tx),
            worker,
            tx,
            rx,
            ctx,
            loading: None,
            requested: 0,
            requested_by_axis: Vec::new(),
            answered_by_axis: Vec::new(),
            exports: 0,
            comparing: None,
            compare_requested: 0,
            allan: None,
            sent: Vec::new(),
            preview_sent: None,
            reading_calibration: 0,
            verify_requested: 0,
            verifying: None,
            verify_sent: None,
            verify_waiting: None,
            accel_numbers: (0, 0),
            accel_sent: None,
        }
    }

    /// Lets the workers wake the UI.
    pub fn set_context(&self, ctx: &egui::Context) {
        if let Ok(mut c) = self.ctx.lock()
            && c.is_none()
        {
            *c = Some(ctx.clone());
        }
    }

    /// True while anything runs.
    pub fn busy(&self) -> bool {
        self.loading.is_some()
            || self.fitting()
            || self.exports > 0
            || self.comparing.is_some()
            || self.allan.is_some()
            || self.reading_calibration > 0
            || self.verifying.is_some()
    }

    /// True while a refit asked for has not been answered, of any axis (the accelerometer
    /// axes among them).
    pub fn fitting(&self) -> bool {
        (0..self.requested_by_axis.len()).any(|k| self.fitting_axis(k)) || self.fitting_accel()
    }

    /// True while a calibration of the accelerometer axes asked for has not been answered.
    pub fn fitting_accel(&self) -> bool {
        self.accel_numbers.1 < self.accel_numbers.0
    }

    /// The number of the newest calibration of the accelerometer axes asked for (0: none).
    pub fn newest_accel(&self) -> u64 {
        self.accel_numbers.0
    }

    /// Asks for the calibration of the accelerometer axes `request` describes, on a thread,
    /// unless the newest asked for was the same; true when it was asked for.
    pub fn accel(&mut self, request: AccelRequest) -> bool {
        let key = AccelKey::of(&request);
        if self.accel_sent.as_ref() == Some(&key) {
            return false;
        }
        self.accel_numbers.0 += 1;
        let generation = self.accel_numbers.0;
        self.accel_sent = Some(key.clone());
        let (tx, ctx) = (self.tx.clone(), self.ctx.clone());
        let spawned = std::thread::Builder::new()
            .name("driftlab-accel".into())
            .spawn(move || {
                let view = run_accel(&request, generation);
                let _ = tx.send(JobResult::AccelFitted(Arc::new(view)));
                repaint(&ctx);
            });
        if let Err(e) = spawned {
            let _ = self.tx.send(JobResult::AccelFitted(Arc::new(AccelView {
                generation,
                key,
                result: Err(format!("cannot start a thread: {e}")),
            })));
        }
        true
    }

    /// True while a refit of axis `k` asked for has not been answered.
    pub fn fitting_axis(&self, k: usize) -> bool {
        self.answered_by_axis.get(k).copied().unwrap_or(0)
            < self.requested_by_axis.get(k).copied().unwrap_or(0)
    }

    /// The number of the newest refit of axis `k` asked for (0: none).
    pub fn newest(&self, k: usize) -> u64 {
        self.requested_by_axis.get(k).copied().unwrap_or(0)
    }

    /// The log has `n` gyro axes (1 for a log of one): what is kept for any further axis is
    /// forgotten, here and on the worker.
    pub fn set_axes(&mut self, n: usize) {
        let n = n.max(1);
        if self.sent.len() > n {
            self.sent.truncate(n);
            self.requested_by_axis.truncate(n);
            self.answered_by_axis.truncate(n);
        }
        if let Some(tx) = &self.fit_tx {
            let _ = tx.send(FitMsg::Axes(n));
        }
    }

    /// Asks for the refit of axis `axis` (0 for a log of one axis) that `request` describes,
    /// unless the newest one asked for that axis was for the same logs, recipe and knots;
    /// true when it was asked for.
    pub fn refit(&mut self, axis: usize, request: Request) -> bool {
        let key = RefitKey::of(&request);
        if self
            .sent
            .get(axis)
            .is_some_and(|s| s.as_ref() == Some(&key))
        {
            return false;
        }
        self.fit(axis, request);
        if self.sent.len() <= axis {
            self.sent.resize(axis + 1, None);
        }
        self.sent[axis] = Some(key);
        true
    }

    /// Asks for the plateaus and K0 of a plateau edge drag on axis `axis` (not a refit: K1,
    /// K2 and the correction follow the release), unless the newest asked for was the same;
    /// true when it was asked for.
    pub fn preview(
        &mut self,
        axis: usize,
        log: &Arc<Log>,
        ranges: &[crate::signal::plateau::PlateauRange],
        recipe: &Recipe,
    ) -> bool {
        let key = (axis, Same::of(log), ranges.to_vec(), recipe.k0.clone());
        if self.preview_sent.as_ref() == Some(&key) {
            return false;
        }
        self.requested += 1;
        let ask = PreviewAsk {
            log: log.clone(),
            ranges: ranges.to_vec(),
            recipe: recipe.clone(),
        };
        let sent = self.fit_tx.as_ref().is_some_and(|tx| {
            tx.send(FitMsg::Preview(axis, self.requested, Box::new(ask)))
                .is_ok()
        });
        self.preview_sent = Some(key);
        sent
    }

    /// Asks for a refit of axis `axis`; an older one of that axis still queued is dropped.
    pub fn fit(&mut self, axis: usize, request: Request) -> u64 {
        self.requested += 1;
        // A drag to the same place after this refit is previewed again.
        self.preview_sent = None;
        let generation = self.requested;
        if self.requested_by_axis.len() <= axis {
            self.requested_by_axis.resize(axis + 1, 0);
            self.answered_by_axis.resize(axis + 1, 0);
        }
        self.requested_by_axis[axis] = generation;
        let sent = self.fit_tx.as_ref().is_some_and(|tx| {
            tx.send(FitMsg::Fit(axis, generation, Box::new(request)))
                .is_ok()
        });
        if !sent {
            let _ = self.tx.send(JobResult::FitFailed(
                axis,
                generation,
                "the fitting thread has stopped".into(),
            ));
        }
        generation
    }

    fn answered(&mut self, axis: usize, generation: u64) {
        if let Some(a) = self.answered_by_axis.get_mut(axis) {
            *a = (*a).max(generation);
        }
    }

    /// Starts reading a log (cancelling a read already running).
    pub fn load(&mut self, path: PathBuf, options: LoadOptions, target: Target) {
        self.cancel_load();
        let handle = LoadHandle {
            target,
            path: path.clone(),
            progress: Arc::new(AtomicU64::new(0f64.to_bits())),
            cancel: Arc::new(AtomicBool::new(false)),
            started: Instant::now(),
        };
        let (tx, ctx, h) = (self.tx.clone(), self.ctx.clone(), handle.clone());
        let spawned = std::thread::Builder::new()
            .name("driftlab-load".into())
            .spawn(move || {
                let result = load_log(&h, options);
                let _ = tx.send(result);
                repaint(&ctx);
            });
        match spawned {
            Ok(_) => self.loading = Some(handle),
            Err(e) => {
                let _ = self.tx.send(JobResult::LoadFailed(
                    target,
                    path,
                    format!("cannot start a thread: {e}"),
                ));
            }
        }
    }

    /// Stops the read in progress (its result arrives as cancelled).
    pub fn cancel_load(&mut self) {
        if let Some(h) = &self.loading {
            h.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Runs `work` on a thread; its result comes back as [`JobResult::Exported`] named `what`.
    pub fn spawn_export(
        &mut self,
        what: &str,
        work: impl FnOnce() -> Result<PathBuf, String> + Send + 'static,
    ) {
        let (tx, ctx, what) = (self.tx.clone(), self.ctx.clone(), what.to_string());
        self.exports += 1;
        let spawned = std::thread::Builder::new()
            .name("driftlab-export".into())
            .spawn(move || {
                let r = work();
                let _ = tx.send(JobResult::Exported(what, r));
                repaint(&ctx);
            });
        if let Err(e) = spawned {
            self.exports -= 1;
            let _ = self.tx.send(JobResult::Exported(
                "export".into(),
                Err(format!("cannot start a thread: {e}")),
            ));
        }
    }

    /// Starts a comparison of models on a thread (one already running finishes, its answer
    /// is dropped as stale); returns its number.
    pub fn compare(&mut self, request: CompareRequest) -> u64 {
        self.compare_requested += 1;
        let generation = self.compare_requested;
        let handle = CompareHandle::new(
            generation,
            request.choices.iter().map(|c| c.name()).collect(),
        );
        let (tx, ctx, h) = (self.tx.clone(), self.ctx.clone(), handle.clone());
        let spawned = std::thread::Builder::new()
            .name("driftlab-compare".into())
            .spawn(move || {
                let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_compare(&request, &h, &ctx)
                }));
                let result = match run {
                    Ok(_) if h.cancelled() => Err(crate::Error::Cancelled),
                    Ok(c) => Ok(Arc::new(c)),
                    Err(_) => Err(crate::Error::Internal(
                        "the comparison stopped on a defect (the terminal shows where)",
                    )),
                };
                let _ = tx.send(JobResult::Compared(h.generation, result));
                repaint(&ctx);
            });
        match spawned {
            Ok(_) => self.comparing = Some(handle),
            Err(_) => {
                let _ = self.tx.send(JobResult::Compared(
                    generation,
                    Err(crate::Error::Internal(
                        "no thread could be started for the comparison",
                    )),
                ));
            }
        }
        generation
    }

    /// The number of the newest comparison asked for.
    pub fn compare_requested(&self) -> u64 {
        self.compare_requested
    }

    /// Starts the Allan deviations of a log, raw and corrected, on a thread.
    pub fn allan(&mut self, request: AllanRequest) {
        let key = request.key;
        let (tx, ctx) = (self.tx.clone(), self.ctx.clone());
        let spawned = std::thread::Builder::new()
            .name("driftlab-allan".into())
            .spawn(move || {
                let view = run_allan(&request);
                let _ = tx.send(JobResult::Allan(Arc::new(view)));
                repaint(&ctx);
            });
        if spawned.is_ok() {
            self.allan = Some(key);
        }
    }

    /// The next result, waiting at most `wait`.
    pub fn next(&mut self, wait: Duration) -> Option<JobResult> {
        let r = if wait.is_zero() {
            self.rx.try_recv().ok()
        } else {
            self.rx.recv_timeout(wait).ok()
        }?;
        match &r {
            JobResult::Loaded(..) | JobResult::LoadFailed(..) | JobResult::LoadCancelled(..) => {
                self.loading = None;
            }
            JobResult::Fitted(v) => self.answered(v.axis, v.generation),
            JobResult::FitFailed(axis, g, _) => self.answered(*axis, *g),
            JobResult::Previewed(_) => {}
            JobResult::AccelFitted(v) => {
                self.accel_numbers.1 = self.accel_numbers.1.max(v.generation);
            }
            JobResult::Exported(..) => self.exports = self.exports.saturating_sub(1),
            JobResult::Compared(g, _) => {
                if self.comparing.as_ref().is_some_and(|c| c.generation == *g) {
                    self.comparing = None;
                }
            }
            JobResult::Allan(v) => {
                if self.allan == Some(v.key) {
                    self.allan = None;
                }
            }
            JobResult::CalibrationRead(..) => {
                self.reading_calibration = self.reading_calibration.saturating_sub(1);
            }
            JobResult::Verified(v) => {
                if self.verifying == Some(v.generation) {
                    self.verifying = None;
                    if let Some((generation, request)) = self.verify_waiting.take() {
                        self.start_verify(generation, *request);
                    }
                }
            }
        }
        Some(r)
    }
}

impl Drop for Jobs {
    fn drop(&mut self) {
        self.cancel_load();
        self.fit_tx = None; // the worker's channel closes, it ends after its current fit
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }
}
