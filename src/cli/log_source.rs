//! Drone and robot logs on every command that reads a log: `--gyro N` and `--temp-from`, the
//! CSV options refused for them by name, and what the reader noticed printed as warnings.

use super::common::LogArgs;
use driftlab::Log;
use driftlab::log::formats::Format;
use driftlab::log::ingest::ReadOptions;
use driftlab::log::read::{self, DroneLog, FormatChoice, ReadError, TempFrom};
use std::path::Path;

/// Which gyro of a drone or robot log a command works on.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct FormatArgs {
    /// The gyro instance of a drone or robot log (PX4 ULog, ArduPilot DataFlash, ROS bag,
    /// MCAP), as `driftlab inspect` lists them (default: the first whose temperature has a
    /// finite value).
    #[arg(long, value_name = "N")]
    pub gyro: Option<usize>,
    /// A temperature for a gyro whose own is missing: accel (its accelerometer's) or
    /// imu-status (PX4 vehicle_imu_status); none (no temperature) for `allan` only.
    #[arg(long, value_name = "accel|imu-status")]
    pub temp_from: Option<TempFrom>,
    /// The gyro the calibration a command reads the log for was fitted on (its
    /// `source.instance`, set by `evaluate`, `apply` and `report`): read when `--gyro` is
    /// not given. No option of its own.
    #[arg(skip)]
    pub fitted_on: Option<driftlab::log::DroneGyro>,
}

impl FormatArgs {
    /// The engine's choice for these arguments.
    pub fn choice(&self) -> FormatChoice {
        FormatChoice {
            gyro: self.gyro,
            temp_from: self.temp_from,
            fitted_on: self.fitted_on.clone(),
        }
    }
}

/// The command-line flag of a read setting the engine names (`rate_col` → `--rate-col`): the
/// settings of [`ReadOptions`] and of [`FormatChoice`]; a setting without a flag keeps its name.
pub fn flag_of(setting: &'static str) -> &'static str {
    match setting {
        "time_col" => "--time-col",
        "rate_col" => "--rate-col",
        "temp_col" => "--temp-col",
        "rate_unit" => "--rate-unit",
        "time_unit" => "--time-unit",
        "sample_rate_hz" => "--sample-rate",
        "delimiter" => "--delimiter",
        "decimal_comma" => "--decimal-comma",
        "gyro" => "--gyro",
        "temp_from" => "--temp-from",
        other => other,
    }
}

/// The settings a reader's message may name, each with its flag: as [`flag_of`], and the
/// bin length of `--bin`. `gyro` is named with its value's placeholder (`gyro N`), because
/// the word alone is also the reader's word for a gyro; the separator's name is an everyday
/// word too, and the reader does not name it as a setting.
const SETTING_FLAGS: [(&str, &str); 10] = [
    ("time_col", "--time-col"),
    ("rate_col", "--rate-col"),
    ("temp_col", "--temp-col"),
    ("rate_unit", "--rate-unit"),
    ("time_unit", "--time-unit"),
    ("sample_rate_hz", "--sample-rate"),
    ("decimal_comma", "--decimal-comma"),
    ("temp_from", "--temp-from"),
    ("gyro N", "--gyro N"),
    ("bin_s", "--bin"),
];

/// A message of the reader (an error, a problem it worked around, a note on the gyro it
/// chose) in the command line's words: the settings it names are named by their flags
/// (`temp_col "temp_C"` → `--temp-col "temp_C"`).
pub fn in_flags(message: &str) -> String {
    read::reworded(message, &SETTING_FLAGS)
}

/// The problems the reader worked around in `log`, in the command line's words, as every
/// command prints them (`inspect` both as text and as JSON).
pub fn problems_in_flags(log: &mut Log) {
    for p in &mut log.info.problems {
        p.message = in_flags(&p.message);
    }
}

/// The engine's refusal of a read in the command line's words: the options it names by their
/// settings are named by their flags.
pub fn worded(e: ReadError) -> String {
    let flags = |settings: &[&'static str]| -> Vec<&'static str> {
        settings.iter().map(|s| flag_of(s)).collect()
    };
    match e {
        ReadError::ChoiceOnCsv { path, settings } => {
            let given = flags(&settings);
            format!(
                "{path}: {} choose{} what is read from a drone or robot log (its gyro, its \
                 temperature source) (PX4 ULog, ArduPilot DataFlash, ROS bag, MCAP); this file \
                 is none of them (a CSV's columns are chosen with --rate-col, --temp-col)",
                given.join(" and "),
                if given.len() == 1 { "s" } else { "" }
            )
        }
        ReadError::CsvOptionsOnDroneLog {
            path,
            format,
            settings,
        } => {
            let given = flags(&settings);
            format!(
                "{path}: a {format} log has its format's own channels and units: {} do{} not \
                 apply to it (choose its gyro with --gyro N and --temp-from)",
                given.join(", "),
                if given.len() == 1 { "es" } else { "" }
            )
        }
        ReadError::NoTemperature { path } => format!(
            "{path}: --temp-from none leaves the log without a temperature: only `driftlab \
             allan` reads such a log (use --temp-from accel or imu-status, see `driftlab \
             inspect`)"
        ),
        other => in_flags(&other.to_string()),
    }
}

/// The drone-log format of `path`, refusing the options that do not fit the kind of file:
/// `--gyro`/`--temp-from` on a CSV, the CSV options on a drone log, each by name.
///
/// # Errors
/// The file cannot be opened, or options that do not apply.
pub fn check(args: &LogArgs, path: &Path, opts: &ReadOptions) -> Result<Option<Format>, String> {
    read::check_options(path, opts, &args.format.choice()).map_err(worded)
}

/// Prints what the format reader and the choice of gyro said, on standard error.
pub fn print_notes(drone: &DroneLog, log: &Log) {
    for p in &drone.problems {
        note!("warning: {}: {}", log.source, in_flags(&p.to_string()));
    }
    note!("note: {}", in_flags(&drone.note));
    for p in &log.info.problems {
        // A count only when there are several and the message does not give it.
        let times = p.times();
        note!("warning: {}: {}{times}", log.source, p.message);
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
    let Some(mut any) = read::read_drone_log(path, opts, &args.format.choice(), needs_temperature)
        .map_err(worded)?
    else {
        return Ok(None);
    };
    let drone = any.drone.ok_or("a drone log read as a CSV")?;
    problems_in_flags(&mut any.log);
    print_notes(&drone, &any.log);
    Ok(Some((any.log, drone)))
}
