//! A calibration written for a gyro's processor: a self-contained C99 header with the
//! coefficients and the streaming corrector ([`c_header`]), or the coefficients tabulated over
//! their fitted ranges as CSV ([`csv_table`]).
//!
//! The header is a port of [`crate::models::vakhrameev::correct::StreamCorrector`], of
//! [`crate::models::regression::RegressionCorrector`] and of
//! [`crate::models::approx::Approx::eval`] that repeats their arithmetic operation for
//! operation, with every constant printed to round-trip precision, so on an IEEE-754 machine it
//! corrects a log bit for bit as driftlab does (the tests compile it and compare). The code it
//! runs is one static C source, `runtime.c` ([`c_runtime`]), copied in beside the tables
//! generated for the calibration. The tables are for processors that interpolate coefficients
//! instead of evaluating curves.
//!
//! Every output has one writer, which takes a unit ([`export_unit`]): the header
//! ([`c_header::c_header`]), the tables ([`csv_table::csv_table`]) and a flight controller's
//! file with the unit's three axes as the gyro's X, Y and Z ([`flight_unit`], through
//! [`crate::export::flight`]). A single-axis calibration is the unit of one unnamed axis
//! ([`UnitCalibration::single`]); each writer chooses at its edge to write it as driftlab always
//! has, so its files are what they were. Inside a writer each model has its own part: the
//! Vakhrameev model's curves ([`c_vakhrameev`]), a regression model's constants and corrector
//! ([`c_regression`], [`c_corrector`]).

mod c_corrector;
mod c_curves;
pub mod c_header;
mod c_names;
mod c_regression;
mod c_runtime;
mod c_vakhrameev;
pub mod csv_table;
mod flight_of;

pub use flight_of::{flight, flight_axes, flight_of, flight_unit};

use crate::export::flight::FlightError;
use crate::export::flight::ardupilot::ArduPilotTarget;
use crate::export::flight::px4::Px4Target;
use crate::models::fitted::DriftModel;
use crate::models::unit::UnitCalibration;
use crate::models::vakhrameev::Calibration;
use flight_of::picked;
use std::fmt;
use std::str::FromStr;

/// What `export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A C99 header: constants, curve evaluator and the streaming corrector.
    CHeader,
    /// K0, K1±, K2± tabulated over their fitted ranges, as CSV (a regression model: its
    /// coefficients with standard errors).
    CsvTable,
    /// PX4's thermal compensation (`TC_G*`) as a QGroundControl `.params` file
    /// ([`crate::export::flight::px4`]).
    Px4Params,
    /// ArduPilot's IMU temperature calibration (`INS_TCALn_*`) as a parameter file
    /// ([`crate::export::flight::ardupilot`]).
    ArdupilotParm,
}

impl Format {
    /// Every format, in the order `--help` lists them.
    pub const ALL: [Format; 4] = [
        Format::CHeader,
        Format::CsvTable,
        Format::Px4Params,
        Format::ArdupilotParm,
    ];

    /// Whether the format is a flight controller's parameter file, which holds the static
    /// part of a model as a polynomial in T.
    pub fn is_flight(self) -> bool {
        matches!(self, Format::Px4Params | Format::ArdupilotParm)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::CHeader => "c-header",
            Format::CsvTable => "csv-table",
            Format::Px4Params => "px4-params",
            Format::ArdupilotParm => "ardupilot-parm",
        })
    }
}

impl FromStr for Format {
    type Err = UnknownFormat;
    fn from_str(s: &str) -> Result<Self, UnknownFormat> {
        match s.trim().to_ascii_lowercase().as_str() {
            "c-header" | "c_header" | "c" | "h" => Ok(Format::CHeader),
            "csv-table" | "csv_table" | "csv" | "table" => Ok(Format::CsvTable),
            "px4-params" | "px4_params" | "px4" => Ok(Format::Px4Params),
            "ardupilot-parm" | "ardupilot_parm" | "ardupilot" => Ok(Format::ArdupilotParm),
            other => Err(UnknownFormat(other.to_string())),
        }
    }
}

/// Settings of an export.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExportOptions {
    /// Grid points per coefficient in a table, end points included.
    pub points: usize,
    /// The gyro's device id and slot of a PX4 parameter file.
    pub px4: Px4Target,
    /// The IMU of an ArduPilot parameter file.
    pub ardupilot: ArduPilotTarget,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            points: 101,
            px4: Px4Target::default(),
            ardupilot: ArduPilotTarget::default(),
        }
    }
}

/// Most grid points per coefficient a table may have (10 columns of this many rows is already
/// far more than any processor's memory, and about 20 MB of text).
pub const MAX_TABLE_POINTS: usize = 100_000;

/// Largest smoothing window or derivative step, in samples, a header will size a ring buffer
/// for (about 134 MB of doubles: anything near it is a mistake in the calibration file).
pub const MAX_RING_SAMPLES: usize = 1 << 24;

/// Why a calibration could not be exported.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExportError {
    /// A table with fewer than two points cannot interpolate.
    #[error("a table needs at least 2 points per coefficient, got {0}")]
    TooFewPoints(usize),
    /// More points than [`MAX_TABLE_POINTS`].
    #[error("at most {MAX_TABLE_POINTS} points per coefficient, got {0}")]
    TooManyPoints(usize),
    /// A number of the calibration that is not finite (a validated calibration has none).
    #[error("{what} is {value}: not a number a processor can use")]
    NotANumber {
        /// What the number is (`K0(T): coefficient`).
        what: String,
        value: f64,
    },
    /// A smoothing window, derivative step or delay that needs a larger ring buffer than
    /// [`MAX_RING_SAMPLES`].
    #[error("{}", ring_too_long(axis, *smooth, *step, *delay))]
    RingTooLong {
        /// The axis of a unit, empty for a single axis.
        axis: String,
        smooth: usize,
        step: usize,
        /// A regression model's longest delay, in samples.
        delay: Option<f64>,
    },
    /// Two Vakhrameev axes of a unit whose T is sampled, smoothed or differentiated
    /// differently: one header keeps one temperature history.
    #[error(
        "axes {first} and {second}: sampled every {} s and {} s, T smoothed over {} and {} \
         samples, differentiated over {} and {}: the axes of a unit share one temperature \
         history, so these must be one",
        .first_history.0, .second_history.0, .first_history.1, .second_history.1,
        .first_history.2, .second_history.2
    )]
    TemperatureHistories {
        first: String,
        second: String,
        /// Sampling period (s), smoothing window and derivative step (samples) of each.
        first_history: (f64, usize, usize),
        second_history: (f64, usize, usize),
    },
    /// A regression axis of a unit that reads more than the unit's one temperature.
    #[error(
        "axis {axis}: its regression model reads {}; the unit's header takes one temperature \
         for all axes: export that axis alone",
        reads.join(", ")
    )]
    MoreThanOneTemperature {
        axis: String,
        /// What else it reads (`the second temperature temp_chamber_c`).
        reads: Vec<String>,
    },
    /// Axes of a unit whose tables have different columns, which one table file cannot hold.
    #[error("{0}")]
    TableColumns(Box<TableColumns>),
    /// A knot curve read without its segment cubics.
    #[error("{0}: a knot curve without its segments")]
    KnotCurveWithoutSegments(String),
    /// A calibration without axes.
    #[error("no calibration to export")]
    NoAxes,
    /// A flight controller's file asked for in a format that is not one.
    #[error("{0} is not a flight controller's parameter file")]
    NotFlight(Format),
    /// An axis asked for by name that the unit does not have.
    #[error("no axis {name} (the unit's axes: {})", axes.join(", "))]
    NoSuchAxis {
        /// The name asked for.
        name: String,
        /// The unit's axes.
        axes: Vec<String>,
    },
    /// One axis asked for from a calibration of a single axis, which is not a unit.
    #[error("a calibration of a single axis has no axes to pick from: export it whole")]
    NotAUnit,
    /// What went wrong with one axis of a unit.
    #[error("axis {axis}: {source}")]
    Axis {
        axis: String,
        source: Box<ExportError>,
    },
    /// The calibration does not hold together.
    #[error(transparent)]
    Invalid(#[from] crate::error::Invalid),
    /// The calibration cannot be written for a flight controller.
    #[error(transparent)]
    Flight(#[from] FlightError),
}

/// Two axes of a unit whose tables have different columns ([`ExportError::TableColumns`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "axes {first} ({first_model}) and {second} ({second_model}) have tables of different \
     columns ({first_columns} and {second_columns}): one file cannot hold both; export each \
     axis alone"
)]
pub struct TableColumns {
    pub first: String,
    pub first_model: &'static str,
    pub first_columns: String,
    pub second: String,
    pub second_model: &'static str,
    pub second_columns: String,
}

/// [`ExportError::RingTooLong`]'s message.
fn ring_too_long(axis: &str, smooth: usize, step: usize, delay: Option<f64>) -> String {
    let axis = if axis.is_empty() {
        String::new()
    } else {
        format!("axis {axis}: ")
    };
    let what = match delay {
        None => format!(
            "a smoothing window of {smooth} samples and a derivative step of {step} samples"
        ),
        Some(d) => format!(
            "a smoothing window of {smooth} samples, a derivative step of {step} samples and a \
             delay of {d} samples"
        ),
    };
    format!("{axis}{what}: more than the {MAX_RING_SAMPLES} samples a ring buffer is sized for")
}

/// A name that is not one of the export formats.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown export format \"{0}\": use c-header, csv-table, px4-params or ardupilot-parm")]
pub struct UnknownFormat(pub String);

/// Writes a single-axis Vakhrameev calibration in `format`, as [`export_unit`] writes the unit
/// of that one axis.
pub fn export(
    cal: &Calibration,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    export_model(&DriftModel::Vakhrameev(Box::new(cal.clone())), format, opts)
}

/// Writes any model's calibration in `format`, as [`export_unit`] writes the single-axis
/// calibration of it.
pub fn export_model(
    model: &DriftModel,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    export_unit(&UnitCalibration::single(model.clone()), format, opts)
}

/// Writes a calibration in `format`: every output has one writer, which takes a unit; a
/// single-axis calibration is the unit of one unnamed axis ([`UnitCalibration::single`]), and
/// each writer chooses at its edge to write it as driftlab always has (see
/// [`c_header::c_header`], [`csv_table::csv_table`] and [`flight_unit`]).
///
/// # Errors
/// As the format's writer.
pub fn export_unit(
    unit: &UnitCalibration,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    match format {
        Format::CHeader => c_header::c_header(unit),
        Format::CsvTable => csv_table::csv_table(unit, opts.points),
        Format::Px4Params | Format::ArdupilotParm => Ok(flight_unit(unit, format, opts)?.text),
    }
}

/// One axis of a unit written alone in `format`, under its own name: a flight controller's
/// file places it as the whole unit's file does ([`flight_of`]), the other axes at zero; the
/// C header and the table are the single-axis ones of its model (one rate per push, no `axis`
/// column), their comments naming the axis (and the header's `DRIFTLAB_AXIS`).
///
/// # Errors
/// `name` is no axis of the unit, or `unit` is a single-axis calibration; as the format's
/// writer.
pub fn export_axis(
    unit: &UnitCalibration,
    name: &str,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    if !unit.is_unit() {
        return Err(ExportError::NotAUnit);
    }
    let axis = picked(unit, name)?;
    let of = AxisOfUnit {
        name: &axis.name,
        rate_column: &axis.rate_column,
        unit_axes: unit.axis_names(),
        kind: axis.kind,
    };
    match format {
        Format::CHeader => c_header::c_header_of_axis(&axis.model, &of),
        Format::CsvTable => csv_table::csv_table_of_axis(&axis.model, &of, opts.points),
        Format::Px4Params | Format::ArdupilotParm => {
            Ok(flight_of(unit, Some(name), format, opts)?.text)
        }
    }
}

/// One axis of a unit exported alone, as the single-axis files name it.
pub(crate) struct AxisOfUnit<'a> {
    /// The axis's name (`gy`).
    pub name: &'a str,
    /// The rate column it was calibrated from, empty when not known.
    pub rate_column: &'a str,
    /// Every axis of its unit, in order.
    pub unit_axes: Vec<&'a str>,
    /// What the axis measures.
    pub kind: crate::log::AxisKind,
}

impl AxisOfUnit<'_> {
    /// One line of printable ASCII (no comment delimiters) naming the axis: `gy (rate column
    /// gy_dps), one of the unit's axes gx, gy, gz, exported alone`; an accelerometer's says so,
    /// with its unit: `acc_z, an accelerometer in m/s^2 (column acc_z_g), one of ...`.
    pub(crate) fn describe(&self) -> String {
        let column = match (self.kind, self.rate_column.is_empty()) {
            (crate::log::AxisKind::Gyro, true) => String::new(),
            (crate::log::AxisKind::Gyro, false) => {
                format!(" (rate column {})", comment_text(self.rate_column))
            }
            (crate::log::AxisKind::Accel, true) => ", an accelerometer in m/s^2".to_string(),
            (crate::log::AxisKind::Accel, false) => format!(
                ", an accelerometer in m/s^2 (column {})",
                comment_text(self.rate_column)
            ),
        };
        let axes: Vec<String> = self.unit_axes.iter().map(|n| comment_text(n)).collect();
        format!(
            "{}{column}, one of the unit's axes {}, exported alone",
            comment_text(self.name),
            axes.join(", ")
        )
    }
}

/// A text from a calibration file made safe to quote inside a comment of either format: one
/// line of printable ASCII (others become `?`), no `*/`, `/*` or `??` (a C trigraph), at most
/// 200 characters.
pub(crate) fn comment_text(s: &str) -> String {
    let mut out: String = s
        .chars()
        .take(200)
        .map(|c| {
            if c.is_ascii_graphic() || c == ' ' {
                c
            } else {
                '?'
            }
        })
        .collect();
    while out.contains("*/") || out.contains("/*") || out.contains("??") {
        out = out
            .replace("*/", "* /")
            .replace("/*", "/ *")
            .replace("??", "? ?");
    }
    out
}

/// The SHA-256 of a calibration's log for a comment of either format, or that it was not
/// recorded.
fn sha_text(src: &crate::models::vakhrameev::SourceInfo) -> String {
    if src.sha256.is_empty() {
        "(not recorded)".to_string()
    } else {
        comment_text(&src.sha256)
    }
}

/// The shortest decimal that reads back as exactly `v` (Rust's `{:?}`), valid as a C double
/// literal and in CSV; non-finite numbers are refused (a validated calibration has none).
pub(crate) fn number(v: f64, what: &str) -> Result<String, ExportError> {
    if v.is_finite() {
        Ok(format!("{v:?}"))
    } else {
        Err(ExportError::NotANumber {
            what: what.to_string(),
            value: v,
        })
    }
}
