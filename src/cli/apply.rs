//! `driftlab apply`: correct a log with a calibration and write the result as CSV.

use super::common::{self, CliError, LogArgs};
use driftlab::{files::calibration, files::corrected_csv};
use std::path::PathBuf;

/// Arguments of `apply`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON) made by `driftlab calibrate`.
    pub calibration: PathBuf,
    /// The log to correct.
    pub log: PathBuf,
    /// Where to write `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`.
    #[arg(long, short)]
    pub out: PathBuf,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    common::refuse_overwriting(
        "--out",
        &a.out,
        &[("the calibration", &a.calibration), ("the log", &a.log)],
    )?;
    let model = calibration::load_model(&a.calibration).map_err(|e| e.to_string())?;
    let log = a.log_args.read_for(&a.log_args.open(&a.log)?, &model)?;
    // The predicted drift alone, batch by batch as the rows are written: the corrected rate
    // is written as Ω − pred row by row, so no column of it (nor of rates and regimes) is held.
    let mut predictor = model
        .predictor(&log)
        .map_err(|e| format!("{}: {e}", a.calibration.display()))?;
    let bar = common::progress_bar(&format!("writing {}", a.out.display()));
    corrected_csv::write_streamed(&a.out, &log, &mut predictor, &|f| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    })
    .map_err(|e| format!("{}: {e}", a.out.display()))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let outside_fraction = predictor.outside_fraction();
    if outside_fraction > 0.0 {
        note!(
            "note: {:.1}% of the samples lie outside the calibrated ranges of the model's \
             inputs; edge values were held there",
            outside_fraction * 100.0
        );
    }
    note!(
        "{} samples corrected, written to {}",
        log.len(),
        a.out.display()
    );
    Ok(())
}
