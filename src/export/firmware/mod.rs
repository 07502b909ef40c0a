//! A calibration written for a gyro's processor: a self-contained C99 header with the
//! coefficients and the streaming corrector ([`c_header`]), or the coefficients tabulated over
//! their fitted ranges as CSV ([`csv_table`]).
//!
//! The header is a port of [`crate::models::vakhrameev::correct::StreamCorrector`] and of
//! [`crate::models::approx::Approx::eval`] that repeats their arithmetic operation for operation, with
//! every constant printed to round-trip precision, so on an IEEE-754 machine it corrects a log
//! bit for bit as driftlab does (the tests compile it and compare). The tables are for
//! processors that interpolate coefficients instead of evaluating curves.
//!
//! Each model a calibration file can hold is written by its own function: the Vakhrameev model
//! by [`c_header::c_header`] and [`csv_table::vakhrameev`], a regression model by
//! [`c_regression::regression`] (a port of [`crate::models::regression::RegressionCorrector`], bit for bit
//! in the same way) and [`csv_table::regression`] (its coefficients with standard errors, the
//! ranges and settings as comments). [`export_model`] picks by the model. The flight
//! controllers' parameter files ([`Format::Px4Params`], [`Format::ArdupilotParm`]) are written
//! by [`crate::export::flight`] from the model's static part, through [`flight`].
//!
//! A unit of several gyro axes ([`UnitCalibration::is_unit`]) is written by [`export_unit`]:
//! one header correcting every axis in one push ([`c_unit`]), one table file with an axis
//! column ([`csv_unit`]), or a flight controller's file with the unit's three axes as the
//! gyro's X, Y and Z ([`flight_unit`]). A single-axis calibration goes through the functions
//! above, unchanged.

mod c_corrector;
mod c_curves;
pub mod c_header;
pub mod c_regression;
pub mod c_unit;
pub mod csv_table;
pub mod csv_unit;

use crate::export::flight::ardupilot::{ArduPilotTarget, ardupilot_parm};
use crate::export::flight::px4::{Px4Target, px4_params};
use crate::export::flight::{AxisFit, FlightError, FlightFile, ImuFits};
use crate::models::fitted::DriftModel;
use crate::models::unit::UnitCalibration;
use crate::models::vakhrameev::Calibration;
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
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "c-header" | "c_header" | "c" | "h" => Ok(Format::CHeader),
            "csv-table" | "csv_table" | "csv" | "table" => Ok(Format::CsvTable),
            "px4-params" | "px4_params" | "px4" => Ok(Format::Px4Params),
            "ardupilot-parm" | "ardupilot_parm" | "ardupilot" => Ok(Format::ArdupilotParm),
            other => Err(format!(
                "unknown export format \"{other}\": use c-header, csv-table, px4-params or \
                 ardupilot-parm"
            )),
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
    /// A number of the calibration cannot be written for a processor.
    #[error("{0}")]
    Calibration(String),
    /// The calibration does not hold together.
    #[error(transparent)]
    Invalid(#[from] crate::error::Invalid),
    /// The calibration cannot be written for a flight controller.
    #[error(transparent)]
    Flight(#[from] FlightError),
}

/// Writes `cal` in `format`.
pub fn export(
    cal: &Calibration,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    match format {
        Format::CHeader => c_header::c_header(cal),
        Format::CsvTable => csv_table::csv_table(cal, opts.points),
        Format::Px4Params | Format::ArdupilotParm => {
            Ok(flight(&DriftModel::Vakhrameev(Box::new(cal.clone())), format, opts)?.text)
        }
    }
}

/// A one-model calibration as a flight controller's parameter file: the model's axis (a
/// calibration file names none yet) written as the gyro's X, what was chosen in
/// [`FlightFile::notes`] and left out in [`FlightFile::warnings`] (both also comments in the
/// file). PX4's device id is `opts.px4`'s, else the calibration's gyro id when that is one
/// (decimal or 0x hex).
///
/// # Errors
/// `format` is not a flight controller's, or the model cannot be written for one.
pub fn flight(
    model: &DriftModel,
    format: Format,
    opts: &ExportOptions,
) -> Result<FlightFile, ExportError> {
    flight_axes(&[("", model)], format, opts)
}

/// As [`flight`], one model per gyro axis: `(axis, model)` with the axis `x`, `y` or `z`
/// (or a name holding one, `gyro_y`), put in X, Y, Z order; the device id from the first
/// model's gyro id when `opts` gives none.
///
/// # Errors
/// As [`flight`], and axes that cannot be told apart.
pub fn flight_axes(
    axes: &[(&str, &DriftModel)],
    format: Format,
    opts: &ExportOptions,
) -> Result<FlightFile, ExportError> {
    let Some(&(_, model)) = axes.first() else {
        return Err(ExportError::Calibration("no calibration to export".into()));
    };
    let fits = ImuFits {
        gyro: axes
            .iter()
            .map(|&(axis, model)| AxisFit { axis, model })
            .collect(),
        accel: Vec::new(),
    };
    Ok(match format {
        Format::Px4Params => {
            // A gyro id that is a device id (as a drone log's gyro has) serves as one.
            let from_id = crate::export::flight::px4::parse_device_id(model.gyro_id())
                .filter(|_| opts.px4.gyro_device_id.is_none());
            let target = Px4Target {
                gyro_device_id: opts.px4.gyro_device_id.or(from_id),
                ..opts.px4
            };
            let mut file = px4_params(&fits, &target)?;
            if let Some(id) = from_id {
                file.notes.push(format!(
                    "TC_G{}_ID is the calibration's gyro id {id}",
                    target.slot
                ));
            }
            file
        }
        Format::ArdupilotParm => ardupilot_parm(&fits, &opts.ardupilot)?,
        other => {
            return Err(ExportError::Calibration(format!(
                "{other} is not a flight controller's parameter file"
            )));
        }
    })
}

/// Writes any model's calibration in `format`: a Vakhrameev calibration as [`export`] does, a
/// regression model as [`c_regression::regression`] or [`csv_table::regression`] (its coefficients
/// table: regression coefficients are constants, so there is nothing to tabulate over a range
/// and `opts.points` is not used).
pub fn export_model(
    model: &DriftModel,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    if format.is_flight() {
        return Ok(flight(model, format, opts)?.text);
    }
    match model {
        DriftModel::Vakhrameev(cal) => export(cal, format, opts),
        DriftModel::Regression(r) => match format {
            Format::CHeader => c_regression::regression(r),
            Format::CsvTable => csv_table::regression(r),
            Format::Px4Params | Format::ArdupilotParm => Ok(flight(model, format, opts)?.text),
        },
    }
}

/// Writes a unit's calibration in `format`; a single-axis calibration (not
/// [`UnitCalibration::is_unit`]) exactly as [`export_model`] writes its model.
///
/// # Errors
/// As the format's writer; see [`c_unit::c_unit_header`], [`csv_unit::csv_unit`] and
/// [`flight_unit`].
pub fn export_unit(
    unit: &UnitCalibration,
    format: Format,
    opts: &ExportOptions,
) -> Result<String, ExportError> {
    if !unit.is_unit() {
        let model = unit
            .first()
            .map_err(|e| ExportError::Calibration(e.to_string()))?;
        return export_model(model, format, opts);
    }
    match format {
        Format::CHeader => c_unit::c_unit_header(unit),
        Format::CsvTable => {
            check_points(opts.points)?;
            csv_unit::csv_unit(unit, opts.points)
        }
        Format::Px4Params | Format::ArdupilotParm => Ok(flight_unit(unit, format, opts)?.text),
    }
}

/// The table's points checked as [`csv_table::csv_table`] checks them, before any axis.
fn check_points(points: usize) -> Result<(), ExportError> {
    if points < 2 {
        Err(ExportError::TooFewPoints(points))
    } else if points > MAX_TABLE_POINTS {
        Err(ExportError::TooManyPoints(points))
    } else {
        Ok(())
    }
}

/// A unit of three gyro axes as a flight controller's parameter file, the axes as the gyro's
/// X, Y and Z: by the letter their names end with (`gx`, `gyro_y`) when the three names give
/// x, y and z, else in the unit's order (and a note says so). A single-axis calibration is
/// written as [`flight`] writes it.
///
/// # Errors
/// A unit without exactly three axes (naming the axes it has); as [`flight_axes`].
pub fn flight_unit(
    unit: &UnitCalibration,
    format: Format,
    opts: &ExportOptions,
) -> Result<FlightFile, ExportError> {
    if !unit.is_unit() {
        let model = unit
            .first()
            .map_err(|e| ExportError::Calibration(e.to_string()))?;
        return flight(model, format, opts);
    }
    let names = unit.axis_names();
    if names.len() != 3 {
        return Err(FlightError::Axes(format!(
            "the unit has {} gyro {} ({}): {format} holds a gyro's X, Y and Z, so it takes a \
             unit of three axes",
            names.len(),
            if names.len() == 1 { "axis" } else { "axes" },
            names.join(", ")
        ))
        .into());
    }
    let by_letter: Vec<Option<usize>> = names
        .iter()
        .map(|n| crate::export::flight::axis_index(n))
        .collect();
    let distinct = (0..3).all(|k| by_letter.contains(&Some(k)));
    let labels: Vec<String> = if distinct {
        names.iter().map(|n| n.to_string()).collect()
    } else {
        // The letter first: it is the word that places the axis.
        names
            .iter()
            .zip(["x", "y", "z"])
            .map(|(n, l)| format!("{l} (axis {n})"))
            .collect()
    };
    let axes: Vec<(&str, &DriftModel)> = labels
        .iter()
        .zip(&unit.axes)
        .map(|(l, a)| (l.as_str(), &a.model))
        .collect();
    let mut file = flight_axes(&axes, format, opts)?;
    if !distinct {
        file.notes.push(format!(
            "the unit's axes {} do not name x, y and z: written as X, Y, Z in their order",
            names.join(", ")
        ));
    }
    Ok(file)
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

/// The shortest decimal that reads back as exactly `v` (Rust's `{:?}`), valid as a C double
/// literal and in CSV; non-finite numbers are refused (a validated calibration has none).
pub(crate) fn number(v: f64, what: &str) -> Result<String, ExportError> {
    if v.is_finite() {
        Ok(format!("{v:?}"))
    } else {
        Err(ExportError::Calibration(format!(
            "{what} is {v}: not a number a processor can use"
        )))
    }
}
