//! Several models fitted on one log and judged side by side on it (in-sample) and on other
//! logs of the same gyro (held out) — what tells an engineer which model to ship.

use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::judge::runs_left_out::{LeaveOneRunOut, leave_one_run_out};
use crate::log::Log;
use crate::log::run_sketch::Shared;
use crate::models::fitted::DriftModel;
use crate::models::presets::ModelChoice;
use crate::models::recipe::CheckedRecipe;
use crate::models::vakhrameev::correct::Correction;
use rayon::prelude::*;
use serde::Serialize;

/// One model judged on one log.
#[derive(Debug, Clone, Serialize)]
pub struct Judgement {
    /// The log's name.
    pub log: String,
    /// False for the log the model was fitted on, also when it is passed again as a test log
    /// (the same samples, under any name): figures on it are in-sample. False too when the
    /// training log's sketch cannot tell (`cannot_tell`): such figures are no held-out
    /// evidence.
    pub held_out: bool,
    /// Why the training log's sketch cannot tell whether this log is the training run (too
    /// few of its values compared, a column written coarser than the training log's); `None`
    /// when it tells.
    pub cannot_tell: Option<String>,
    /// The figures, or why the model could not be applied to this log.
    #[serde(flatten)]
    pub result: Outcome,
}

impl Judgement {
    /// What the figures on this log are, in the words every face uses: "in-sample", "held
    /// out" or "cannot tell" ([`crate::judge::verify::sample_kind`]'s words).
    pub fn kind(&self) -> &'static str {
        match (self.held_out, &self.cannot_tell) {
            (_, Some(_)) => "cannot tell",
            (true, None) => "held out",
            (false, None) => "in-sample",
        }
    }
}

/// Figures of merit, or an error message.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Raw against corrected.
    Evaluation(Evaluation),
    /// Why there are no figures.
    Error(String),
}

/// One model: how it was fitted and how it did on every log.
#[derive(Debug, Clone, Serialize)]
pub struct ModelReport {
    /// The model's name.
    pub model: String,
    /// What the model is.
    pub description: String,
    /// Whether it is a reference row, a firmware script's own fit shown beside driftlab's
    /// models (`px4-script`, `ardupilot-script`), rather than a model driftlab recommends.
    pub reference: bool,
    /// The fit's error, when it failed (then `logs` is empty).
    pub error: Option<String>,
    /// The fitted model (not serialised here: calibration files hold it).
    #[serde(skip)]
    pub fitted: Option<DriftModel>,
    /// The training log first, then the test logs in order.
    pub logs: Vec<Judgement>,
    /// On a campaign, the model judged on each run left out in turn (fitted on the others);
    /// `None` for a training log of one run, or a model that was not fitted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub leave_one_run_out: Option<LeaveOneRunOut>,
}

/// Fits every choice on `train` and judges it on `train` and on each of `tests`.
pub fn compare(
    train: &Log,
    tests: &[Log],
    choices: &[ModelChoice],
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
) -> Vec<ModelReport> {
    compare_telling(train, tests, choices, recipe, merit, &|| {})
}

/// [`compare`], calling `model_done` as each model is fitted and judged (a face's progress:
/// on a campaign each model is fitted once more per run, so a comparison of many runs takes
/// long).
pub fn compare_telling(
    train: &Log,
    tests: &[Log],
    choices: &[ModelChoice],
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    model_done: &(dyn Fn() + Sync),
) -> Vec<ModelReport> {
    let tests = tests_of(train, &tests.iter().collect::<Vec<_>>());
    choices
        .par_iter()
        .map(|choice| {
            let report = compare_one(
                train,
                &tests,
                choice,
                recipe,
                merit,
                &|_| true,
                &mut |_, _| {},
            );
            model_done();
            report
        })
        .collect()
}

/// A test log of a comparison, with how much of it is the training run.
#[derive(Debug, Clone, Copy)]
pub struct TestLog<'a> {
    /// The log.
    pub log: &'a Log,
    /// How much of it is the training run, by the training log's sketch.
    pub run: Shared,
}

/// The test logs of a comparison, each told against the training log's sketch (once for every
/// model compared).
pub fn tests_of<'a>(train: &Log, tests: &[&'a Log]) -> Vec<TestLog<'a>> {
    tests
        .par_iter()
        .map(|&log| TestLog {
            log,
            run: train.run_shared(log),
        })
        .collect()
}

/// One model of [`compare`]: fitted on `train`, judged on `train` then each of `tests`, and,
/// when `train` is a campaign, on each of its runs left out in turn
/// ([`crate::judge::runs_left_out`]).
/// `progress` is told the share of the fit done (0 to 1) and stops it by returning false (the
/// report then holds the error "cancelled"); `seen(k, correction)` gets each log's correction
/// (log `k`, the training log first) before it is dropped, for a caller that also draws them.
pub fn compare_one(
    train: &Log,
    tests: &[TestLog],
    choice: &ModelChoice,
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
    seen: &mut dyn FnMut(usize, &Correction),
) -> ModelReport {
    let mut report = ModelReport {
        model: choice.name(),
        description: choice.describe(),
        reference: choice.is_reference(),
        error: None,
        fitted: None,
        logs: Vec::new(),
        leave_one_run_out: None,
    };
    match crate::models::fit_with_progress(train, choice, recipe, progress) {
        Ok(m) => {
            let told = |s: Option<&Shared>| match s {
                None => (false, None),
                Some(s) => match s.cannot_tell() {
                    Some(why) => (false, Some(why)),
                    None => (!s.in_sample(), None),
                },
            };
            report.logs = std::iter::once((train, told(None)))
                .chain(tests.iter().map(|t| (t.log, told(Some(&t.run)))))
                .enumerate()
                .map(|(k, (log, (held_out, cannot_tell)))| Judgement {
                    log: log.source.clone(),
                    held_out,
                    cannot_tell,
                    result: match crate::models::check_axis_readings(log)
                        .and_then(|()| m.correct(log))
                    {
                        Ok(c) => {
                            seen(k, &c);
                            Outcome::Evaluation(
                                Evaluation::of_correction(log, &c, merit).of_model(&m),
                            )
                        }
                        Err(e) => Outcome::Error(e.to_string()),
                    },
                })
                .collect();
            report.fitted = Some(m);
            // The fit is done: a Cancel asked now stops the runs left out.
            report.leave_one_run_out =
                leave_one_run_out(train, choice, recipe, merit, &|| progress(1.0));
        }
        Err(e) => report.error = Some(e.to_string()),
    }
    report
}
