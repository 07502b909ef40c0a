//! A gyro test log after ingest: synchronous columns already converted to driftlab's units
//! (time in s, rate in °/h, temperature in °C), plus what the reader noticed on the way.
//!
//! The readers: [`read::read_any`] reads every format and chooses by the first bytes;
//! [`ingest`] is the CSV reader, [`formats`] the drone and robot logs' (PX4 ULog, ArduPilot
//! DataFlash, ROS bag, MCAP). [`mapping_check`] holds the one rule set for what a column may
//! plausibly hold; [`resample`] averages into bins or bursts.

pub mod accel_axes;
pub mod campaign;
mod drone_gyro;
pub mod formats;
pub mod impossible;
pub mod ingest;
pub mod kept_samples;
pub mod mapping_check;
pub mod read;
pub mod resample;
mod rows;
pub mod run_sketch;
pub(crate) mod temp_glitch;
pub(crate) mod temp_rate;

use crate::signal::time_order::Told;
use serde::{Deserialize, Serialize};

pub use drone_gyro::{DroneGyro, GyroIdentity};

/// One recorded test run of a motionless gyro.
///
/// The three calibration columns are always present and of equal length; every other numeric
/// column of the file (a second temperature sensor, laser power, piezo voltage...) is kept by
/// name in `extra`, so that models which need them can find them.
#[derive(Debug, Clone, Default)]
pub struct Log {
    /// Where the log came from (file name or a label), used in messages and calibration files.
    pub source: String,
    /// Time since an arbitrary origin, seconds, strictly increasing.
    pub time_s: Vec<f64>,
    /// The output of the axis `axis` names, in its kind's unit ([`Log::axis_kind`]): a gyro's
    /// rate in °/h, an accelerometer's reading in m/s². Every stage from the fit on reads an
    /// axis here, whatever it measures (one path for both kinds).
    pub omega_dph: Vec<f64>,
    /// The temperature the calibration uses (coil or frame sensor), °C.
    pub temp_c: Vec<f64>,
    /// Every other numeric column, by name, aligned with `time_s`.
    pub extra: Vec<Channel>,
    /// The name of the axis `omega_dph` holds (`gx`, `x`, ...), empty for a log with one
    /// rate column that names no axis.
    pub axis: String,
    /// What the axis `omega_dph` holds measures: a gyro's, unless an accelerometer axis was
    /// selected.
    pub axis_kind: AxisKind,
    /// The log's other axes (a multi-axis IMU's gyros; its accelerometers once
    /// [`accel_axes::take`] made them axes), each aligned with `time_s`:
    /// [`Log::select_axis`] swaps one of them into `omega_dph`, so every stage that reads
    /// `omega_dph` calibrates any axis without a copy of the columns they share. The gyro
    /// axes come first.
    pub other_axes: Vec<Axis>,
    /// How the file was read and what was wrong with it.
    pub info: LogInfo,
}

/// Samples a run's fingerprint reads ([`Log::run_fingerprint`]).
pub const FINGERPRINT_SAMPLES: usize = 4096;

/// One axis of a multi-axis log.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Axis {
    /// The axis's name: the column's name without its unit (`gx` for `gx_dps`, `acc_x` for
    /// `acc_x_m_s2`).
    pub name: String,
    /// The output, in the kind's unit: a rate in °/h, an acceleration in m/s².
    pub omega_dph: Vec<f64>,
    /// What the axis measures.
    pub kind: AxisKind,
}

/// What an axis of a unit measures. The kind decides the unit of its samples and of every
/// figure and column written of it (°/h for a gyro, m/s² for an accelerometer), the models it
/// may take, and where a flight controller's file puts it; every stage in between is the same
/// for both.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisKind {
    /// A gyro: a rate, °/h.
    #[default]
    Gyro,
    /// An accelerometer: an acceleration, m/s² (gravity included, on the axis that carries
    /// it).
    #[serde(rename = "accelerometer")]
    Accel,
}

impl AxisKind {
    /// The unit's word in a column's or a field's name: `dph`, `m_s2`.
    pub fn unit_suffix(self) -> &'static str {
        match self {
            AxisKind::Gyro => "dph",
            AxisKind::Accel => "m_s2",
        }
    }

    /// The unit as tables and messages print it: `°/h`, `m/s²`.
    pub const fn unit(self) -> &'static str {
        match self {
            AxisKind::Gyro => "°/h",
            AxisKind::Accel => "m/s²",
        }
    }

    /// The unit in printable ASCII, for files that hold no other: `deg/h`, `m/s^2`.
    pub fn unit_ascii(self) -> &'static str {
        match self {
            AxisKind::Gyro => "deg/h",
            AxisKind::Accel => "m/s^2",
        }
    }

    /// The sensor in words: `gyro`, `accelerometer`.
    pub fn sensor(self) -> &'static str {
        match self {
            AxisKind::Gyro => "gyro",
            AxisKind::Accel => "accelerometer",
        }
    }

    /// The ending of a JSON field that holds a reading in this kind's unit: `_dph`, `_m_s2`.
    pub fn field_suffix(self) -> &'static str {
        match self {
            AxisKind::Gyro => "_dph",
            AxisKind::Accel => "_m_s2",
        }
    }

    /// `value` (figures, a model's body, as the engine's types serialise them, every reading
    /// named `…_dph`) with each field ending in `_dph`, at any depth, named in this kind's
    /// unit: an accelerometer axis's `p2p_dph` holds m/s², and is written `p2p_m_s2`, so that
    /// no script reads m/s² as °/h.
    pub fn name_fields_in_unit(self, value: &mut serde_json::Value) {
        if self == AxisKind::Gyro {
            return;
        }
        match value {
            serde_json::Value::Object(map) => {
                let old = std::mem::take(map);
                for (k, mut v) in old {
                    self.name_fields_in_unit(&mut v);
                    let key = match k.strip_suffix("_dph") {
                        Some(stem) => format!("{stem}{}", self.field_suffix()),
                        None => k,
                    };
                    map.insert(key, v);
                }
            }
            serde_json::Value::Array(items) => {
                items.iter_mut().for_each(|v| self.name_fields_in_unit(v));
            }
            _ => {}
        }
    }
}

/// A named column kept alongside the calibration columns.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Channel {
    /// The column's header name (or `colN` for a file without a header).
    pub name: String,
    /// Unit as read from the header, or empty when the header does not say.
    pub unit: String,
    /// Values, aligned with the log's `time_s`; temperatures in °C.
    pub values: Vec<f64>,
}

/// The unit accelerometer channels are kept in when the reader knows them in SI: a drone
/// log's, and a CSV column whose name says `m_s2` or `[m/s^2]`.
pub const ACCEL_UNIT_M_S2: &str = "m/s^2";

/// m/s² in one g: the standard gravity (ISO 80000-3, the CGPM's of 1901), by which an
/// accelerometer read in g or mg is taken to m/s².
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;

impl Channel {
    /// Whether the channel is an accelerometer axis: its name reads as one (`ax_g`, `acc_x`,
    /// `accel_x_m_s2`, `linear_acceleration_x`), as the CSV reader recognises it. The one
    /// place that decides, so that every face and writer agrees on which channels are
    /// accelerometers.
    pub fn is_accelerometer(&self) -> bool {
        ingest::names_an_accelerometer(&self.name)
    }

    /// Whether the channel is an accelerometer axis held in m/s² (what Kalibr's noise model
    /// and every SI figure read; an axis in g or mg is kept in its own unit and left out).
    pub fn is_accelerometer_m_s2(&self) -> bool {
        self.is_accelerometer() && self.unit == ACCEL_UNIT_M_S2
    }

    /// The factor that takes an accelerometer axis from the unit it is kept in to m/s² (what
    /// Kalibr's noise model and every SI figure read): 1 for m/s², the standard gravity
    /// 9.80665 m/s² for g (ISO 80000-3, the CGPM's of 1901), a thousandth of it for mg. `None`
    /// for a channel that is no accelerometer, or one whose name says no unit.
    pub fn accelerometer_to_m_s2(&self) -> Option<f64> {
        if !self.is_accelerometer() {
            return None;
        }
        match self.unit.as_str() {
            ACCEL_UNIT_M_S2 => Some(1.0),
            "g" => Some(STANDARD_GRAVITY_M_S2),
            "mg" => Some(STANDARD_GRAVITY_M_S2 / 1000.0),
            _ => None,
        }
    }
}

/// What the reader found: dialect, column mapping with units, and problems.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct LogInfo {
    /// Field separator that was used.
    pub delimiter: char,
    /// Whether numbers were written with a decimal comma.
    pub decimal_comma: bool,
    /// Whether the first non-comment line was a header.
    pub has_header: bool,
    /// Every column of the file with the role it was given.
    pub columns: Vec<ColumnInfo>,
    /// Data rows read from the file (before any row was dropped).
    pub rows_read: usize,
    /// Things that were wrong but did not stop the read (dropped rows, gaps, ...).
    pub problems: Vec<Problem>,
    /// The gyro of a drone or robot log the samples are, `None` for a CSV: a drone log holds
    /// several IMUs, and a calibration records which one it was fitted on
    /// ([`crate::models::vakhrameev::SourceInfo::instance`]) so that a flight controller's
    /// parameters go to that IMU rather than to the first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<DroneGyro>,
    /// The runs of a campaign's joined log ([`campaign::join`]), in order; empty for a log of
    /// one run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub runs: Vec<campaign::RunSpan>,
}

/// One column of the source file.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ColumnInfo {
    /// 1-based column index in the file.
    pub index: usize,
    /// Header name, or `colN` without a header.
    pub name: String,
    /// What driftlab uses the column for.
    pub role: ColumnRole,
    /// The unit the column was read in (`deg/h`, `rad/s`, `ms`, `°C`, ...), empty if unknown.
    pub unit: String,
}

impl ColumnInfo {
    /// Whether the column is an accelerometer axis, by the rule of
    /// [`Channel::is_accelerometer`].
    pub fn is_accelerometer(&self) -> bool {
        ingest::names_an_accelerometer(&self.name)
    }
}

/// The use driftlab makes of a column.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ColumnRole {
    /// Time axis.
    Time,
    /// Gyro rate output.
    Rate,
    /// The calibration temperature.
    Temperature,
    /// Another gyro axis of a multi-axis unit, kept in `Log::other_axes`.
    OtherAxis,
    /// An accelerometer axis, kept in `Log::other_axes` in m/s² ([`accel_axes::take`]).
    AccelAxis,
    /// Kept by name in `Log::extra`.
    #[default]
    Extra,
    /// Not numeric, not kept.
    Ignored,
}

/// Something wrong in a log that the reader worked around, with where it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Problem {
    /// 1-based line in the file where it was first seen.
    pub line: usize,
    /// 1-based column, when the problem is in one cell.
    pub column: Option<usize>,
    /// What kind of problem.
    pub kind: ProblemKind,
    /// How many times it occurred (the first occurrence is at `line`).
    pub count: usize,
    /// A sentence a test engineer can act on.
    pub message: String,
}

impl Problem {
    /// The problem both readers report for what time order dropped ([`Told`]), at `line`
    /// (the file's line or the sample's number) and `column`.
    pub fn of_time_order(t: Told, line: usize, column: Option<usize>) -> Problem {
        Problem {
            line,
            column,
            kind: if t.repeated {
                ProblemKind::TimeRepeated
            } else {
                ProblemKind::TimeBackwards
            },
            count: t.count,
            message: t.message,
        }
    }

    /// How often, for a line that tells it: " (3 times)" when it occurred more than once and
    /// its message does not already begin with the count ("3 rows dropped: …"), else nothing.
    pub fn times(&self) -> String {
        if self.count > 1 && !self.message.starts_with(&format!("{} ", self.count)) {
            format!(" ({} times)", self.count)
        } else {
            String::new()
        }
    }
}

/// Kinds of problems the reader reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProblemKind {
    /// Blank, NaN or infinite cells in a used column: the row was dropped.
    MissingValue,
    /// Unreadable cells in an extra column: kept as NaN, the row was kept.
    BadExtraValue,
    /// Time went backwards, or a stamp stands alone at an end of the log past a gap far
    /// longer than the rest of it (a stray stamp, 1e300 s after the others): the row was
    /// dropped.
    TimeBackwards,
    /// Time repeated: the row was dropped.
    TimeRepeated,
    /// The time step jumped well above the nominal step.
    Gap,
    /// A row with fewer or more fields than the header.
    RaggedRow,
    /// A column taken for a role holds values that role cannot have (a temperature in
    /// thousands of counts, a rate beyond any gyro's): the message names the column and the
    /// option that chooses another.
    Implausible,
    /// A column taken for a role shares its name with another column of the header: the
    /// message names both and the option that takes the other.
    DuplicateName,
    /// A rate column read in a unit its own name contradicts (an explicit rate unit wins):
    /// the message names both.
    UnitMismatch,
    /// A channel that some runs of a campaign do not have (or hold in another unit): left out
    /// of the joined log ([`campaign::join`]).
    LeftOut,
    /// What joining a campaign's runs could not check (which drone-log gyro a run is, when
    /// it records none: a CSV): the runs were joined, and the message says what to make sure
    /// of ([`campaign::join`]).
    Unchecked,
}

impl Log {
    /// The names of every axis, `omega_dph`'s first, then the others in file order (the gyro
    /// axes, then any accelerometer axes).
    pub fn axis_names(&self) -> Vec<String> {
        std::iter::once(self.axis.clone())
            .chain(self.other_axes.iter().map(|a| a.name.clone()))
            .collect()
    }

    /// The kind of the axis named `name`.
    pub fn kind_of(&self, name: &str) -> Option<AxisKind> {
        if self.axis == name {
            return Some(self.axis_kind);
        }
        self.other_axes
            .iter()
            .find(|a| a.name == name)
            .map(|a| a.kind)
    }

    /// The names of the axes of kind `kind`, in [`Log::axis_names`]'s order.
    pub fn axes_of(&self, kind: AxisKind) -> Vec<String> {
        self.axis_names()
            .into_iter()
            .filter(|n| self.kind_of(n) == Some(kind))
            .collect()
    }

    /// Makes `name` the axis `omega_dph` holds, swapping columns (no copy). Returns false when
    /// the log has no such axis.
    pub fn select_axis(&mut self, name: &str) -> bool {
        if self.axis == name {
            return true;
        }
        let Some(k) = self.other_axes.iter().position(|a| a.name == name) else {
            return false;
        };
        let a = &mut self.other_axes[k];
        std::mem::swap(&mut self.omega_dph, &mut a.omega_dph);
        std::mem::swap(&mut self.axis, &mut a.name);
        std::mem::swap(&mut self.axis_kind, &mut a.kind);
        true
    }

    /// Puts the axes other than `omega_dph`'s back in the order of `order` (the order of
    /// [`Log::axis_names`] before some [`Log::select_axis`]), so that a caller that visited
    /// every axis leaves them listed as it found them.
    pub fn order_axes_as(&mut self, order: &[String]) {
        let rank = |name: &str| order.iter().position(|n| n == name).unwrap_or(usize::MAX);
        self.other_axes.sort_by_key(|a| rank(&a.name));
    }

    /// The rate of the axis named `name`, °/h, whichever column holds it now.
    pub fn axis_rate(&self, name: &str) -> Option<&[f64]> {
        if self.axis == name {
            return Some(&self.omega_dph);
        }
        self.other_axes
            .iter()
            .find(|a| a.name == name)
            .map(|a| a.omega_dph.as_slice())
    }

    /// The axis of this log that holds what a calibration's axis `name` (read from column
    /// `rate_column` on its own log) measured: the axis of that name, or of that column.
    pub fn matching_axis(&self, name: &str, rate_column: &str) -> Option<String> {
        let names = self.axis_names();
        if names.iter().any(|n| n == name) {
            return Some(name.to_string());
        }
        (!rate_column.is_empty())
            .then(|| self.find_axis(rate_column))
            .flatten()
    }

    /// The axis an engineer means by `asked`: an axis's name (`gx`), its rate column's name
    /// (`gx_dps`), or the one axis whose name ends with it (`x` for `gx`, `gyro_x`).
    pub fn find_axis(&self, asked: &str) -> Option<String> {
        let names = self.axis_names();
        if names.iter().any(|n| n == asked) {
            return Some(asked.to_string());
        }
        let by_column = self
            .axis_columns()
            .into_iter()
            .find(|(_, column)| column == asked)
            .map(|(axis, _)| axis)
            .filter(|n| names.contains(n));
        if by_column.is_some() {
            return by_column;
        }
        let lower = asked.to_ascii_lowercase();
        let mut ending = names
            .iter()
            .filter(|n| !lower.is_empty() && n.to_ascii_lowercase().ends_with(&lower));
        match (ending.next(), ending.next()) {
            (Some(n), None) => Some(n.clone()),
            _ => None,
        }
    }

    /// The name of the file's column that `omega_dph` was read from (`gx_dps` for axis `gx`),
    /// when the reader recorded it.
    pub fn rate_column(&self) -> Option<String> {
        self.axis_columns()
            .into_iter()
            .find(|(axis, _)| *axis == self.axis)
            .map(|(_, column)| column)
    }

    /// Each axis's name with the name of the file's column it was read from, as the reader
    /// named them ([`ingest::names::axis_names`]: two columns never share an axis), the
    /// accelerometer axes as [`accel_axes::take`] named them. The names depend on every
    /// column at once, so a caller pairing every axis with its column takes this list once
    /// rather than asking [`Log::find_axis`] per column (which names them all each time).
    pub fn axis_columns(&self) -> Vec<(String, String)> {
        let columns: Vec<(usize, &str)> = self
            .info
            .columns
            .iter()
            .filter(|c| matches!(c.role, ColumnRole::Rate | ColumnRole::OtherAxis))
            .map(|c| (c.index, c.name.as_str()))
            .collect();
        let gyros = ingest::names::axis_names(&columns);
        let accels = accel_axes::names_of(self, &gyros);
        gyros
            .into_iter()
            .zip(columns.iter().map(|(_, n)| n.to_string()))
            .chain(accels)
            .collect()
    }

    /// The run's fingerprint: SHA-256 (hex) of the number of samples and of the time and
    /// temperature, bit for bit, at up to [`FINGERPRINT_SAMPLES`] evenly spaced samples. Two
    /// reads of one run give the same, whatever the file's bytes (line endings, comments,
    /// separators, another format); two chamber runs never do, since their noise differs at
    /// every sample. A few samples apart are still the same run, as they should be: figures
    /// judged on them are in-sample. Spaced samples keep it cheap enough for every fit.
    pub fn run_fingerprint(&self) -> String {
        use sha2::{Digest, Sha256};
        let n = self.len().min(self.temp_c.len());
        let mut hasher = Sha256::new();
        hasher.update((n as u64).to_le_bytes());
        let m = n.min(FINGERPRINT_SAMPLES);
        for k in 0..m {
            let i = if m < 2 { 0 } else { k * (n - 1) / (m - 1) };
            hasher.update(self.time_s[i].to_bits().to_le_bytes());
            hasher.update(self.temp_c[i].to_bits().to_le_bytes());
        }
        hasher
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }

    /// Whether `other` holds samples of this log's run, enough for figures judged on it to
    /// be in-sample ([`run_sketch`]): the whole run under other bytes, or a part of it, by a
    /// sketch 32 times a calibration file's, as both logs are at hand (the run thinned to
    /// every 20th row is told, where a file's sketch compares too few of its values).
    pub fn same_run(&self, other: &Log) -> bool {
        self.run_shared(other).in_sample()
    }

    /// How much of `other` is this log's run, by [`Log::same_run`]'s sketch of this log: in
    /// words too, and why the sketch cannot tell when it cannot (too few of `other`'s values
    /// compared, a column of `other` written coarser than this log's). `self` is the
    /// calibration log, `other` the log judged: the sketch is always of the calibration log.
    pub fn run_shared(&self, other: &Log) -> run_sketch::Shared {
        run_sketch::RunSketch::in_memory(self).shared_with(other, self.len())
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// True when the log has no samples.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Nominal sampling step within the log's segments, s ([`crate::signal::timing::Timing`]):
    /// robust to gaps (they split segments) and to host time stamps that bunch (the mean step
    /// within segments, not the median), so windows and derivative steps given in seconds are
    /// converted with the step the gyro was really sampled at.
    pub fn nominal_dt_s(&self) -> f64 {
        if self.info.runs.len() > 1 {
            return self.timing().nominal_dt_s;
        }
        nominal_dt_s(&self.time_s)
    }

    /// How the log was sampled in real time: its nominal step, its segments between gaps,
    /// jitter and bursts ([`crate::signal::timing::Timing`]).
    pub fn timing(&self) -> crate::signal::timing::Timing {
        crate::signal::timing::Timing::of_runs(&self.time_s, &self.run_ranges())
    }

    /// Duration from the first to the last sample, s.
    pub fn duration_s(&self) -> f64 {
        match (self.time_s.first(), self.time_s.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// A named extra channel.
    pub fn channel(&self, name: &str) -> Option<&Channel> {
        self.extra.iter().find(|c| c.name == name)
    }

    /// Builds a log from columns already in driftlab's units (tests, the simulator).
    pub fn from_columns(
        source: &str,
        time_s: Vec<f64>,
        omega_dph: Vec<f64>,
        temp_c: Vec<f64>,
    ) -> Log {
        let rows = time_s.len();
        Log {
            source: source.to_string(),
            time_s,
            omega_dph,
            temp_c,
            extra: Vec::new(),
            axis: String::new(),
            axis_kind: AxisKind::Gyro,
            other_axes: Vec::new(),
            info: LogInfo {
                delimiter: ',',
                rows_read: rows,
                ..LogInfo::default()
            },
        }
    }
}

/// Nominal time step of a time column, s (1.0 for fewer than two samples): see
/// [`Log::nominal_dt_s`].
pub fn nominal_dt_s(time_s: &[f64]) -> f64 {
    crate::signal::timing::Timing::of(time_s).nominal_dt_s
}
