//! `driftlab export`: a calibration for a gyro's processor, as a C header or lookup tables, or
//! for a flight controller, as PX4 or ArduPilot parameters.

use super::common::CliError;
use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::export::flight::ardupilot::ArduPilotTarget;
use driftlab::export::flight::px4::{self, Px4Target};
use driftlab::files::calibration;
use driftlab::models::UnitCalibration;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// Arguments of `export`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON) made by `driftlab calibrate`: one axis, or a unit of several
    /// (c-header: one header correcting every axis in one push; csv-table: one file, the
    /// axis's name in its first column; px4-params, ardupilot-parm: the unit's three axes as
    /// the gyro's X, Y, Z).
    pub calibration: PathBuf,
    /// c-header: one self-contained C99 header with the coefficients and the streaming corrector
    /// (init/reset/push), correcting bit for bit as driftlab does; csv-table: K0(T), K1±(Ṫ) and
    /// K2±(T̈) tabulated over their fitted ranges, to interpolate linearly (a regression model:
    /// its coefficients with standard errors, ranges and settings as comments); px4-params:
    /// PX4's TC_G* thermal compensation as a QGroundControl .params file; ardupilot-parm:
    /// ArduPilot's INS_TCALn_* parameters. The flight controllers read a polynomial in T:
    /// poly-t, a custom model of 1,T,T^2,T^3, or Vakhrameev's K0 (linear or parabolic) with its
    /// rate terms left out.
    #[arg(
        long,
        value_name = "c-header|csv-table|px4-params|ardupilot-parm",
        verbatim_doc_comment
    )]
    pub format: Format,
    /// Where to write (atomically); standard output when not given, or given as `-`.
    #[arg(long, short, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Rows of each table, end points included (csv-table of a Vakhrameev calibration only).
    #[arg(long, value_name = "N")]
    pub points: Option<usize>,
    /// px4-params: the gyro's device_id, decimal or 0x hex (`driftlab inspect LOG` lists each
    /// gyro's); PX4 applies the parameters to the sensor of that id (default: the
    /// calibration's gyro id, when it is one).
    #[arg(long, value_name = "ID")]
    pub device_id: Option<String>,
    /// px4-params: the accelerometer's device_id, decimal or 0x hex, for a calibration with
    /// accelerometer axes (default: the gyro's, one chip; a log whose accelerometer had an id
    /// of its own is refused until it is given).
    #[arg(long, value_name = "ID")]
    pub accel_device_id: Option<String>,
    /// px4-params: the calibration slot N of TC_GN_* (0 to 3; default 0).
    #[arg(long, value_name = "N")]
    pub slot: Option<usize>,
    /// ardupilot-parm: the IMU N of INS_TCALN_* (1 to 3, 1 for the first IMU, DataFlash I=0;
    /// default: the IMU the calibration was fitted on, when its log was a DataFlash log, else
    /// 1, with a note).
    #[arg(long, value_name = "N")]
    pub imu: Option<usize>,
    /// px4-params, ardupilot-parm: the calibration of the gyro's Y axis (CALIBRATION is then
    /// its X axis; without --y and --z a single calibration is written as X).
    #[arg(long, value_name = "CAL_Y")]
    pub y: Option<PathBuf>,
    /// px4-params, ardupilot-parm: the calibration of the gyro's Z axis.
    #[arg(long, value_name = "CAL_Z")]
    pub z: Option<PathBuf>,
    /// A unit's calibration: export this axis alone (by its name). A flight controller's file
    /// writes it where the whole unit's file does (gy as Y), the other axes at zero; the C
    /// header and the table are its single-axis ones, naming the axis.
    #[arg(long, value_name = "NAME")]
    pub axis: Option<String>,
}

/// A device id as `inspect` prints it, given to option `flag`: decimal or `0x` hex.
fn device_id(flag: &str, s: &str) -> Result<u32, String> {
    px4::parse_device_id(s)
        .ok_or_else(|| format!("{flag} {s}: give PX4's device_id, decimal or 0x hex"))
}

impl Args {
    /// The options, each refused by name where the format does not read it.
    fn options(&self) -> Result<ExportOptions, String> {
        let refuse = |given: bool, flag: &str, formats: &str| {
            if given {
                Err(format!(
                    "{flag} applies to --format {formats}, not {}",
                    self.format
                ))
            } else {
                Ok(())
            }
        };
        let px4 = self.format == Format::Px4Params;
        let ardupilot = self.format == Format::ArdupilotParm;
        refuse(
            self.points.is_some() && self.format != Format::CsvTable,
            "--points",
            "csv-table",
        )?;
        refuse(
            self.device_id.is_some() && !px4,
            "--device-id",
            "px4-params",
        )?;
        refuse(
            self.accel_device_id.is_some() && !px4,
            "--accel-device-id",
            "px4-params",
        )?;
        refuse(self.slot.is_some() && !px4, "--slot", "px4-params")?;
        refuse(self.imu.is_some() && !ardupilot, "--imu", "ardupilot-parm")?;
        let flight = "px4-params or ardupilot-parm";
        refuse(self.y.is_some() && !self.format.is_flight(), "--y", flight)?;
        refuse(self.z.is_some() && !self.format.is_flight(), "--z", flight)?;
        let d = ExportOptions::default();
        Ok(ExportOptions {
            points: self.points.unwrap_or(d.points),
            px4: Px4Target {
                gyro_device_id: self
                    .device_id
                    .as_deref()
                    .map(|s| device_id("--device-id", s))
                    .transpose()?,
                accel_device_id: self
                    .accel_device_id
                    .as_deref()
                    .map(|s| device_id("--accel-device-id", s))
                    .transpose()?,
                slot: self.slot.unwrap_or(d.px4.slot),
            },
            ardupilot: ArduPilotTarget { imu: self.imu },
        })
    }
}

pub fn run(mut a: Args) -> Result<(), CliError> {
    // `-` is standard output, as it is standard input where a log is read.
    if a.out.as_deref() == Some(Path::new("-")) {
        a.out = None;
    }
    if let Some(out) = &a.out {
        let mut reads = super::common::Reads::of("the calibration", &a.calibration);
        if let Some(y) = &a.y {
            reads.add("the calibration of the Y axis (--y)", y);
        }
        if let Some(z) = &a.z {
            reads.add("the calibration of the Z axis (--z)", z);
        }
        super::common::refuse_outputs(&[("--out", out)], &reads)?;
    }
    let unit = super::common::load_calibration(&a.calibration)?;
    refuse_accel_device_id(&a, &unit)?;
    if unit.is_unit() {
        return run_unit(&a, &unit);
    }
    if a.axis.is_some() {
        return Err(format!(
            "--axis: {} is the calibration of a single axis; --axis picks one axis of a unit",
            a.calibration.display()
        )
        .into());
    }
    let model = unit.first()?;
    refuse_points(&a, &unit)?;
    let opts = a.options()?;
    let fail = |e: firmware::ExportError| export_failed(&a.calibration, &e);
    let text = if a.format.is_flight() {
        // The other axes' calibrations, each read (and refused) by its own path.
        let mut others = Vec::new();
        for (axis, path) in [("y", &a.y), ("z", &a.z)] {
            if let Some(p) = path {
                let m = calibration::load_model(p).map_err(|e| e.to_string())?;
                others.push((axis, m));
            }
        }
        let x_axis = if others.is_empty() { "" } else { "x" };
        let mut axes = vec![(x_axis, model)];
        axes.extend(others.iter().map(|(axis, m)| (*axis, m)));
        let file = firmware::flight_axes(&axes, a.format, &opts).map_err(fail)?;
        note_flight(&file);
        file.text
    } else {
        firmware::export_model(model, a.format, &opts).map_err(fail)?
    };
    let what = if model.gyro_id().is_empty() {
        model.source().name.clone()
    } else {
        model.gyro_id().to_string()
    };
    write(&a, &text, &what)
}

/// Refuses `--accel-device-id` where no accelerometer axis is written: a calibration of gyro
/// axes alone, or a gyro axis picked with `--axis`.
fn refuse_accel_device_id(a: &Args, unit: &UnitCalibration) -> Result<(), CliError> {
    if a.accel_device_id.is_none() {
        return Ok(());
    }
    let written: Vec<&str> = unit
        .axes
        .iter()
        .filter(|x| a.axis.as_ref().is_none_or(|n| *n == x.name))
        .filter(|x| x.kind == driftlab::log::AxisKind::Accel)
        .map(|x| x.name.as_str())
        .collect();
    if written.is_empty() {
        return Err(format!(
            "--accel-device-id: {}{} has no accelerometer axis to write ({})",
            a.calibration.display(),
            a.axis
                .as_ref()
                .map_or(String::new(), |n| format!(" --axis {n}")),
            if unit.is_unit() {
                format!("its axes: {}", unit.axis_names().join(", "))
            } else {
                "it is the calibration of one gyro axis".to_string()
            }
        )
        .into());
    }
    Ok(())
}

/// Refuses `--points` for a calibration with a regression model: its csv-table is its terms
/// and coefficients, with no curve sampled at points, so the option would change nothing.
fn refuse_points(a: &Args, unit: &UnitCalibration) -> Result<(), CliError> {
    if a.points.is_none() {
        return Ok(());
    }
    match unit
        .axes
        .iter()
        .find(|x| !matches!(x.model, driftlab::models::fitted::DriftModel::Vakhrameev(_)))
    {
        Some(x) => Err(format!(
            "--points sets the rows of a Vakhrameev calibration's K0/K1/K2 tables; {}{} holds \
             model {}, whose table is its coefficients",
            a.calibration.display(),
            if x.name.is_empty() {
                String::new()
            } else {
                format!(" (axis {})", x.name)
            },
            x.model.name()
        )
        .into()),
        None => Ok(()),
    }
}

/// An export's refusal about `calibration`, with the option that gets around it.
fn export_failed(calibration: &std::path::Path, e: &firmware::ExportError) -> String {
    use driftlab::export::flight::FlightError;
    use firmware::ExportError;
    if let ExportError::NoSuchAxis { name, axes } = e {
        return format!(
            "--axis {name}: {} has no axis {name} (its axes: {})",
            calibration.display(),
            axes.join(", ")
        );
    }
    let hint = match e {
        ExportError::MoreThanOneTemperature { axis, .. } => format!(" (--axis {axis})"),
        ExportError::TableColumns(_) => " (--axis NAME)".to_string(),
        ExportError::Flight(f) => match f.innermost() {
            FlightError::K0NotPolynomial { .. } => {
                " (--k0 parabolic, --model poly-t, or --model custom --terms 1,T,T^2,T^3)"
                    .to_string()
            }
            FlightError::NoGyroDeviceId => " (--device-id N)".to_string(),
            FlightError::AccelDeviceId(_) => " (--accel-device-id N)".to_string(),
            FlightError::ImuNumber(_) => " (--imu N)".to_string(),
            _ => String::new(),
        },
        _ => String::new(),
    };
    format!("{}: {e}{hint}", calibration.display())
}

/// `export` of a unit: every axis in one file, or the axis `--axis` names alone.
fn run_unit(a: &Args, unit: &UnitCalibration) -> Result<(), CliError> {
    for (given, flag) in [(a.y.is_some(), "--y"), (a.z.is_some(), "--z")] {
        if given {
            return Err(format!(
                "{flag}: {} is a unit of axes {}, which gives the gyro's X, Y and Z itself; \
                 export it without --y and --z",
                a.calibration.display(),
                unit.axis_names().join(", ")
            )
            .into());
        }
    }
    refuse_points(a, unit)?;
    let opts = a.options()?;
    let fail = |e: firmware::ExportError| export_failed(&a.calibration, &e);
    let text = match (&a.axis, a.format.is_flight()) {
        (pick, true) => {
            let file = firmware::flight_of(unit, pick.as_deref(), a.format, &opts).map_err(fail)?;
            note_flight(&file);
            file.text
        }
        (Some(name), false) => firmware::export_axis(unit, name, a.format, &opts).map_err(fail)?,
        (None, false) => firmware::export_unit(unit, a.format, &opts).map_err(fail)?,
    };
    let what = match &a.axis {
        Some(name) => format!("axis {name}"),
        None => format!("the unit's axes {}", unit.axis_names().join(", ")),
    };
    write(a, &text, &what)
}

/// A flight file's warnings and notes, on standard error.
fn note_flight(file: &driftlab::export::flight::FlightFile) {
    for w in &file.warnings {
        note!("warning: {w}");
    }
    for note in &file.notes {
        note!("note: {note}");
    }
}

/// Writes `text` to `--out` (atomically) or standard output; `what` names what was exported.
fn write(a: &Args, text: &str, what: &str) -> Result<(), CliError> {
    match &a.out {
        Some(path) => {
            driftlab::files::atomic::write_bytes(path, text.as_bytes())
                .map_err(|e| format!("{}: {e}", path.display()))?;
            note!("{} of {what} written to {}", a.format, path.display());
        }
        None => {
            let mut out = std::io::stdout().lock();
            // On a terminal, nothing in a name the file holds that it would obey; through a
            // pipe or into a file, the file as it is.
            let text = if out.is_terminal() {
                super::common::terminal_text(text)
            } else {
                std::borrow::Cow::Borrowed(text)
            };
            out.write_all(text.as_bytes())
                .and_then(|()| out.flush())
                .map_err(super::common::stdout_error)?;
        }
    }
    Ok(())
}
