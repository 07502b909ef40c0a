//! A calibration as a flight controller's parameter file: a single axis, axes given one
//! calibration each, or a unit, whose gyro axes go to the gyro's X, Y, Z (`TC_G0_*`,
//! `INS_TCALn_GYR*`) and whose accelerometer axes to the accelerometer's (`TC_A0_*`,
//! `INS_TCALn_ACC*`), each sensor placed by its own axes' names. The files themselves are
//! written by [`crate::export::flight`].

use super::{ExportError, ExportOptions, Format};
use crate::export::flight::ardupilot::ardupilot_parm;
use crate::export::flight::px4::{Px4Target, px4_params};
use crate::export::flight::{AxisFit, FlightError, FlightFile, ImuFits};
use crate::log::AxisKind;
use crate::models::fitted::DriftModel;
use crate::models::unit::{AxisModel, UnitCalibration};

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
    flight_sensors(axes, &[], format, opts)
}

/// The one writer behind every flight file: the gyro's axes `gyro` and the accelerometer's
/// `accel`, each `(axis, model)` placed by its name's x, y or z; the device id from the first
/// model's gyro id when `opts` gives none.
///
/// # Errors
/// No axis at all, one calibration given for two axes of a sensor, and as the format's
/// writer.
fn flight_sensors(
    gyro: &[(&str, &DriftModel)],
    accel: &[(&str, &DriftModel)],
    format: Format,
    opts: &ExportOptions,
) -> Result<FlightFile, ExportError> {
    let Some(&(_, model)) = gyro.first().or(accel.first()) else {
        return Err(ExportError::NoAxes);
    };
    // One calibration given for two axes (`--y x.json`, or a copy of it) would write one
    // axis's drift as another's: every axis of a sensor drifts its own way.
    for axes in [gyro, accel] {
        for (i, &(a, first)) in axes.iter().enumerate() {
            if let Some(&(b, _)) = axes[i + 1..].iter().find(|&&(_, m)| m == first) {
                return Err(ExportError::Flight(FlightError::Axes(format!(
                    "axes {} and {} are given the same calibration (every coefficient equal): \
                     each axis of a sensor drifts its own way; give each axis its own \
                     calibration",
                    a.to_uppercase(),
                    b.to_uppercase()
                ))));
            }
        }
    }
    let fits = ImuFits {
        gyro: fits_of(gyro),
        accel: fits_of(accel),
    };
    Ok(match format {
        Format::Px4Params => {
            // A gyro id that is a device id (as a drone log's gyro has) serves as one.
            let from_id = crate::export::flight::px4::parse_device_id(model.gyro_id())
                .filter(|_| opts.px4.gyro_device_id.is_none());
            let target = Px4Target {
                gyro_device_id: opts.px4.gyro_device_id.or(from_id),
                accel_device_id: accel_device_id(accel, &opts.px4)?,
                ..opts.px4
            };
            let mut file = px4_params(&fits, &target)?;
            file.warnings
                .extend(ids_not_recorded(gyro, accel, &opts.px4));
            if let Some(id) = from_id {
                let param = if gyro.is_empty() { "TC_A" } else { "TC_G" };
                file.notes.push(format!(
                    "{param}{}_ID is the calibration's gyro id {id}",
                    target.slot
                ));
            }
            file
        }
        Format::ArdupilotParm => ardupilot_parm(&fits, &opts.ardupilot)?,
        other => {
            return Err(ExportError::NotFlight(other));
        }
    })
}

/// The accelerometer's device id for `TC_A{n}_ID`: the one given, else none (the gyro's is
/// taken, one chip); refused when the calibration records that the accelerometer it was
/// fitted on had a device id of its own, which the gyro's would not match, so PX4 would apply
/// the compensation to no accelerometer, with nothing said.
fn accel_device_id(
    accel: &[(&str, &DriftModel)],
    px4: &Px4Target,
) -> Result<Option<u32>, ExportError> {
    let recorded = accel
        .iter()
        .filter_map(|(_, m)| m.source().instance.as_ref())
        .find_map(|g| Some((g.px4_device_id?, g.px4_accel_device_id?)));
    if let Some(given) = px4.accel_device_id {
        // The gyro's id given for the accelerometer that had one of its own: the very
        // mistake the option is there to prevent.
        if let Some((gyro, a)) = recorded
            && given == gyro
        {
            return Err(ExportError::Flight(FlightError::AccelDeviceId(format!(
                "the accelerometer's device_id given, {given}, is that of the gyro the \
                 calibration was fitted on; its accelerometer had its own, {a} (0x{a:X}) \
                 (source.instance.px4_accel_device_id), by which PX4 finds its compensation"
            ))));
        }
        return Ok(Some(given));
    }
    match recorded {
        Some((gyro, a)) => Err(ExportError::Flight(FlightError::AccelDeviceId(format!(
            "TC_A{n}_ID: the accelerometer the calibration was fitted on has its own device_id \
             {a} (0x{a:X}), not the gyro's {gyro} (0x{gyro:X}) \
             (source.instance.px4_accel_device_id): PX4 finds the accelerometer's \
             compensation by it, so give it",
            n = px4.slot
        )))),
        None => Ok(None),
    }
}

/// The device ids given that differ from those the calibration records of the sensors it was
/// fitted on (`source.instance.px4_device_id`, `px4_accel_device_id`): taken, since a unit's
/// calibration may be meant for a sensor on another bus or address, but said, naming both,
/// since PX4 then compensates the sensor of the id given and no other.
fn ids_not_recorded(
    gyro: &[(&str, &DriftModel)],
    accel: &[(&str, &DriftModel)],
    px4: &Px4Target,
) -> Vec<String> {
    use crate::log::DroneGyro;
    let recorded = |axes: &[(&str, &DriftModel)], pick: fn(&DroneGyro) -> Option<u32>| {
        axes.iter()
            .filter_map(|(_, m)| m.source().instance.as_ref())
            .find_map(pick)
    };
    let mut out = Vec::new();
    let gyro_recorded = recorded(gyro, |i| i.px4_device_id);
    // One chip's accelerometer has the gyro's id.
    let accel_recorded = recorded(accel, |i| i.px4_accel_device_id.or(i.px4_device_id));
    for (param, given, recorded, field, what) in [
        (
            "TC_G",
            px4.gyro_device_id,
            gyro_recorded,
            "px4_device_id",
            "gyro",
        ),
        (
            "TC_A",
            px4.accel_device_id,
            accel_recorded,
            "px4_accel_device_id",
            "accelerometer",
        ),
    ] {
        if let (Some(given), Some(rec)) = (given, recorded)
            && given != rec
        {
            out.push(format!(
                "{param}{}_ID is the device_id given, {given} (0x{given:X}), not that of the \
                 {what} the calibration was fitted on, {rec} (0x{rec:X}) \
                 (source.instance.{field}): PX4 applies the compensation to the sensor of the \
                 id given",
                px4.slot
            ));
        }
    }
    out
}

/// `(axis, model)` pairs as the flight writers take them.
fn fits_of<'a>(axes: &[(&'a str, &'a DriftModel)]) -> Vec<AxisFit<'a>> {
    axes.iter()
        .map(|&(axis, model)| AxisFit { axis, model })
        .collect()
}

/// Labelled models as `(axis, model)` pairs.
fn as_refs<'a>(axes: &'a [(String, &'a DriftModel)]) -> Vec<(&'a str, &'a DriftModel)> {
    axes.iter().map(|(l, m)| (l.as_str(), *m)).collect()
}

/// A unit as a flight controller's parameter file: its three gyro axes as the gyro's X, Y and
/// Z, its three accelerometer axes (if any) as the accelerometer's, each by the letter their
/// names end with (`gx`, `gyro_y`, `acc_z`) when the three names give x, y and z, else in the
/// unit's order (and a note says so). A single-axis calibration is written as [`flight`]
/// writes it.
///
/// # Errors
/// A sensor of the unit without exactly three axes (naming the axes it has); as
/// [`flight_axes`].
pub fn flight_unit(
    unit: &UnitCalibration,
    format: Format,
    opts: &ExportOptions,
) -> Result<FlightFile, ExportError> {
    flight_of(unit, None, format, opts)
}

/// The flight file of a unit, or of the one axis `pick` names alone: the one writer behind
/// [`flight_unit`] and [`super::export_axis`]. Every axis's place (X, Y or Z of its sensor) is
/// the one the whole unit's file gives it ([`flight_places`]), so an axis written alone lands
/// in the parameters the unit's file writes it in, the others at zero (and a note says so).
///
/// # Errors
/// `pick` names no axis of the unit ([`ExportError::NoSuchAxis`]) or is given for a
/// single-axis calibration ([`ExportError::NotAUnit`]); the whole of a unit whose gyro or
/// accelerometer has other than three axes; as [`flight_axes`].
pub fn flight_of(
    unit: &UnitCalibration,
    pick: Option<&str>,
    format: Format,
    opts: &ExportOptions,
) -> Result<FlightFile, ExportError> {
    if !unit.is_unit() {
        if pick.is_some() {
            return Err(ExportError::NotAUnit);
        }
        let model = &unit.axes.first().ok_or(ExportError::NoAxes)?.model;
        return flight(model, format, opts);
    }
    if let Some(name) = pick {
        picked(unit, name)?;
    }
    let mut notes = Vec::new();
    let mut sensors: Vec<Vec<(String, &DriftModel)>> = Vec::with_capacity(2);
    for kind in [AxisKind::Gyro, AxisKind::Accel] {
        let axes: Vec<&AxisModel> = unit.axes.iter().filter(|a| a.kind == kind).collect();
        let names: Vec<&str> = axes.iter().map(|a| a.name.as_str()).collect();
        if pick.is_none() && !(names.is_empty() || names.len() == 3) {
            let of = match kind {
                AxisKind::Gyro => "a unit of three axes".to_string(),
                AxisKind::Accel => "three accelerometer axes".to_string(),
            };
            return Err(FlightError::Axes(format!(
                "the unit has {} {} {} ({}): {format} holds a {}'s X, Y and Z, so it takes {of}",
                names.len(),
                kind.sensor(),
                if names.len() == 1 { "axis" } else { "axes" },
                names.join(", "),
                kind.sensor(),
            ))
            .into());
        }
        let (labels, in_order) = flight_places(&names);
        if in_order && axes.iter().any(|a| pick.is_none_or(|p| a.name == p)) {
            let which = match kind {
                AxisKind::Gyro => "",
                AxisKind::Accel => " accelerometer",
            };
            notes.push(format!(
                "the unit's{which} axes {} do not name x, y and z: written as X, Y, Z in their \
                 order",
                names.join(", ")
            ));
        }
        sensors.push(
            labels
                .into_iter()
                .zip(axes)
                .filter(|(_, a)| pick.is_none_or(|p| a.name == p))
                .map(|(l, a)| (l, &a.model))
                .collect(),
        );
    }
    let mut file = flight_sensors(&as_refs(&sensors[0]), &as_refs(&sensors[1]), format, opts)?;
    file.notes.extend(notes);
    Ok(file)
}

/// The label each axis of a sensor of a unit named `names` is written under in a flight
/// file, whose x, y or z places it ([`crate::export::flight::axis_index`]), and whether the
/// places are the unit's order: its names when they give each axis a letter of its own; for
/// three axes whose names do not, `x (axis a)`, `y (axis b)`, `z (axis c)` in the unit's
/// order; else the names as they are (one axis of such a unit, written alone, goes where its
/// name places it, or into X with a note when it names no letter).
fn flight_places(names: &[&str]) -> (Vec<String>, bool) {
    let by_letter: Vec<Option<usize>> = names
        .iter()
        .map(|n| crate::export::flight::axis_index(n))
        .collect();
    let distinct = by_letter
        .iter()
        .enumerate()
        .all(|(i, k)| k.is_some() && !by_letter[..i].contains(k));
    if distinct || names.len() != 3 {
        (names.iter().map(|n| n.to_string()).collect(), false)
    } else {
        // The letter first: it is the word that places the axis.
        let labels = names
            .iter()
            .zip(["x", "y", "z"])
            .map(|(n, l)| format!("{l} (axis {n})"))
            .collect();
        (labels, true)
    }
}

/// The axis `name` of `unit`, or the refusal naming the axes it has.
pub(super) fn picked<'a>(
    unit: &'a UnitCalibration,
    name: &str,
) -> Result<&'a AxisModel, ExportError> {
    unit.axis(name).ok_or_else(|| ExportError::NoSuchAxis {
        name: name.to_string(),
        axes: unit.axis_names().iter().map(|n| n.to_string()).collect(),
    })
}
