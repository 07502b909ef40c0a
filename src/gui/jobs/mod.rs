//! Work off the UI thread: reading logs (with progress and cancel), the live refit (newest
//! request wins) and long exports. Results come back through one channel; each sender asks
//! egui for a repaint so the UI shows them at once.
//!
//! One file a job: `load` (a log, with progress and cancel), `fit` (the live refit and its
//! plot levels of detail), `compare` (the Models page) and `allan` (the Allan page); this
//! file holds the workers' handle and the channel their results come back through.

mod allan;
mod compare;
mod fit;
mod load;

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

use super::plot_items::Segments;
use super::same::Same;
use crate::judge::allan::{AllanDeviation, AllanOptions};
use crate::judge::compare::ModelReport;
use crate::judge::metrics::MeritOptions;
use crate::live::{Outcome, Pipeline, Request};
use crate::log::Log;
use crate::log::ingest::ReadOptions;
use crate::models::presets::ModelChoice;
use crate::models::recipe::Recipe;
use crate::models::vakhrameev::{PointSet, Prepared};
use crate::signal::lod::{ClassLod, MinMaxPyramid, ScatterLod};
use eframe::egui;
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The error of a comparison stopped by Cancel.
pub const CANCELLED: &str = "cancelled";

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
    /// A refit failed.
    FitFailed(u64, String),
    /// A long export finished.
    Exported(String, Result<PathBuf, String>),
    /// A comparison of models finished (or stopped on an internal error).
    Compared(u64, Result<Arc<Compared>, String>),
    /// Allan deviations finished.
    Allan(Arc<AllanView>),
}

enum FitMsg {
    Fit(u64, Box<Request>),
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
    /// Number of the newest refit asked for.
    pub requested: u64,
    /// Number of the newest refit answered (result or failure).
    pub answered: u64,
    /// Exports running.
    pub exports: usize,
    /// The comparison of models in progress, if any.
    pub comparing: Option<CompareHandle>,
    /// Number of the newest comparison asked for.
    compare_requested: u64,
    /// The Allan deviations in progress, if any.
    pub allan: Option<(u64, bool)>,
    /// What the newest refit was asked for.
    sent: Option<RefitKey>,
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
            answered: 0,
            exports: 0,
            comparing: None,
            compare_requested: 0,
            allan: None,
            sent: None,
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
    }

    /// True while a refit asked for has not been answered.
    pub fn fitting(&self) -> bool {
        self.answered < self.requested
    }

    /// Asks for the refit `request` describes unless the newest one asked was for the same
    /// logs, recipe and knots; true when it was asked for.
    pub fn refit(&mut self, request: Request) -> bool {
        let key = RefitKey::of(&request);
        if self.sent.as_ref() == Some(&key) {
            return false;
        }
        self.fit(request);
        self.sent = Some(key);
        true
    }

    /// Asks for a refit; an older one still queued is dropped.
    pub fn fit(&mut self, request: Request) -> u64 {
        self.requested += 1;
        let generation = self.requested;
        let sent = self
            .fit_tx
            .as_ref()
            .is_some_and(|tx| tx.send(FitMsg::Fit(generation, Box::new(request))).is_ok());
        if !sent {
            let _ = self.tx.send(JobResult::FitFailed(
                generation,
                "the fitting thread has stopped".into(),
            ));
        }
        generation
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
                    Ok(_) if h.cancelled() => Err(CANCELLED.to_string()),
                    Ok(c) => Ok(Arc::new(c)),
                    Err(_) => {
                        Err("the comparison stopped on an internal error (see the terminal)".into())
                    }
                };
                let _ = tx.send(JobResult::Compared(h.generation, result));
                repaint(&ctx);
            });
        match spawned {
            Ok(_) => self.comparing = Some(handle),
            Err(e) => {
                let _ = self.tx.send(JobResult::Compared(
                    generation,
                    Err(format!("cannot start a thread: {e}")),
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
            JobResult::Fitted(v) => self.answered = self.answered.max(v.generation),
            JobResult::FitFailed(g, _) => self.answered = self.answered.max(*g),
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
