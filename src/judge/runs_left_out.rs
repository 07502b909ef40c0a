//! Leave-one-run-out: a model judged on a campaign's runs, each held out in turn. For every
//! run, the model is fitted on the campaign of every other run and judged on the run left out,
//! which it never saw: a held-out judge made of the campaign itself, as strong as the runs
//! are different (another day's turn-on, another program, another rate).
//!
//! The figure is the comparison's: raw ÷ corrected peak-to-peak of the filtered drift on the
//! run left out, with the corrected peak-to-peak in °/h beside it. The mean (the ratio of the
//! mean raw to the mean corrected peak-to-peak) and the worst over the runs are kept; the worst is what the recommendation ranks by, as a calibration ships to
//! every run of the gyro.

use crate::judge::metrics::RATIO_FLOOR;
use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::Log;
use crate::models::presets::ModelChoice;
use crate::models::recipe::CheckedRecipe;
use serde::Serialize;

/// One run left out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunLeftOut {
    /// The run's name.
    pub run: String,
    /// Raw ÷ corrected peak-to-peak of the filtered drift on it; `None` with `error`.
    pub p2p_ratio: Option<f64>,
    /// Peak-to-peak of the corrected filtered drift on it, °/h; `None` with `error`.
    pub corrected_p2p_dph: Option<f64>,
    /// Peak-to-peak of the raw filtered drift on it, °/h; `None` with `error`.
    pub raw_p2p_dph: Option<f64>,
    /// Why the model was not judged on it: not fitted on the other runs, or not applied.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// A model judged on every run of a campaign left out in turn.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeaveOneRunOut {
    /// Each run, in the campaign's order.
    pub runs: Vec<RunLeftOut>,
    /// The runs' mean raw peak-to-peak over their mean corrected peak-to-peak (the ratio of
    /// the two means beside it, not the mean of the runs' ratios, which one run's large ratio
    /// lifts above a run made many times worse); `None` when a run was not judged (or a
    /// figure is n/a).
    pub mean_p2p_ratio: Option<f64>,
    /// The worst (smallest) of the runs' ratios; `None` as the mean.
    pub worst_p2p_ratio: Option<f64>,
    /// The mean of the runs' raw peak-to-peak, °/h; `None` as the mean.
    pub mean_raw_p2p_dph: Option<f64>,
    /// The mean of the runs' corrected peak-to-peak, °/h; `None` as the mean.
    pub mean_corrected_p2p_dph: Option<f64>,
    /// The worst (largest) of the runs' corrected peak-to-peak, °/h; `None` as the mean.
    pub worst_corrected_p2p_dph: Option<f64>,
}

/// `choice` judged on each run of the campaign `train` left out in turn; `None` for a log of
/// one run (there is nothing to leave out). Each fit starts only while `keep_going` says so
/// (a face's Cancel: the run is then "cancelled").
pub fn leave_one_run_out(
    train: &Log,
    choice: &ModelChoice,
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> Option<LeaveOneRunOut> {
    let n = train.runs().len();
    if n < 2 {
        return None;
    }
    let runs: Vec<RunLeftOut> = (0..n)
        .map(|k| one_run(train, k, choice, recipe, merit, keep_going))
        .collect();
    Some(summed(runs))
}

/// Run `k` of `train` left out.
fn one_run(
    train: &Log,
    k: usize,
    choice: &ModelChoice,
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> RunLeftOut {
    let name = train.runs()[k].name.clone();
    let failed = |e: String| RunLeftOut {
        run: name.clone(),
        p2p_ratio: None,
        corrected_p2p_dph: None,
        raw_p2p_dph: None,
        error: Some(e),
    };
    if !keep_going() {
        return failed("cancelled".into());
    }
    let (Some(rest), Some(held)) = (train.without_run(k), train.run_log(k)) else {
        return failed("the run could not be set apart from the campaign".into());
    };
    let model = match crate::models::fit(&rest, choice, recipe) {
        Ok(m) => m,
        Err(e) => return failed(format!("not fitted on the other runs: {e}")),
    };
    let corrected =
        match crate::models::check_axis_readings(&held).and_then(|()| model.correct(&held)) {
            Ok(c) => c,
            Err(e) => return failed(format!("not applied to it: {e}")),
        };
    let c = Evaluation::of_correction(&held, &corrected, merit).comparison;
    RunLeftOut {
        run: name,
        p2p_ratio: Some(c.p2p_ratio),
        corrected_p2p_dph: Some(c.corrected.p2p_dph),
        raw_p2p_dph: Some(c.raw.p2p_dph),
        error: None,
    }
}

/// The runs with their mean and worst figures, which need every run judged with a finite
/// figure.
fn summed(runs: Vec<RunLeftOut>) -> LeaveOneRunOut {
    let all = |f: fn(&RunLeftOut) -> Option<f64>| -> Option<Vec<f64>> {
        runs.iter()
            .map(|r| f(r).filter(|x| x.is_finite()))
            .collect()
    };
    let ratios = all(|r| r.p2p_ratio);
    let raw = all(|r| r.raw_p2p_dph);
    let corrected = all(|r| r.corrected_p2p_dph);
    let mean = |v: &Vec<f64>| v.iter().sum::<f64>() / v.len() as f64;
    let (mean_raw, mean_corrected) = (raw.as_ref().map(mean), corrected.as_ref().map(mean));
    // The ratio of the means, as every ratio is taken (n/a for a corrected figure of zero).
    let mean_ratio = match (ratios.as_ref(), mean_raw, mean_corrected) {
        (Some(_), Some(r), Some(c)) if c > 0.0 && c > r.abs() * RATIO_FLOOR => Some(r / c),
        _ => None,
    };
    LeaveOneRunOut {
        mean_p2p_ratio: mean_ratio,
        mean_raw_p2p_dph: mean_raw,
        worst_p2p_ratio: ratios
            .as_ref()
            .map(|v| v.iter().copied().fold(f64::INFINITY, f64::min)),
        mean_corrected_p2p_dph: mean_corrected,
        worst_corrected_p2p_dph: corrected
            .as_ref()
            .map(|v| v.iter().copied().fold(f64::NEG_INFINITY, f64::max)),
        runs,
    }
}
