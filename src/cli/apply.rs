//! `driftlab apply`: correct a log with a calibration and write the result as CSV.

use super::common::{self, CliError, LogArgs};
use driftlab::files::corrected_csv::{self, WriteError};
use driftlab::models::UnitCalibration;
use driftlab::models::vakhrameev::LeftOut;
use std::path::{Path, PathBuf};

/// Arguments of `apply`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON) made by `driftlab calibrate`.
    pub calibration: PathBuf,
    /// The log to correct.
    pub log: PathBuf,
    /// Where to write `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`; for a unit
    /// of several axes `time_s`, then `<axis>_raw_dph,<axis>_pred_dph,<axis>_cor_dph` for each
    /// axis in the calibration's order (`<axis>_raw_m_s2,…` for an accelerometer axis, after
    /// the gyro axes), then `temp_c`.
    #[arg(long, short)]
    pub out: PathBuf,
    #[command(flatten)]
    pub log_args: LogArgs,
}

/// Every axis of the calibration (the one axis of a single-axis calibration, or each axis of
/// a unit from the log's axis of the same name or rate column) corrected and written side by
/// side, predicted batch by batch as the rows are written: no column of the prediction, the
/// corrected rate, rates or regimes is held.
pub fn run(mut a: Args) -> Result<(), CliError> {
    let mut reads = common::Reads::of("the calibration", &a.calibration);
    common::refuse_outputs(&[("--out", &a.out)], reads.add("the log", &a.log))?;
    let unit = common::load_calibration(&a.calibration)?;
    // A drone log is read on the gyro the calibration was fitted on unless --gyro says
    // otherwise.
    a.log_args.format.fitted_on = unit.fitted_on();
    let input = a.log_args.open(&a.log)?;
    let log = a.log_args.read_for(&input, &unit)?;
    common::refuse_guessed_axis(&unit, &a.log_args, (&a.log, &log), &a.calibration)?;
    let bar = common::progress_bar(&format!("writing {}", a.out.display()));
    let written = corrected_csv::correct_and_write(&a.out, &log, &unit, &|f| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let outside = written.map_err(|e| in_words(e, &unit, &a.calibration))?;
    for (ax, fraction) in unit.axes.iter().zip(outside) {
        note_outside(&ax.name, fraction, ax.model.left_out());
        note_warm_up(&ax.name, ax.model.warm_up_samples(&log), log.len());
    }
    if unit.is_unit() {
        note!(
            "{} samples of {} axes ({}) corrected, written to {}",
            log.len(),
            unit.axes.len(),
            unit.axis_names().join(", "),
            a.out.display()
        );
    } else {
        note!(
            "{} samples corrected, written to {}",
            log.len(),
            a.out.display()
        );
    }
    Ok(())
}

/// The command line's words for why the log was not corrected: a missing axis with the flag
/// that maps the rate columns, a model's error with the calibration file.
fn in_words(e: WriteError, unit: &UnitCalibration, calibration: &Path) -> CliError {
    match e {
        WriteError::MissingAxis {
            log,
            axis,
            rate_column,
            log_axes,
        } => {
            super::evaluate::missing_axis(&log, (unit, &axis), &rate_column, &log_axes, calibration)
        }
        WriteError::Predict { .. } => format!("{}: {e}", calibration.display()).into(),
        WriteError::Io { .. } => e.to_string().into(),
    }
}

/// Says what share of the samples (of `axis`, when named) lay outside the calibrated ranges.
/// Warns when most of the log (or all of it) is corrected before T's history is full: a log
/// shorter than the calibration's smoothing and derivative windows gets its static part
/// alone, which the engineer should hear rather than read as a full correction.
fn note_warm_up(axis: &str, warming: usize, samples: usize) {
    if samples == 0 || warming * 2 <= samples {
        return;
    }
    let of = if axis.is_empty() {
        String::new()
    } else {
        format!(" of axis {axis}")
    };
    let share = if warming >= samples {
        "every sample".to_string() + &of + " lies"
    } else {
        format!("{warming} of the {samples} samples{of} lie")
    };
    note!(
        "warning: {share} before the temperature history the calibration's rates need \
         (its smoothing and derivative windows, after the start and each gap): their Ṫ and T̈ \
         are no reading, so they are corrected by the static part of the model alone; a longer \
         log corrects fully"
    );
}

fn note_outside(axis: &str, outside_fraction: f64, left_out: LeftOut) {
    if outside_fraction > 0.0 {
        let of = if axis.is_empty() {
            String::new()
        } else {
            format!(" of axis {axis}")
        };
        let left = if left_out.is_none() {
            String::new()
        } else {
            format!(" ({left_out})")
        };
        note!(
            "note: {}% of the samples{of} lie outside the calibrated ranges of the model's \
             inputs{left}; edge values were held there",
            driftlab::number::percent(outside_fraction)
        );
    }
}
