//! Several models fitted on one log and judged side by side on it (in-sample) and on other
//! logs of the same gyro (held out) — what tells an engineer which model to ship.

use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::Log;
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
    /// (the same samples, under any name): figures on it are in-sample.
    pub held_out: bool,
    /// The figures, or why the model could not be applied to this log.
    #[serde(flatten)]
    pub result: Outcome,
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
    /// The fit's error, when it failed (then `logs` is empty).
    pub error: Option<String>,
    /// The fitted model (not serialised here: calibration files hold it).
    #[serde(skip)]
    pub fitted: Option<DriftModel>,
    /// The training log first, then the test logs in order.
    pub logs: Vec<Judgement>,
}

/// Fits every choice on `train` and judges it on `train` and on each of `tests`.
pub fn compare(
    train: &Log,
    tests: &[Log],
    choices: &[ModelChoice],
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
) -> Vec<ModelReport> {
    let tests: Vec<&Log> = tests.iter().collect();
    choices
        .par_iter()
        .map(|choice| {
            compare_one(
                train,
                &tests,
                choice,
                recipe,
                merit,
                &|_| true,
                &mut |_, _| {},
            )
        })
        .collect()
}

/// One model of [`compare`]: fitted on `train`, judged on `train` then each of `tests`.
/// `progress` is told the share of the fit done (0 to 1) and stops it by returning false (the
/// report then holds the error "cancelled"); `seen(k, correction)` gets each log's correction
/// (log `k`, the training log first) before it is dropped, for a caller that also draws them.
pub fn compare_one(
    train: &Log,
    tests: &[&Log],
    choice: &ModelChoice,
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
    seen: &mut dyn FnMut(usize, &Correction),
) -> ModelReport {
    let mut report = ModelReport {
        model: choice.name(),
        description: choice.describe(),
        error: None,
        fitted: None,
        logs: Vec::new(),
    };
    match crate::models::fit_with_progress(train, choice, recipe, progress) {
        Ok(m) => {
            report.logs = std::iter::once((train, false))
                .chain(tests.iter().map(|t| (*t, !train.same_run(t))))
                .enumerate()
                .map(|(k, (log, held_out))| Judgement {
                    log: log.source.clone(),
                    held_out,
                    result: match crate::models::check_rate_moves(log).and_then(|()| m.correct(log))
                    {
                        Ok(c) => {
                            seen(k, &c);
                            Outcome::Evaluation(Evaluation::of_correction(log, &c, merit))
                        }
                        Err(e) => Outcome::Error(e.to_string()),
                    },
                })
                .collect();
            report.fitted = Some(m);
        }
        Err(e) => report.error = Some(e.to_string()),
    }
    report
}
