//! ArduPilot's IMU temperature calibration as the parameter file
//! `Tools/scripts/tempcal_IMU.py` writes: `NAME VALUE` lines, `INS_TCALn_ENABLE`, `_TMIN`,
//! `_TMAX`, then the accelerometer's and the gyro's coefficients of orders 1 to 3, each
//! multiplied by 10⁶ and written with nine decimals (more for values below 1, so that nine
//! significant digits remain), in fixed notation as parameter editors expect. `TMIN` and
//! `TMAX` are written as the float32 the firmware will hold, inside the range driftlab fitted
//! (the script writes `%.1f`, which would move either end by up to 0.05 °C and let the
//! firmware evaluate the curve where driftlab holds it).
//!
//! The firmware (`AP_InertialSensor::TCal::correct_sensor`) holds T and the calibration
//! temperature `INS_GYRn_CALTEMP` to `[TMIN, TMAX]` and computes
//! `v −= p(T − 35) − p(T_cal − 35)`, `p(x) = (c1 + (c2 + c3·x)·x)·x·1e-6` in float32: the
//! polynomial has no constant term and is centred on a fixed 35 °C. The constant is carried by
//! the offsets measured at boot (`INS_GYROFFS_*` at `INS_GYR1_CALTEMP`), so what a file can
//! hold is driftlab's correction up to a constant: its polynomial re-centred on 35 °C, the
//! constant dropped. The firmware subtracts it, as driftlab subtracts its prediction.
//!
//! One range `[TMIN, TMAX]` serves the accelerometer and the gyro, and `ENABLE = 1` turns both
//! on: a gyro calibration alone writes the accelerometer's coefficients as zero, as the script
//! writes both, so that no older accelerometer coefficients are applied over the new range.

use super::numbers::{f32_text, f32_toward};
use super::{Axes3, FlightError, FlightFile, ImuFits, Sensor, axes3, comments, finite, provenance};

/// ArduPilot's fixed reference temperature (`TEMP_REFERENCE`), °C.
pub const TEMP_REFERENCE_C: f64 = 35.0;

/// The factor parameters are stored with (`SCALE_FACTOR`).
pub const SCALE_FACTOR: f64 = 1.0e6;

/// The most IMUs ArduPilot calibrates (`INS_TCAL1` to `INS_TCAL3`).
pub const IMUS: usize = 3;

/// Which IMU's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ArduPilotTarget {
    /// `n` of `INS_TCALn`: 1 for the first IMU (DataFlash `IMU` instance `I = 0`). `None`:
    /// the IMU the calibration was fitted on, when it was fitted on a DataFlash log's
    /// ([`crate::models::vakhrameev::SourceInfo::instance`]), else the first, with a note
    /// ([`imu_of`]).
    pub imu: Option<usize>,
}

/// The IMU number `n` of `INS_TCALn` for `fits`: the one asked for, else the one the models
/// were fitted on. A log of several IMUs names none of them by its file name, and the
/// parameters of another IMU than the one calibrated would correct it with a stranger's
/// drift, so what was chosen on the user's behalf, or what the calibration says against the
/// choice, goes into `notes`.
///
/// # Errors
/// Nothing asked for, and models fitted on different IMUs (one file calibrates one IMU).
pub fn imu_of(
    fits: &ImuFits<'_>,
    target: &ArduPilotTarget,
    notes: &mut Vec<String>,
) -> Result<usize, FlightError> {
    let mut fitted_on: Vec<u8> = fits
        .gyro
        .iter()
        .chain(&fits.accel)
        .filter_map(|f| f.model.source().instance.as_ref()?.dataflash_imu)
        .collect();
    fitted_on.sort_unstable();
    fitted_on.dedup();
    let said = |i: &u8| format!("IMU {} (DataFlash I={i})", usize::from(*i) + 1);
    match (target.imu, fitted_on.as_slice()) {
        (Some(n), recorded) => {
            if recorded.iter().any(|&i| usize::from(i) + 1 != n) {
                notes.push(format!(
                    "written as IMU {n} (INS_TCAL{n}) as asked, but the calibration was fitted \
                     on {}",
                    recorded.iter().map(said).collect::<Vec<_>>().join(" and ")
                ));
            }
            Ok(n)
        }
        (None, [one]) => {
            let n = usize::from(*one) + 1;
            notes.push(format!(
                "INS_TCAL{n}: the calibration was fitted on {} of its log",
                said(one)
            ));
            Ok(n)
        }
        (None, []) => {
            notes.push(
                "INS_TCAL1, the first IMU: the calibration records no DataFlash log's IMU \
                 (its log was a CSV or another format, or the file is older than the record); \
                 give the export the IMU number if it is another"
                    .into(),
            );
            Ok(1)
        }
        (None, several) => Err(FlightError::ImuNumber(format!(
            "the axes were fitted on different IMUs ({}): one INS_TCALn calibrates one IMU; \
             give the export the IMU number to write them as one",
            several.iter().map(said).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// The three lines of one order of one sensor: `(name, value)`.
fn order_lines(
    prefix: &str,
    kind: &str,
    axes: Option<&Axes3>,
    order: usize,
    out: &mut Vec<(String, String)>,
) -> Result<(), FlightError> {
    for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
        let c = match axes.and_then(|a| a.polys[k].as_ref()) {
            Some(p) => p.around(TEMP_REFERENCE_C)[order],
            None => 0.0,
        };
        let name = format!("{prefix}_{kind}{order}_{axis}");
        let v = finite(c * SCALE_FACTOR, &name)?;
        out.push((name, fixed(v)));
    }
    Ok(())
}

/// `v` in fixed notation as the script writes it (`%.9f`), with more decimals where nine
/// would keep fewer than nine significant digits: a fibre-optic gyro's coefficients, even
/// scaled by 10⁶, are far below 1, and a float32 parameter holds seven digits of them.
fn fixed(v: f64) -> String {
    let decimals = if v == 0.0 {
        9
    } else {
        (8 - v.abs().log10().floor() as i32).clamp(9, 30) as usize
    };
    format!("{v:.decimals$}")
}

/// The parameter text of `fits` for ArduPilot.
///
/// # Errors
/// A model whose static part is not a polynomial of degree ≤ 3 in T, axes that cannot be put
/// in order, an IMU number ArduPilot does not have, a gyro and an accelerometer that share no
/// temperature range.
pub fn ardupilot_parm(
    fits: &ImuFits<'_>,
    target: &ArduPilotTarget,
) -> Result<FlightFile, FlightError> {
    let mut notes = Vec::new();
    let n = imu_of(fits, target, &mut notes)?;
    if !(1..=IMUS).contains(&n) {
        return Err(FlightError::ImuNumber(format!(
            "ArduPilot calibrates IMUs 1 to {IMUS} (INS_TCAL1 to INS_TCAL{IMUS}), not {n}{}",
            if target.imu.is_none() {
                " (the IMU the calibration was fitted on): give the export another IMU number"
            } else {
                ""
            }
        )));
    }
    let mut warnings = Vec::new();
    let gyro = axes3(&fits.gyro, Sensor::Gyro, &mut notes, &mut warnings)?;
    let accel = axes3(&fits.accel, Sensor::Accel, &mut notes, &mut warnings)?;
    let (t_min, t_max) = match (&gyro, &accel) {
        (None, None) => {
            return Err(FlightError::Missing(
                "nothing to export: no gyro or accelerometer model".into(),
            ));
        }
        (Some(g), None) => {
            notes.push(
                "no accelerometer model: INS_TCAL*_ACC* are written as 0 (ArduPilot applies \
                 both sensors' coefficients over the one TMIN .. TMAX)"
                    .into(),
            );
            (g.t_min, g.t_max)
        }
        (None, Some(a)) => {
            notes.push(
                "no gyro model: INS_TCAL*_GYR* are written as 0 (ArduPilot applies both \
                 sensors' coefficients over the one TMIN .. TMAX)"
                    .into(),
            );
            (a.t_min, a.t_max)
        }
        (Some(g), Some(a)) => {
            let (lo, hi) = (g.t_min.max(a.t_min), g.t_max.min(a.t_max));
            // NaN ends count as no range.
            if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
                return Err(FlightError::Missing(format!(
                    "the gyro ({} .. {} degC) and the accelerometer ({} .. {} degC) share no \
                     temperature range: ArduPilot holds one for both",
                    g.t_min, g.t_max, a.t_min, a.t_max
                )));
            }
            if (lo, hi) != (g.t_min, g.t_max) || (lo, hi) != (a.t_min, a.t_max) {
                notes.push(format!(
                    "the gyro and the accelerometer were fitted over different temperatures: \
                     the file's range is the one both cover, {lo} .. {hi} degC"
                ));
            }
            (lo, hi)
        }
    };
    notes.push(format!(
        "the constant (the bias at {TEMP_REFERENCE_C} degC) is left to the offsets ArduPilot \
         measures at boot at INS_GYRn_CALTEMP / INS_ACCn_CALTEMP: the file corrects the change \
         with temperature"
    ));
    let lo = f32_toward(finite(t_min, "TMIN")?, t_max);
    let hi = f32_toward(finite(t_max, "TMAX")?, t_min);
    let prefix = format!("INS_TCAL{n}");
    let mut lines = vec![
        (format!("{prefix}_ENABLE"), "1".to_string()),
        (format!("{prefix}_TMIN"), f32_text(lo)),
        (format!("{prefix}_TMAX"), f32_text(hi)),
    ];
    for order in 1..=3 {
        order_lines(&prefix, "ACC", accel.as_ref(), order, &mut lines)?;
    }
    for order in 1..=3 {
        order_lines(&prefix, "GYR", gyro.as_ref(), order, &mut lines)?;
    }
    let mut text = format!(
        "# driftlab {}: ArduPilot IMU {n} temperature calibration; v -= p(T - 35) - p(T_cal - \
         35), p(x) = (c1 + (c2 + c3*x)*x)*x*1e-6, T held to [TMIN, TMAX], in rad/s (m/s^2)\n",
        env!("CARGO_PKG_VERSION")
    );
    for p in provenance(fits) {
        text.push_str(&format!("# {p}\n"));
    }
    text.push_str(&comments(&notes, &warnings));
    for (name, value) in lines {
        text.push_str(&format!("{name} {value}\n"));
    }
    Ok(FlightFile {
        text,
        notes,
        warnings,
    })
}
