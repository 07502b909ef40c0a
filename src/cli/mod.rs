//! The command line: argument parsing and printing over the engine's calls. No calculation
//! lives here; if the CLI needs a number, the engine computes it.

// First: its `out!` and `note!` macros are for every module below.
#[macro_use]
mod common;
mod accel;
mod allan;
mod apply;
mod calibrate;
mod calibrate_accel;
mod calibrate_print;
mod calibrate_runs;
mod campaign_print;
mod compare;
mod convert;
mod evaluate;
mod export;
mod figures;
mod inspect;
mod log_source;
mod lot;
mod report;
mod simulate;

use clap::{Parser, Subcommand};

/// driftlab: calibrate the thermal drift of gyroscopes from thermal-chamber test logs.
#[derive(Parser, Debug)]
#[command(name = "driftlab", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Fit a calibration to a chamber log and save it as JSON: Vakhrameev's K0, K1±, K2± by
    /// default, or any model of `compare` with --model.
    Calibrate(Box<calibrate::Args>),
    /// Correct a log with a calibration and write time, raw, predicted and corrected rate as CSV.
    Apply(apply::Args),
    /// Figures of merit of a log before and after correction (peak-to-peak, std, 10-min mean/RMS).
    Evaluate(evaluate::Args),
    /// Write a calibration for a gyro's processor: a C99 header with the streaming corrector, or
    /// lookup tables as CSV.
    Export(export::Args),
    /// Show what driftlab reads in a log: columns, units, sampling, plateaus, problems.
    Inspect(inspect::Args),
    /// Write the test report: figures (PNG and SVG) and one self-contained HTML page.
    Report(report::Args),
    /// Simulate a motionless gyro (fibre-optic; ring laser for `laser-gyro`) in a thermal
    /// chamber and write the log as CSV.
    Simulate(simulate::Args),
    /// Fit several models on one log and compare them on it and on held-out logs.
    Compare(compare::Args),
    /// Write one gyro of a drone or robot log (PX4 ULog, ArduPilot DataFlash, ROS bag, MCAP)
    /// as a CSV the other commands read.
    Convert(convert::Args),
    /// Allan deviation of a log's rate with intervals, and ARW, bias instability and RRW.
    Allan(allan::Args),
    /// Calibrate every unit of a lot, judge each against an acceptance spec, and find the
    /// outliers: a line per unit, lot.csv and lot.json; exit 0 when every unit passes, 2 when
    /// one fails, 3 when one could not be calibrated.
    Lot(lot::Args),
    /// Open the workbench (the default when no command is given).
    Gui(GuiArgs),
}

/// Arguments of `gui`.
#[derive(clap::Args, Debug, Default)]
pub struct GuiArgs {
    /// Log (or saved session .json) to open (default: sample_logs/calibration.csv when
    /// present), and a calibration .json to open beside its fit to compare, in any order.
    /// Several logs are the runs of one campaign, calibrated together (read as the first is).
    /// The import view shows first when a column is ambiguous or implausible.
    #[arg(value_name = "LOG|SESSION|CALIBRATION")]
    pub files: Vec<std::path::PathBuf>,
    /// Render the workbench once the log is loaded and calibrated (or the calibration has
    /// failed, with its message), save the window as PNG here and exit.
    #[arg(long, value_name = "PNG")]
    pub screenshot: Option<std::path::PathBuf>,
    /// A validation log to open beside the log (held out: the calibration is judged on it),
    /// read as the log is.
    #[arg(long, value_name = "LOG")]
    pub validation: Option<std::path::PathBuf>,
    /// The window's size in points, WIDTHxHEIGHT (at least 900x620), for a screenshot at a
    /// known size too.
    #[arg(long, value_name = "WxH")]
    pub window_size: Option<String>,
    /// A lot to open on the Lot page: its output folder (as `driftlab lot --out` made it), or
    /// its lot.json or lot.csv. Given alone, no sample log is opened behind it.
    #[arg(long, value_name = "OUT")]
    pub lot: Option<std::path::PathBuf>,
    /// How to read the log (a session keeps its own mapping).
    #[command(flatten)]
    pub log_args: common::LogArgs,
}

pub use common::{CliError, write_err};

/// The command line parsed, as `Cli::parse` does, except that clap's refusal of an argument
/// holding a line break or another character a terminal would obey (a file name a glob gave
/// too many of) shows that argument escaped, so it cannot forge a line of its own.
pub fn parse() -> Cli {
    let e = match Cli::try_parse() {
        Ok(cli) => return cli,
        Err(e) => e,
    };
    // Each argument, and the value of an `--option=value` (clap quotes the value alone).
    let crafted: Vec<String> = std::env::args_os()
        .skip(1)
        .map(|a| a.to_string_lossy().into_owned())
        .filter(|a| common::shown(a) != a.as_str())
        .flat_map(|a| {
            let value = a
                .strip_prefix("--")
                .and_then(|o| o.split_once('='))
                .map(|(_, v)| v.to_string());
            std::iter::once(a).chain(value)
        })
        .collect();
    if crafted.is_empty() || !e.use_stderr() {
        e.exit();
    }
    let mut text = e.render().to_string();
    for arg in &crafted {
        text = text.replace(arg.as_str(), &common::shown(arg));
    }
    let _ = std::io::Write::write_all(&mut std::io::stderr(), text.as_bytes());
    std::process::exit(e.exit_code());
}

/// Runs a parsed command line; the error is printed by `main`. Standard output is flushed
/// before the command counts as done, so that a full disk is never a silent success.
pub fn run(command: Command) -> Result<(), CliError> {
    let result = match command {
        Command::Calibrate(a) => calibrate::run(*a),
        Command::Apply(a) => apply::run(a),
        Command::Evaluate(a) => evaluate::run(a),
        Command::Export(a) => export::run(a),
        Command::Inspect(a) => inspect::run(a),
        Command::Report(a) => report::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Allan(a) => allan::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Lot(a) => lot::run(a),
        Command::Gui(a) => gui(a).map_err(CliError::Message),
    };
    result.and_then(|()| common::flush_out())
}

#[cfg(feature = "gui")]
fn gui(a: GuiArgs) -> Result<(), String> {
    let read = a.log_args.options()?;
    let accel = a.log_args.accel_ask()?;
    let instance = driftlab::log::read::InstanceChoice {
        gyro: a.log_args.format.gyro,
        temp_from: a.log_args.format.temp_from,
    };
    let driftlab::gui::StartFiles {
        log,
        more_runs,
        calibration,
    } = driftlab::gui::split_files(&a.files)?;
    let session = log.as_ref().is_some_and(|p| {
        p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    });
    if session
        && (read != driftlab::ReadOptions::default()
            || a.log_args.bin.is_some()
            || !accel.is_default())
    {
        return Err(
            "--time-col, --rate-col, --temp-col, --rate-unit, --time-unit, --sample-rate, \
             --delimiter, --decimal-comma, --accel-col, --accel-unit and --bin apply to a log: \
             a session keeps the mapping it was saved with (open it, then File › Column \
             mapping…)"
                .into(),
        );
    }
    if session && !instance.is_default() {
        return Err(
            "--gyro and --temp-from choose a gyro of a drone or robot log: a session keeps the \
             gyro it was saved with (open it, then File › Gyro of the log)"
                .into(),
        );
    }
    if session && a.validation.is_some() {
        return Err(
            "--validation opens a log beside a log: a session keeps its own validation log \
             (open it, then File › Open validation log…)"
                .into(),
        );
    }
    // The screenshot is written over nothing the workbench opens (nor a file named `-`), as
    // every other output is.
    if let Some(shot) = &a.screenshot {
        let mut reads = common::Reads::default();
        if let Some(log) = &log {
            reads.add(if session { "the session" } else { "the log" }, log);
        }
        for run in &more_runs {
            reads.add("a run of the campaign", run);
        }
        if let Some(cal) = &calibration {
            reads.add("the calibration", cal);
        }
        if let Some(v) = &a.validation {
            reads.add("the validation log", v);
        }
        if let Err(common::CliError::Message(m)) =
            common::refuse_outputs(&[("--screenshot", shot)], &reads)
        {
            return Err(m);
        }
    }
    let window_size = match &a.window_size {
        Some(s) => Some(driftlab::gui::parse_size(s).ok_or_else(|| {
            format!(
                "--window-size {}: give the window's size as WIDTHxHEIGHT, from 900x620 to \
                 16384x16384",
                common::shown(s)
            )
        })?),
        None => None,
    };
    driftlab::gui::run(driftlab::gui::GuiOptions {
        log,
        calibration,
        screenshot: a.screenshot,
        read,
        bin_s: a.log_args.bin,
        instance,
        validation: a.validation,
        window_size,
        more_runs,
        accel,
        lot: a.lot,
    })
}

#[cfg(not(feature = "gui"))]
fn gui(_: GuiArgs) -> Result<(), String> {
    Err(
        "this driftlab was built without the workbench (cargo feature `gui`); \
         use the commands listed by --help"
            .into(),
    )
}
