//! `driftlab report`: the test report of a calibration judged on one or more logs.

use super::common::{self, CliError, LogArgs};
use driftlab::export::report;
use driftlab::files::calibration;
use driftlab::log::ingest::{ExtraColumns, Needs};
use std::path::{Path, PathBuf};

/// Arguments of `report`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON): a Vakhrameev calibration or a regression model.
    pub calibration: PathBuf,
    /// The logs to judge it on: its own log (in-sample) and other runs (held out).
    #[arg(required = true, num_args = 1..)]
    pub logs: Vec<PathBuf>,
    /// Folder to write the figures and report.html into (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Moving-average window of the filtered drift, s (default: a Vakhrameev calibration's
    /// filter; 100 s for a regression model).
    #[arg(long, value_name = "S")]
    pub filter: Option<f64>,
    /// Length of the consecutive mean/RMS windows, s (default 600). One asked for that is
    /// shorter than a log's step is refused; the default's figures are then n/a, with why.
    #[arg(long, value_name = "S")]
    pub window: Option<f64>,
    /// With a calibration fitted on several runs: plateaus share a temperature within this,
    /// degC (the campaign section's repeatability and hysteresis). Default 1, as calibrate's.
    #[arg(long, value_name = "DEGC")]
    pub temp_tolerance: Option<f64>,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(mut a: Args) -> Result<(), CliError> {
    let mut reads = common::Reads::of("the calibration", &a.calibration);
    common::refuse_folder_over("--out", &a.out, reads.add_all("a log", &a.logs))?;
    let logs: Vec<&Path> = a.logs.iter().map(PathBuf::as_path).collect();
    common::refuse_stream_twice(&logs)?;
    let unit = common::load_calibration(&a.calibration)?;
    // The tolerance the campaign was grouped by when it was fitted, unless one is given; a
    // tolerance given for a calibration of one run would group nothing.
    let recorded = unit.campaign_tolerance_c();
    let tolerance_c = match (a.temp_tolerance, recorded) {
        (Some(_), None) => {
            return Err(CliError::Message(format!(
                "--temp-tolerance is for a calibration fitted on several runs; {} was fitted \
                 on one",
                a.calibration.display()
            )));
        }
        (Some(t), Some(_)) => t,
        (None, Some(t)) => t,
        (None, None) => driftlab::models::campaign::DEFAULT_TOLERANCE_C,
    };
    driftlab::models::campaign::check_tolerance("--temp-tolerance", tolerance_c)
        .map_err(|e| CliError::Message(e.to_string()))?;
    // A drone log is read on the gyro the calibration was fitted on unless --gyro says
    // otherwise.
    a.log_args.format.fitted_on = unit.fitted_on();
    let merit = report::UnitMerit {
        filter_s: a.filter,
        window_s: a
            .window
            .unwrap_or(driftlab::MeritOptions::default().window_s),
    };
    let (mut logs, hashes) = read_logs(&a, &unit, |path, log| {
        common::refuse_guessed_axis(&unit, &a.log_args, (path, log), &a.calibration)?;
        super::evaluate::unit_axes(log, &unit, &a.calibration)?;
        for ax in &unit.axes {
            common::check_merit(&merit.for_model(&ax.model), a.window.is_some(), log)
                .map_err(|e| super::evaluate::in_axis(&ax.name, e))?;
        }
        Ok(())
    })?;
    common::status(&match unit.axes.len() {
        1 => format!("writing the report into {}", a.out.display()),
        n => format!("writing the report of {n} axes into {}", a.out.display()),
    });
    // One writer for every calibration, a single axis being a unit of one; the lines printed
    // are those of a unit of named axes, or the one line per log of a single axis.
    let summary = report::write_unit(&unit, &mut logs, &a.out, merit, Some(hashes), tolerance_c)
        .map_err(|e| e.to_string())?;
    if unit.is_unit() {
        print_axes(&logs, &summary)?;
    } else {
        print_single(&summary, logs.len())?;
    }
    let mut notes: Vec<&String> = Vec::new();
    for ax in &summary.axes {
        for n in &ax.summary.notes {
            if !notes.contains(&n) {
                notes.push(n);
            }
        }
    }
    for n in notes {
        out!("note: {n}")?;
    }
    print_files(&summary.files)
}

/// The figures of the one axis of a single-axis calibration, a line per log of the `count`
/// given, or why it was left out.
fn print_single(summary: &report::UnitReportSummary, count: usize) -> Result<(), CliError> {
    for k in 0..count {
        for (_, o) in summary.left_out(k) {
            out!("{} (left out): {}", o.name, o.reason)?;
        }
        for (_, l) in summary.log(k) {
            out!(
                "{} ({}): peak-to-peak of filtered drift {} -> {} deg/h ({})",
                l.name,
                l.kind,
                common::fixed(l.evaluation.comparison.raw.p2p_dph, 4),
                common::fixed(l.evaluation.comparison.corrected.p2p_dph, 4),
                common::ratio(l.evaluation.comparison.p2p_ratio)
            )?;
        }
    }
    Ok(())
}

/// The report's logs, each with the path it was read from.
type LogsRead = Vec<(PathBuf, driftlab::Log)>;

/// Reads every log of the report, each checked by `check`, with the SHA-256 of each file as
/// read: the columns `unit`'s models read, and the log's other temperatures, which the
/// temperature figure draws; no other column is parsed or held.
fn read_logs(
    a: &Args,
    unit: &driftlab::UnitCalibration,
    check: impl Fn(&Path, &driftlab::Log) -> Result<(), CliError>,
) -> Result<(LogsRead, Vec<String>), CliError> {
    let mut kept = ExtraColumns {
        temperatures: true,
        ..ExtraColumns::default()
    };
    for ax in &unit.axes {
        let (temp2, channels) = ax.model.inputs();
        kept.names.extend(temp2);
        kept.names.extend(channels);
    }
    // The accelerometer axes' columns, made axes once read.
    let accel = if unit.has_accelerometers() {
        let ask = a.log_args.accel_ask_for(unit)?;
        kept.names.extend(super::accel::by_name(&ask));
        kept.accelerometers |= super::accel::by_name(&ask).len() < ask.columns.len();
        Some(ask)
    } else {
        a.log_args.refuse_accel_without(unit)?;
        None
    };
    let needs = Needs {
        extras: Some(kept),
        ..Needs::default()
    };
    let mut logs = Vec::with_capacity(a.logs.len());
    let mut hashes = Vec::with_capacity(a.logs.len());
    for path in &a.logs {
        let input = a.log_args.open(path)?;
        let mut log = a.log_args.read_needing(&input, &needs)?;
        if let Some(ask) = &accel {
            a.log_args.take_accelerometers(&mut log, ask)?;
        }
        check(path, &log)?;
        logs.push((path.clone(), log));
        hashes.push(calibration::sha256_input(&input).unwrap_or_default());
    }
    Ok((logs, hashes))
}

fn print_files(files: &[PathBuf]) -> Result<(), CliError> {
    out!("wrote {} files:", files.len())?;
    for f in files {
        out!("  {}", f.display())?;
    }
    Ok(())
}

/// The figures of every axis of a unit, a block per log.
fn print_axes(logs: &LogsRead, summary: &report::UnitReportSummary) -> Result<(), CliError> {
    for (k, (path, _)) in logs.iter().enumerate() {
        let judged = summary.log(k);
        for (axis, o) in summary.left_out(k) {
            out!("{} (left out), axis {axis}: {}", o.name, o.reason)?;
        }
        let Some((_, first)) = judged.first() else {
            continue;
        };
        // Each axis in its unit where the unit has accelerometers, else in deg/h as always.
        let mixed = judged.iter().any(|(_, l)| l.unit != judged[0].1.unit);
        out!(
            "{} ({}): peak-to-peak of filtered drift, {}:",
            super::calibrate::file_name(path),
            first.kind,
            if mixed { "deg/h, m/s^2" } else { "deg/h" }
        )?;
        for (axis, l) in &judged {
            let c = &l.evaluation.comparison;
            let (unit, kind) = match (mixed, l.unit) {
                (_, "m/s²") => (" m/s^2", driftlab::log::AxisKind::Accel),
                (true, _) => (" deg/h", driftlab::log::AxisKind::Gyro),
                (false, _) => ("", driftlab::log::AxisKind::Gyro),
            };
            let unit = if mixed { unit } else { "" };
            out!(
                "  axis {axis:<6} {} -> {}{unit} ({})",
                common::figure_in(c.raw.p2p_dph, kind),
                common::figure_in(c.corrected.p2p_dph, kind),
                common::ratio(c.p2p_ratio)
            )?;
            if c.worse_than_raw.any() {
                out!(
                    "    worse than raw: {} (ratio below 1)",
                    c.worse_than_raw.names().join(", ")
                )?;
            }
        }
    }
    Ok(())
}
