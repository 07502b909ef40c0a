//! The workbench's live refit: a calibration as a pure function of (log, recipe, knots moved by
//! hand), run in stages with each stage's result kept until its inputs change.
//!
//! The stages are those of [`model::fit_prepared`](crate::model::fit_prepared), called through
//! the same public stage functions, so the result is the same calibration (a test holds them
//! equal). What this adds is memory between calls:
//!
//! * [`Prepared`] (filtered Ω, Ṫ, T̈) is kept while the filter, smoothing and step stay;
//! * the plateau mask, statistics and dead-bands while the plateaus stay;
//! * each set (+ and −) of K1/K2 while its inputs (K0, dead-bands, its two approximations,
//!   its hand-set knots) stay — changing K1+ refits only the + set;
//! * the raw figures of merit and the validation log's derivatives while they stay.
//!
//! Knots set by hand ([`KnotEdits`]) replace the fitted knot values of their approximation;
//! a hand-edited K1 is followed by a fresh K2 fit on what it leaves (unless K2's knots are
//! set by hand too), as the paper's K2 step asks.
//!
//! The correction is made from the kept derivatives by reference ([`correct`]); it equals
//! [`Calibration::correct_with`](crate::model::Calibration) sample for sample.

use crate::approx::{Approx, ApproxSpec};
use crate::log::Log;
use crate::metrics::{Comparison, Evaluation, Figures, MeritOptions};
use crate::model::{self, Calibration, PointSet, Prepared, Regime};
use crate::plateau::{PlateauRange, PlateauStats};
use crate::recipe::{Recipe, Weighting};
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
    /// The correction (shared: the next refit patches a copy of it).
    pub corrected: Arc<Corrected>,
    /// Raw against corrected.
    pub evaluation: Evaluation,
    /// Ω filtered as for the figures (centred moving average), °/h.
    pub raw_filtered_dph: Arc<Vec<f64>>,
    /// Corrected Ω filtered alike, °/h.
    pub cor_filtered_dph: Vec<f64>,
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
    raw_figures: Option<((usize, usize, MeritOptions), Figures)>,
    raw_filtered: Option<(RawFilteredKey, Arc<Vec<f64>>)>,
    validation: Option<ValidationCache>,
    correction: Option<CorrectionCache>,
}

/// The last correction of the calibration log and what it was made with, so that a change
/// of one set's approximations recomputes only that set's samples.
struct CorrectionCache {
    log: usize,
    prepared: usize,
    k0: Approx,
    sets: [(Approx, Approx); 2],
    corrected: Arc<Corrected>,
    /// Samples outside the calibrated ranges, per regime (static, +, −).
    outside: [usize; 3],
    /// Indices of the + and − samples.
    index: Arc<[Vec<u32>; 2]>,
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
        let ranges = model::plateau_ranges(log, &prepared, recipe);
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
        let fitted: Vec<(usize, SetFit)> = todo
            .par_iter()
            .map(|&s| {
                let regime = if s == 0 { Regime::Plus } else { Regime::Minus };
                let fit = fit_set(log, &prepared, &mask, &k0, deadbands, regime, recipe);
                (s, fit)
            })
            .collect();
        for (s, fit) in fitted {
            self.sets[s] = Some((keys[s].clone(), fit));
        }
        if !todo.is_empty() {
            timings.fit_ms = ms(t);
        }
        let t = Instant::now();
        let edited = |s: usize, regime: Regime| {
            self.sets[s].as_ref().map(|(_, fit)| {
                apply_knot_edits(
                    fit, log, &prepared, &mask, &k0, deadbands, regime, recipe, &req.knots,
                )
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
        let (cor_figures, cor_filtered) = rayon::join(
            || {
                crate::metrics::figures(
                    &corrected.cor_dph,
                    prepared.dt_s,
                    corrected.ready_from,
                    &merit,
                )
            },
            || signal::moving_average_centered(&corrected.cor_dph, filter),
        );
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

    /// Corrects the calibration log; when only one set's approximations changed since the last
    /// run, only that set's samples are recomputed (the rest is copied).
    fn correct_kept(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        prepared: &Arc<Prepared>,
    ) -> Arc<Corrected> {
        let sets = [
            (cal.k1_plus.clone(), cal.k2_plus.clone()),
            (cal.k1_minus.clone(), cal.k2_minus.clone()),
        ];
        let reusable = self
            .correction
            .as_ref()
            .filter(|c| c.log == ptr(log) && c.prepared == ptr(prepared) && c.k0 == cal.k0);
        let (corrected, outside, index) = match reusable {
            Some(c) if c.sets == sets => (c.corrected.clone(), c.outside, c.index.clone()),
            Some(c) => {
                let changed = [c.sets[0] != sets[0], c.sets[1] != sets[1]];
                let (corrected, outside) = patch(
                    cal,
                    log,
                    &prepared.deriv,
                    &c.corrected,
                    c.outside,
                    &c.index,
                    changed,
                );
                (Arc::new(corrected), outside, c.index.clone())
            }
            None => {
                let corrected = cal.correct_with(log, &prepared.deriv);
                let outside = corrected.outside_by_regime;
                let index = Arc::new(regime_index(&corrected.regime));
                (Arc::new(corrected), outside, index)
            }
        };
        self.correction = Some(CorrectionCache {
            log: ptr(log),
            prepared: ptr(prepared),
            k0: cal.k0.clone(),
            sets,
            corrected: corrected.clone(),
            outside,
            index,
        });
        corrected
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
        let corrected = cal.correct_with(log, &v.deriv);
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
            corrected: Arc::new(corrected),
            evaluation,
            raw_filtered_dph: v.raw_filtered.clone(),
            cor_filtered_dph: cor_filtered,
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

/// K1 and K2 of one set, by the engine's own per-set fit.
fn fit_set(
    log: &Log,
    prepared: &Prepared,
    mask: &[bool],
    k0: &Approx,
    deadbands: (f64, f64),
    regime: Regime,
    recipe: &Recipe,
) -> SetFit {
    let f = model::fit_set(log, prepared, mask, k0, deadbands, regime, recipe);
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
#[allow(clippy::too_many_arguments)]
fn apply_knot_edits(
    fit: &SetFit,
    log: &Log,
    prepared: &Prepared,
    mask: &[bool],
    k0: &Approx,
    (_, db2): (f64, f64),
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
            let p2 = model::k2_points(log, prepared, mask, k0, &out.k1, db2, regime);
            let mut w = Vec::new();
            out.k2 = model::fit_points(
                &format!("K2{sign}"),
                c2.spec(recipe),
                &p2,
                recipe.weighting,
                &mut w,
            );
            out.p2 = Arc::new(p2);
            out.warnings
                .retain(|m| !m.starts_with(&format!("K2{sign}")));
            out.warnings.extend(w);
        }
    }
    out.k2 = with_knots(&out.k2, knots.get(c2));
    out
}

/// Indices of the + and − samples.
fn regime_index(regime: &[Regime]) -> [Vec<u32>; 2] {
    let mut out = [Vec::new(), Vec::new()];
    for (i, r) in regime.iter().enumerate() {
        match r {
            Regime::Plus => out[0].push(i as u32),
            Regime::Minus => out[1].push(i as u32),
            Regime::Static => {}
        }
    }
    out
}

/// A copy of `prev` with the samples of the `changed` sets recomputed with `cal`.
fn patch(
    cal: &Calibration,
    log: &Log,
    deriv: &Derivatives,
    prev: &Corrected,
    prev_outside: [usize; 3],
    index: &[Vec<u32>; 2],
    changed: [bool; 2],
) -> (Corrected, [usize; 3]) {
    let mut c = prev.clone();
    let mut counts = prev_outside;
    for s in 0..2 {
        if !changed[s] {
            continue;
        }
        let fresh: Vec<(f64, bool)> = index[s]
            .par_iter()
            .map(|&i| {
                let i = i as usize;
                let (t, td, tdd) = (log.temp_c[i], deriv.tdot[i], deriv.tddot[i]);
                let (p, r) = cal.predict(t, td, tdd);
                (p, cal.is_outside(t, td, tdd, r))
            })
            .collect();
        let mut out = 0;
        for (&i, &(p, o)) in index[s].iter().zip(&fresh) {
            let i = i as usize;
            c.pred_dph[i] = p;
            c.cor_dph[i] = log.omega_dph[i] - p;
            out += usize::from(o);
        }
        counts[s + 1] = out;
    }
    c.outside_by_regime = counts;
    c.update_outside_fraction();
    (c, counts)
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
}
