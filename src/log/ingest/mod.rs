//! The CSV reader: test-stand logs in any CSV dialect into a [`Log`].
//!
//! It reads CSV only. The drone and robot logs (PX4 ULog, ArduPilot DataFlash, ROS bag, MCAP)
//! are read by [`super::formats`], and [`crate::log::read::read_any`] is the reader of every
//! format: it tells them apart by their first bytes and calls this module for a CSV. The
//! crate's `driftlab::read_path` is its front door; this module's [`read_path`] reads CSV
//! only.
//!
//! Thermal-chamber stands write CSV in many dialects: comma, semicolon, tab or aligned
//! columns; decimal points or (Russian and European stands) decimal commas; with or without
//! a header; rates in °/h, °/s or rad/s; time in s, ms, minutes or as a sample counter.
//! This module tells the dialect from the first lines, maps columns by name (or by the
//! options), converts every calibration column to driftlab's units (time s, rate °/h,
//! temperature °C) and reports, rather than hides, what was wrong with the file: a cell that
//! cannot be read stops the read with its file, line and column; blank cells, time going
//! backwards and gaps are worked around and listed in
//! [`LogInfo::problems`](crate::log::LogInfo::problems).
//!
//! # Column mapping
//!
//! * With a header, columns are found by name, case-insensitively and ignoring units:
//!   time (`time`, `t`, `sec`, `timestamp`, `Time [ms]`, `t_min`, a sample counter such as
//!   `sample` or `n`), rate (`omega`, `rate`, `gyro`, `drift`, `w`, `omega_dph`,
//!   `gyro_x_rad_s`, `Rate (deg/s)`...), temperature (`temp`, `temperature`, `t_c`,
//!   `Temp [°C]`, `T1`...). The first temperature column is the calibration temperature;
//!   every other numeric column is kept by name in [`Log::extra`] (other temperatures
//!   converted to °C). `rate` and a bare `w` name a gyro's rate only alone, with notes or
//!   beside an angular rate's unit (`rate_x`, `rate_dps`): a chamber's channels hold them
//!   too (`coolant_flow_rate_lpm`, `heater_power_w`), and stay channels.
//! * Without a header, column 1 is time, 2 the rate and 3 the temperature, unless the
//!   options map them; a two-column file without a header is rate and temperature and needs
//!   [`ReadOptions::sample_rate_hz`].
//! * [`ReadOptions::time_col`], `rate_col` and `temp_col` (a name or a 1-based index)
//!   always override guessing.
//! * A file of one column is not a log (it has no temperature); [`read_rate_series`] reads it
//!   as a bare rate series, for noise analysis (`driftlab allan`).
//!
//! # Units
//!
//! Units are read from the column names (`omega_dph`, `gyro_x_rad_s`, `Rate [deg/s]`,
//! `time_ms`, `t [min]`, `Temp [K]`) and can be overridden with
//! [`ReadOptions::rate_unit`] and [`ReadOptions::time_unit`]; without either, rate is in
//! °/h and time in seconds. A temperature is read in °C, K, °F or tenths, hundredths or
//! thousandths of a degree Celsius (`d°C`, `c°C`, `m°C`) as its name states; there is no
//! setting for it, and a name stating a unit of another quantity (`temp [V]`) is refused. The
//! unit each column was read in is recorded in [`ColumnInfo::unit`].
//!
//! # What is an error and what is a problem
//!
//! A calibration must not be fitted on numbers the reader made up, so:
//!
//! * a cell of the time, rate or temperature column that is not a number, or a row too short
//!   to have one, stops the read with an [`IngestError`] at that line and column;
//! * a blank, `NaN` (or `NA`, `null`, infinite) cell in one of those columns drops the row:
//!   `MissingValue`, with the first line and the count;
//! * a time equal to or below an earlier one drops the row (`TimeRepeated`,
//!   `TimeBackwards`); a step above 2.5 × the median step is a `Gap` (rows kept);
//! * a time column whose step is shorter than a gigahertz's or whose span is past the largest
//!   number stops the read; one that spans longer than any chamber run, or steps by more than a
//!   day, is `Implausible`, with the unit its numbers fit (`time_scale.rs`);
//! * in an extra column, blanks are NaN silently; unreadable cells are NaN and reported
//!   (`BadExtraValue`, naming the column), and a row too short for an extra column is a
//!   `RaggedRow`. A column that is mostly text is `Ignored`. Extra trailing fields are fine.
//!
//! # Speed
//!
//! Files are never held whole in memory (a stream that can be read only once, standard input
//! or a FIFO, is, up to [`MAX_STREAM_BYTES`]: see [`Input`]): they are read in blocks of a few
//! MB cut at line ends, parsed in parallel (rayon) and stitched together in order, with exact
//! line numbers. Only the columns the caller uses are parsed and held ([`Needs`]).
//! Plain numeric rows take a fast path (memchr + fast-float); quoted, blank or odd rows a
//! careful one; a file whose quoted fields span lines is read again sequentially.

mod checks;
mod columns;
pub(crate) mod names;
mod option_error;
mod parse;
mod plausible;
pub(crate) use columns::CORRECTED_LOG_RATES;
pub(crate) use plausible::check as plausibility_problems;
mod read;
mod record;
mod series;
mod sniff;
mod time_scale;
mod units;

pub use option_error::OptionError;
pub use series::{RateSeries, read_rate_series};
pub use time_scale::STATED_UNIT_LONGEST_S;

use std::io::Read;
use std::path::PathBuf;
pub use units::{RateUnit, TimeUnit};
pub(crate) use units::{rate_factor_to_dph, temp_to_celsius};

use crate::log::{ColumnInfo, Log};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// More columns than this means the separator was misread (or the file is not a log).
pub(crate) const MAX_COLUMNS: usize = 4096;

/// A log that could not be read, with file, line and column, so that a test engineer can
/// open the file at the offending cell.
///
/// Displayed as `file:line:column: message`; the column (and the line) are left out when
/// they are 0, i.e. when the error is not about one cell (or one line).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IngestError {
    /// File name.
    pub file: String,
    /// 1-based line, 0 when not about a line.
    pub line: usize,
    /// 1-based column, 0 when not about a column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for IngestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.column) {
            (0, _) => write!(f, "{}: {}", self.file, self.message),
            (l, 0) => write!(f, "{}:{}: {}", self.file, l, self.message),
            (l, c) => write!(f, "{}:{}:{}: {}", self.file, l, c, self.message),
        }
    }
}

impl std::error::Error for IngestError {}

/// An error before the file name is attached.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Fail {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl Fail {
    pub(crate) fn new(line: usize, column: usize, message: String) -> Fail {
        Fail {
            line,
            column,
            message,
        }
    }

    /// An error about the whole file.
    pub(crate) fn file(message: impl Into<String>) -> Fail {
        Fail::new(0, 0, message.into())
    }

    pub(crate) fn at(self, file: &str) -> IngestError {
        IngestError {
            file: file.to_string(),
            line: self.line,
            column: self.column,
            message: self.message,
        }
    }
}

/// A column named in the options: recipes and the command line say `omega_dph` or `2`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ColumnRef {
    /// A header name, matched case-insensitively, with or without its unit
    /// (`omega` finds `Omega [deg/s]`); `col3` names the third column of a file without a
    /// header, and a number written as text (`"3"`) that matches no name is a column number.
    Name(String),
    /// A 1-based column number, for files without a header or with unhelpful names.
    Index(usize),
}

impl FromStr for ColumnRef {
    type Err = OptionError;
    /// `"3"` is the third column; anything else a name.
    fn from_str(s: &str) -> Result<Self, OptionError> {
        let t = s.trim();
        if t.is_empty() {
            return Err(OptionError::EmptyColumn);
        }
        Ok(match t.parse::<usize>() {
            Ok(i) => ColumnRef::Index(i),
            Err(_) => ColumnRef::Name(t.to_string()),
        })
    }
}

impl fmt::Display for ColumnRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ColumnRef::Index(i) => write!(f, "{i}"),
            ColumnRef::Name(n) => f.write_str(n),
        }
    }
}

/// Everything an engineer may have to tell the reader about a file; `None` fields are
/// sniffed or guessed, so the default reads most logs as they are. Recipes store these.
#[derive(Default, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReadOptions {
    /// The time column, when its name does not say so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_col: Option<ColumnRef>,
    /// The gyro rate column, when its name does not say so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rate_col: Option<ColumnRef>,
    /// The other gyro axes of a multi-axis unit, when their names do not say so (the rate
    /// columns after the first that `--rate-col` names); empty: every other column whose name
    /// reads as a rate.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub axis_cols: Vec<ColumnRef>,
    /// The calibration temperature, when there are several sensors or the name is unclear.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temp_col: Option<ColumnRef>,
    /// Unit of the rate column, when the header does not say or says it wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rate_unit: Option<RateUnit>,
    /// Unit of the time column, when the header does not say or says it wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_unit: Option<TimeUnit>,
    /// Sampling rate, Hz: needed when time is a sample index, or when the file has no time
    /// column at all (time is then the data row's index over this rate, counting rows that
    /// were dropped, so that gaps stay visible).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample_rate_hz: Option<f64>,
    /// Field separator, when sniffing gets it wrong; `b' '` means runs of blanks (aligned
    /// columns). Stored as a one-character string (`";"`, `"\t"`).
    #[serde(skip_serializing_if = "Option::is_none", with = "delimiter_serde")]
    pub delimiter: Option<u8>,
    /// Whether numbers use a decimal comma (`1,5`), when sniffing gets it wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decimal_comma: Option<bool>,
    /// Whether the first non-comment line is a header, when sniffing gets it wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub has_header: Option<bool>,
    /// Read only time, rate and temperature: other columns are neither parsed nor kept (they
    /// are listed as ignored), which saves their memory and parse time for a caller that needs
    /// just those three. A choice of the caller, not of the file: recipes do not store it.
    #[serde(skip)]
    pub skip_extras: bool,
}

/// What a caller uses of a log besides its time and rate, so that a read parses and holds no
/// more: which extra columns, and whether the temperature. A choice of the caller, not of the
/// file (recipes do not store it), beside the [`ReadOptions`] that say how to read the file.
///
/// The default is every column, and a temperature on every row, as [`Input::read`] reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Needs {
    /// Whether the log must have a calibration temperature, as every fit and judgement does.
    /// Without it (`false`: the noise analysis of `driftlab allan`, which reads the rate alone),
    /// a log with no temperature column is read with NaN for one, and a blank or NaN (or
    /// unreadable) temperature cell is NaN in a row that is kept, where it would drop the row.
    pub temperature: bool,
    /// The extra columns kept: `None`, every one (unless [`ReadOptions::skip_extras`] leaves
    /// them all out); else only those [`ExtraColumns`] names, the others neither parsed nor
    /// held (listed as ignored, as `skip_extras` lists them).
    pub extras: Option<ExtraColumns>,
}

impl Default for Needs {
    fn default() -> Needs {
        Needs {
            temperature: true,
            extras: None,
        }
    }
}

/// The extra columns a caller keeps when it uses only some of a log's ([`Needs::extras`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExtraColumns {
    /// Columns by their header name: the channels a model reads, its second temperature.
    pub names: Vec<String>,
    /// Every accelerometer axis ([`names_an_accelerometer`]): Kalibr's noise model reads them.
    pub accelerometers: bool,
    /// Every other temperature: a column whose name says `temp` or that is kept in °C (or in
    /// `degC`, `C`), the columns the report's temperature figure draws and among which a model
    /// guesses its second sensor.
    pub temperatures: bool,
}

impl ExtraColumns {
    /// Whether the extra column `name`, kept in `unit`, is one of these.
    pub fn keeps(&self, name: &str, unit: &str) -> bool {
        let u = unit.to_lowercase();
        self.names.iter().any(|n| n == name)
            || (self.accelerometers && names_an_accelerometer(name))
            || (self.temperatures
                && (name.to_lowercase().contains("temp")
                    || u.contains("°c")
                    || u == "degc"
                    || u == "c"))
    }
}

/// Whether a column's name reads as an accelerometer axis (`ax_g`, `acc_x`, `accel_x_m_s2`,
/// `linear_acceleration_x`), as `inspect` marks such a kept column.
pub fn names_an_accelerometer(name: &str) -> bool {
    names::is_accelerometer(name)
}

/// The words of a temperature column's name that say which sensor it reads, sorted (`chamber`
/// in `temp_chamber_c`, `t2` in `T2 [°C]`); none for a name that says only "the temperature"
/// or "the gyro's temperature" (`temp_c`, `Temperature [°C]`, `gyro_temp_c`). Two temperature
/// columns read one sensor when their words are the same: a campaign refuses runs whose
/// temperatures are other sensors ([`crate::log::campaign::join`]).
pub fn temperature_sensor(name: &str) -> Vec<String> {
    names::temperature_sensor_words(name)
}

/// Reads a separator as people write it on a command line or in a recipe: `,`, `;`, `\t`
/// or `tab`, `space` or `whitespace` (runs of blanks), or any single ASCII character.
///
/// # Errors
/// Anything else, with a message listing what is accepted.
pub fn parse_delimiter(s: &str) -> Result<u8, OptionError> {
    match s {
        "\\t" | "\t" => return Ok(b'\t'),
        " " => return Ok(b' '),
        _ => {}
    }
    match s.trim().to_ascii_lowercase().as_str() {
        "tab" => Ok(b'\t'),
        "space" | "spaces" | "whitespace" | "blank" | "blanks" => Ok(b' '),
        "comma" => Ok(b','),
        "semicolon" => Ok(b';'),
        t if t.len() == 1 && t.is_ascii() && !matches!(t, "\"" | "\n" | "\r" | "#") => {
            Ok(t.as_bytes()[0])
        }
        _ => Err(OptionError::Delimiter(s.to_string())),
    }
}

mod delimiter_serde {
    use serde::de::Error;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(d: &Option<u8>, s: S) -> Result<S::Ok, S::Error> {
        match d {
            Some(b) => s.serialize_some(&char::from(*b).to_string()),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u8>, D::Error> {
        match Option::<String>::deserialize(d)? {
            None => Ok(None),
            Some(s) => super::parse_delimiter(&s)
                .map(Some)
                .map_err(D::Error::custom),
        }
    }
}

/// What the reader would do with a file, for the import view: the GUI shows it so the
/// engineer can correct the mapping before a long read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Preview {
    /// Field separator (a blank for runs of blanks).
    pub delimiter: char,
    /// Whether numbers use a decimal comma.
    pub decimal_comma: bool,
    /// Whether the first non-comment line is a header.
    pub has_header: bool,
    /// Line of the header, 0 without one.
    pub header_line: usize,
    /// Column names (`colN` without a header).
    pub names: Vec<String>,
    /// The first data rows, cell by cell as text.
    pub rows: Vec<Vec<String>>,
    /// The file line of each row in `rows`.
    pub row_lines: Vec<usize>,
    /// Every column with the role and unit it would be read with.
    pub columns: Vec<ColumnInfo>,
    /// True when time would be the row index over `sample_rate_hz` (no time column).
    pub time_from_sample_rate: bool,
    /// Why the columns cannot be mapped with these options (roles then only say which
    /// columns are numeric); `None` when a read would start.
    pub mapping_error: Option<String>,
}

/// A log to read, opened once: a file by its path, read in blocks as often as the reader needs
/// (to sniff, to read, to read again sequentially), or the bytes of a source that gives them
/// only once (standard input named `-`, a FIFO, a character device, a socket), read whole
/// when it is opened. Opening such a source a second time would block until another writer
/// came, or find nothing; and its hash must be taken of the same bytes the log was read from
/// ([`Input::bytes`]).
///
/// A stream is held in memory while it is read (its size and about as much again for the
/// columns), and is read up to [`MAX_STREAM_BYTES`]; a file is not held.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Input {
    /// A regular file (or a path that is not there or is a folder, which the read reports).
    Path(PathBuf),
    /// The whole content of a source that can be read once.
    Bytes {
        /// How messages name it: the path, or `standard input`.
        name: String,
        /// What it gave.
        bytes: Vec<u8>,
    },
}

/// The first bytes of a stream, looked at before the rest is read: a stream that starts with a
/// NUL byte (`/dev/zero`, random bytes) is binary and is not read on forever.
const STREAM_HEAD: usize = 64 << 10;

/// The most a stream (standard input, a FIFO, a device) may give: 1 GiB. A stream that gives
/// more is refused at that point, with the bound and how to read a larger log: as a file.
///
/// Why this bound: a file is neither held nor memory-mapped. The reader takes it in blocks of
/// 4 MiB cut at line ends, a few blocks in flight at a time, and keeps only the columns it
/// parses, 8 bytes a value: whatever the file's size, its read holds its used columns and a few
/// MB of text. A stream cannot be opened again (to sniff, to read, to read again sequentially),
/// so its text is held whole, on top of those same columns. A row's text is about as long as
/// its columns are wide (the bundled `0,-0.2554,20.000,20.000` is 24 bytes, its four values
/// 32; 30 bytes a row of three columns in the benchmarks' 10-million-row log), so a stream's
/// read holds about its own size more than a file read of the same log keeps. The bound is
/// what a file read of the longest everyday logs keeps: 1 GiB of text is about 36 million rows
/// of time, rate and temperature (10 hours at 1 kHz), whose three columns take 0.8 GiB; a
/// stream up to that size costs at most about twice its file read, and a longer log is read as
/// a file, at the cost of its columns alone. Without a bound, an endless stream
/// (`yes 1,0.1,20 | driftlab inspect -`) was read until an allocation failed, at 2.1 GB.
pub const MAX_STREAM_BYTES: u64 = 1 << 30;

impl Input {
    /// Opens `path`: `-` is standard input; a FIFO, a device or a socket is read whole now;
    /// anything else is left to be read from its path.
    ///
    /// # Errors
    /// A stream that cannot be read, naming it.
    pub fn open(path: &Path) -> Result<Input, IngestError> {
        if path.as_os_str() == "-" {
            return Input::read_stream("standard input".into(), std::io::stdin().lock());
        }
        let name = path.display().to_string();
        match std::fs::metadata(path) {
            Ok(m) if !m.is_file() && !m.is_dir() => {
                let f = std::fs::File::open(path)
                    .map_err(|e| Fail::file(format!("cannot open: {e}")).at(&name))?;
                Input::read_stream(name, f)
            }
            _ => Ok(Input::Path(path.to_path_buf())),
        }
    }

    fn read_stream(name: String, r: impl Read) -> Result<Input, IngestError> {
        Input::read_stream_within(name, r, MAX_STREAM_BYTES)
    }

    /// [`Input::read_stream`] with a bound of `limit` bytes.
    fn read_stream_within(
        name: String,
        mut r: impl Read,
        limit: u64,
    ) -> Result<Input, IngestError> {
        let fail = |e: std::io::Error| Fail::file(format!("cannot read: {e}")).at(&name);
        let mut bytes = Vec::new();
        (&mut r)
            .take(STREAM_HEAD.min(limit as usize) as u64)
            .read_to_end(&mut bytes)
            .map_err(fail)?;
        // A binary head is refused by the reader from what is here already.
        if memchr::memchr(0, &bytes).is_some() {
            return Ok(Input::Bytes { name, bytes });
        }
        let limit = usize::try_from(limit).unwrap_or(usize::MAX);
        let mut block = vec![0u8; 1 << 16];
        loop {
            let n = match r.read(&mut block) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(fail(e)),
            };
            if n > limit - bytes.len() {
                return Err(Fail::file(format!(
                    "more than {}: a log from standard input, a pipe or a device is held in \
                     memory whole while it is read, and at most {0} of it is read; give a \
                     larger log as a file (save the stream to one), which is read in blocks and \
                     never held whole",
                    size_in_words(limit)
                ))
                .at(&name));
            }
            if bytes.capacity() - bytes.len() < n {
                // Grown by half at a time, never past the bound: an allocation of twice the
                // bound (a Vec's doubling) is not made for a stream the bound refuses.
                let to = (bytes.capacity() + bytes.capacity() / 2)
                    .max(bytes.len() + n)
                    .max(1 << 20)
                    .min(limit);
                bytes
                    .try_reserve_exact(to - bytes.len())
                    .map_err(|e| Fail::file(format!("cannot hold the stream: {e}")).at(&name))?;
            }
            bytes.extend_from_slice(&block[..n]);
        }
        Ok(Input::Bytes { name, bytes })
    }

    /// How messages name the input.
    pub fn name(&self) -> String {
        match self {
            Input::Path(p) => p.display().to_string(),
            Input::Bytes { name, .. } => name.clone(),
        }
    }

    /// The bytes of a stream (`None` for a file, which is read from its path).
    pub fn bytes(&self) -> Option<&[u8]> {
        match self {
            Input::Path(_) => None,
            Input::Bytes { bytes, .. } => Some(bytes),
        }
    }

    /// Reads the log, telling `progress` the fraction done as
    /// [`read_path_with_progress`] does.
    ///
    /// # Errors
    /// As [`read_path_with_progress`].
    pub fn read(
        &self,
        opts: &ReadOptions,
        progress: &(dyn Fn(f64) -> bool + Sync),
    ) -> Result<Log, IngestError> {
        self.read_needing(opts, &Needs::default(), progress)
    }

    /// Reads what the caller `needs` of the log (the extra columns it uses, whether it must
    /// have a temperature): the other columns are neither parsed nor held. As [`Input::read`]
    /// otherwise.
    ///
    /// # Errors
    /// As [`read_path_with_progress`].
    pub fn read_needing(
        &self,
        opts: &ReadOptions,
        needs: &Needs,
        progress: &(dyn Fn(f64) -> bool + Sync),
    ) -> Result<Log, IngestError> {
        let name = self.name();
        let src = match self {
            Input::Path(p) => read::Src::Path(p),
            Input::Bytes { bytes, .. } => read::Src::Bytes(bytes),
        };
        read::read(src, &name, opts, needs, progress).map_err(|f| f.at(&name))
    }

    /// Reads the input as a rate series of one column ([`read_rate_series`]).
    ///
    /// # Errors
    /// As [`read_rate_series`].
    pub fn rate_series(&self, opts: &ReadOptions) -> Result<Option<RateSeries>, IngestError> {
        let name = self.name();
        match self {
            Input::Path(p) => {
                let f = std::fs::File::open(p).map_err(|e| IngestError {
                    file: name.clone(),
                    line: 0,
                    column: 0,
                    message: e.to_string(),
                })?;
                series::read_rate_series_from(name, f, opts)
            }
            Input::Bytes { bytes, .. } => series::read_rate_series_from(name, &bytes[..], opts),
        }
    }
}

/// Reads a CSV log file (a drone or robot log is read by
/// [`read_any`](crate::log::read::read_any), which reads every format).
///
/// # Errors
/// An unreadable file or cell, with file, line and column; see the module documentation.
pub fn read_path(path: &Path, opts: &ReadOptions) -> Result<Log, IngestError> {
    read_path_with_progress(path, opts, &|_| true)
}

/// Reads a log file, telling `progress` the fraction done (0 to 1) every few MB so a GUI
/// can draw a bar; when `progress` returns false the read stops with the error
/// `cancelled`. A path that can be read only once (`-`, a FIFO) is read once ([`Input`]).
///
/// # Errors
/// As [`read_path`], plus `cancelled`.
pub fn read_path_with_progress(
    path: &Path,
    opts: &ReadOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<Log, IngestError> {
    Input::open(path)?.read(opts, progress)
}

/// Reads a log already in memory (a test, a paste, an upload); `source` names it in messages.
///
/// # Errors
/// As [`read_path`].
pub fn read_bytes(source: &str, bytes: &[u8], opts: &ReadOptions) -> Result<Log, IngestError> {
    read::read(
        read::Src::Bytes(bytes),
        source,
        opts,
        &Needs::default(),
        &|_| true,
    )
    .map_err(|f| f.at(source))
}

/// Sniffs a log file and shows what a read would do, reading only its first lines.
///
/// # Errors
/// Only when the file cannot be read as a text table at all (missing, empty, binary, one
/// column); a mapping the options cannot make is reported in [`Preview::mapping_error`].
pub fn preview(path: &Path, opts: &ReadOptions, max_rows: usize) -> Result<Preview, IngestError> {
    let name = path.display().to_string();
    read::preview(read::Src::Path(path), opts, max_rows).map_err(|f| f.at(&name))
}

/// [`preview`] of a log already in memory.
///
/// # Errors
/// As [`preview`].
pub fn preview_bytes(
    source: &str,
    bytes: &[u8],
    opts: &ReadOptions,
    max_rows: usize,
) -> Result<Preview, IngestError> {
    read::preview(read::Src::Bytes(bytes), opts, max_rows).map_err(|f| f.at(source))
}

/// A size in bytes as a person says it: `1 GiB`, `64 KiB`, `100 bytes`.
fn size_in_words(bytes: usize) -> String {
    match bytes {
        b if b >= 1 << 30 && b % (1 << 30) == 0 => format!("{} GiB", b >> 30),
        b if b >= 1 << 20 && b % (1 << 20) == 0 => format!("{} MiB", b >> 20),
        b if b >= 1 << 10 && b % (1 << 10) == 0 => format!("{} KiB", b >> 10),
        b => format!("{b} bytes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stream_is_read_up_to_its_bound_and_refused_past_it() {
        let log = "time_s,omega_dph,temp_c\n0,0.1,20\n1,0.2,20\n";
        let n = log.len() as u64;
        // At the bound, read whole; a byte more, refused with the bound.
        let at = Input::read_stream_within("s".into(), log.as_bytes(), n).unwrap();
        assert_eq!(at.bytes(), Some(log.as_bytes()));
        let past = Input::read_stream_within("s".into(), log.as_bytes(), n - 1).unwrap_err();
        assert!(
            past.message.contains(&format!("more than {} bytes", n - 1))
                && past.message.contains("as a file"),
            "{past}"
        );
        // Past a head, and in the reads of a reader that gives a few bytes at a time.
        let long = log.repeat(5000);
        struct Trickle<'a>(&'a [u8]);
        impl Read for Trickle<'_> {
            fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
                let n = buf.len().min(7).min(self.0.len());
                buf[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        let trickle = Trickle(long.as_bytes());
        let read = Input::read_stream_within("s".into(), trickle, long.len() as u64).unwrap();
        assert_eq!(read.bytes(), Some(long.as_bytes()));
        let e = Input::read_stream_within("s".into(), long.as_bytes(), 80 << 10).unwrap_err();
        assert!(e.to_string().starts_with("s: more than 80 KiB"), "{e}");
        assert_eq!(size_in_words(MAX_STREAM_BYTES as usize), "1 GiB");
    }
}
