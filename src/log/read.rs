//! The reader of every format ([`read_any`]; `ingest/read.rs` is the CSV reader's pipeline
//! only). Any log driftlab reads, told by its first bytes: a test-stand CSV through
//! [`super::ingest`], or a drone or robot log (PX4 ULog, ArduPilot DataFlash, ROS 1
//! bag, MCAP) through [`super::formats`], turned into the same [`Log`].
//!
//! A drone log holds several IMUs; one gyro instance becomes the log ([`FormatChoice`]:
//! `--gyro N`, `--temp-from`, by default the first whose temperature has a finite value, with a
//! note saying which):
//!
//! | `Log` field | from the instance |
//! |---|---|
//! | `time_s` | the format's own time stamp (ULog `timestamp`, DataFlash `TimeUS`, ROS `header.stamp`), s |
//! | `omega_dph`, `axis` | gyro x, rad/s → °/h, axis `gyro_x` |
//! | `other_axes` | gyro y and z, °/h, axes `gyro_y`, `gyro_z` |
//! | `temp_c` | the instance's temperature (or the one `--temp-from` names), °C |
//! | `extra` | the accelerometer axes `accel_x_m_s2` … in m/s², when the instance has them |
//!
//! The names are those of the CSV `driftlab convert` writes for the same instance, so a
//! calibration that reads a channel by name applies to either. Rows whose gyro axes or
//! temperature are NaN are dropped, and so are rows whose time does not increase, as the CSV
//! reader drops them (one pass, [`super::kept_samples`], which `driftlab convert` goes
//! through too, so that its CSV holds the same samples); each is reported in
//! [`LogInfo::problems`] with the 1-based sample number in the instance as its `line`. What the format reader noticed (dropouts, a cut last
//! message) is in [`DroneLog::problems`] with its byte offset.

use super::formats::{self, Format, FormatError, ImuRecording, InstanceSummary, SelectionError};
use super::ingest::{self, IngestError, ReadOptions};
use super::kept_samples::{KeptSamples, kept_samples};
use super::{Axis, AxisKind, Channel, ColumnInfo, ColumnRole, DroneGyro, Log, LogInfo, Problem};
use std::path::Path;

pub use super::formats::TempFrom;

/// Which gyro of a drone or robot log, and which temperature (the CSV reader takes neither).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FormatChoice {
    /// The instance (as [`ImuRecording::instances`] numbers them); `None`: the first whose
    /// temperature (of `temp_from`'s kind) has a finite value.
    pub gyro: Option<usize>,
    /// Where the temperature comes from; `None`: the gyro's own.
    pub temp_from: Option<TempFrom>,
    /// The gyro the calibration a log is read for was fitted on (its `source.instance`): read
    /// when `gyro` is `None`, and named in the note when `gyro` is another. Not a setting the
    /// user gave, so a CSV is read without a word about it.
    pub fitted_on: Option<DroneGyro>,
}

impl FormatChoice {
    /// True when nothing was chosen.
    pub fn is_default(&self) -> bool {
        *self == FormatChoice::default()
    }

    /// The settings chosen, by their names (`gyro`, `temp_from`): none applies to a CSV.
    pub fn settings_set(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        if self.gyro.is_some() {
            v.push("gyro");
        }
        if self.temp_from.is_some() {
            v.push("temp_from");
        }
        v
    }
}

/// The gyro and temperature of a drone or robot log the engineer chose, as a session keeps
/// them: [`FormatChoice`] less what a calibration says (`fitted_on`), which is not a choice.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InstanceChoice {
    /// The gyro instance (as `inspect` numbers them); `None`: the reader's default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gyro: Option<usize>,
    /// Where the temperature comes from; `None`: the gyro's own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temp_from: Option<TempFrom>,
}

impl InstanceChoice {
    /// True when nothing was chosen (a CSV, or a drone log read as by default).
    pub fn is_default(&self) -> bool {
        *self == InstanceChoice::default()
    }

    /// The reader's choice.
    pub fn format_choice(self) -> FormatChoice {
        FormatChoice {
            gyro: self.gyro,
            temp_from: self.temp_from,
            fitted_on: None,
        }
    }
}

/// A message of the reader in a face's words: the reader names the settings of
/// [`ReadOptions`] and [`FormatChoice`] as the code does (`temp_col "temp_C"`, `gyro N`), and
/// each face words them as its own controls are named (a flag, a label). `words` pairs a
/// setting's name with the face's word; only whole names are replaced, so `temp_col` inside
/// `temp_col_2` or `gyro` in `gyro 1` stay as they are.
pub fn reworded(message: &str, words: &[(&str, &str)]) -> String {
    let part_of_name = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = String::with_capacity(message.len());
    let mut before: Option<char> = None;
    let mut rest = message;
    'scan: while let Some(c) = rest.chars().next() {
        if !before.is_some_and(part_of_name) {
            for &(setting, word) in words {
                if let Some(after) = rest.strip_prefix(setting)
                    && !after.chars().next().is_some_and(part_of_name)
                {
                    out.push_str(word);
                    before = setting.chars().last();
                    rest = after;
                    continue 'scan;
                }
            }
        }
        out.push(c);
        before = Some(c);
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// What a drone or robot log was, beyond the [`Log`] made of one of its gyros.
#[derive(Debug, Clone)]
pub struct DroneLog {
    /// The format its magic bytes said.
    pub format: Format,
    /// Every gyro instance of the file (what `inspect` lists).
    pub instances: Vec<InstanceSummary>,
    /// The instance the log holds.
    pub chosen: usize,
    /// Which gyro and temperature were chosen, and why, in a sentence.
    pub note: String,
    /// What the format reader worked around, with byte offsets.
    pub problems: Vec<formats::Problem>,
}

/// A log as read, and what it was when it was a drone or robot log.
#[derive(Debug, Clone)]
pub struct AnyLog {
    /// The log.
    pub log: Log,
    /// `None` for a CSV.
    pub drone: Option<DroneLog>,
}

/// Why a log could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// A CSV that could not be read (file, line and column).
    #[error(transparent)]
    Ingest(#[from] IngestError),
    /// A drone or robot log that could not be read (file and byte offset).
    #[error(transparent)]
    Format(#[from] FormatError),
    /// No gyro (or temperature) of the log can be used as asked; the alternatives named.
    #[error(transparent)]
    Selection(#[from] SelectionError),
    /// A gyro or temperature chosen (`settings`: `gyro`, `temp_from`) for a file that is no
    /// drone or robot log.
    #[error(
        "{path}: {} choose{} an instance of a drone or robot log (PX4 ULog, ArduPilot \
         DataFlash, ROS bag, MCAP); this file is none of them (a CSV is read by its columns: \
         time_col, rate_col, temp_col)",
        settings.join(" and "),
        if settings.len() == 1 { "s" } else { "" }
    )]
    ChoiceOnCsv {
        /// The file.
        path: String,
        /// The settings given, by their names in [`FormatChoice`].
        settings: Vec<&'static str>,
    },
    /// CSV options (`settings`, by their names in [`ReadOptions`]) given for a drone or robot
    /// log, whose channels and units are its format's own.
    #[error(
        "{path}: a {format} log has its format's own channels and units: {} do{} not apply to \
         it (choose the gyro with gyro and temp_from)",
        settings.join(", "),
        if settings.len() == 1 { "es" } else { "" }
    )]
    CsvOptionsOnDroneLog {
        /// The file.
        path: String,
        /// Its format.
        format: Format,
        /// The CSV options set, by their names in [`ReadOptions`].
        settings: Vec<&'static str>,
    },
    /// `temp_from` none for a reader that needs a temperature (every use but noise analysis).
    #[error(
        "{path}: temp_from none leaves the log without a temperature, which only noise \
         analysis reads (choose temp_from accel or imu-status)"
    )]
    NoTemperature {
        /// The file.
        path: String,
    },
    /// The chosen gyro has no sample left once the unusable ones are dropped.
    #[error("{path}: {message}")]
    NoSamples {
        /// The file.
        path: String,
        /// Why none is left.
        message: String,
    },
    /// No gyro was asked for, and the log has none the calibration it is read for was
    /// fitted on.
    #[error("{path}: {message}")]
    NoFittedGyro {
        /// The file.
        path: String,
        /// The gyro fitted on, and the log's gyros.
        message: String,
    },
    /// Most of the chosen gyro's samples go back in time: the log is not in time order.
    #[error("{path}: {message}")]
    NotInTimeOrder {
        /// The file.
        path: String,
        /// How many go back, and the first.
        message: String,
    },
    /// The chosen gyro's samples switch back and forth between two clocks: two recorders'
    /// samples interleaved ([`crate::signal::interleaved`]).
    #[error("{path}: {message}")]
    TwoClocks {
        /// The file.
        path: String,
        /// Where the samples first switch clock, and how to part them.
        message: String,
    },
}

/// The CSV options set in `opts`, by their names in a recipe: none of them applies to a
/// drone log, whose columns and units are its format's own.
pub fn csv_options_set(opts: &ReadOptions) -> Vec<&'static str> {
    let mut v = Vec::new();
    let mut flag = |set: bool, name| {
        if set {
            v.push(name);
        }
    };
    flag(opts.time_col.is_some(), "time_col");
    flag(opts.rate_col.is_some(), "rate_col");
    flag(opts.temp_col.is_some(), "temp_col");
    flag(opts.rate_unit.is_some(), "rate_unit");
    flag(opts.time_unit.is_some(), "time_unit");
    flag(opts.sample_rate_hz.is_some(), "sample_rate_hz");
    flag(opts.delimiter.is_some(), "delimiter");
    flag(opts.decimal_comma.is_some(), "decimal_comma");
    flag(opts.has_header.is_some(), "has_header");
    v
}

/// The drone-log format of the file at `path`, or `None` for anything else (a CSV).
///
/// # Errors
/// The file cannot be opened or read.
pub fn drone_format(path: &Path) -> Result<Option<Format>, FormatError> {
    formats::sniff_path(path)
}

/// The drone-log format of the file at `path` (`None` for a CSV), refusing the options that
/// do not fit its kind: a gyro or temperature choice for a CSV, CSV options for a drone log.
///
/// # Errors
/// The file cannot be opened, or options of one kind of file given for the other.
pub fn check_options(
    path: &Path,
    opts: &ReadOptions,
    choice: &FormatChoice,
) -> Result<Option<Format>, ReadError> {
    let name = || path.display().to_string();
    let format = drone_format(path)?;
    match format {
        None => {
            let settings = choice.settings_set();
            if !settings.is_empty() {
                return Err(ReadError::ChoiceOnCsv {
                    path: name(),
                    settings,
                });
            }
        }
        Some(format) => {
            let settings = csv_options_set(opts);
            if !settings.is_empty() {
                return Err(ReadError::CsvOptionsOnDroneLog {
                    path: name(),
                    format,
                    settings,
                });
            }
        }
    }
    Ok(format)
}

/// Reads `path` when it is a drone or robot log: one gyro as `choice` says, as recorded
/// ([`from_recording`]); `None` for a CSV, which the caller reads as it reads CSV (with
/// progress, from a stream). `needs_temperature`: refuse `temp_from` none, which leaves the
/// log without the temperature every use but noise analysis needs.
///
/// # Errors
/// As [`check_options`], [`ReadError::NoTemperature`], a file that cannot be read, no gyro
/// as asked.
pub fn read_drone_log(
    path: &Path,
    opts: &ReadOptions,
    choice: &FormatChoice,
    needs_temperature: bool,
) -> Result<Option<AnyLog>, ReadError> {
    if check_options(path, opts, choice)?.is_none() {
        return Ok(None);
    }
    if needs_temperature && choice.temp_from == Some(TempFrom::None) {
        return Err(ReadError::NoTemperature {
            path: path.display().to_string(),
        });
    }
    let rec = formats::read_path(path)?;
    from_recording(&rec, opts.skip_extras, choice).map(Some)
}

/// Reads the log at `path`, whatever its format, as every face does by default: a CSV as
/// [`ingest::read_path`] reads it, a drone or robot log's first gyro with a temperature (as
/// [`read_any`] chooses with the default [`FormatChoice`]). The library's front door,
/// `driftlab::read_path`.
///
/// # Errors
/// As [`read_any`].
pub fn read_path(path: &Path, opts: &ReadOptions) -> Result<Log, ReadError> {
    Ok(read_any(path, opts, &FormatChoice::default())?.log)
}

/// Reads any log driftlab reads: a CSV as [`ingest::read_path`] does (`choice` must then be
/// the default), a drone or robot log as [`from_recording`] makes it (`opts` must then set
/// no CSV option; `skip_extras` leaves the accelerometer out).
///
/// # Errors
/// The file cannot be read or is malformed (with line and column, or byte offset), options
/// that do not apply to the kind of file, or no usable gyro as asked.
pub fn read_any(
    path: &Path,
    opts: &ReadOptions,
    choice: &FormatChoice,
) -> Result<AnyLog, ReadError> {
    read_any_with_progress(path, opts, choice, &|_| true)
}

/// [`read_any`], telling `progress` the share read of a CSV (a drone log is read whole at
/// once, in a fraction of a second per 100 MB).
///
/// # Errors
/// As [`read_any`], and `cancelled` when `progress` returns false.
pub fn read_any_with_progress(
    path: &Path,
    opts: &ReadOptions,
    choice: &FormatChoice,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<AnyLog, ReadError> {
    match read_drone_log(path, opts, choice, false)? {
        Some(any) => Ok(any),
        None => Ok(AnyLog {
            log: ingest::read_path_with_progress(path, opts, progress)?,
            drone: None,
        }),
    }
}

/// The angular rate of a drone log (rad/s) in driftlab's °/h: the factor the CSV reader uses
/// for a column in rad/s.
pub(crate) fn rad_s_to_dph() -> f64 {
    ingest::RateUnit::RadPerSec.to_dph_factor()
}

/// Names of the gyro axes as a log made from a drone log calls them (the columns of the CSV
/// `driftlab convert` writes, without their unit).
pub const GYRO_AXES: [&str; 3] = ["gyro_x", "gyro_y", "gyro_z"];

/// Names of the accelerometer channels a log made from a drone log keeps in `extra` (the
/// columns of the CSV `driftlab convert` writes).
pub const ACCEL_CHANNELS: [&str; 3] = ["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"];

/// The unit of [`ACCEL_CHANNELS`].
pub const ACCEL_UNIT: &str = super::ACCEL_UNIT_M_S2;

/// One gyro instance of a recording as a [`Log`]: the instance and temperature `choice`
/// names (see the module documentation for the mapping), without the accelerometer when
/// `skip_extras`.
///
/// # Errors
/// No instance or temperature as asked (the alternatives named), or no sample left once the
/// unusable ones are dropped.
pub fn from_recording(
    rec: &ImuRecording,
    skip_extras: bool,
    choice: &FormatChoice,
) -> Result<AnyLog, ReadError> {
    let (gyro, fitted_note) = gyro_for_calibration(rec, choice)?;
    let sel = formats::select(rec, gyro, choice.temp_from)?;
    let inst = sel.instance;
    let n = inst.len();
    let to_dph = rad_s_to_dph();
    let KeptSamples {
        rows,
        time_s,
        problems,
    } = kept_samples(&sel)?;
    let pick = |v: &formats::Values, scale: f64| -> Vec<f64> {
        rows.iter().map(|&i| v.get(i) * scale).collect()
    };

    let [gx, gy, gz] = &inst.gyro.xyz;
    let mut columns = vec![
        column(1, "time_s", ColumnRole::Time, "s"),
        column(2, "gyro_x_rad_s", ColumnRole::Rate, "rad/s"),
        column(3, "gyro_y_rad_s", ColumnRole::Rate, "rad/s"),
        column(4, "gyro_z_rad_s", ColumnRole::Rate, "rad/s"),
        column(5, "temp_c", ColumnRole::Temperature, "°C"),
    ];
    let mut extra = Vec::new();
    if let Some(acc) = &inst.accel {
        for (k, (v, name)) in acc.xyz.iter().zip(ACCEL_CHANNELS).enumerate() {
            if skip_extras {
                columns.push(column(6 + k, name, ColumnRole::Ignored, ACCEL_UNIT));
            } else {
                columns.push(column(6 + k, name, ColumnRole::Extra, ACCEL_UNIT));
                extra.push(Channel {
                    name: name.to_string(),
                    unit: ACCEL_UNIT.to_string(),
                    values: pick(v, 1.0),
                });
            }
        }
    }
    let mut log = Log {
        source: rec.source.clone(),
        time_s,
        omega_dph: pick(gx, to_dph),
        temp_c: pick(&sel.temp_c, 1.0),
        extra,
        axis: GYRO_AXES[0].to_string(),
        axis_kind: AxisKind::Gyro,
        other_axes: vec![
            Axis {
                name: GYRO_AXES[1].to_string(),
                omega_dph: pick(gy, to_dph),
                kind: AxisKind::Gyro,
            },
            Axis {
                name: GYRO_AXES[2].to_string(),
                omega_dph: pick(gz, to_dph),
                kind: AxisKind::Gyro,
            },
        ],
        info: LogInfo {
            delimiter: ',',
            decimal_comma: false,
            has_header: false,
            columns,
            rows_read: n,
            problems,
            instance: Some(drone_gyro(inst)),
            runs: Vec::new(),
        },
    };
    let doubts = super::ingest::plausibility_problems(&log);
    log.info
        .problems
        .extend(doubts.into_iter().map(|p| Problem {
            message: in_flight_log_terms(&p.message, other_temperatures(rec, sel.temp_from)),
            ..p
        }));
    Ok(AnyLog {
        log,
        drone: Some(DroneLog {
            format: rec.format,
            instances: rec.summaries(),
            chosen: inst.index,
            note: match fitted_note {
                // Chosen for the user, not asked for: said so, and how to choose another.
                Some(FittedNote::Chose { by_number }) => sel.note.replacen(
                    "(as asked)",
                    &format!(
                        "(the gyro the calibration was fitted on, its source.instance{}; \
                         gyro N chooses another)",
                        by_number.map_or(String::new(), |why| format!(", {why}"))
                    ),
                    1,
                ),
                Some(FittedNote::Differs(n)) => format!("{}; {n}", sel.note),
                None => sel.note.clone(),
            },
            problems: rec.problems.clone(),
        }),
    })
}

/// How a calibration file records `inst` (`source.instance`): its number and what its
/// format calls it.
fn drone_gyro(inst: &formats::GyroInstance) -> DroneGyro {
    let mut g = DroneGyro::numbered(inst.index);
    match &inst.device {
        Some(formats::DeviceId::DataFlash { instance }) => g.dataflash_imu = Some(*instance),
        Some(formats::DeviceId::Ulog { device_id }) => {
            g.px4_device_id = Some(*device_id);
            g.px4_accel_device_id = inst.accel_device_id.filter(|a| a != device_id);
        }
        Some(formats::DeviceId::Ros { topic, frame_id }) => {
            g.ros_topic = Some(topic.clone());
            g.ros_frame_id = Some(frame_id.clone());
        }
        None => {}
    }
    g
}

/// What the record of the gyro a calibration was fitted on did to the choice of gyro.
enum FittedNote {
    /// No gyro was asked for: the recorded one was read, found by what its format calls it
    /// (`by_number: None`), or by its number alone, for the reason given.
    Chose { by_number: Option<String> },
    /// Another gyro was asked for and read: the sentence saying which was fitted on.
    Differs(String),
}

/// The gyro of `rec` that `fitted` names, and, when it was found by its number alone, why:
/// by what the format calls it when the record holds that and the log's gyros have it in the
/// same kind (a PX4 `device_id` is looked for among `device_id`s); by number when the record
/// holds no identity (a calibration file written before driftlab recorded one) or the log's
/// gyros have none of its kind (another format, a ULog without `device_id`).
///
/// # Errors
/// The gyros that all answer to the recorded identity, when more than one does (two PX4
/// gyros reporting one `device_id`): which of them was fitted on cannot be told.
fn find_fitted(
    rec: &ImuRecording,
    fitted: &DroneGyro,
) -> Result<(Option<usize>, Option<String>), Vec<usize>> {
    let gyros: Vec<DroneGyro> = rec.instances.iter().map(drone_gyro).collect();
    if let Some(recorded) = fitted.identity()
        && gyros
            .iter()
            .any(|g| g.identity().is_some_and(|id| id.same_kind(&recorded)))
    {
        let found: Vec<usize> = gyros
            .iter()
            .filter(|g| g.same_gyro(fitted))
            .map(|g| g.index)
            .collect();
        return match found[..] {
            [] => Ok((None, None)),
            [k] => Ok((Some(k), None)),
            _ => Err(found),
        };
    }
    let found = gyros.iter().find(|g| g.index == fitted.index);
    let why = match (found.and_then(DroneGyro::identity), fitted.identity()) {
        (Some(_), None) => Some(
            "found by its number alone: the calibration file records no identity of the \
             chip (written before driftlab recorded one), so another chip at that number \
             would not be told apart"
                .to_string(),
        ),
        (_, Some(id)) => Some(format!(
            "found by its number alone: the calibration records {id}, and this log names \
             its gyros otherwise"
        )),
        (None, None) => None,
    };
    Ok((found.map(|g| g.index), why))
}

/// The gyro to read of `rec` for `choice`, with a note when a calibration's record of the
/// gyro it was fitted on ([`FormatChoice::fitted_on`]) chose it or differs from the gyro
/// asked for. Without a choice, another gyro than the one calibrated would be read and its
/// figures shown as the calibration's; with one, the user may well mean another gyro (a
/// held-out IMU of the same board), so it is read, and the difference said.
///
/// # Errors
/// No gyro asked for, and the log has none the calibration was fitted on: any other would
/// be a stranger's, and which one cannot be guessed.
fn gyro_for_calibration(
    rec: &ImuRecording,
    choice: &FormatChoice,
) -> Result<(Option<usize>, Option<FittedNote>), ReadError> {
    let Some(fitted) = &choice.fitted_on else {
        return Ok((choice.gyro, None));
    };
    let fitted_words = fitted.describe();
    let (found, by_number) = match (find_fitted(rec, fitted), choice.gyro) {
        (Ok(found), _) => found,
        // One of them asked for: read, as any gyro asked for is.
        (Err(_), Some(g)) => return Ok((Some(g), None)),
        (Err(several), None) => {
            let id = fitted
                .identity()
                .map_or_else(|| fitted_words.clone(), |id| id.to_string());
            return Err(ReadError::NoFittedGyro {
                path: rec.source.clone(),
                message: format!(
                    "the calibration was fitted on {fitted_words} (its source.instance), and \
                     gyros {} of this log all report {id}: which of them it was fitted on \
                     cannot be told; choose the gyro to read with gyro N",
                    several
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join(" and ")
                ),
            });
        }
    };
    match (choice.gyro, found) {
        (None, Some(k)) => Ok((Some(k), Some(FittedNote::Chose { by_number }))),
        (None, None) => Err(ReadError::NoFittedGyro {
            path: rec.source.clone(),
            message: format!(
                "the calibration was fitted on {fitted_words} (its source.instance), and this \
                 log has no such gyro (it has {}): choose the gyro to read with gyro N",
                rec.instances
                    .iter()
                    .map(|i| drone_gyro(i).describe())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }),
        (Some(g), Some(k)) if g == k => Ok((Some(g), None)),
        (Some(g), _) => Ok((
            Some(g),
            Some(FittedNote::Differs(format!(
                "but the calibration was fitted on {fitted_words}{} (its source.instance): \
                 what is read is another gyro than the one calibrated",
                match found {
                    Some(k) => format!(", gyro {k} of this log"),
                    None => ", which this log does not have".to_string(),
                }
            ))),
        )),
    }
}

/// The `temp_from` choices other than `chosen` that some gyro of `rec` has numbers for.
fn other_temperatures(rec: &formats::ImuRecording, chosen: TempFrom) -> Vec<TempFrom> {
    [TempFrom::Own, TempFrom::Accel, TempFrom::ImuStatus]
        .into_iter()
        .filter(|&f| f != chosen)
        .filter(|&f| {
            rec.instances.iter().any(|i| match f {
                TempFrom::Own => i.temp_c.has_numbers(),
                f => i.alt_temp(f).is_some_and(|a| a.values.has_numbers()),
            })
        })
        .collect()
}

/// A doubt of the CSV checks about a log made of a flight log's gyro, with the remedies a
/// flight log has: its columns are the format's own, so where the CSV reader would say to
/// choose another column or unit, another gyro (`gyro`) or temperature (`temp_from`, when the
/// log has another: `others`) is what can be chosen.
fn in_flight_log_terms(message: &str, others: Vec<TempFrom>) -> String {
    let temperature = if others.is_empty() {
        "the log holds no other temperature to choose: this one is not in °C as its format \
         says, and no calibration can be made against it"
            .to_string()
    } else {
        let names: Vec<&str> = others.iter().map(|f| f.option_name()).collect();
        format!(
            "choose another of the log's temperatures with temp_from ({})",
            names.join(", ")
        )
    };
    [
        (
            "choose the temperature column with temp_col NAME",
            temperature.as_str(),
        ),
        (
            "check its unit (rate_unit) or choose another column (rate_col)",
            "check the gyro chosen (gyro N; inspect lists them)",
        ),
        (
            "or choose another temperature with temp_col",
            "or choose another temperature with temp_from",
        ),
    ]
    .iter()
    .fold(message.to_string(), |m, (csv, flight)| {
        m.replace(csv, flight)
    })
}

fn column(index: usize, name: &str, role: ColumnRole, unit: &str) -> ColumnInfo {
    ColumnInfo {
        index,
        name: name.to_string(),
        role,
        unit: unit.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::reworded;

    #[test]
    fn only_whole_setting_names_are_reworded() {
        let words = [
            ("temp_col", "Temperature column"),
            ("gyro N", "The gyro control"),
        ];
        assert_eq!(
            reworded("choose it with temp_col \"temp_col_2\"", &words),
            "choose it with Temperature column \"temp_col_2\""
        );
        assert_eq!(
            reworded("gyro 1 is the first of 2; gyro N picks another", &words),
            "gyro 1 is the first of 2; The gyro control picks another"
        );
        assert_eq!(reworded("my_temp_col °C", &words), "my_temp_col °C");
        assert_eq!(reworded("temp_col", &words), "Temperature column");
    }
}
