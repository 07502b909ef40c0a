//! `driftlab apply`: correct a log with a calibration and write the result as CSV.

use super::common::{self, CliError, LogArgs};
use driftlab::models::UnitCalibration;
use driftlab::{files::calibration, files::corrected_csv};
use std::path::PathBuf;

/// Arguments of `apply`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON) made by `driftlab calibrate`.
    pub calibration: PathBuf,
    /// The log to correct.
    pub log: PathBuf,
    /// Where to write `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`; for a unit
    /// of several axes `time_s`, then `<axis>_raw_dph,<axis>_pred_dph,<axis>_cor_dph` for each
    /// axis in the calibration's order, then `temp_c`.
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
    let unit = calibration::load_unit(&a.calibration).map_err(|e| e.to_string())?;
    if unit.is_unit() {
        return run_unit(&a, &unit);
    }
    let model = unit.first()?;
    let log = a.log_args.read_for(&a.log_args.open(&a.log)?, model)?;
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
    note_outside("", predictor.outside_fraction());
    note!(
        "{} samples corrected, written to {}",
        log.len(),
        a.out.display()
    );
    Ok(())
}

/// Says what share of the samples (of `axis`, when named) lay outside the calibrated ranges.
fn note_outside(axis: &str, outside_fraction: f64) {
    if outside_fraction > 0.0 {
        let of = if axis.is_empty() {
            String::new()
        } else {
            format!(" of axis {axis}")
        };
        note!(
            "note: {:.1}% of the samples{of} lie outside the calibrated ranges of the model's \
             inputs; edge values were held there",
            outside_fraction * 100.0
        );
    }
}

/// `apply` for a unit: every axis corrected from the log's axis of the same name (or rate
/// column), written side by side.
fn run_unit(a: &Args, unit: &UnitCalibration) -> Result<(), CliError> {
    let input = a.log_args.open(&a.log)?;
    let plain = unit
        .axes
        .iter()
        .all(|ax| matches!(ax.model.inputs(), (None, c) if c.is_empty()));
    let log = if plain {
        a.log_args.read_columns(&input)?
    } else {
        a.log_args.read(&input)?
    };
    let columns = super::evaluate::unit_axes(&log, unit, &a.calibration)?;
    let mut predictors = Vec::with_capacity(unit.axes.len());
    for ax in &unit.axes {
        predictors.push(
            ax.model
                .predictor(&log)
                .map_err(|e| format!("{}: axis {}: {e}", a.calibration.display(), ax.name))?,
        );
    }
    let mut axes = Vec::with_capacity(unit.axes.len());
    for ((ax, column), p) in unit.axes.iter().zip(&columns).zip(predictors.iter_mut()) {
        let rate = log
            .axis_rate(column)
            .ok_or("an axis found in the log has no rate")?;
        axes.push((ax.name.as_str(), rate, p));
    }
    let bar = common::progress_bar(&format!("writing {}", a.out.display()));
    corrected_csv::write_unit_streamed(&a.out, &log, axes, &|f| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    })
    .map_err(|e| format!("{}: {e}", a.out.display()))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for (ax, p) in unit.axes.iter().zip(&predictors) {
        note_outside(&ax.name, p.outside_fraction());
    }
    note!(
        "{} samples of {} axes ({}) corrected, written to {}",
        log.len(),
        unit.axes.len(),
        unit.axis_names().join(", "),
        a.out.display()
    );
    Ok(())
}
