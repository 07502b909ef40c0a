//! `driftlab report`: the test report of a calibration judged on one or more logs.

use super::common::{self, CliError, LogArgs};
use driftlab::export::report::{self, ReportOptions};
use driftlab::files::calibration;
use driftlab::judge::metrics::MeritOptions;
use std::path::PathBuf;

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
    /// Length of the consecutive mean/RMS windows, s.
    #[arg(long, value_name = "S", default_value_t = 600.0)]
    pub window: f64,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    let model = calibration::load_model(&a.calibration).map_err(|e| e.to_string())?;
    let merit = MeritOptions {
        filter_s: a
            .filter
            .unwrap_or(report::default_merit_for(&model).filter_s),
        window_s: a.window,
    };
    let mut logs = Vec::with_capacity(a.logs.len());
    let mut hashes = Vec::with_capacity(a.logs.len());
    for path in &a.logs {
        let input = a.log_args.open(path)?;
        let log = a.log_args.read(&input)?;
        common::check_merit(&merit, &log)?;
        logs.push((path.clone(), log));
        hashes.push(calibration::sha256_input(&input).unwrap_or_default());
    }
    common::status(&format!("writing the report into {}", a.out.display()));
    let summary = report::write_model(
        &model,
        &logs,
        &a.out,
        &ReportOptions {
            merit: Some(merit),
            allan: None,
            sha256: Some(hashes),
        },
    )
    .map_err(|e| e.to_string())?;
    for l in &summary.logs {
        out!(
            "{} ({}): peak-to-peak of filtered drift {} -> {} deg/h ({})",
            l.name,
            if l.in_sample { "in-sample" } else { "held out" },
            common::fixed(l.evaluation.comparison.raw.p2p_dph, 4),
            common::fixed(l.evaluation.comparison.corrected.p2p_dph, 4),
            common::ratio(l.evaluation.comparison.p2p_ratio)
        )?;
    }
    for n in &summary.notes {
        out!("note: {n}")?;
    }
    out!("wrote {} files:", summary.files.len())?;
    for f in &summary.files {
        out!("  {}", f.display())?;
    }
    Ok(())
}
