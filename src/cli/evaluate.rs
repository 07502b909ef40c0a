//! `driftlab evaluate`: figures of merit of a log, raw and corrected.

use super::common::{self, CliError, LogArgs};
use driftlab::files::calibration;
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::models::fitted::DriftModel;
use std::path::PathBuf;

/// Arguments of `evaluate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON).
    pub calibration: PathBuf,
    /// The log to judge it on.
    pub log: PathBuf,
    /// Moving-average window of the filtered drift, s (default: the calibration's filter).
    #[arg(long, value_name = "S")]
    pub filter: Option<f64>,
    /// Length of the consecutive mean/RMS windows, s.
    #[arg(long, value_name = "S", default_value_t = 600.0)]
    pub window: f64,
    /// Print the figures as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    let model = calibration::load_model(&a.calibration).map_err(|e| e.to_string())?;
    let input = a.log_args.open(&a.log)?;
    let log = a.log_args.read_for(&input, &model)?;
    // The log is the calibration's own when its bytes are (hashed as they were read), or by
    // name for a calibration that recorded no hash.
    let hash = calibration::sha256_input(&input).unwrap_or_default();
    let in_sample = driftlab::export::report::is_source(model.source(), &a.log, &hash);
    let default_filter = match &model {
        DriftModel::Vakhrameev(cal) => cal.recipe.filter_s,
        DriftModel::Regression(_) => MeritOptions::default().filter_s,
    };
    let opts = MeritOptions {
        filter_s: a.filter.unwrap_or(default_filter),
        window_s: a.window,
    };
    common::check_merit(&opts, &log)?;
    let correction = model
        .correct(&log)
        .map_err(|e| format!("{}: {e}", a.calibration.display()))?;
    let eval = Evaluation::of_correction(&log, &correction, &opts);
    if a.json {
        return common::print_json(&serde_json::json!({
            "calibration": a.calibration,
            "log": a.log,
            "model": model.name(),
            "in_sample": in_sample,
            "options": opts,
            "evaluation": eval,
        }));
    }
    out!(
        "{} on {} ({}):",
        super::calibrate::file_name(&a.calibration),
        super::calibrate::file_name(&a.log),
        if in_sample {
            "in-sample: the calibration log"
        } else {
            "held out: not the calibration log"
        }
    )?;
    common::print_evaluation(&eval, opts.window_s)
}
