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
    /// The knots moved by hand it was fitted with (the recipe is the calibration's own).
    pub knots: crate::files::session::KnotEdits,
    /// The engine's result.
    pub outcome: Outcome,
    /// Drawing data.
    pub lods: FitLods,
}

/// Drawing data kept between refits while its source stays the same.
#[derive(Default)]
pub(super) struct LodCache {
    prepared: Option<(usize, [Arc<MinMaxPyramid>; 3], Arc<ClassLod>)>,
    raw_filtered: Option<(usize, Arc<MinMaxPyramid>)>,
    held_raw: Option<(usize, Arc<MinMaxPyramid>)>,
    scatter: Vec<(usize, Arc<ScatterLod>)>,
}

pub(super) fn addr<T>(a: &Arc<T>) -> usize {
    Arc::as_ptr(a) as usize
}

impl LodCache {
    fn prepared(
        &mut self,
        p: &Arc<Prepared>,
        regime: &[crate::models::vakhrameev::Regime],
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

pub(super) fn fit_worker(rx: Receiver<FitMsg>, tx: Sender<JobResult>, ctx: SharedCtx) {
    let mut pipeline = Pipeline::new();
    let mut cache = LodCache::default();
    while let Ok(mut msg) = rx.recv() {
        // Newest request wins: requests queued behind it are stale.
        while let Ok(newer) = rx.try_recv() {
            msg = newer;
        }
        let FitMsg::Fit(generation, request) = msg;
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let outcome = pipeline.run(&request).map_err(|e| e.to_string())?;
            let lods = build_lods(&mut cache, &outcome);
            Ok::<_, String>(FitView {
                generation,
                knots: request.knots.clone(),
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

pub(super) fn build_lods(cache: &mut LodCache, o: &Outcome) -> FitLods {
    let ([omega_filtered, tdot, tddot], regime) =
        cache.prepared(&o.prepared, &o.in_sample.corrected.regime);
    let raw_filtered = LodCache::series(&mut cache.raw_filtered, &o.in_sample.raw_filtered_dph);
    let filter = o.prepared.filter_samples;
    let ((pred_filtered, pred), cor_filtered) = rayon::join(
        || {
            let f = crate::signal::moving_average_centered(&o.in_sample.corrected.pred_dph, filter);
            let p = MinMaxPyramid::new(&f);
            (f, p)
        },
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
        pred_filtered,
        pred,
        raw_filtered,
        cor_filtered,
        scatter,
        held_out,
    }
}
