//! The workbench's live refit: a calibration as a pure function of (log, recipe), the knots
//! placed and set by hand among the recipe's choices, run in stages with each stage's result
//! kept until its inputs change.
//!
//! The fit is the one Vakhrameev pipeline: the T stages as [`vakhrameev::Pipeline`] runs them,
//! then the Ω stages through [`StageMemory::run`], the very function a batch fit calls, here
//! with a memory kept between runs (a batch fit starts from an empty one). So the result is the
//! batch fit's calibration, bit for bit (a test holds them equal). What this module adds is the
//! memory around the fit and what the window shows of it:
//!
//! * [`Prepared`] (filtered Ω, Ṫ, T̈) is kept while the filter, smoothing and step stay;
//! * the plateau ranges while the signals and the plateau choice stay;
//! * in the stage memory: the plateau statistics, dead-bands and the sets' sample indices
//!   while the plateaus and the dead-band settings stay; `Ω_f − K0(T)` while K0 stays; each set
//!   (+ and −) of K1/K2 while its inputs (K0, dead-bands, its two approximations) stay, so
//!   changing K1+ refits only the + set; each set's first-pass K1 while only its K2 changes;
//! * the raw figures of merit and the validation log's derivatives while they stay;
//! * each regime's samples with `K0(T)` and `K1(Ṫ)·Ṫ` per sample (`terms.rs`), so that a
//!   patch of the correction walks only the samples of the set that changed, and a K2 edit
//!   re-evaluates K2 alone.
//!
//! The files: this one holds the run in order; `cache.rs` what is kept and under which key;
//! `correction.rs` the kept corrections and their buffers; `preview.rs` what a plateau edge
//! drag shows before its release; `terms.rs` the patch over one
//! regime's samples; `evaluate.rs` the figures of merit and the validation log; `average.rs`
//! the display series' centred moving average; `plateaus.rs` the plateau ranges and "Suggest
//! plateaus".
//!
//! Knot values set by hand (`ApproxSpec::values`) replace the fitted knot values of their
//! approximation; a hand-edited K1 is followed by a fresh K2 fit on what it leaves (unless K2's
//! knots are set by hand too), as the paper's K2 step asks. Knots placed by hand
//! (`ApproxSpec::at`) are where the set's fit puts them: moving one refits its set.
//!
//! The correction is made from the kept derivatives ([`Calibration::correct_into`], or a patch
//! of the samples of the sets that changed); it equals
//! [`Calibration::correct_with`](crate::models::vakhrameev::Calibration) sample for sample.

mod average;
mod cache;
mod correction;
mod evaluate;
mod plateaus;
mod preview;
mod same;
mod terms;
#[cfg(test)]
mod tests;
mod unit;

pub use plateaus::suggest_plateaus;
pub use preview::{PlateauPreview, preview_plateaus};
pub use same::Same;
pub use unit::{run_unit, run_unit_each};

use crate::error::Error;
use crate::files::session::Coefficient;
use crate::judge::metrics::{Comparison, Evaluation, Figures, MeritOptions};
use crate::log::Log;
use crate::models::approx::Approx;
use crate::models::recipe::{PlateauChoice, Recipe};
use crate::models::vakhrameev::{
    self, Calibration, PointSet, Prepared, Regime, StageInputs, StageMemory,
};
use crate::signal::plateau::{self, PlateauRange};
use crate::signal::{self, DerivativeSteps, Derivatives};
use cache::*;
use correction::CorrectionBuf;
use evaluate::evaluation;
use rayon::prelude::*;
use std::borrow::Cow;
use std::sync::Arc;
use std::time::Instant;
use terms::Terms;

/// What to fit.
#[derive(Debug, Clone)]
pub struct Request {
    /// The calibration log.
    pub log: Arc<Log>,
    /// Every choice, the knots placed and set by hand among them.
    pub recipe: Recipe,
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
    /// Corrected Ω filtered alike within the correction's ready stretches (no window reaches
    /// into a segment's warm-up, where the correction is no reading; outside them the
    /// corrected rate as it is, which the workbench does not draw), °/h (shared: kept while
    /// the correction stays). The workbench draws this series: it does not filter again.
    pub cor_filtered_dph: Arc<Vec<f64>>,
    /// Raw against corrected on each run of a campaign on its own, in run order; empty for a
    /// log of one run.
    pub per_run: Vec<Comparison>,
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
    /// A campaign's runs as the calibration records them (each run's plateaus among
    /// `ranges`, with this axis's bias), at the default tolerance; empty for a log of one run,
    /// or when a run has no plateau (said in `warnings`).
    pub runs: Vec<crate::models::campaign::RunRecord>,
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

/// A run up to its calibration ([`Pipeline::fit_part`]), before its correction.
struct Fitted {
    calibration: Calibration,
    prepared: Arc<Prepared>,
    ranges: Vec<PlateauRange>,
    /// K1+, K1−, K2+, K2− points.
    points: [Arc<PointSet>; 4],
    warnings: Vec<String>,
    timings: Timings,
    /// When the run began.
    t_all: Instant,
}

/// A run before its Ω stages ([`Pipeline::fit_inputs`]).
struct FitInputs {
    prepared: Arc<Prepared>,
    ranges: Vec<PlateauRange>,
    timings: Timings,
    t_all: Instant,
}

impl FitInputs {
    /// The run up to its calibration, with what its Ω stages made.
    fn fitted(self, staged: vakhrameev::Staged) -> Fitted {
        let FitInputs {
            prepared,
            ranges,
            mut timings,
            t_all,
        } = self;
        timings.plateaus_ms = staged.plateaus_ms;
        timings.fit_ms = staged.fit_ms;
        Fitted {
            calibration: staged.calibration,
            prepared,
            ranges,
            points: staged.points,
            warnings: staged.warnings,
            timings,
            t_all,
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
    /// The Ω stages (plateau statistics, the sets' samples, `Ω_f − K0(T)`, each set's fit and
    /// first-pass K1), kept while their inputs stay.
    stages: StageMemory<Same<Prepared>>,
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
    /// Each regime's samples with `K0(T)` and `K1(Ṫ)·Ṫ` kept, for patching a correction.
    terms: Terms,
    /// The plateau ranges of the last run, with the signals and plateau choice they came from.
    ranges: Option<(Same<Prepared>, PlateauChoice, Vec<PlateauRange>)>,
    /// The log as calibrations record it (its samples' sketch reads every sample), kept while
    /// the log stays.
    source: Option<(Same<Log>, vakhrameev::SourceInfo)>,
    /// This pipeline's signals and another axis's found to hold the same T
    /// ([`Pipeline::share_t_stages`]).
    t_twin: Option<unit::TwinKey>,
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
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
        let mut fitted = self.fit_part(req)?;
        let t = Instant::now();
        let corrected = self.correct_kept(&fitted.calibration, &req.log, &fitted.prepared);
        fitted.timings.correct_ms = ms(t);
        Ok(self.judge_part(req, fitted, corrected))
    }

    /// The stages up to the calibration: the signals, the plateaus, K0 and the sets' fits.
    fn fit_part(&mut self, req: &Request) -> Result<Fitted, Error> {
        let pre = self.fit_inputs(req)?;
        let staged = self.stages.run(StageInputs {
            log: &req.log,
            signals: Same::of(&pre.prepared),
            prepared: &pre.prepared,
            omega_filtered_dph: Cow::Borrowed(&pre.prepared.omega_filtered_dph),
            ranges: &pre.ranges,
            recipe: &req.recipe,
            points: true,
            source: self.source.as_ref().map(|(_, s)| s),
        })?;
        Ok(pre.fitted(staged))
    }

    /// The stages before the Ω stages: the checks, the signals, the plateau ranges and the log
    /// as calibrations record it.
    fn fit_inputs(&mut self, req: &Request) -> Result<FitInputs, Error> {
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

        let ranges = self.plateau_ranges(log, &prepared, recipe);
        if self.source.as_ref().is_none_or(|(l, _)| !l.is(log)) {
            self.source = Some((Same::of(log), vakhrameev::SourceInfo::of(log)));
        }
        Ok(FitInputs {
            prepared,
            ranges,
            timings,
            t_all,
        })
    }

    /// The stages after the correction: the figures of merit, the display series and the
    /// validation log.
    fn judge_part(&mut self, req: &Request, fitted: Fitted, corrected: Arc<Correction>) -> Outcome {
        let Fitted {
            calibration,
            prepared,
            ranges,
            points:
                [
                    k1_plus_points,
                    k1_minus_points,
                    k2_plus_points,
                    k2_minus_points,
                ],
            mut warnings,
            mut timings,
            t_all,
        } = fitted;
        let log = &req.log;
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
        let evaluation = evaluation(raw_figures, cor_figures, &corrected, &calibration);
        // The warning the command line gives for a calibration worse than raw on its own log.
        warnings.extend(crate::models::worse_than_raw("vakhrameev", &evaluation));
        let per_run = Comparison::of_runs(log, &corrected.cor_dph, &corrected.ready, &merit);
        let in_sample = Judged {
            log: log.clone(),
            per_run,
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
        if log.runs().len() > 1 {
            let across = crate::models::campaign::run_of_each(log, &ranges)
                .iter()
                .filter(|r| r.is_none())
                .count();
            if across > 0 {
                warnings.push(format!(
                    "{across} plateau{} placed across the end of a run: a plateau of neither \
                     run, its samples from both; move it within one run",
                    if across == 1 { " is" } else { "s are" }
                ));
            }
        }
        let runs = match crate::models::campaign::run_records(
            log,
            "",
            &ranges,
            &crate::models::campaign::CampaignOptions::default(),
        ) {
            Ok(r) => r,
            Err(e) => {
                warnings.push(e.to_string());
                Vec::new()
            }
        };
        timings.total_ms = ms(t_all);
        Outcome {
            runs,
            calibration,
            prepared,
            ranges,
            k1_plus_points,
            k1_minus_points,
            k2_plus_points,
            k2_minus_points,
            warnings,
            in_sample,
            held_out,
            timings,
        }
    }
}
