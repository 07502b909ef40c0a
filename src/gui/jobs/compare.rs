//! The Models page's comparison: every chosen model fitted on the calibration log and judged
//! on it and on the held-out logs, on a worker, with a count of the models done.

use super::*;

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
    /// The workbench's recipe (the Vakhrameev model's choices, its knots placed and set by hand
    /// among them).
    pub recipe: crate::models::CheckedRecipe,
    /// How the figures are computed.
    pub merit: MeritOptions,
}

/// One model's corrected drift on one log, filtered as for the figures, with its pyramid.
pub struct ModelSeries {
    /// Corrected Ω filtered, °/h.
    pub cor_filtered_dph: Vec<f64>,
    /// Its pyramid.
    pub lod: MinMaxPyramid,
    /// The samples the correction reads (rates with their history), where it is drawn.
    pub ready: Segments,
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
    /// Its segments between gaps, drawn apart.
    pub segments: Segments,
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
    /// The windows of its figures of merit, s.
    pub window_s: f64,
    /// The model to use, as `driftlab compare` names it (`None` when none was judged on
    /// every part, or the comparison was cancelled).
    pub recommended: Option<crate::judge::recommend::Recommendation>,
}

/// A comparison in progress.
#[derive(Debug, Clone)]
pub struct CompareHandle {
    /// The request number.
    pub generation: u64,
    /// Models asked for.
    pub total: usize,
    /// Their names, in table order.
    pub names: Vec<String>,
    pub(super) done: Arc<AtomicUsize>,
    /// Per model: where it is (see [`ModelProgress`]).
    pub(super) models: Arc<Vec<Mutex<ModelProgress>>>,
    pub(super) cancel: Arc<AtomicBool>,
    /// When it started.
    pub started: Instant,
}

/// Where one model of a comparison is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelProgress {
    /// Not started yet (the cores are busy with others).
    Waiting,
    /// Being fitted: the share of its searches done, since when.
    Fitting(f64, Instant),
    /// Fitted and judged, in this many seconds.
    Done(f64),
    /// Could not be fitted (the reason is in the report).
    Failed(f64),
    /// Stopped by Cancel.
    Cancelled,
}

impl CompareHandle {
    pub(super) fn new(generation: u64, names: Vec<String>) -> CompareHandle {
        CompareHandle {
            generation,
            total: names.len(),
            models: Arc::new(
                names
                    .iter()
                    .map(|_| Mutex::new(ModelProgress::Waiting))
                    .collect(),
            ),
            names,
            done: Arc::new(AtomicUsize::new(0)),
            cancel: Arc::new(AtomicBool::new(false)),
            started: Instant::now(),
        }
    }

    /// Models fitted and judged so far.
    pub fn done(&self) -> usize {
        self.done.load(Ordering::Relaxed).min(self.total)
    }

    /// Where model `k` is.
    pub fn model(&self, k: usize) -> ModelProgress {
        self.models
            .get(k)
            .and_then(|m| m.lock().ok().map(|m| *m))
            .unwrap_or(ModelProgress::Waiting)
    }

    fn set(&self, k: usize, p: ModelProgress) {
        if let Some(Ok(mut m)) = self.models.get(k).map(|m| m.lock()) {
            *m = p;
        }
    }

    /// Stops the comparison: models being fitted stop at their next step, the others do not
    /// start.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// True once Cancel was pressed.
    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// The comparison: each model fitted and judged by the engine (in parallel, counting them
/// done), then its correction of every log filtered as the figures filter it, for drawing.
pub(super) fn run_compare(req: &CompareRequest, h: &CompareHandle, ctx: &SharedCtx) -> Compared {
    let t = Instant::now();
    let tests = crate::judge::compare::tests_of(
        &req.train,
        &req.tests.iter().map(|l| &**l).collect::<Vec<_>>(),
    );
    let all: Vec<(Arc<Log>, bool)> = std::iter::once((req.train.clone(), false))
        .chain(req.tests.iter().map(|l| (l.clone(), true)))
        .collect();
    let filter = |log: &Log| {
        crate::signal::seconds_to_samples(req.merit.filter_s, log.nominal_dt_s()).max(1)
    };
    // Each log's segments between gaps, once: no filter window reaches across a gap.
    let segments: Vec<Vec<std::ops::Range<usize>>> =
        all.iter().map(|(log, _)| log.timing().segments).collect();
    let done: Vec<(ModelReport, Vec<Option<ModelSeries>>)> = req
        .choices
        .par_iter()
        .enumerate()
        .map(|(m, choice)| {
            // Each log's correction is filtered for drawing as the engine judges it, once.
            let mut series: Vec<Option<ModelSeries>> = all.iter().map(|_| None).collect();
            let t0 = Instant::now();
            let last_paint = Mutex::new(Instant::now());
            let progress = |share: f64| {
                if h.cancelled() {
                    return false;
                }
                h.set(m, ModelProgress::Fitting(share, t0));
                // Four repaints a second at most: a search reports hundreds of steps, and on a
                // machine drawing in software each frame costs the fit a share of a core.
                if let Ok(mut last) = last_paint.lock()
                    && last.elapsed() > Duration::from_millis(250)
                {
                    *last = Instant::now();
                    repaint(ctx);
                }
                true
            };
            let report = crate::judge::compare::compare_one(
                &req.train,
                &tests,
                choice,
                &req.recipe,
                &req.merit,
                &progress,
                &mut |k, c| {
                    let f = crate::signal::moving_average_centered_in(
                        &c.cor_dph,
                        filter(&all[k].0),
                        &segments[k],
                    );
                    series[k] = Some(ModelSeries {
                        lod: MinMaxPyramid::new(&f),
                        cor_filtered_dph: f,
                        ready: Segments::from_ranges(&all[k].0.time_s, &c.ready),
                    });
                },
            );
            if report.fitted.is_none() {
                series.clear();
            }
            let secs = t0.elapsed().as_secs_f64();
            h.set(
                m,
                match (&report.fitted, h.cancelled()) {
                    (Some(_), _) => ModelProgress::Done(secs),
                    (None, true) => ModelProgress::Cancelled,
                    (None, false) => ModelProgress::Failed(secs),
                },
            );
            h.done.fetch_add(1, Ordering::Relaxed);
            repaint(ctx);
            (report, series)
        })
        .collect();
    let logs = all
        .par_iter()
        .zip(&segments)
        .map(|((log, held_out), segments)| {
            let f =
                crate::signal::moving_average_centered_in(&log.omega_dph, filter(log), segments);
            ComparedLog {
                log: log.clone(),
                held_out: *held_out,
                raw_lod: MinMaxPyramid::new(&f),
                raw_filtered_dph: f,
                segments: Segments::from_ranges(&log.time_s, segments),
            }
        })
        .collect();
    let (reports, series): (Vec<ModelReport>, _) = done.into_iter().unzip();
    // With no validation log the models are fitted again on blocks of the calibration log
    // (what `driftlab compare` does), still on this worker, stopped by Cancel.
    let recommended = (!h.cancelled())
        .then(|| {
            crate::judge::recommend::recommend(
                &req.train,
                &reports,
                &req.choices,
                &req.recipe,
                &req.merit,
                &|| !h.cancelled(),
            )
        })
        .flatten();
    Compared {
        generation: h.generation,
        choices: req.choices.clone(),
        reports,
        series,
        logs,
        seconds: t.elapsed().as_secs_f64(),
        window_s: req.merit.window_s,
        recommended,
    }
}
