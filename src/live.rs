//! The workbench's live refit: a calibration as a pure function of (log, recipe, knots moved by
//! hand), run in stages with each stage's result kept until its inputs change.
//!
//! The stages are those of [`model::fit_prepared`], called through
//! the same public stage functions, so the result is the same calibration (a test holds them
//! equal). What this adds is memory between calls:
//!
//! * [`Prepared`] (filtered Ω, Ṫ, T̈) is kept while the filter, smoothing and step stay;
//! * the plateau mask, statistics and dead-bands while the plateaus stay;
//! * each set (+ and −) of K1/K2 while its inputs (K0, dead-bands, its two approximations,
//!   its hand-set knots) stay — changing K1+ refits only the + set;
//! * each set's first-pass K1 (fitted before any K2) while its samples, K0 and K1 spec stay —
//!   changing K2's kind refits one K1 less;
//! * the raw figures of merit and the validation log's derivatives while they stay;
//! * the plateau ranges while the signals and the plateau choice stay;
//! * `Ω_f − K0(T)` while K0 stays, and the sets' sample indices while the plateaus stay;
//! * `K0(T) + K1(Ṫ)·Ṫ` per sample, so that a K2 edit re-evaluates K2 alone.
//!
//! Knots set by hand ([`KnotEdits`]) replace the fitted knot values of their approximation;
//! a hand-edited K1 is followed by a fresh K2 fit on what it leaves (unless K2's knots are
//! set by hand too), as the paper's K2 step asks.
//!
//! The correction is made from the kept derivatives ([`Calibration::correct_into`], or a patch
//! of the samples of the sets that changed); it equals
//! [`Calibration::correct_with`](crate::model::Calibration) sample for sample.

use crate::approx::{Approx, ApproxSpec};
use crate::log::Log;
use crate::metrics::{Comparison, Evaluation, Figures, MeritOptions};
use crate::model::{self, Calibration, PointSet, Prepared, Regime, SetInputs, SetSamples};
use crate::plateau::{PlateauRange, PlateauStats};
use crate::recipe::{PlateauChoice, Recipe, Weighting};
use crate::session::{Coefficient, KnotEdits};
use crate::signal::{self, DerivativeSteps, Derivatives};
use rayon::prelude::*;
use std::sync::Arc;
use std::time::Instant;

/// What to fit.
#[derive(Debug, Clone)]
pub struct Request {
    /// The calibration log.
    pub log: Arc<Log>,
    /// Every choice.
    pub recipe: Recipe,
    /// Knots moved by hand.
    pub knots: KnotEdits,
    /// How the figures of merit are computed.
    pub merit: MeritOptions,
    /// A held-out log to judge the calibration on.
    pub validation: Option<Arc<Log>>,
}

/// A corrected log: the engine's correction.
pub use crate::correct::Correction as Corrected;

/// The calibration judged on one log.
#[derive(Debug, Clone)]
pub struct Judged {
    /// The log.
    pub log: Arc<Log>,
    /// The correction (shared: the next refit patches it in place once this is dropped, or a
    /// copy of it while it is held).
    pub corrected: Arc<Corrected>,
    /// Raw against corrected.
    pub evaluation: Evaluation,
    /// Ω filtered as for the figures (centred moving average), °/h.
    pub raw_filtered_dph: Arc<Vec<f64>>,
    /// Corrected Ω filtered alike, °/h (shared: kept while the correction stays).
    pub cor_filtered_dph: Arc<Vec<f64>>,
}

/// Milliseconds spent per stage of one run (0 for a stage that was reused).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Filtering and derivatives.
    pub prepare_ms: f64,
    /// Plateau mask, statistics, dead-bands and K0.
    pub plateaus_ms: f64,
    /// K1 and K2 of both sets.
    pub fit_ms: f64,
    /// Correction of the calibration log.
    pub correct_ms: f64,
    /// Figures of merit and the filtered display series.
    pub evaluate_ms: f64,
    /// The validation log, corrected and judged.
    pub validation_ms: f64,
    /// Everything.
    pub total_ms: f64,
}

/// The result of one run.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The calibration, hand-set knots applied.
    pub calibration: Calibration,
    /// Filtered Ω and derivatives of the calibration log.
    pub prepared: Arc<Prepared>,
    /// The plateau ranges used (detected or given).
    pub ranges: Vec<PlateauRange>,
    /// Pointwise K1+ points.
    pub k1_plus_points: Arc<PointSet>,
    /// Pointwise K1− points.
    pub k1_minus_points: Arc<PointSet>,
    /// Pointwise K2+ points.
    pub k2_plus_points: Arc<PointSet>,
    /// Pointwise K2− points.
    pub k2_minus_points: Arc<PointSet>,
    /// What the fit had to work around.
    pub warnings: Vec<String>,
    /// The calibration log, corrected and judged (in-sample).
    pub in_sample: Judged,
    /// The validation log, corrected and judged (held out).
    pub held_out: Option<Judged>,
    /// Time per stage.
    pub timings: Timings,
}

impl Outcome {
    /// The pointwise points of a K1/K2 coefficient (empty for K0).
    pub fn points(&self, c: Coefficient) -> &PointSet {
        static EMPTY: PointSet = PointSet {
            x: Vec::new(),
            y: Vec::new(),
        };
        match c {
            Coefficient::K0 => &EMPTY,
            Coefficient::K1Plus => &self.k1_plus_points,
            Coefficient::K1Minus => &self.k1_minus_points,
            Coefficient::K2Plus => &self.k2_plus_points,
            Coefficient::K2Minus => &self.k2_minus_points,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
struct PrepKey {
    log: usize,
    filter_s: f64,
    smoothing_s: f64,
    step_h_s: f64,
}

#[derive(Debug, Clone, PartialEq)]
struct PlateauKey {
    prepared: usize,
    ranges: Vec<PlateauRange>,
    deadband_tdot: Option<f64>,
    deadband_tddot: Option<f64>,
}

struct PlateauStage {
    key: PlateauKey,
    stats: Vec<PlateauStats>,
    mask: Arc<Vec<bool>>,
    deadbands: (f64, f64),
}

#[derive(Debug, Clone, PartialEq)]
struct SetKey {
    plateaus: PlateauKey,
    k0: Approx,
    spec1: ApproxSpec,
    spec2: ApproxSpec,
    weighting: Weighting,
    refinements: usize,
}

/// What the first pass's K1 of a set depends on (not K2: it is fitted before any K2), so that
/// it is kept while only the set's K2 changes.
#[derive(Debug, Clone, PartialEq)]
struct FirstKey {
    plateaus: PlateauKey,
    k0: Approx,
    spec1: ApproxSpec,
    weighting: Weighting,
}

#[derive(Clone)]
struct SetFit {
    k1: Approx,
    k2: Approx,
    p1: Arc<PointSet>,
    p2: Arc<PointSet>,
    warnings: Vec<String>,
}

struct ValidationCache {
    log: usize,
    steps: DerivativeSteps,
    deriv: Arc<Derivatives>,
    filter: usize,
    raw_filtered: Arc<Vec<f64>>,
    raw_key: (usize, MeritOptions),
    raw_figures: Figures,
}

/// (log, filter samples) of a kept filtered raw Ω.
type RawFilteredKey = (usize, usize);

/// The staged, caching fitter. Keep one per workbench (it is not shared between threads).
#[derive(Default)]
pub struct Pipeline {
    prepared: Option<(PrepKey, Arc<Prepared>)>,
    plateaus: Option<PlateauStage>,
    sets: [Option<(SetKey, SetFit)>; 2],
    /// Each set's first-pass K1, kept while only its K2 changes.
    first_k1: [Option<(FirstKey, Approx)>; 2],
    raw_figures: Option<((usize, usize, MeritOptions), Figures)>,
    raw_filtered: Option<(RawFilteredKey, Arc<Vec<f64>>)>,
    validation: Option<ValidationCache>,
    /// The validation log's last correction, reused in place once the UI has dropped it.
    validation_corrected: Option<Arc<Corrected>>,
    /// The last corrections of the calibration log, newest first (at most two: the one the
    /// UI shows and the one before, whose buffers the next run reuses once they are free).
    corrections: Vec<CorrectionBuf>,
    /// Counts the corrections made, so that what is derived from one can be kept with it.
    correction_generation: u64,
    /// The figures and display series of the last correction.
    evaluated: Option<EvalCache>,
    /// A display series buffer to reuse.
    spare_filtered: Option<Arc<Vec<f64>>>,
    /// Scratch prefix sums of the display average.
    prefix: Vec<f64>,
    /// The per-set samples the pointwise K1/K2 are made from.
    samples: Option<SamplesCache>,
    /// `Ω_f − K0(T)` over the calibration log.
    rest: Option<RestCache>,
    /// `K0(T) + K1(Ṫ)·Ṫ` per sample, for patching a correction when only K2 changes.
    base: Option<BaseTerms>,
    /// The plateau ranges of the last run, with the signals and plateau choice they came from.
    ranges: Option<(usize, PlateauChoice, Vec<PlateauRange>)>,
}

/// What a correction of the calibration log was made with.
#[derive(Debug, Clone, PartialEq)]
struct CorrectionKey {
    log: usize,
    prepared: usize,
    k0: Approx,
    sets: [(Approx, Approx); 2],
}

impl CorrectionKey {
    /// Whether a correction made with `self` can be turned into one with `other` by
    /// recomputing the samples of the sets whose approximations differ.
    fn patchable_to(&self, other: &CorrectionKey) -> bool {
        self.log == other.log && self.prepared == other.prepared && self.k0 == other.k0
    }

    /// The sets whose approximations differ, and of those, the ones whose x-ranges differ
    /// too (only then can a sample's "outside the calibrated ranges" change).
    fn changed(&self, other: &CorrectionKey) -> Changed {
        let ranges = |a: &Approx| (a.x_min(), a.x_max());
        let differ = |s: usize| self.sets[s] != other.sets[s];
        let moved = |s: usize| {
            let ((a1, a2), (b1, b2)) = (&self.sets[s], &other.sets[s]);
            ranges(a1) != ranges(b1) || ranges(a2) != ranges(b2)
        };
        Changed {
            sets: [differ(0), differ(1)],
            ranges: [differ(0) && moved(0), differ(1) && moved(1)],
        }
    }
}

/// `K0(T) + K1(Ṫ)·Ṫ` of the samples of each set: the part of their prediction that stays while
/// only the set's K2 changes (a K2 knot dragged), so that a patch evaluates K2 alone.
#[derive(Default)]
struct BaseTerms {
    log: usize,
    prepared: usize,
    k0: Option<Approx>,
    /// The K1 each set's values were made with (`None`: not made yet).
    k1: [Option<Approx>; 2],
    values: Vec<f64>,
}

impl BaseTerms {
    /// Made ready for a log, its signals and K0 (forgetting values made with others).
    fn ready_for(&mut self, log: usize, prepared: usize, k0: &Approx, n: usize) {
        if self.log != log
            || self.prepared != prepared
            || self.k0.as_ref() != Some(k0)
            || self.values.len() != n
        {
            self.log = log;
            self.prepared = prepared;
            self.k0 = Some(k0.clone());
            self.k1 = [None, None];
            self.values.clear();
            self.values.resize(n, 0.0);
        }
    }
}

/// Which sets of a correction must be recomputed.
#[derive(Debug, Clone, Copy)]
struct Changed {
    /// The set's approximations changed.
    sets: [bool; 2],
    /// Their x-ranges changed too.
    ranges: [bool; 2],
}

/// A correction of the calibration log and what it was made with.
struct CorrectionBuf {
    key: CorrectionKey,
    corrected: Arc<Corrected>,
}

/// Figures of merit and display series of one correction.
struct EvalCache {
    generation: u64,
    merit: MeritOptions,
    filter: usize,
    figures: Figures,
    filtered: Arc<Vec<f64>>,
}

/// Per-set sample indices, kept while the plateaus (and so the derivatives) stay.
struct SamplesCache {
    plateaus: PlateauKey,
    sets: Arc<[SetSamples; 2]>,
}

/// `Ω_f − K0(T)`, kept while the filtered Ω and K0 stay.
struct RestCache {
    prepared: usize,
    k0: Approx,
    rest: Arc<Vec<f64>>,
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn ptr<T>(a: &Arc<T>) -> usize {
    Arc::as_ptr(a) as usize
}

/// `approx` with its knot values replaced by `values`, when the counts agree.
pub fn with_knots(approx: &Approx, values: Option<&Vec<f64>>) -> Approx {
    let Some(values) = values else {
        return approx.clone();
    };
    if approx.knots().1.len() != values.len() {
        return approx.clone();
    }
    values
        .iter()
        .enumerate()
        .fold(approx.clone(), |a, (j, &y)| a.with_knot_value(j, y))
}

impl Pipeline {
    /// A pipeline with nothing kept.
    pub fn new() -> Pipeline {
        Pipeline::default()
    }

    /// Forgets everything kept (after a new log is loaded, say).
    pub fn clear(&mut self) {
        *self = Pipeline::default();
    }

    /// The filtered and differentiated signals for the recipe, kept between runs.
    pub fn prepared(&mut self, log: &Arc<Log>, recipe: &Recipe) -> (Arc<Prepared>, bool) {
        let key = PrepKey {
            log: ptr(log),
            filter_s: recipe.filter_s,
            smoothing_s: recipe.temp_smoothing_s,
            step_h_s: recipe.step_h_s,
        };
        if let Some((k, p)) = &self.prepared
            && *k == key
        {
            return (p.clone(), true);
        }
        let p = Arc::new(Prepared::new(log, recipe));
        self.prepared = Some((key, p.clone()));
        (p, false)
    }

    /// Runs every stage whose inputs changed since the last run.
    ///
    /// # Errors
    /// An invalid recipe, a log too short to calibrate, no plateaus.
    pub fn run(&mut self, req: &Request) -> Result<Outcome, String> {
        let t_all = Instant::now();
        let mut timings = Timings::default();
        let log = &req.log;
        let recipe = &req.recipe;
        recipe.validate()?;
        if log.len() < 16 {
            return Err(format!(
                "{}: {} samples are too few to calibrate",
                log.source,
                log.len()
            ));
        }

        let t = Instant::now();
        let (prepared, reused) = self.prepared(log, recipe);
        if !reused {
            timings.prepare_ms = ms(t);
        }

        let t = Instant::now();
        let ranges = self.plateau_ranges(log, &prepared, recipe);
        let pkey = PlateauKey {
            prepared: ptr(&prepared),
            ranges: ranges.clone(),
            deadband_tdot: recipe.deadband_tdot,
            deadband_tddot: recipe.deadband_tddot,
        };
        if self.plateaus.as_ref().is_none_or(|s| s.key != pkey) {
            let stats = model::plateau_stats(log, &ranges);
            let mask = model::plateau_mask(&log.time_s, &ranges);
            let deadbands = model::deadbands(&prepared, &mask, recipe);
            self.plateaus = Some(PlateauStage {
                key: pkey.clone(),
                stats,
                mask: Arc::new(mask),
                deadbands,
            });
            timings.plateaus_ms = ms(t);
        }
        let stage = self.plateaus.as_ref().ok_or("plateau stage missing")?;
        let mut warnings = Vec::new();
        let k0 =
            model::fit_k0(&stage.stats, &recipe.k0, &mut warnings).map_err(|e| e.to_string())?;
        let k0 = with_knots(&k0, req.knots.get(Coefficient::K0));
        let stats = stage.stats.clone();
        let mask = stage.mask.clone();
        let deadbands = stage.deadbands;

        let t = Instant::now();
        let set_key = |regime: Regime| {
            let (c1, c2) = match regime {
                Regime::Minus => (Coefficient::K1Minus, Coefficient::K2Minus),
                _ => (Coefficient::K1Plus, Coefficient::K2Plus),
            };
            SetKey {
                plateaus: pkey.clone(),
                k0: k0.clone(),
                spec1: *c1.spec(recipe),
                spec2: *c2.spec(recipe),
                weighting: recipe.weighting,
                refinements: recipe.refinements,
            }
        };
        let keys = [set_key(Regime::Plus), set_key(Regime::Minus)];
        let todo: Vec<usize> = (0..2)
            .filter(|&s| self.sets[s].as_ref().is_none_or(|(k, _)| *k != keys[s]))
            .collect();
        let inputs = if !todo.is_empty() || !req.knots.is_empty() {
            Some(self.set_inputs(&pkey, &prepared, &mask, deadbands, &k0, &log.temp_c))
        } else {
            None
        };
        let fitted: Vec<(usize, SetFit)> = match &inputs {
            Some((samples, rest)) => {
                let inputs = SetInputs {
                    tdot: &prepared.deriv.tdot,
                    tddot: &prepared.deriv.tddot,
                    rest,
                };
                let first_keys = [0, 1].map(|s| FirstKey {
                    plateaus: pkey.clone(),
                    k0: k0.clone(),
                    spec1: keys[s].spec1,
                    weighting: recipe.weighting,
                });
                let kept = [0, 1].map(|s| {
                    self.first_k1[s]
                        .as_ref()
                        .filter(|(k, _)| *k == first_keys[s])
                        .map(|(_, a)| a.clone())
                });
                let fitted: Vec<(usize, SetFit, Option<Approx>)> = todo
                    .par_iter()
                    .map(|&s| {
                        let regime = if s == 0 { Regime::Plus } else { Regime::Minus };
                        // The first pass's K1 only serves when a refinement follows it.
                        let first = (recipe.refinements > 0).then(|| {
                            kept[s].clone().unwrap_or_else(|| {
                                model::first_k1(&samples[s], inputs, regime, recipe)
                            })
                        });
                        let fit = fit_set(&samples[s], inputs, regime, recipe, first.as_ref());
                        (s, fit, first)
                    })
                    .collect();
                for (s, _, first) in &fitted {
                    if let Some(a) = first {
                        self.first_k1[*s] = Some((first_keys[*s].clone(), a.clone()));
                    }
                }
                fitted.into_iter().map(|(s, f, _)| (s, f)).collect()
            }
            None => Vec::new(),
        };
        for (s, fit) in fitted {
            self.sets[s] = Some((keys[s].clone(), fit));
        }
        if !todo.is_empty() {
            timings.fit_ms = ms(t);
        }
        let t = Instant::now();
        let edited = |s: usize, regime: Regime| {
            self.sets[s].as_ref().map(|(_, fit)| match &inputs {
                Some((samples, rest)) => {
                    let inputs = SetInputs {
                        tdot: &prepared.deriv.tdot,
                        tddot: &prepared.deriv.tddot,
                        rest,
                    };
                    apply_knot_edits(fit, &samples[s], inputs, regime, recipe, &req.knots)
                }
                None => fit.clone(),
            })
        };
        let plus = edited(0, Regime::Plus).ok_or("+ set missing")?;
        let minus = edited(1, Regime::Minus).ok_or("− set missing")?;
        if !req.knots.is_empty() {
            timings.fit_ms += ms(t);
        }
        warnings.extend(plus.warnings.iter().cloned());
        warnings.extend(minus.warnings.iter().cloned());

        let calibration = Calibration::assemble(
            log,
            &prepared,
            recipe,
            deadbands,
            stats,
            [k0, plus.k1, minus.k1, plus.k2, minus.k2],
        );

        let t = Instant::now();
        let corrected = self.correct_kept(&calibration, log, &prepared);
        timings.correct_ms = ms(t);

        let t = Instant::now();
        let merit = req.merit;
        let raw_key = (ptr(log), corrected.ready_from, merit);
        let raw_figures = match &self.raw_figures {
            Some((k, f)) if *k == raw_key => *f,
            _ => {
                let f = crate::metrics::figures(
                    &log.omega_dph,
                    prepared.dt_s,
                    corrected.ready_from,
                    &merit,
                );
                self.raw_figures = Some((raw_key, f));
                f
            }
        };
        let filter = signal::seconds_to_samples(merit.filter_s, prepared.dt_s).max(1);
        let raw_filtered = match &self.raw_filtered {
            Some((k, f)) if *k == (ptr(log), filter) => f.clone(),
            _ => {
                let f = Arc::new(signal::moving_average_centered(&log.omega_dph, filter));
                self.raw_filtered = Some(((ptr(log), filter), f.clone()));
                f
            }
        };
        let (cor_figures, cor_filtered) =
            self.evaluate_kept(&corrected, prepared.dt_s, &merit, filter);
        let evaluation = evaluation(raw_figures, cor_figures, &corrected);
        let in_sample = Judged {
            log: log.clone(),
            corrected,
            evaluation,
            raw_filtered_dph: raw_filtered,
            cor_filtered_dph: cor_filtered,
        };
        timings.evaluate_ms = ms(t);

        let t = Instant::now();
        let held_out = req
            .validation
            .as_ref()
            .map(|v| self.judge_validation(&calibration, v, &merit));
        if held_out.is_some() {
            timings.validation_ms = ms(t);
        }
        timings.total_ms = ms(t_all);
        Ok(Outcome {
            calibration,
            prepared,
            ranges,
            k1_plus_points: plus.p1,
            k1_minus_points: minus.p1,
            k2_plus_points: plus.p2,
            k2_minus_points: minus.p2,
            warnings,
            in_sample,
            held_out,
            timings,
        })
    }

    /// The plateau ranges the recipe asks for (the detector walks the whole log), kept while
    /// the signals and the plateau choice stay.
    fn plateau_ranges(
        &mut self,
        log: &Log,
        prepared: &Arc<Prepared>,
        recipe: &Recipe,
    ) -> Vec<PlateauRange> {
        if let Some((p, choice, ranges)) = &self.ranges
            && *p == ptr(prepared)
            && *choice == recipe.plateaus
        {
            return ranges.clone();
        }
        let ranges = model::plateau_ranges(log, prepared, recipe);
        self.ranges = Some((ptr(prepared), recipe.plateaus.clone(), ranges.clone()));
        ranges
    }

    /// The sets' samples and `Ω_f − K0(T)`, kept while their inputs stay.
    fn set_inputs(
        &mut self,
        pkey: &PlateauKey,
        prepared: &Arc<Prepared>,
        mask: &[bool],
        deadbands: (f64, f64),
        k0: &Approx,
        temp_c: &[f64],
    ) -> (Arc<[SetSamples; 2]>, Arc<Vec<f64>>) {
        let samples = match &self.samples {
            Some(c) if c.plateaus == *pkey => c.sets.clone(),
            _ => {
                let sets = Arc::new(model::set_samples(&prepared.deriv, mask, deadbands));
                self.samples = Some(SamplesCache {
                    plateaus: pkey.clone(),
                    sets: sets.clone(),
                });
                sets
            }
        };
        let rest = match &self.rest {
            Some(c) if c.prepared == ptr(prepared) && c.k0 == *k0 => c.rest.clone(),
            _ => {
                let rest = Arc::new(model::rest_dph(&prepared.omega_filtered_dph, temp_c, k0));
                self.rest = Some(RestCache {
                    prepared: ptr(prepared),
                    k0: k0.clone(),
                    rest: rest.clone(),
                });
                rest
            }
        };
        (samples, rest)
    }

    /// Corrects the calibration log; when only one set's approximations changed since the last
    /// run, only that set's samples are recomputed. The buffers of a correction the UI no
    /// longer holds are reused in place; one it still holds is copied first.
    fn correct_kept(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        prepared: &Arc<Prepared>,
    ) -> Arc<Corrected> {
        let key = CorrectionKey {
            log: ptr(log),
            prepared: ptr(prepared),
            k0: cal.k0.clone(),
            sets: [
                (cal.k1_plus.clone(), cal.k2_plus.clone()),
                (cal.k1_minus.clone(), cal.k2_minus.clone()),
            ],
        };
        if let Some(cur) = self.corrections.first()
            && cur.key == key
        {
            return cur.corrected.clone();
        }
        self.correction_generation += 1;
        let deriv = &prepared.deriv;
        let terms = self.base.get_or_insert_with(BaseTerms::default);
        terms.ready_for(ptr(log), ptr(prepared), &cal.k0, log.len());
        let mut bufs = std::mem::take(&mut self.corrections);
        // A buffer nobody else holds, preferably one that only needs patching.
        let free = bufs
            .iter_mut()
            .position(|b| b.key.patchable_to(&key) && Arc::get_mut(&mut b.corrected).is_some())
            .or_else(|| {
                bufs.iter_mut()
                    .position(|b| Arc::get_mut(&mut b.corrected).is_some())
            });
        let fresh = match free {
            Some(j) => {
                let mut b = bufs.remove(j);
                let Some(c) = Arc::get_mut(&mut b.corrected) else {
                    unreachable!("the buffer was just found unshared")
                };
                let base = bufs.first().filter(|cur| cur.key.patchable_to(&key));
                if b.key.patchable_to(&key) {
                    patch(cal, log, deriv, c, b.key.changed(&key), terms);
                } else if let Some(cur) = base {
                    copy_correction(c, &cur.corrected);
                    patch(cal, log, deriv, c, cur.key.changed(&key), terms);
                } else {
                    cal.correct_into(log, deriv, c);
                }
                b.key = key;
                b
            }
            None => {
                let corrected = match bufs.first().filter(|cur| cur.key.patchable_to(&key)) {
                    Some(cur) => {
                        let mut c = Corrected::clone(&cur.corrected);
                        patch(cal, log, deriv, &mut c, cur.key.changed(&key), terms);
                        c
                    }
                    None => cal.correct_with(log, deriv),
                };
                CorrectionBuf {
                    key,
                    corrected: Arc::new(corrected),
                }
            }
        };
        let corrected = fresh.corrected.clone();
        bufs.truncate(1);
        bufs.insert(0, fresh);
        self.corrections = bufs;
        corrected
    }

    /// The figures of merit and the display series of the correction made last, kept while
    /// that correction stays; the display series reuses a buffer the UI no longer holds.
    fn evaluate_kept(
        &mut self,
        corrected: &Corrected,
        dt_s: f64,
        merit: &MeritOptions,
        filter: usize,
    ) -> (Figures, Arc<Vec<f64>>) {
        let generation = self.correction_generation;
        if let Some(e) = &self.evaluated
            && e.generation == generation
            && e.merit == *merit
            && e.filter == filter
        {
            return (e.figures, e.filtered.clone());
        }
        let mut pool: Vec<Arc<Vec<f64>>> = self
            .evaluated
            .take()
            .map(|e| e.filtered)
            .into_iter()
            .chain(self.spare_filtered.take())
            .collect();
        let mut target = match pool.iter_mut().position(|a| Arc::get_mut(a).is_some()) {
            Some(j) => pool.swap_remove(j),
            None => Arc::new(Vec::new()),
        };
        self.spare_filtered = pool.pop();
        let Some(out) = Arc::get_mut(&mut target) else {
            unreachable!("the buffer was just found unshared")
        };
        let prefix = &mut self.prefix;
        let (figures, ()) = rayon::join(
            || crate::metrics::figures(&corrected.cor_dph, dt_s, corrected.ready_from, merit),
            || moving_average_centered_into(&corrected.cor_dph, filter, prefix, out),
        );
        self.evaluated = Some(EvalCache {
            generation,
            merit: *merit,
            filter,
            figures,
            filtered: target.clone(),
        });
        (figures, target)
    }

    /// Corrects and judges the validation log, keeping its derivatives and raw figures.
    fn judge_validation(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        merit: &MeritOptions,
    ) -> Judged {
        let dt = log.nominal_dt_s();
        let steps = cal.steps_for(dt);
        let filter = signal::seconds_to_samples(merit.filter_s, dt).max(1);
        let fresh = match &self.validation {
            Some(v) => v.log != ptr(log) || v.steps != steps || v.filter != filter,
            None => true,
        };
        if fresh {
            let (deriv, raw_filtered) = rayon::join(
                || signal::derivatives(&log.temp_c, steps, dt),
                || signal::moving_average_centered(&log.omega_dph, filter),
            );
            self.validation = Some(ValidationCache {
                log: ptr(log),
                steps,
                deriv: Arc::new(deriv),
                filter,
                raw_filtered: Arc::new(raw_filtered),
                raw_key: (usize::MAX, *merit),
                raw_figures: Figures::default(),
            });
        }
        let Some(v) = self.validation.as_mut() else {
            unreachable!("validation cache was just filled")
        };
        let mut corrected = self
            .validation_corrected
            .take()
            .and_then(|mut c| Arc::get_mut(&mut c).is_some().then_some(c))
            .unwrap_or_default();
        let Some(c) = Arc::get_mut(&mut corrected) else {
            unreachable!("the buffer was just found unshared")
        };
        cal.correct_into(log, &v.deriv, c);
        self.validation_corrected = Some(corrected.clone());
        if v.raw_key != (corrected.ready_from, *merit) {
            v.raw_figures =
                crate::metrics::figures(&log.omega_dph, dt, corrected.ready_from, merit);
            v.raw_key = (corrected.ready_from, *merit);
        }
        let (cor_figures, cor_filtered) = rayon::join(
            || crate::metrics::figures(&corrected.cor_dph, dt, corrected.ready_from, merit),
            || signal::moving_average_centered(&corrected.cor_dph, filter),
        );
        let evaluation = evaluation(v.raw_figures, cor_figures, &corrected);
        Judged {
            log: log.clone(),
            corrected,
            evaluation,
            raw_filtered_dph: v.raw_filtered.clone(),
            cor_filtered_dph: Arc::new(cor_filtered),
        }
    }
}

/// Raw against corrected figures, with the ratios as [`Comparison::of`] makes them.
fn evaluation(raw: Figures, corrected: Figures, c: &Corrected) -> Evaluation {
    Evaluation {
        comparison: Comparison::from_figures(raw, corrected),
        outside_fraction: c.outside_fraction,
        warmup_samples: c.ready_from,
    }
}

/// K1 and K2 of one set by the engine's per-set fit, with the points shared for display.
fn fit_set(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    first_k1: Option<&Approx>,
) -> SetFit {
    let f = model::fit_set_from(samples, inputs, regime, recipe, true, first_k1);
    SetFit {
        k1: f.k1,
        k2: f.k2,
        p1: Arc::new(f.k1_points),
        p2: Arc::new(f.k2_points),
        warnings: f.warnings,
    }
}

fn set_names(regime: Regime) -> (Coefficient, Coefficient, &'static str) {
    match regime {
        Regime::Minus => (Coefficient::K1Minus, Coefficient::K2Minus, "-"),
        _ => (Coefficient::K1Plus, Coefficient::K2Plus, "+"),
    }
}

/// The hand-set knots applied to a fitted set: a hand-set K1 is followed by a K2 fitted on
/// what it leaves (unless K2's knots are set by hand too), then K2's hand-set knots.
fn apply_knot_edits(
    fit: &SetFit,
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    knots: &KnotEdits,
) -> SetFit {
    let (c1, c2, sign) = set_names(regime);
    let mut out = fit.clone();
    let edit1 = knots.get(c1).filter(|v| v.len() == fit.k1.knots().1.len());
    if edit1.is_some() {
        out.k1 = with_knots(&fit.k1, edit1);
        if knots.get(c2).is_none() {
            let mut w = Vec::new();
            // The points are gathered for display anyway; the fit reads them rather than
            // evaluating the edited K1 again in each of its passes.
            let p2 = model::k2_points_of(samples, inputs, &out.k1);
            out.k2 = model::fit_k2_gathered(samples, &p2, regime, recipe, &mut w);
            out.p2 = Arc::new(p2);
            out.warnings
                .retain(|m| !m.starts_with(&format!("K2{sign}")));
            out.warnings.extend(w);
        }
    }
    out.k2 = with_knots(&out.k2, knots.get(c2));
    out
}

/// `dst` made equal to `src`, reusing `dst`'s buffers.
fn copy_correction(dst: &mut Corrected, src: &Corrected) {
    dst.pred_dph.clone_from(&src.pred_dph);
    dst.cor_dph.clone_from(&src.cor_dph);
    dst.regime.clone_from(&src.regime);
    dst.outside_fraction = src.outside_fraction;
    dst.outside_by_regime = src.outside_by_regime;
    dst.ready_from = src.ready_from;
}

/// Recomputes in place the samples of the `changed` sets of a correction made with the same
/// log, derivatives and K0 (the regime of a sample depends on its derivatives only). A sample's
/// prediction is [`Calibration::predict`]'s, term for term; its "outside" flag is recounted
/// only where the set's ranges moved.
fn patch(
    cal: &Calibration,
    log: &Log,
    deriv: &Derivatives,
    c: &mut Corrected,
    changed: Changed,
    base: &mut BaseTerms,
) {
    let Changed {
        sets: changed,
        ranges: recount,
    } = changed;
    if !changed.contains(&true) {
        return;
    }
    let approx = [
        (&cal.k1_plus, &cal.k2_plus, Regime::Plus),
        (&cal.k1_minus, &cal.k2_minus, Regime::Minus),
    ];
    if base.values.len() != c.pred_dph.len() {
        base.k1 = [None, None];
        base.values.clear();
        base.values.resize(c.pred_dph.len(), 0.0);
    }
    // Whether a set's kept K0 + K1 terms are those of this calibration.
    let kept = [0, 1].map(|s| base.k1[s].as_ref() == Some(approx[s].0));
    let k0 = cal.k0.evaluator();
    let eval = [0, 1].map(|s| (approx[s].0.evaluator(), approx[s].1.evaluator()));
    const CHUNK: usize = 1 << 15;
    let counts = c
        .pred_dph
        .par_chunks_mut(CHUNK)
        .zip(c.cor_dph.par_chunks_mut(CHUNK))
        .zip(c.regime.par_chunks(CHUNK))
        .zip(base.values.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(ci, (((p, q), r), b))| {
            let base = ci * CHUNK;
            let mut out = [0usize; 3];
            for k in 0..p.len() {
                let s = match r[k] {
                    Regime::Plus => 0,
                    Regime::Minus => 1,
                    Regime::Static => continue,
                };
                if !changed[s] {
                    continue;
                }
                let i = base + k;
                let (t, td, tdd) = (log.temp_c[i], deriv.tdot[i], deriv.tddot[i]);
                let (k1, k2) = &eval[s];
                let regime = approx[s].2;
                // `predict`'s sum, (K0 + K1·Ṫ) + K2·T̈, with the first part kept.
                if !kept[s] {
                    b[k] = k0.eval(t) + k1.eval(td) * td;
                }
                let pred = b[k] + k2.eval(tdd) * tdd;
                p[k] = pred;
                q[k] = log.omega_dph[i] - pred;
                if recount[s] {
                    out[s + 1] += usize::from(cal.is_outside(t, td, tdd, regime));
                }
            }
            out
        })
        .reduce(|| [0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
    for s in 0..2 {
        if changed[s] {
            base.k1[s] = Some(approx[s].0.clone());
        }
    }
    for s in 0..2 {
        if recount[s] {
            c.outside_by_regime[s + 1] = counts[s + 1];
        }
    }
    c.update_outside_fraction();
}

/// [`signal::moving_average_centered`] into `out`, with the same arithmetic (so the same
/// bits), reusing `out` and the scratch `prefix`; the averages are taken in parallel.
fn moving_average_centered_into(
    x: &[f64],
    window: usize,
    prefix: &mut Vec<f64>,
    out: &mut Vec<f64>,
) {
    let n = x.len();
    if window <= 1 || n == 0 {
        out.clear();
        out.extend_from_slice(x);
        return;
    }
    let back = (window - 1) / 2;
    let ahead = window / 2;
    let origin = x[0];
    prefix.clear();
    prefix.reserve(n + 1);
    prefix.push(0.0);
    let mut s = 0.0;
    for &v in x {
        s += v - origin;
        prefix.push(s);
    }
    if out.len() != n {
        out.clear();
        out.resize(n, 0.0);
    }
    const CHUNK: usize = 1 << 15;
    let prefix = &prefix[..];
    // Samples whose whole window lies inside the log: the divisor is the window itself.
    let (full_lo, full_hi) = (back, n.saturating_sub(ahead));
    let w = window as f64;
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
        let base = c * CHUNK;
        let (a, b) = (
            full_lo.clamp(base, base + o.len()),
            full_hi.clamp(base, base + o.len()),
        );
        if a < b {
            let (lo_p, hi_p) = (
                &prefix[a - back..b - back],
                &prefix[a + ahead + 1..b + ahead + 1],
            );
            for ((v, &h), &l) in o[a - base..b - base].iter_mut().zip(hi_p).zip(lo_p) {
                *v = origin + (h - l) / w;
            }
        }
        // The rest (none unless the chunk reaches an end of the log): shrunk windows.
        let end = base + o.len();
        let (a, b) = if a < b { (a, b) } else { (end, end) };
        for i in (base..a).chain(b..end) {
            let v = &mut o[i - base];
            let lo = i.saturating_sub(back);
            let hi = (i + ahead).min(n - 1);
            *v = origin + (prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo) as f64;
        }
    });
}

/// The plateaus the engine's detector finds on a log with the recipe's filters, for
/// "Suggest plateaus" (whatever the recipe's own plateau choice is).
pub fn suggest_plateaus(log: &Log, prepared: &Prepared) -> Vec<PlateauRange> {
    let auto = Recipe {
        plateaus: crate::recipe::PlateauChoice::default(),
        ..Recipe::default()
    };
    model::plateau_ranges(log, prepared, &auto)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::approx::ApproxKind;

    fn sample_log() -> Arc<Log> {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
        Arc::new(crate::ingest::read_path(&path, &Default::default()).expect("sample log reads"))
    }

    fn request(log: &Arc<Log>, recipe: Recipe) -> Request {
        Request {
            log: log.clone(),
            merit: MeritOptions {
                filter_s: recipe.filter_s,
                ..MeritOptions::default()
            },
            recipe,
            knots: KnotEdits::default(),
            validation: None,
        }
    }

    fn same(a: &Calibration, b: &Calibration) {
        let strip = |c: &Calibration| Calibration {
            created: String::new(),
            ..c.clone()
        };
        assert_eq!(strip(a), strip(b));
    }

    #[test]
    fn staged_fit_is_the_engines_fit() {
        let log = sample_log();
        let mut recipe = Recipe {
            k1_plus: ApproxSpec {
                kind: ApproxKind::Spline,
                knots: 6,
                extrapolate: false,
            },
            ..Recipe::default()
        };
        let mut p = Pipeline::new();
        let out = p.run(&request(&log, recipe.clone())).unwrap();
        let fit = model::fit(&log, &recipe).unwrap();
        same(&out.calibration, &fit.calibration);
        assert_eq!(*out.k1_plus_points, fit.k1_plus_points);
        assert_eq!(*out.k2_minus_points, fit.k2_minus_points);
        assert_eq!(out.warnings, fit.warnings);

        // The correction and figures are the engine's too.
        let c = fit.calibration.correct_with(&log, &fit.prepared.deriv);
        assert_eq!(out.in_sample.corrected.cor_dph, c.cor_dph);
        assert_eq!(out.in_sample.corrected.regime, c.regime);
        assert_eq!(out.in_sample.corrected.outside_fraction, c.outside_fraction);
        let e = Evaluation::of_correction(&log, &c, &request(&log, recipe.clone()).merit);
        assert_eq!(out.in_sample.evaluation, e);

        // A change of K1− only refits the − set, and still equals a fit from scratch; its
        // correction (only the − samples recomputed) equals a whole one.
        recipe.k1_minus.kind = ApproxKind::Parabolic;
        let out2 = p.run(&request(&log, recipe.clone())).unwrap();
        let whole = out2.calibration.correct_with(&log, &out2.prepared.deriv);
        assert_eq!(out2.in_sample.corrected.cor_dph, whole.cor_dph);
        assert_eq!(out2.in_sample.corrected.pred_dph, whole.pred_dph);
        assert_eq!(
            out2.in_sample.corrected.outside_fraction,
            whole.outside_fraction
        );
        assert_eq!(out2.timings.prepare_ms, 0.0);
        assert_eq!(out2.timings.plateaus_ms, 0.0);
        assert!(Arc::ptr_eq(&out.k1_plus_points, &out2.k1_plus_points));
        let fit2 = model::fit(&log, &recipe).unwrap();
        same(&out2.calibration, &fit2.calibration);
    }

    #[test]
    fn a_k2_kind_change_with_the_kept_first_k1_is_the_engines_fit() {
        // The + set refits from the first pass's K1 kept from the run before; the − set and
        // the kept K1 of other specs must not leak in either.
        let log = sample_log();
        let mut recipe = Recipe::default();
        let mut p = Pipeline::new();
        p.run(&request(&log, recipe.clone())).unwrap();
        for (kind, k1_minus) in [
            (ApproxKind::Parabolic, ApproxKind::Linear),
            (ApproxKind::Pwl, ApproxKind::Linear),
            (ApproxKind::Linear, ApproxKind::Parabolic),
            (ApproxKind::Spline, ApproxKind::Parabolic),
        ] {
            recipe.k2_plus.kind = kind;
            recipe.k1_minus.kind = k1_minus;
            let req = request(&log, recipe.clone());
            let out = p.run(&req).unwrap();
            let fit = model::fit(&log, &recipe).unwrap();
            same(&out.calibration, &fit.calibration);
            assert_eq!(*out.k1_plus_points, fit.k1_plus_points);
            assert_eq!(*out.k2_plus_points, fit.k2_plus_points);
            assert_eq!(*out.k2_minus_points, fit.k2_minus_points);
            assert_eq!(out.warnings, fit.warnings);
            judged_afresh(&log, &req, &out);
        }
    }

    #[test]
    fn hand_set_knots_replace_the_fitted_ones_and_k2_follows() {
        let log = sample_log();
        let recipe = Recipe {
            k1_plus: ApproxSpec {
                kind: ApproxKind::Pwl,
                knots: 4,
                extrapolate: false,
            },
            ..Recipe::default()
        };
        let mut p = Pipeline::new();
        let out = p.run(&request(&log, recipe.clone())).unwrap();
        let mut values = out.calibration.k1_plus.knots().1.to_vec();
        values[1] += 50.0;
        let mut req = request(&log, recipe);
        req.knots.k1_plus = Some(values.clone());
        let out2 = p.run(&req).unwrap();
        assert_eq!(out2.calibration.k1_plus.knots().1, &values[..]);
        assert_ne!(out2.calibration.k2_plus, out.calibration.k2_plus);
        assert_eq!(out2.calibration.k1_minus, out.calibration.k1_minus);
        // A list of the wrong length is ignored.
        req.knots.k1_plus = Some(vec![1.0; 3]);
        let out3 = p.run(&req).unwrap();
        assert_eq!(out3.calibration.k1_plus, out.calibration.k1_plus);
    }

    /// The correction, figures and display series of `out` are the engine's, made afresh.
    fn judged_afresh(log: &Arc<Log>, req: &Request, out: &Outcome) {
        let c = out.calibration.correct_with(log, &out.prepared.deriv);
        let got = &out.in_sample.corrected;
        assert_eq!(got.pred_dph, c.pred_dph);
        assert_eq!(got.cor_dph, c.cor_dph);
        assert_eq!(got.regime, c.regime);
        assert_eq!(got.outside_by_regime, c.outside_by_regime);
        assert_eq!(got.outside_fraction, c.outside_fraction);
        assert_eq!(got.ready_from, c.ready_from);
        assert_eq!(
            out.in_sample.evaluation,
            Evaluation::of_correction(log, &c, &req.merit)
        );
        let filter = signal::seconds_to_samples(req.merit.filter_s, out.prepared.dt_s).max(1);
        assert_eq!(
            *out.in_sample.cor_filtered_dph,
            signal::moving_average_centered(&c.cor_dph, filter)
        );
    }

    #[test]
    fn reused_buffers_give_a_fresh_correction() {
        let log = sample_log();
        let base = Recipe {
            k1_plus: ApproxSpec::of(ApproxKind::Pwl),
            k2_plus: ApproxSpec::of(ApproxKind::Pwl),
            k2_minus: ApproxSpec::of(ApproxKind::Pwl),
            ..Recipe::default()
        };
        let mut p = Pipeline::new();
        let first = request(&log, base.clone());
        let out = p.run(&first).unwrap();
        judged_afresh(&log, &first, &out);
        let k1p = out.calibration.k1_plus.knots().1.to_vec();
        let k2m = out.calibration.k2_minus.knots().1.to_vec();
        // A sequence of edits touching one set, the other, both, K0 and nothing; each outcome
        // is kept for a while (the UI holds it) or dropped at once (its buffers are reused).
        let mut reqs = Vec::new();
        for j in 0..6 {
            let mut r = request(&log, base.clone());
            let mut v = k1p.clone();
            v[1] += 10.0 * j as f64;
            r.knots.k1_plus = Some(v);
            if j % 2 == 1 {
                let mut v = k2m.clone();
                v[0] -= 3.0 * j as f64;
                r.knots.k2_minus = Some(v);
            }
            reqs.push(r);
        }
        let mut other = request(&log, base.clone());
        other.recipe.k2_minus.kind = ApproxKind::Parabolic;
        reqs.push(other.clone());
        reqs.push(other);
        let mut k0 = request(&log, base.clone());
        k0.recipe.k0.kind = ApproxKind::Linear;
        reqs.push(k0);
        reqs.push(first.clone());
        let mut merit = first.clone();
        merit.merit.window_s = 300.0;
        reqs.push(merit);
        let mut held: Vec<(Request, Outcome)> = Vec::new();
        for (j, r) in reqs.iter().enumerate() {
            let out = p.run(r).unwrap();
            judged_afresh(&log, r, &out);
            // Held outcomes are never written to by later runs.
            for (hr, h) in &held {
                judged_afresh(&log, hr, h);
            }
            if j % 3 != 0 {
                held.push((r.clone(), out));
            }
            if held.len() > 2 {
                held.remove(0);
            }
        }
        // A free buffer made with another K0 while the UI holds the one to patch: copied into.
        held.clear();
        let k0 = &reqs[8];
        judged_afresh(&log, k0, &p.run(k0).unwrap());
        let kept = p.run(&first).unwrap();
        let edit = &reqs[3];
        let out = p.run(edit).unwrap();
        judged_afresh(&log, edit, &out);
        judged_afresh(&log, &first, &kept);
    }

    #[test]
    fn knot_edits_follow_with_the_engines_k2_points() {
        let log = sample_log();
        let recipe = Recipe {
            k1_minus: ApproxSpec::of(ApproxKind::Pwl),
            refinements: 2,
            ..Recipe::default()
        };
        let mut p = Pipeline::new();
        let req = request(&log, recipe.clone());
        let out = p.run(&req).unwrap();
        let fit = model::fit(&log, &recipe).unwrap();
        same(&out.calibration, &fit.calibration);
        assert_eq!(*out.k1_minus_points, fit.k1_minus_points);
        assert_eq!(*out.k2_plus_points, fit.k2_plus_points);
        let mut values = out.calibration.k1_minus.knots().1.to_vec();
        values[2] -= 20.0;
        let mut req = request(&log, recipe.clone());
        req.knots.k1_minus = Some(values);
        let out2 = p.run(&req).unwrap();
        judged_afresh(&log, &req, &out2);
        let mask = model::plateau_mask(&log.time_s, &out2.ranges);
        let (_, db2) = model::deadbands(&out2.prepared, &mask, &recipe);
        let p2 = model::k2_points(
            &log,
            &out2.prepared,
            &mask,
            &out2.calibration.k0,
            &out2.calibration.k1_minus,
            db2,
            Regime::Minus,
        );
        assert_eq!(*out2.k2_minus_points, p2);
        let mut w = Vec::new();
        let k2 = model::fit_points("K2-", &recipe.k2_minus, &p2, recipe.weighting, &mut w);
        assert_eq!(out2.calibration.k2_minus, k2);
    }
}
