//! PX4's thermal compensation as the QGroundControl parameter file
//! `Tools/process_sensor_caldata.py` writes: a tab-separated line per parameter
//! (`vehicle component name value type`, type 6 for int32, 9 for float32), the keys of each
//! gyro sorted as the script sorts them.
//!
//! PX4 (`TemperatureCompensation::calc_thermal_offsets_3D`) holds T to `[TMIN, TMAX]` and
//! computes `offset[i] = X0_i + X1_i·dT + X2_i·dT² + X3_i·dT³` with `dT = T − TREF` in
//! float32; `calibration::Gyroscope::Correct` then subtracts it (`data − thermal_offset −
//! offset`), as driftlab subtracts its prediction, so the coefficients are driftlab's
//! polynomial re-centred on TREF, in rad/s. The sensor is found by `TC_G{n}_ID`, compared
//! with its `device_id` as `(uint32_t)ID`: an id above 2³¹ is written as the negative int32
//! of the same bits. The compensation is read at boot and only when `TC_G_ENABLE` is 1.
//!
//! The accelerometer's constant (gravity on one axis, and its bias) is left to PX4's
//! accelerometer calibration, as the script leaves it by fitting `x − median(x)`: here the
//! curve is taken relative to its value at TREF, so `X0` of `TC_A{n}` is zero.

use super::numbers::{f32_text, f32_toward, python_repr};
use super::{Axes3, FlightError, FlightFile, ImuFits, Sensor, axes3, comments, finite, provenance};

/// Which of PX4's calibration slots, and the sensors' device ids.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Px4Target {
    /// The gyro's `device_id` (as `driftlab inspect` lists it); needed for a gyro
    /// calibration.
    pub gyro_device_id: Option<u32>,
    /// The accelerometer's `device_id`; by default the gyro's (one chip).
    pub accel_device_id: Option<u32>,
    /// The slot `n` of `TC_G{n}_*` and `TC_A{n}_*` (0 to 3; PX4 matches the sensor by id,
    /// so any free slot serves).
    pub slot: usize,
}

/// A device id as `driftlab inspect` prints it: decimal or `0x` hex; `None` for anything
/// else (a serial number).
pub fn parse_device_id(s: &str) -> Option<u32> {
    let t = s.trim();
    match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16).ok(),
        None => t.parse::<u32>().ok(),
    }
}

/// Refuses the device id 0, PX4's "no device": a slot whose `param` is 0 matches no sensor,
/// so the calibration written there would never be applied, with nothing said by the firmware.
fn refuse_no_device(id: u32, sensor: &str, param: &str) -> Result<(), FlightError> {
    if id == 0 {
        return Err(FlightError::Missing(format!(
            "device_id 0 is PX4's \"no device\": {param} 0 matches no {sensor}, so the \
             calibration would never be applied; give the {sensor}'s device_id (driftlab inspect \
             LOG lists each sensor's)"
        )));
    }
    Ok(())
}

/// The most slots PX4 reads (`GYRO_COUNT_MAX`, `ACCEL_COUNT_MAX`).
pub const SLOTS: usize = 4;

/// One parameter line's value and MAVLink type.
enum Value {
    Int(i32),
    Real(String),
}

fn sensor_params(
    prefix: &str,
    id: u32,
    axes: &Axes3,
    keep_constant: bool,
    out: &mut Vec<(String, Value)>,
) -> Result<(), FlightError> {
    let t_min = f32_toward(finite(axes.t_min, "TMIN")?, axes.t_max);
    let t_max = f32_toward(finite(axes.t_max, "TMAX")?, axes.t_min);
    // The middle of the range, as the script puts TREF, held by a float32.
    let t_ref = (0.5 * (f64::from(t_min) + f64::from(t_max))) as f32;
    out.push((format!("{prefix}_ID"), Value::Int(id as i32)));
    out.push((format!("{prefix}_TMIN"), Value::Real(f32_text(t_min))));
    out.push((format!("{prefix}_TMAX"), Value::Real(f32_text(t_max))));
    out.push((format!("{prefix}_TREF"), Value::Real(f32_text(t_ref))));
    for (axis, p) in axes.polys.iter().enumerate() {
        let b = match p {
            Some(p) => p.around(f64::from(t_ref)),
            None => [0.0; 4],
        };
        for (k, &c) in b.iter().enumerate() {
            let c = if k == 0 && !keep_constant { 0.0 } else { c };
            let name = format!("{prefix}_X{k}_{axis}");
            let v = finite(c, &name)?;
            out.push((name, Value::Real(python_repr(v))));
        }
    }
    Ok(())
}

/// The `.params` text of `fits` for PX4.
///
/// # Errors
/// A model whose static part is not a polynomial of degree ≤ 3 in T, axes that cannot be put
/// in order, a gyro calibration without the gyro's device id, a slot past the last.
pub fn px4_params(fits: &ImuFits<'_>, target: &Px4Target) -> Result<FlightFile, FlightError> {
    if target.slot >= SLOTS {
        return Err(FlightError::Missing(format!(
            "PX4 has calibration slots 0 to {}, not {}",
            SLOTS - 1,
            target.slot
        )));
    }
    let mut notes = Vec::new();
    let mut warnings = Vec::new();
    let gyro = axes3(&fits.gyro, Sensor::Gyro, &mut notes, &mut warnings)?;
    let accel = axes3(&fits.accel, Sensor::Accel, &mut notes, &mut warnings)?;
    if gyro.is_none() && accel.is_none() {
        return Err(FlightError::Missing(
            "nothing to export: no gyro or accelerometer model".into(),
        ));
    }
    let n = target.slot;
    let mut lines: Vec<(String, Value)> = Vec::new();
    // The script writes the accelerometers, then the barometers, then the gyros.
    if let Some(a) = &accel {
        let id = target
            .accel_device_id
            .or(target.gyro_device_id)
            .ok_or_else(|| {
                FlightError::Missing(
                    "PX4 finds the accelerometer by its device_id (TC_A0_ID): give it (driftlab \
                     inspect LOG lists each sensor's)"
                        .into(),
                )
            })?;
        refuse_no_device(id, "accelerometer", &format!("TC_A{n}_ID"))?;
        if id > i32::MAX as u32 {
            notes.push(format!(
                "device_id {id} is above 2^31: TC_A{n}_ID holds it as the int32 {} (PX4 \
                 compares it as uint32)",
                id as i32
            ));
        }
        if target.accel_device_id.is_none() {
            notes.push(format!(
                "TC_A{n}_ID is the gyro's device_id {id}: give the accelerometer's if the IMU \
                 reports another"
            ));
        }
        notes.push(format!(
            "the accelerometer's constant (gravity and its bias at TREF) is left to PX4's \
             accelerometer calibration: TC_A{n}_X0_* are 0, the curve taken relative to TREF \
             (process_sensor_caldata.py likewise removes the median of each axis)"
        ));
        lines.push(("TC_A_ENABLE".into(), Value::Int(1)));
        // The script writes the accelerometer's keys in the order it defines them (its
        // `sort` is never called), the gyro's sorted.
        sensor_params(&format!("TC_A{n}"), id, a, false, &mut lines)?;
    }
    if let Some(g) = &gyro {
        let id = target.gyro_device_id.ok_or(FlightError::NoGyroDeviceId)?;
        refuse_no_device(id, "gyro", &format!("TC_G{n}_ID"))?;
        if id > i32::MAX as u32 {
            notes.push(format!(
                "device_id {id} is above 2^31: TC_G{n}_ID holds it as the int32 {} (PX4 \
                 compares it as uint32)",
                id as i32
            ));
        }
        lines.push(("TC_G_ENABLE".into(), Value::Int(1)));
        let mut p = Vec::new();
        sensor_params(&format!("TC_G{n}"), id, g, true, &mut p)?;
        p.sort_by(|x, y| x.0.cmp(&y.0));
        lines.extend(p);
    }
    let mut text = String::from(
        "# Sensor thermal compensation parameters\n#\n# Vehicle-Id Component-Id Name Value Type\n",
    );
    text.push_str(&format!(
        "# driftlab {}: offset = X0 + X1*dT + X2*dT^2 + X3*dT^3, dT = T - TREF with T held to \
         [TMIN, TMAX], in rad/s (m/s^2); PX4 subtracts it from the reading\n",
        env!("CARGO_PKG_VERSION")
    ));
    for p in provenance(fits) {
        text.push_str(&format!("# {p}\n"));
    }
    text.push_str(&comments(&notes, &warnings));
    text.push_str(&format!(
        "# only slot {n} is written: the other slots keep their calibrations\n"
    ));
    for (name, v) in lines {
        let (value, ty) = match v {
            Value::Int(i) => (i.to_string(), 6),
            Value::Real(s) => (s, 9),
        };
        text.push_str(&format!("1\t1\t{name}\t{value}\t{ty}\n"));
    }
    Ok(FlightFile {
        text,
        notes,
        warnings,
    })
}
