//! Work off the UI thread: reading logs (with progress and cancel), the live refit (newest
//! request wins) and long exports. Results come back through one channel; each sender asks
//! egui for a repaint so the UI shows them at once.

use crate::allan::{AllanDeviation, AllanOptions};
use crate::compare::{self, ModelReport};
use crate::ingest::{self, ReadOptions};
use crate::live::{Outcome, Pipeline, Request};
use crate::lod::{ClassLod, MinMaxPyramid, ScatterLod};
use crate::log::Log;
use crate::metrics::MeritOptions;
use crate::model::{PointSet, Prepared};
use crate::presets::ModelChoice;
use crate::recipe::Recipe;
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

/// Pyramids and thinned clouds of one fit, for drawing.
pub struct FitLods {
    /// Filtered Ω (the fit's filter).
    pub omega_filtered: Arc<MinMaxPyramid>,
    /// Ṫ.
    pub tdot: Arc<MinMaxPyramid>,
    /// T̈.
    pub tddot: Arc<MinMaxPyramid>,
    /// Regime per sample (1 = +, 2 = −).
    pub regime: Arc<ClassLod>,
    /// Predicted drift.
    pub pred: MinMaxPyramid,
    /// Raw Ω filtered as for the figures.
    pub raw_filtered: Arc<MinMaxPyramid>,
    /// Corrected Ω filtered alike.
    pub cor_filtered: MinMaxPyramid,
    /// K1+, K1−, K2+, K2− points.
    pub scatter: [Arc<ScatterLod>; 4],
    /// The validation log's series.
    pub held_out: Option<HeldLods>,
}

/// Drawing data of the validation log.
pub struct HeldLods {
    /// Raw Ω filtered.
    pub raw_filtered: Arc<MinMaxPyramid>,
    /// Corrected Ω filtered.
    pub cor_filtered: MinMaxPyramid,
    /// Regime per sample.
    pub regime: ClassLod,
}

/// One refit's result, ready to draw.
pub struct FitView {
    /// The request number it answers.
    pub generation: u64,
    /// The engine's result.
    pub outcome: Outcome,
    /// Drawing data.
    pub lods: FitLods,
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

/// A comparison of models to run: every choice fitted on `train`, judged on `train` and on
/// each of `tests` (what `driftlab compare` does).
#[derive(Clone)]
pub struct CompareRequest {
    /// The log the models are fitted on.
    pub train: Arc<Log>,
    /// Held-out logs of the same gyro.
    pub tests: Vec<Arc<Log>>,
    /// The models.
    pub choices: Vec<ModelChoice>,
    /// The workbench's recipe (the Vakhrameev model's choices; knots moved by hand are not
    /// part of it).
    pub recipe: Recipe,
    /// How the figures are computed.
    pub merit: MeritOptions,
}

/// One model's corrected drift on one log, filtered as for the figures, with its pyramid.
pub struct ModelSeries {
    /// Corrected Ω filtered, °/h.
    pub cor_filtered_dph: Vec<f64>,
    /// Its pyramid.
    pub lod: MinMaxPyramid,
}

/// A log of a comparison with its raw drift filtered as for the figures.
pub struct ComparedLog {
    /// The log.
    pub log: Arc<Log>,
    /// False for the training log.
    pub held_out: bool,
    /// Raw Ω filtered, °/h.
    pub raw_filtered_dph: Vec<f64>,
    /// Its pyramid.
    pub raw_lod: MinMaxPyramid,
}

/// What a comparison of models gives back, ready to draw.
pub struct Compared {
    /// The request number it answers.
    pub generation: u64,
    /// The models asked for, in order.
    pub choices: Vec<ModelChoice>,
    /// The engine's reports, one per choice.
    pub reports: Vec<ModelReport>,
    /// Per report, per log (training first): the corrected drift, or `None` when the model
    /// could not be fitted or applied.
    pub series: Vec<Vec<Option<ModelSeries>>>,
    /// The training log first, then the held-out ones.
    pub logs: Vec<ComparedLog>,
    /// Seconds the comparison took.
    pub seconds: f64,
}

/// A comparison in progress.
#[derive(Debug, Clone)]
pub struct CompareHandle {
    /// The request number.
    pub generation: u64,
    /// Models asked for.
    pub total: usize,
    done: Arc<AtomicUsize>,
    /// When it started.
    pub started: Instant,
}

impl CompareHandle {
    /// Models fitted and judged so far.
    pub fn done(&self) -> usize {
        self.done.load(Ordering::Relaxed).min(self.total)
    }
}

/// Allan deviations of a log's raw rate and of the same rate corrected.
#[derive(Clone)]
pub struct AllanRequest {
    /// What the answer is for (the fit's generation, and which log), to tell stale answers.
    pub key: (u64, bool),
    /// The log.
    pub log: Arc<Log>,
    /// Its correction.
    pub corrected: Arc<crate::live::Corrected>,
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

/// A read in progress.
#[derive(Debug, Clone)]
pub struct LoadHandle {
    /// Which slot.
    pub target: Target,
    /// The file.
    pub path: PathBuf,
    /// Fraction done (f64 bits).
    progress: Arc<AtomicU64>,
    /// Set to stop the read.
    cancel: Arc<AtomicBool>,
    /// When it started.
    pub started: Instant,
}

impl LoadHandle {
    /// Fraction done, 0 to 1.
    pub fn progress(&self) -> f64 {
        f64::from_bits(self.progress.load(Ordering::Relaxed)).clamp(0.0, 1.0)
    }
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
    pub fn load(&mut self, path: PathBuf, read: ReadOptions, target: Target) {
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
                let result = load_log(&h, read);
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
        let handle = CompareHandle {
            generation,
            total: request.choices.len(),
            done: Arc::new(AtomicUsize::new(0)),
            started: Instant::now(),
        };
        let (tx, ctx, h) = (self.tx.clone(), self.ctx.clone(), handle.clone());
        let spawned = std::thread::Builder::new()
            .name("driftlab-compare".into())
            .spawn(move || {
                let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_compare(&request, &h, &ctx)
                }));
                let result = run.map(Arc::new).map_err(|_| {
                    "the comparison stopped on an internal error (see the terminal)".to_string()
                });
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

fn load_log(h: &LoadHandle, read: ReadOptions) -> JobResult {
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
                || crate::calfile::sha256_file(&path).ok(),
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

/// Drawing data kept between refits while its source stays the same.
#[derive(Default)]
struct LodCache {
    prepared: Option<(usize, [Arc<MinMaxPyramid>; 3], Arc<ClassLod>)>,
    raw_filtered: Option<(usize, Arc<MinMaxPyramid>)>,
    held_raw: Option<(usize, Arc<MinMaxPyramid>)>,
    scatter: Vec<(usize, Arc<ScatterLod>)>,
}

fn addr<T>(a: &Arc<T>) -> usize {
    Arc::as_ptr(a) as usize
}

impl LodCache {
    fn prepared(
        &mut self,
        p: &Arc<Prepared>,
        regime: &[crate::model::Regime],
    ) -> ([Arc<MinMaxPyramid>; 3], Arc<ClassLod>) {
        if let Some((k, s, r)) = &self.prepared
            && *k == addr(p)
        {
            return (s.clone(), r.clone());
        }
        let ((a, b), c) = rayon::join(
            || {
                rayon::join(
                    || MinMaxPyramid::new(&p.omega_filtered_dph),
                    || MinMaxPyramid::new(&p.deriv.tdot),
                )
            },
            || MinMaxPyramid::new(&p.deriv.tddot),
        );
        let s = [Arc::new(a), Arc::new(b), Arc::new(c)];
        let r = Arc::new(ClassLod::new(regime.iter().map(|&r| r as u8).collect(), 2));
        self.prepared = Some((addr(p), s.clone(), r.clone()));
        (s, r)
    }

    fn series(
        slot: &mut Option<(usize, Arc<MinMaxPyramid>)>,
        v: &Arc<Vec<f64>>,
    ) -> Arc<MinMaxPyramid> {
        if let Some((k, p)) = slot
            && *k == addr(v)
        {
            return p.clone();
        }
        let p = Arc::new(MinMaxPyramid::new(v));
        *slot = Some((addr(v), p.clone()));
        p
    }

    fn scatter(&mut self, sets: [&Arc<PointSet>; 4]) -> [Arc<ScatterLod>; 4] {
        let mut out: Vec<Arc<ScatterLod>> = Vec::with_capacity(4);
        let mut keep = Vec::with_capacity(4);
        for s in sets {
            let lod = match self.scatter.iter().find(|(k, _)| *k == addr(s)) {
                Some((_, l)) => l.clone(),
                None => Arc::new(ScatterLod::new(&s.x, &s.y)),
            };
            keep.push((addr(s), lod.clone()));
            out.push(lod);
        }
        self.scatter = keep;
        [
            out[0].clone(),
            out[1].clone(),
            out[2].clone(),
            out[3].clone(),
        ]
    }
}

fn fit_worker(rx: Receiver<FitMsg>, tx: Sender<JobResult>, ctx: SharedCtx) {
    let mut pipeline = Pipeline::new();
    let mut cache = LodCache::default();
    while let Ok(mut msg) = rx.recv() {
        // Newest request wins: requests queued behind it are stale.
        while let Ok(newer) = rx.try_recv() {
            msg = newer;
        }
        let FitMsg::Fit(generation, request) = msg;
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let outcome = pipeline.run(&request)?;
            let lods = build_lods(&mut cache, &outcome);
            Ok::<_, String>(FitView {
                generation,
                outcome,
                lods,
            })
        }));
        let result = match run {
            Ok(Ok(view)) => JobResult::Fitted(Arc::new(view)),
            Ok(Err(message)) => JobResult::FitFailed(generation, message),
            Err(_) => {
                pipeline.clear();
                cache = LodCache::default();
                JobResult::FitFailed(
                    generation,
                    "the fit stopped on an internal error (see the terminal)".into(),
                )
            }
        };
        if tx.send(result).is_err() {
            break;
        }
        repaint(&ctx);
    }
}

fn build_lods(cache: &mut LodCache, o: &Outcome) -> FitLods {
    let ([omega_filtered, tdot, tddot], regime) =
        cache.prepared(&o.prepared, &o.in_sample.corrected.regime);
    let raw_filtered = LodCache::series(&mut cache.raw_filtered, &o.in_sample.raw_filtered_dph);
    let (pred, cor_filtered) = rayon::join(
        || MinMaxPyramid::new(&o.in_sample.corrected.pred_dph),
        || MinMaxPyramid::new(&o.in_sample.cor_filtered_dph),
    );
    let scatter = cache.scatter([
        &o.k1_plus_points,
        &o.k1_minus_points,
        &o.k2_plus_points,
        &o.k2_minus_points,
    ]);
    let held_out = o.held_out.as_ref().map(|h| HeldLods {
        raw_filtered: LodCache::series(&mut cache.held_raw, &h.raw_filtered_dph),
        cor_filtered: MinMaxPyramid::new(&h.cor_filtered_dph),
        regime: ClassLod::new(h.corrected.regime.iter().map(|&r| r as u8).collect(), 2),
    });
    FitLods {
        omega_filtered,
        tdot,
        tddot,
        regime,
        pred,
        raw_filtered,
        cor_filtered,
        scatter,
        held_out,
    }
}

/// The comparison: each model fitted and judged by the engine (in parallel, counting them
/// done), then its correction of every log filtered as the figures filter it, for drawing.
fn run_compare(req: &CompareRequest, h: &CompareHandle, ctx: &SharedCtx) -> Compared {
    let t = Instant::now();
    let tests: Vec<&Log> = req.tests.iter().map(|l| &**l).collect();
    let all: Vec<(Arc<Log>, bool)> = std::iter::once((req.train.clone(), false))
        .chain(req.tests.iter().map(|l| (l.clone(), true)))
        .collect();
    let filter = |log: &Log| {
        crate::signal::seconds_to_samples(req.merit.filter_s, log.nominal_dt_s()).max(1)
    };
    let done: Vec<(ModelReport, Vec<Option<ModelSeries>>)> = req
        .choices
        .par_iter()
        .map(|choice| {
            // Each log's correction is filtered for drawing as the engine judges it, once.
            let mut series: Vec<Option<ModelSeries>> = all.iter().map(|_| None).collect();
            let report = compare::compare_one(
                &req.train,
                &tests,
                choice,
                &req.recipe,
                &req.merit,
                &mut |k, c| {
                    let f = crate::signal::moving_average_centered(&c.cor_dph, filter(&all[k].0));
                    series[k] = Some(ModelSeries {
                        lod: MinMaxPyramid::new(&f),
                        cor_filtered_dph: f,
                    });
                },
            );
            if report.fitted.is_none() {
                series.clear();
            }
            h.done.fetch_add(1, Ordering::Relaxed);
            repaint(ctx);
            (report, series)
        })
        .collect();
    let logs = all
        .par_iter()
        .map(|(log, held_out)| {
            let f = crate::signal::moving_average_centered(&log.omega_dph, filter(log));
            ComparedLog {
                log: log.clone(),
                held_out: *held_out,
                raw_lod: MinMaxPyramid::new(&f),
                raw_filtered_dph: f,
            }
        })
        .collect();
    let (reports, series) = done.into_iter().unzip();
    Compared {
        generation: h.generation,
        choices: req.choices.clone(),
        reports,
        series,
        logs,
        seconds: t.elapsed().as_secs_f64(),
    }
}

/// Octave Allan deviations of the raw and the corrected rate over the same samples (after
/// the correction's warm-up).
fn run_allan(req: &AllanRequest) -> AllanView {
    let t = Instant::now();
    let log = &req.log;
    let end = req.corrected.cor_dph.len().min(log.len());
    let from = req.corrected.ready_from.min(end);
    let opts = AllanOptions {
        tau0_s: log.nominal_dt_s(),
        ..AllanOptions::default()
    };
    let (raw, corrected) = rayon::join(
        || crate::allan::allan(&log.omega_dph[from..end], &opts).map_err(|e| e.to_string()),
        || crate::allan::allan(&req.corrected.cor_dph[from..end], &opts).map_err(|e| e.to_string()),
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
