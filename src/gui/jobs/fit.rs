//! The live refit's worker: the newest request wins, and its outcome comes back with the
//! plot levels of detail built from it (cached while their inputs stay the same).

use super::*;

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
    /// Predicted drift filtered as Ω is for the time plot (the recipe's centred moving
    /// average): sample by sample the prediction switches between the + and − coefficients
    /// wherever the sign of d²T/dt² flickers, which drawn unfiltered over filtered Ω chatters.
    pub pred_filtered: Vec<f64>,
    /// Its pyramid.
    pub pred: MinMaxPyramid,
    /// Raw Ω filtered as for the figures.
    pub raw_filtered: Arc<MinMaxPyramid>,
    /// Corrected Ω filtered alike, within the stretches of [`FitLods::ready`] only (before a
    /// segment's rates have their history the correction is no reading, and a window reaching
    /// into those samples would draw a transient the figures do not see), °/h: the engine's
    /// series ([`crate::refit::Judged::cor_filtered_dph`]), not filtered again here.
    pub cor_filtered_dph: Arc<Vec<f64>>,
    /// Its pyramid.
    pub cor_filtered: MinMaxPyramid,
    /// K1+, K1−, K2+, K2− points.
    pub scatter: [Arc<ScatterLod>; 4],
    /// The samples whose rates have their full history, one stretch per segment of the log:
    /// Ṫ, T̈, the model and the corrected drift are drawn there only (before a segment's
    /// history fills they are no reading).
    pub ready: Segments,
    /// The log's segments between gaps (raw series are drawn over these).
    pub segments: Segments,
    /// The validation log's series.
    pub held_out: Option<HeldLods>,
}

/// Drawing data of the validation log.
pub struct HeldLods {
    /// Raw Ω filtered.
    pub raw_filtered: Arc<MinMaxPyramid>,
    /// Corrected Ω filtered within its ready stretches (see [`FitLods::cor_filtered_dph`]).
    pub cor_filtered_dph: Arc<Vec<f64>>,
    /// Its pyramid.
    pub cor_filtered: MinMaxPyramid,
    /// Regime per sample.
    pub regime: ClassLod,
    /// The samples its correction reads (see [`FitLods::ready`]).
    pub ready: Segments,
    /// Its segments between gaps.
    pub segments: Segments,
}

/// One refit's result, ready to draw.
pub struct FitView {
    /// The gyro axis it fits (0 for a log of one axis).
    pub axis: usize,
    /// The request number it answers.
    pub generation: u64,
    /// The engine's result.
    pub outcome: Outcome,
    /// Drawing data.
    pub lods: FitLods,
}

/// What a refit was asked for: the logs by identity, the choices by value. The same inputs
/// again need no refit.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct RefitKey {
    log: Same<Log>,
    validation: Option<Same<Log>>,
    recipe: Recipe,
    /// The figures' filter and windows: a session's windows change the figures alone.
    merit: MeritOptions,
}

impl RefitKey {
    pub(super) fn of(r: &Request) -> RefitKey {
        RefitKey {
            log: Same::of(&r.log),
            validation: r.validation.as_ref().map(Same::of),
            recipe: r.recipe.clone(),
            merit: r.merit,
        }
    }
}

/// Pyramids of a fit's filtered Ω, Ṫ and T̈, and its regimes, with the signals they were
/// built from.
struct PreparedLods {
    source: Same<Prepared>,
    series: [Arc<MinMaxPyramid>; 3],
    regime: Arc<ClassLod>,
}

/// Drawing data kept between refits while its source stays the same (the source held by
/// identity: see [`Same`]).
#[derive(Default)]
pub(super) struct LodCache {
    prepared: Option<PreparedLods>,
    raw_filtered: Option<(Same<Vec<f64>>, Arc<MinMaxPyramid>)>,
    held_raw: Option<(Same<Vec<f64>>, Arc<MinMaxPyramid>)>,
    scatter: Vec<(Same<PointSet>, Arc<ScatterLod>)>,
}

impl LodCache {
    fn prepared(
        &mut self,
        p: &Arc<Prepared>,
        regime: &[crate::models::vakhrameev::Regime],
    ) -> ([Arc<MinMaxPyramid>; 3], Arc<ClassLod>) {
        if let Some(kept) = &self.prepared
            && kept.source.is(p)
        {
            return (kept.series.clone(), kept.regime.clone());
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
        self.prepared = Some(PreparedLods {
            source: Same::of(p),
            series: s.clone(),
            regime: r.clone(),
        });
        (s, r)
    }

    fn series(
        slot: &mut Option<(Same<Vec<f64>>, Arc<MinMaxPyramid>)>,
        v: &Arc<Vec<f64>>,
    ) -> Arc<MinMaxPyramid> {
        if let Some((k, p)) = slot
            && k.is(v)
        {
            return p.clone();
        }
        let p = Arc::new(MinMaxPyramid::new(v));
        *slot = Some((Same::of(v), p.clone()));
        p
    }

    fn scatter(&mut self, sets: [&Arc<PointSet>; 4]) -> [Arc<ScatterLod>; 4] {
        let mut out: Vec<Arc<ScatterLod>> = Vec::with_capacity(4);
        let mut keep = Vec::with_capacity(4);
        for s in sets {
            let lod = match self.scatter.iter().find(|(k, _)| k.is(s)) {
                Some((_, l)) => l.clone(),
                None => Arc::new(ScatterLod::new(&s.x, &s.y)),
            };
            keep.push((Same::of(s), lod.clone()));
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

/// What the worker keeps for one axis between its refits.
#[derive(Default)]
struct AxisWork {
    pipeline: Pipeline,
    cache: LodCache,
}

/// The refit worker. Each axis has its own pipeline (its caches stay warm while another axis
/// is edited); per axis the newest request wins. Previews of a plateau drag go first (they read
/// the plateaus' samples alone); then the refits waiting, together as the engine runs a unit's
/// axes ([`refit_unit`]), as after the release of a plateau edge, which all the axes of a unit
/// share.
pub(super) fn fit_worker(rx: Receiver<FitMsg>, tx: Sender<JobResult>, ctx: SharedCtx) {
    let mut work: Vec<AxisWork> = vec![AxisWork::default()];
    let mut waiting: Vec<(usize, u64, Box<Request>)> = Vec::new();
    let mut previews: Vec<(usize, u64, Box<PreviewAsk>)> = Vec::new();
    loop {
        if waiting.is_empty() && previews.is_empty() {
            match rx.recv() {
                Ok(m) => queue(&mut waiting, &mut previews, &mut work, m),
                Err(_) => break,
            }
        }
        while let Ok(m) = rx.try_recv() {
            queue(&mut waiting, &mut previews, &mut work, m);
        }
        for (axis, generation, ask) in previews.drain(..) {
            let result = match crate::refit::preview_plateaus(&ask.log, &ask.ranges, &ask.recipe) {
                Ok(preview) => JobResult::Previewed(Arc::new(PreviewView {
                    axis,
                    generation,
                    preview,
                })),
                // What the release's refit will say; the last fit stays shown meanwhile.
                Err(_) => continue,
            };
            if tx.send(result).is_err() {
                return;
            }
            repaint(&ctx);
        }
        if waiting.is_empty() {
            continue;
        }
        let mut batch = std::mem::take(&mut waiting);
        batch.sort_by_key(|w| w.0);
        if let Some(top) = batch.last().map(|w| w.0)
            && work.len() <= top
        {
            work.resize_with(top + 1, AxisWork::default);
        }
        if !refit_unit(&mut work, &batch, &tx, &ctx) {
            break;
        }
    }
}

/// Refits the axes of `batch` (sorted by axis) as the engine runs a unit's axes
/// (`refit::run_unit_each`: the first axis's fit alone, the others with what its T stages made,
/// the whole corrections in one pass), each axis sent with its drawing data as soon as it is
/// judged. A panic in the refit becomes a failure of each axis not yet sent (their caches are
/// dropped). Returns `false` once the window has gone.
fn refit_unit(
    work: &mut [AxisWork],
    batch: &[(usize, u64, Box<Request>)],
    tx: &Sender<JobResult>,
    ctx: &SharedCtx,
) -> bool {
    let requests: Vec<Request> = batch.iter().map(|(_, _, r)| (**r).clone()).collect();
    let axes: Vec<usize> = batch.iter().map(|b| b.0).collect();
    let (mut pipes, caches): (Vec<&mut Pipeline>, Vec<Mutex<&mut LodCache>>) = work
        .iter_mut()
        .enumerate()
        .filter(|(a, _)| axes.binary_search(a).is_ok())
        .map(|(_, AxisWork { pipeline, cache })| (pipeline, Mutex::new(cache)))
        .unzip();
    let sent: Vec<AtomicBool> = batch.iter().map(|_| AtomicBool::new(false)).collect();
    let gone = AtomicBool::new(false);
    let send = |result: JobResult| {
        if tx.send(result).is_err() {
            gone.store(true, Ordering::Relaxed);
        }
        repaint(ctx);
    };
    let each = |k: usize, outcome: Result<Outcome, crate::error::Error>| {
        let (axis, generation) = (batch[k].0, batch[k].1);
        let result = match outcome {
            Ok(outcome) => {
                let mut cache = caches[k].lock().unwrap_or_else(|e| e.into_inner());
                let lods = build_lods(&mut cache, &outcome);
                JobResult::Fitted(Arc::new(FitView {
                    axis,
                    generation,
                    outcome,
                    lods,
                }))
            }
            Err(e) => JobResult::FitFailed(axis, generation, e.to_string()),
        };
        sent[k].store(true, Ordering::Relaxed);
        send(result);
    };
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        crate::refit::run_unit_each(&mut pipes, &requests, each);
    }));
    if run.is_err() {
        for (k, (pipeline, cache)) in pipes.iter_mut().zip(&caches).enumerate() {
            if sent[k].load(Ordering::Relaxed) {
                continue;
            }
            pipeline.clear();
            **cache.lock().unwrap_or_else(|e| e.into_inner()) = LodCache::default();
            send(JobResult::FitFailed(
                batch[k].0,
                batch[k].1,
                "the fit stopped on an internal error (see the terminal)".into(),
            ));
        }
    }
    !gone.load(Ordering::Relaxed)
}

/// Adds a message to the requests waiting: a refit replaces the one of its axis still
/// waiting, a preview the preview of its axis; a new count of axes drops what was kept or
/// waiting for axes past it.
fn queue(
    waiting: &mut Vec<(usize, u64, Box<Request>)>,
    previews: &mut Vec<(usize, u64, Box<PreviewAsk>)>,
    work: &mut Vec<AxisWork>,
    m: FitMsg,
) {
    match m {
        FitMsg::Fit(axis, generation, request) => {
            waiting.retain(|(a, ..)| *a != axis);
            waiting.push((axis, generation, request));
        }
        FitMsg::Preview(axis, generation, ask) => {
            previews.retain(|(a, ..)| *a != axis);
            previews.push((axis, generation, ask));
        }
        FitMsg::Axes(n) => {
            work.truncate(n.max(1));
            waiting.retain(|(a, ..)| *a < n.max(1));
            previews.retain(|(a, ..)| *a < n.max(1));
        }
    }
}

/// `x` with the centred moving average of `window` samples taken within each of `ranges`
/// alone (a window is truncated at a range's ends); samples outside every range are left as
/// they are (they are not drawn). Same length as `x`.
pub(super) fn filtered_within(
    x: &[f64],
    window: usize,
    ranges: &[std::ops::Range<usize>],
) -> Vec<f64> {
    let mut out = x.to_vec();
    for r in ranges.iter().filter(|r| r.end <= x.len()) {
        out[r.clone()].copy_from_slice(&crate::signal::moving_average_centered(
            &x[r.clone()],
            window,
        ));
    }
    out
}

pub(super) fn build_lods(cache: &mut LodCache, o: &Outcome) -> FitLods {
    let ([omega_filtered, tdot, tddot], regime) =
        cache.prepared(&o.prepared, &o.in_sample.corrected.regime);
    let raw_filtered = LodCache::series(&mut cache.raw_filtered, &o.in_sample.raw_filtered_dph);
    let filter = o.prepared.filter_samples;
    let cor_filtered_dph = o.in_sample.cor_filtered_dph.clone();
    let ((pred_filtered, pred), cor_filtered) = rayon::join(
        || {
            let f = filtered_within(
                &o.in_sample.corrected.pred_dph,
                filter,
                &o.in_sample.corrected.ready,
            );
            let p = MinMaxPyramid::new(&f);
            (f, p)
        },
        || MinMaxPyramid::new(&cor_filtered_dph),
    );
    let scatter = cache.scatter([
        &o.k1_plus_points,
        &o.k1_minus_points,
        &o.k2_plus_points,
        &o.k2_minus_points,
    ]);
    let held_out = o.held_out.as_ref().map(|h| HeldLods {
        raw_filtered: LodCache::series(&mut cache.held_raw, &h.raw_filtered_dph),
        cor_filtered_dph: h.cor_filtered_dph.clone(),
        cor_filtered: MinMaxPyramid::new(&h.cor_filtered_dph),
        regime: ClassLod::new(h.corrected.regime.iter().map(|&r| r as u8).collect(), 2),
        ready: Segments::from_ranges(&h.log.time_s, &h.corrected.ready),
        segments: Segments::of(&h.log),
    });
    let ready = Segments::from_ranges(&o.in_sample.log.time_s, &o.in_sample.corrected.ready);
    FitLods {
        omega_filtered,
        tdot,
        tddot,
        regime,
        pred_filtered,
        pred,
        raw_filtered,
        cor_filtered_dph,
        cor_filtered,
        scatter,
        ready,
        segments: Segments::from_ranges(&o.in_sample.log.time_s, &o.prepared.segments),
        held_out,
    }
}
