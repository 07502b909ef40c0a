//! Drone and robot logs on every command that reads a log: `--gyro N` and `--temp-from`, the
//! CSV options refused for them by name, and what the reader noticed printed as warnings.

use super::common::LogArgs;
use driftlab::Log;
use driftlab::log::formats::{self, Format};
use driftlab::log::ingest::ReadOptions;
use driftlab::log::read::{self, DroneLog, FormatChoice, TempFrom};
use std::path::Path;

/// Which gyro of a drone or robot log a command works on.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct FormatArgs {
    /// The gyro instance of a drone or robot log (PX4 ULog, ArduPilot DataFlash, ROS bag,
    /// MCAP), as `driftlab inspect` lists them (default: the first whose temperature is not
    /// all NaN).
    #[arg(long, value_name = "N")]
    pub gyro: Option<usize>,
    /// A temperature for a gyro whose own is missing: accel (its accelerometer's) or
    /// imu-status (PX4 vehicle_imu_status); none (no temperature) for `allan` only.
    #[arg(long, value_name = "accel|imu-status")]
    pub temp_from: Option<TempFrom>,
}

impl FormatArgs {
    /// The engine's choice for these arguments.
    pub fn choice(&self) -> FormatChoice {
        FormatChoice {
            gyro: self.gyro,
            temp_from: self.temp_from,
        }
    }
}

/// The command-line flags of the CSV options set in `opts` (none applies to a drone log).
fn csv_flags(opts: &ReadOptions) -> Vec<&'static str> {
    read::csv_options_set(opts)
        .into_iter()
        .map(|name| match name {
            "time_col" => "--time-col",
            "rate_col" => "--rate-col",
            "temp_col" => "--temp-col",
            "rate_unit" => "--rate-unit",
            "time_unit" => "--time-unit",
            "sample_rate_hz" => "--sample-rate",
            "delimiter" => "--delimiter",
            "decimal_comma" => "--decimal-comma",
            other => other,
        })
        .collect()
}

/// The drone-log format of `path`, refusing the options that do not fit the kind of file:
/// `--gyro`/`--temp-from` on a CSV, the CSV options on a drone log, each by name.
///
/// # Errors
/// The file cannot be opened, or options that do not apply.
pub fn check(args: &LogArgs, path: &Path, opts: &ReadOptions) -> Result<Option<Format>, String> {
    let format = read::drone_format(path).map_err(|e| e.to_string())?;
    match format {
        None => {
            let mut given = Vec::new();
            if args.format.gyro.is_some() {
                given.push("--gyro");
            }
            if args.format.temp_from.is_some() {
                given.push("--temp-from");
            }
            if !given.is_empty() {
                return Err(format!(
                    "{}: {} choose{} a gyro of a drone or robot log (PX4 ULog, ArduPilot \
                     DataFlash, ROS bag, MCAP); this file is none of them (a CSV's columns are \
                     chosen with --rate-col, --temp-col)",
                    path.display(),
                    given.join(" and "),
                    if given.len() == 1 { "s" } else { "" }
                ));
            }
        }
        Some(f) => {
            let flags = csv_flags(opts);
            if !flags.is_empty() {
                return Err(format!(
                    "{}: a {f} log has its format's own channels and units: {} do{} not apply \
                     to it (choose its gyro with --gyro N and --temp-from)",
                    path.display(),
                    flags.join(", "),
                    if flags.len() == 1 { "es" } else { "" }
                ));
            }
        }
    }
    Ok(format)
}

/// Prints what the format reader and the choice of gyro said, on standard error.
pub fn print_notes(drone: &DroneLog, log: &Log) {
    for p in &drone.problems {
        note!("warning: {}: {p}", log.source);
    }
    note!("note: {}", drone.note);
    for p in &log.info.problems {
        note!(
            "warning: {}: {} ({} time{})",
            log.source,
            p.message,
            p.count,
            if p.count == 1 { "" } else { "s" }
        );
    }
}

/// Reads `path` when it is a drone or robot log: one gyro as `--gyro` and `--temp-from` say,
/// the notes printed, as recorded (the caller bins it, [`LogArgs::resampled`]). `None` for a
/// CSV. `needs_temperature`: refuse `--temp-from none` (every command but `allan`).
///
/// # Errors
/// Options that do not apply, a file that cannot be read, no gyro as asked.
pub fn read_drone_log(
    args: &LogArgs,
    path: &Path,
    opts: &ReadOptions,
    needs_temperature: bool,
) -> Result<Option<(Log, DroneLog)>, String> {
    if check(args, path, opts)?.is_none() {
        return Ok(None);
    }
    if needs_temperature && args.format.temp_from == Some(TempFrom::None) {
        return Err(format!(
            "{}: --temp-from none leaves the log without a temperature: only `driftlab allan` \
             reads such a log (use --temp-from accel or imu-status, see `driftlab inspect`)",
            path.display()
        ));
    }
    let rec = formats::read_path(path).map_err(|e| e.to_string())?;
    let any = read::from_recording(&rec, opts.skip_extras, &args.format.choice())
        .map_err(|e| e.to_string())?;
    drop(rec);
    let log = any.log;
    let drone = any.drone.ok_or("a drone log read as a CSV")?;
    print_notes(&drone, &log);
    Ok(Some((log, drone)))
}
