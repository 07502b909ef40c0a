//! Several models fitted on one log and judged side by side on it (in-sample) and on other
//! logs of the same gyro (held out) — what tells an engineer which model to ship.

use crate::drift_model::{self, DriftModel};
use crate::log::Log;
use crate::metrics::{Evaluation, MeritOptions};
use crate::presets::ModelChoice;
use crate::recipe::Recipe;
use rayon::prelude::*;
use serde::Serialize;

/// One model judged on one log.
#[derive(Debug, Clone, Serialize)]
pub struct Judgement {
    /// The log's name.
    pub log: String,
    /// False for the log the model was fitted on.
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
    recipe: &Recipe,
    merit: &MeritOptions,
) -> Vec<ModelReport> {
    choices
        .par_iter()
        .map(|choice| {
            let mut report = ModelReport {
                model: choice.name(),
                description: choice.describe(),
                error: None,
                fitted: None,
                logs: Vec::new(),
            };
            match drift_model::fit(train, choice, recipe) {
                Ok(m) => {
                    report.logs = std::iter::once((train, false))
                        .chain(tests.iter().map(|t| (t, true)))
                        .map(|(log, held_out)| judge(&m, log, held_out, merit))
                        .collect();
                    report.fitted = Some(m);
                }
                Err(e) => report.error = Some(e.to_string()),
            }
            report
        })
        .collect()
}

/// One model on one log.
pub fn judge(model: &DriftModel, log: &Log, held_out: bool, merit: &MeritOptions) -> Judgement {
    Judgement {
        log: log.source.clone(),
        held_out,
        result: match model.correct(log) {
            Ok(c) => Outcome::Evaluation(Evaluation::of_correction(log, &c, merit)),
            Err(e) => Outcome::Error(e.to_string()),
        },
    }
}
