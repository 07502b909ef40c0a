//! `driftlab evaluate`: figures of merit of a log, raw and corrected.

use super::common::{self, CliError, LogArgs};
use driftlab::Log;
use driftlab::files::calibration;
use driftlab::files::corrected_csv::{self, WriteError};
use driftlab::judge::metrics::{Comparison, Evaluation, MeritOptions};
use driftlab::judge::verify;
use driftlab::log::run_sketch::Shared;
use driftlab::models::UnitCalibration;
use driftlab::models::fitted::DriftModel;
use std::path::{Path, PathBuf};

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
    /// Length of the consecutive mean/RMS windows, s (default 600). One asked for that is
    /// shorter than a log's step is refused; the default's figures are then n/a, with why.
    #[arg(long, value_name = "S")]
    pub window: Option<f64>,
    /// Print the figures as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

/// Every axis of the calibration judged on the log's axis it was calibrated on (the log's
/// own axis for a single-axis calibration), then printed: one axis as it always was, a unit
/// axis by axis with a summary.
pub fn run(mut a: Args) -> Result<(), CliError> {
    let unit = common::load_calibration(&a.calibration)?;
    // A drone log is read on the gyro the calibration was fitted on unless --gyro says
    // otherwise.
    a.log_args.format.fitted_on = unit.fitted_on();
    let input = a.log_args.open(&a.log)?;
    let mut log = a.log_args.read_for(&input, &unit)?;
    common::refuse_guessed_axis(&unit, &a.log_args, (&a.log, &log), &a.calibration)?;
    // The log is the calibration's own when its bytes are (hashed as they were read), or by
    // name for a calibration that recorded no hash.
    let hash = calibration::sha256_input(&input).unwrap_or_default();
    let columns = unit_axes(&log, &unit, &a.calibration)?;
    let mut judged = Vec::with_capacity(unit.axes.len());
    for (ax, column) in unit.axes.iter().zip(&columns) {
        if !log.select_axis(column) {
            return Err(format!("{}: axis {column} vanished from the log", log.source).into());
        }
        // An accelerometer axis is judged about the mean its correction keeps, as it was fitted
        // (about the log's own in another orientation, and said).
        if let Some(note) =
            driftlab::models::accel::orientation_note(&log, &ax.name, ax.kind, ax.kept_mean)
        {
            eprintln!("note: {}", driftlab::text::escaped(&note, false));
        }
        let judged_axis = judge(&a, &ax.model, &ax.as_fitted(&log), &hash).map_err(|e| {
            if unit.is_unit() {
                in_axis(&ax.name, e)
            } else {
                e
            }
        })?;
        judged.push(AxisJudged {
            name: ax.name.clone(),
            column: column.clone(),
            model: ax.model.name().to_string(),
            opts: judged_axis.options,
            in_sample: judged_axis.in_sample,
            share: judged_axis.share,
            campaign_run: judged_axis.campaign_run,
            eval: judged_axis.evaluation,
            kind: ax.kind,
            kept_mean: ax.kept_mean,
        });
    }
    if unit.is_unit() {
        // The axes share the log's rows: one that saw too few of them takes what all tell.
        let mut in_sample: Vec<bool> = judged.iter().map(|j| j.in_sample).collect();
        let mut shares: Vec<Option<Shared>> = judged.iter().map(|j| j.share).collect();
        verify::settle_axes(&mut in_sample, &mut shares);
        for ((j, i), s) in judged.iter_mut().zip(in_sample).zip(shares) {
            (j.in_sample, j.share) = (i, s);
        }
        print_unit(&a, &unit, &judged)
    } else {
        print_single(&a, &judged[0])
    }
}

/// One axis's judgement as JSON: the files, the model, its in-sample figures, the options and
/// the evaluation on the log.
fn judged_json(a: &Args, j: &AxisJudged) -> serde_json::Value {
    serde_json::json!({
        "calibration": a.calibration,
        "log": a.log,
        "model": j.model,
        "in_sample": j.in_sample,
        "in_sample_share": j
            .share
            .filter(|s| j.in_sample && s.in_sample())
            .map(|s| s.share_of_log),
        // What the samples' sketch found, whatever the label: the share of the log that is
        // the calibration log's (held-out logs that share some too), and the share of the
        // calibration log it holds; null when it found none, or the file keeps no sketch.
        "shared": j
            .share
            .filter(|s| s.in_sample() || s.partly().is_some())
            .map(|s| serde_json::json!({
                "share_of_log": s.share_of_log,
                "share_of_calibration_log": s.share_of_run(),
                "told_with_other_axes": s.told_with_other_axes(),
            })),
        // Why the sketch cannot tell whether the log is the calibration log's (too few of its
        // samples compared, a column written coarser), in words; null when it tells, or when
        // the log is in-sample by its bytes.
        "cannot_tell": j
            .share
            .filter(|_| !j.in_sample)
            .and_then(|s| s.cannot_tell()),
        "options": j.opts,
        "evaluation": j.eval,
    })
}

/// The figures of a single-axis calibration.
fn print_single(a: &Args, j: &AxisJudged) -> Result<(), CliError> {
    if a.json {
        return common::print_json(&judged_json(a, j));
    }
    out!(
        "{} on {} ({}):",
        super::calibrate::file_name(&a.calibration),
        super::calibrate::file_name(&a.log),
        j.label()
    )?;
    common::print_evaluation(&j.eval, j.opts.window_s)
}

/// The figures of `model` on `log` (whose bytes hash to `hash`), as the engine judges a saved
/// calibration ([`verify::judge`]): the merit options (the calibration's filter unless
/// --filter), whether the log is the calibration's own, and the evaluation.
fn judge(a: &Args, model: &DriftModel, log: &Log, hash: &str) -> Result<verify::Judged, CliError> {
    let name = a.log.file_name().map_or_else(
        || a.log.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let opts = verify::merit_options(model, a.filter, a.window);
    // Checked here first (the engine checks again) so that its warning is printed before
    // anything the judging refuses.
    common::check_merit_to_judge(&opts, a.window.is_some(), log)?;
    let file = verify::LogFile {
        name: &name,
        sha256: hash,
    };
    verify::judge(model, log, file, opts, a.window.is_some()).map_err(|e| match e {
        verify::JudgeError::Options(i) => common::with_option(i),
        verify::JudgeError::FrozenRate(e) => {
            common::fit_failed(&log.source, &e, &common::in_option_words).into()
        }
        verify::JudgeError::Correct(e) => format!("{}: {e}", a.calibration.display()).into(),
    })
}

/// The log's axis that each axis of `unit` was calibrated on (by name, or by the rate column
/// it was read from; the log's own axis for a single-axis calibration), in the calibration's
/// order; an axis the log lacks is an error naming both sides.
pub(super) fn unit_axes(
    log: &Log,
    unit: &UnitCalibration,
    calibration: &Path,
) -> Result<Vec<String>, CliError> {
    corrected_csv::log_axes(log, unit).map_err(|e| match e {
        WriteError::MissingAxis {
            log,
            axis,
            rate_column,
            log_axes,
        } => missing_axis(&log, (unit, &axis), &rate_column, &log_axes, calibration),
        other => other.to_string().into(),
    })
}

/// The log `log` lacks the axis `axis` (read from `rate_column` on its own log) of the
/// calibration file `calibration`.
pub(super) fn missing_axis(
    log: &str,
    (unit, axis): (&UnitCalibration, &str),
    rate_column: &str,
    log_axes: &[String],
    calibration: &Path,
) -> CliError {
    let kind = unit.axis(axis).map_or(Default::default(), |a| a.kind);
    let column = if rate_column.is_empty() {
        "?"
    } else {
        rate_column
    };
    match kind {
        driftlab::log::AxisKind::Gyro => format!(
            "{log}: no gyro axis {axis} (column {column}) for axis {axis} of {} (the log's axes: \
             {}); a unit's axes are found in a log by their names or their rate columns' names, \
             so the log must name its rate columns as the calibration's log did (rename them in \
             its header)",
            calibration.display(),
            log_axes.join(", ")
        ),
        driftlab::log::AxisKind::Accel => format!(
            "{log}: no accelerometer axis {axis} (column {column}) for axis {axis} of {} (the \
             log's axes: {}); name its column with --accel-col, or rename it in the log's header \
             as the calibration's log named it",
            calibration.display(),
            log_axes.join(", ")
        ),
    }
    .into()
}

/// The figures of a unit: each axis as the single-axis command gives them, then a summary.
fn print_unit(a: &Args, unit: &UnitCalibration, judged: &[AxisJudged]) -> Result<(), CliError> {
    if a.json {
        let axes: Vec<serde_json::Value> = judged
            .iter()
            .map(|j| {
                let mut axis = serde_json::json!({
                    "name": j.name,
                    "log_axis": j.column,
                });
                if let (Some(o), driftlab::log::AxisKind::Accel) = (axis.as_object_mut(), j.kind) {
                    o.insert("kind".into(), serde_json::json!(j.kind));
                    o.insert("unit".into(), serde_json::json!(j.kind.unit_ascii()));
                    o.insert("kept_mean_m_s2".into(), serde_json::json!(j.kept_mean));
                }
                let mut rest = judged_json(a, j);
                j.kind.name_fields_in_unit(&mut rest);
                if let (Some(axis), serde_json::Value::Object(rest)) = (axis.as_object_mut(), rest)
                {
                    axis.extend(rest);
                }
                axis
            })
            .collect();
        return common::print_json(&serde_json::json!({
            "calibration": a.calibration,
            "log": a.log,
            "axes": axes,
        }));
    }
    // Each axis is judged on its own samples: one label for the unit when they agree, else
    // the axes grouped by verdict, and each axis's label beside it.
    let labels: Vec<String> = judged.iter().map(AxisJudged::label).collect();
    let one_label = labels.windows(2).all(|w| w[0] == w[1]);
    let kinds: Vec<(&str, &'static str, String)> = judged
        .iter()
        .zip(&labels)
        .map(|(j, l)| {
            (
                j.name.as_str(),
                verify::sample_kind(j.in_sample, j.share),
                l.clone(),
            )
        })
        .collect();
    out!(
        "{} ({} axes: {}) on {} ({}):",
        super::calibrate::file_name(&a.calibration),
        unit.axes.len(),
        unit.axis_names().join(", "),
        super::calibrate::file_name(&a.log),
        verify::unit_label(&kinds)
    )?;
    for (j, label) in judged.iter().zip(&labels) {
        out!()?;
        out!(
            "=== Axis {}{} — model {}, filter {} s{} ===",
            j.name,
            if j.column == j.name {
                String::new()
            } else {
                format!(" (log axis {})", j.column)
            },
            j.model,
            common::num(j.opts.filter_s),
            if one_label {
                String::new()
            } else {
                format!("; {label}")
            }
        )?;
        if let Some(mean) = j.kept_mean {
            out!(
                "  (about its mean on the calibration log, {} {}, which its correction keeps)",
                common::num(mean),
                j.kind.unit_ascii()
            )?;
        }
        common::print_evaluation_in(&j.eval, j.opts.window_s, j.kind)?;
    }
    out!()?;
    let rows: Vec<SummaryRow> = judged
        .iter()
        .map(|j| SummaryRow {
            axis: &j.name,
            model: &j.model,
            comparison: &j.eval.comparison,
            kind: j.kind,
        })
        .collect();
    print_summary(
        &format!(
            "Unit summary on {} ({}; raw -> corrected, raw/cor):",
            super::calibrate::file_name(&a.log),
            if unit.has_accelerometers() {
                "deg/h, m/s^2 for the accelerometer axes"
            } else {
                "deg/h"
            }
        ),
        &rows,
        a.window.unwrap_or(MeritOptions::default().window_s),
    )
}

/// An error of one axis, named with it.
pub(super) fn in_axis(axis: &str, e: CliError) -> CliError {
    match e {
        // The one axis of a single-axis calibration has no name to give.
        CliError::Message(m) if axis.is_empty() => CliError::Message(m),
        CliError::Message(m) => CliError::Message(format!("axis {axis}: {m}")),
        closed => closed,
    }
}

/// One axis of a unit judged on the log.
struct AxisJudged {
    name: String,
    /// The log's axis it was judged on.
    column: String,
    model: String,
    opts: MeritOptions,
    in_sample: bool,
    /// How much of the log is the calibration log's, when its samples' sketch tells.
    share: Option<Shared>,
    /// The run of the calibration's campaign the log is, in words, when it is one.
    campaign_run: Option<String>,
    eval: Evaluation,
    /// What the axis measures: the unit of its figures.
    kind: driftlab::log::AxisKind,
    /// The mean an accelerometer axis keeps, its figures taken about it.
    kept_mean: Option<f64>,
}

impl AxisJudged {
    /// Whether the log is the calibration's own, in words: the run of its campaign it is,
    /// or [`verify::sample_label`]'s.
    fn label(&self) -> String {
        match &self.campaign_run {
            Some(run) if self.in_sample => run.clone(),
            _ => verify::sample_label(self.in_sample, self.share),
        }
    }
}

/// One line of a unit's summary table.
pub(super) struct SummaryRow<'a> {
    pub(super) axis: &'a str,
    pub(super) model: &'a str,
    pub(super) comparison: &'a Comparison,
    /// What the axis measures: the unit its figures are written in.
    pub(super) kind: driftlab::log::AxisKind,
}

/// The summary of every axis: raw -> corrected and the ratio of the four figures, a ratio
/// below 1 marked "worse" (as [`common::ratio`] marks it everywhere), and the axes whose
/// correction made a figure worse than raw named below the table.
pub(super) fn print_summary(
    title: &str,
    rows: &[SummaryRow<'_>],
    window_s: f64,
) -> Result<(), CliError> {
    let w = driftlab::judge::options::window_label(window_s);
    out!("{title}")?;
    out!(
        "  {:<8} {:<12} {:>28} {:>28} {:>28} {:>28}",
        "axis",
        "model",
        "peak-to-peak",
        "std",
        format!("max |{w} mean|"),
        format!("mean {w} RMS")
    )?;
    for r in rows {
        let c = r.comparison;
        let [p2p, std, win_mean] = common::comparison_cells_in(c, r.kind);
        out!(
            "  {:<8} {:<12} {:>28} {:>28} {:>28} {:>28}",
            r.axis,
            r.model,
            p2p,
            std,
            win_mean,
            common::raw_to_corrected_in(
                c.raw.win_rms_mean_dph,
                c.corrected.win_rms_mean_dph,
                c.win_rms_ratio,
                r.kind
            )
        )?;
    }
    for r in rows.iter().filter(|r| r.comparison.worse_than_raw.any()) {
        out!(
            "  axis {}: worse than raw: {} (ratio below 1)",
            r.axis,
            r.comparison.worse_than_raw.names().join(", ")
        )?;
    }
    Ok(())
}
