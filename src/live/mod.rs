//! The workbench's live refit: a calibration as a pure function of (log, recipe, knots moved by
//! hand), run in stages with each stage's result kept until its inputs change.
//!
//! The stages are those of [`vakhrameev::Pipeline`], called through the same stage
//! functions in the same order, so the result is the same calibration (a test holds them
//! equal). What this adds is memory between calls:
//!
//! * [`Prepared`] (filtered Ω, Ṫ, T̈) is kept while the filter, smoothing and step stay;
//! * the plateau statistics, dead-bands and the sets' sample indices while the plateaus and
//!   the dead-band settings stay;
//! * each set (+ and −) of K1/K2 while its inputs (K0, dead-bands, its two approximations,
//!   its hand-set knots) stay — changing K1+ refits only the + set;
//! * each set's first-pass K1 (fitted before any K2) while its samples, K0 and K1 spec stay —
//!   changing K2's kind refits one K1 less;
//! * the raw figures of merit and the validation log's derivatives while they stay;
//! * the plateau ranges while the signals and the plateau choice stay;
//! * `Ω_f − K0(T)` while K0 stays;
//! * each regime's samples with `K0(T)` and `K1(Ṫ)·Ṫ` per sample (`terms.rs`), so that a
//!   patch of the correction walks only the samples of the set that changed, and a K2 edit
//!   re-evaluates K2 alone.
//!
//! The files: this one holds the pipeline and its stages in order; `cache.rs` what is kept and
//! under which key; `correction.rs` the kept corrections and their buffers; `terms.rs` the
//! patch over one regime's samples; `sets.rs` each set's fit with hand-set knots; `evaluate.rs`
//! the figures of merit and the validation log; `average.rs` the display series' centred
//! moving average; `plateaus.rs` the plateau ranges and "Suggest plateaus".
//!
//! Knots set by hand ([`KnotEdits`]) replace the fitted knot values of their approximation;
//! a hand-edited K1 is followed by a fresh K2 fit on what it leaves (unless K2's knots are
//! set by hand too), as the paper's K2 step asks.
//!
//! The correction is made from the kept derivatives ([`Calibration::correct_into`], or a patch
//! of the samples of the sets that changed); it equals
//! [`Calibration::correct_with`](crate::models::vakhrameev::Calibration) sample for sample.

mod average;
mod cache;
mod correction;
mod evaluate;
mod plateaus;
mod same;
mod sets;
mod terms;
#[cfg(test)]
mod tests;

pub use plateaus::suggest_plateaus;
pub use same::Same;

use crate::error::Error;
use crate::files::session::{Coefficient, KnotEdits};
use crate::judge::metrics::{Comparison, Evaluation, Figures, MeritOptions};
use crate::log::Log;
use crate::models::approx::{Approx, ApproxSpec};
use crate::models::recipe::{PlateauChoice, Recipe, Weighting};
use crate::models::vakhrameev::{
    self, Calibration, PointSet, Prepared, Regime, SetInputs, SetSamples, SetsOfSamples,
};
use crate::signal::plateau::{self, PlateauRange, PlateauStats};
use crate::signal::{self, DerivativeSteps, Derivatives};
use cache::*;
use correction::CorrectionBuf;
use evaluate::evaluation;
use rayon::prelude::*;
use sets::{apply_knot_edits, fit_set};
use std::sync::Arc;
use std::time::Instant;
use terms::Terms;

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
pub use crate::models::vakhrameev::correct::Correction;

/// The calibration judged on one log.
#[derive(Debug, Clone)]
pub struct Judged {
    /// The log.
    pub log: Arc<Log>,
    /// The correction (shared: the next refit patches it in place once this is dropped, or a
    /// copy of it while it is held).
    pub corrected: Arc<Correction>,
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

/// (log, filter samples) of a kept filtered raw Ω.
type RawFilteredKey = (Same<Log>, usize);

/// (log, first sample judged, merit options) of kept raw figures.
type RawFiguresKey = (Same<Log>, usize, MeritOptions);

/// The staged, caching fitter. Keep one per workbench (it is not shared between threads).
#[derive(Default)]
pub struct Pipeline {
    prepared: Option<(PrepKey, Arc<Prepared>)>,
    plateaus: Option<PlateauStage>,
    sets: [Option<(SetKey, SetFit)>; 2],
    /// Each set's first-pass K1, kept while only its K2 changes.
    first_k1: [Option<(FirstKey, Approx)>; 2],
    raw_figures: Option<(RawFiguresKey, Figures)>,
    raw_filtered: Option<(RawFilteredKey, Arc<Vec<f64>>)>,
    validation: Option<ValidationCache>,
    /// The validation log's last correction, reused in place once the UI has dropped it.
    validation_corrected: Option<Arc<Correction>>,
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
    /// Scratch filtered drift of the figures of merit.
    merit_filtered: Vec<f64>,
    /// The log and signal settings the last run checked (the checks scan the whole log; a
    /// knot dragged changes neither).
    checked: Option<PrepKey>,
    /// `Ω_f − K0(T)` over the calibration log.
    rest: Option<RestCache>,
    /// Each regime's samples with `K0(T)` and `K1(Ṫ)·Ṫ` kept, for patching a correction.
    terms: Terms,
    /// The plateau ranges of the last run, with the signals and plateau choice they came from.
    ranges: Option<(Same<Prepared>, PlateauChoice, Vec<PlateauRange>)>,
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
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
            log: Same::of(log),
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
    pub fn run(&mut self, req: &Request) -> Result<Outcome, Error> {
        let t_all = Instant::now();
        let mut timings = Timings::default();
        let log = &req.log;
        let recipe = &req.recipe;
        recipe.validate()?;
        // The checks every face's fit makes (`models::fit`): settings that fit in this log,
        // and a temperature span the model can be fitted over; once per log and settings.
        let checked = PrepKey {
            log: Same::of(log),
            filter_s: recipe.filter_s,
            smoothing_s: recipe.temp_smoothing_s,
            step_h_s: recipe.step_h_s,
        };
        if self.checked.as_ref() != Some(&checked) {
            recipe.check_against(log)?;
            crate::models::check_span(
                log,
                &crate::models::ModelChoice::Preset(crate::models::Preset::Vakhrameev),
            )?;
            self.checked = Some(checked);
        }
        vakhrameev::check_sample_count(log)?;

        let t = Instant::now();
        let (prepared, reused) = self.prepared(log, recipe);
        if !reused {
            timings.prepare_ms = ms(t);
        }

        let t = Instant::now();
        let ranges = self.plateau_ranges(log, &prepared, recipe);
        let pkey = PlateauKey {
            prepared: Same::of(&prepared),
            ranges: ranges.clone(),
            deadband_tdot: recipe.deadband_tdot,
            deadband_tddot: recipe.deadband_tddot,
        };
        if self.plateaus.as_ref().is_none_or(|s| s.key != pkey) {
            let stats = plateau::stats_of(&log.time_s, &log.temp_c, &log.omega_dph, &ranges);
            let sets = vakhrameev::sets_of_samples(&log.time_s, &prepared, &ranges, recipe);
            self.plateaus = Some(PlateauStage {
                key: pkey.clone(),
                stats,
                sets: Arc::new(sets),
            });
            timings.plateaus_ms = ms(t);
        }
        let stage = self
            .plateaus
            .as_ref()
            .ok_or(Error::Internal("the plateau stage is missing"))?;
        let mut warnings = Vec::new();
        let k0 = vakhrameev::fit_k0(&stage.stats, &recipe.k0, &mut warnings)?;
        let k0 = with_knots(&k0, req.knots.get(Coefficient::K0));
        let stats = stage.stats.clone();
        let sets = stage.sets.clone();
        let deadbands = sets.deadbands;

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
        let rest = if !todo.is_empty() || !req.knots.is_empty() {
            Some(self.kept_rest(&prepared, &k0, &log.temp_c))
        } else {
            None
        };
        let samples = &sets.samples;
        let fitted: Vec<(usize, SetFit)> = match &rest {
            Some(rest) => {
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
                                vakhrameev::first_k1(&samples[s], inputs, regime, recipe)
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
            self.sets[s].as_ref().map(|(_, fit)| match &rest {
                Some(rest) => {
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
        let plus = edited(0, Regime::Plus).ok_or(Error::Internal("the + set is missing"))?;
        let minus = edited(1, Regime::Minus).ok_or(Error::Internal("the − set is missing"))?;
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
        let raw_key = (Same::of(log), corrected.ready_from, merit);
        let raw_figures = match &self.raw_figures {
            Some((k, f)) if *k == raw_key => *f,
            _ => {
                let f = crate::judge::metrics::figures_over(
                    &log.omega_dph,
                    prepared.dt_s,
                    &corrected.ready,
                    &merit,
                );
                self.raw_figures = Some((raw_key, f));
                f
            }
        };
        let filter = signal::seconds_to_samples(merit.filter_s, prepared.dt_s).max(1);
        let raw_filtered = match &self.raw_filtered {
            Some((k, f)) if *k == (Same::of(log), filter) => f.clone(),
            _ => {
                let f = Arc::new(signal::moving_average_centered_in(
                    &log.omega_dph,
                    filter,
                    &prepared.segments,
                ));
                self.raw_filtered = Some(((Same::of(log), filter), f.clone()));
                f
            }
        };
        let (cor_figures, cor_filtered) =
            self.evaluate_kept(&corrected, prepared.dt_s, &merit, filter);
        let evaluation = evaluation(raw_figures, cor_figures, &corrected);
        // The warning the command line gives for a calibration worse than raw on its own log.
        warnings.extend(crate::models::worse_than_raw("vakhrameev", &evaluation));
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

    /// `Ω_f − K0(T)`, kept while the filtered Ω and K0 stay.
    fn kept_rest(
        &mut self,
        prepared: &Arc<Prepared>,
        k0: &Approx,
        temp_c: &[f64],
    ) -> Arc<Vec<f64>> {
        match &self.rest {
            Some(c) if c.prepared == Same::of(prepared) && c.k0 == *k0 => c.rest.clone(),
            _ => {
                let rest = Arc::new(vakhrameev::rest_dph(
                    &prepared.omega_filtered_dph,
                    temp_c,
                    k0,
                ));
                self.rest = Some(RestCache {
                    prepared: Same::of(prepared),
                    k0: k0.clone(),
                    rest: rest.clone(),
                });
                rest
            }
        }
    }
}
