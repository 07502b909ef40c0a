//! A calibration written for a flight controller: PX4's thermal-compensation parameters as
//! the QGroundControl `.params` file `Tools/process_sensor_caldata.py` writes ([`px4`]), and
//! ArduPilot's `INS_TCALn_*` parameters as `Tools/scripts/tempcal_IMU.py` writes them
//! ([`ardupilot`]).
//!
//! Both firmwares subtract from each axis's reading a polynomial of degree 3 in the sensor's
//! temperature, with T held to `[TMIN, TMAX]`, as driftlab subtracts its prediction; what
//! differs is where the polynomial is centred and what happens to its constant:
//!
//! | | PX4 (`TemperatureCompensation.cpp`) | ArduPilot (`AP_InertialSensor_tempcal.cpp`) |
//! |---|---|---|
//! | correction | `offset = X0 + X1·dT + X2·dT² + X3·dT³`, `dT = T − TREF` | `v −= p(T − 35) − p(T_cal − 35)`, `p(x) = (c1 + (c2 + c3·x)·x)·x·1e-6` |
//! | centre | `TREF`, the middle of the range (as the script sets it) | 35 °C, fixed |
//! | constant | `X0`, the bias at TREF (gyro); left to `CAL_ACCn_*OFF` for the accelerometer | none: the offsets measured at boot at `INS_GYRn_CALTEMP` carry it |
//! | unit | rad/s (m/s²), float32 | rad/s (m/s²) × 10⁶, float32 |
//! | identity | `TC_G0_ID` = the gyro's `device_id` (int32) | the IMU's instance, `INS_TCAL1` for the first |
//!
//! What is exported is the static part of a model as a polynomial in T
//! ([`polynomial::static_polynomial`]): a regression over `1, T, T², T³` (`poly-t` or a custom
//! model), or Vakhrameev's K0 when it is a line or a parabola, its rate terms left out with a
//! warning. A calibration of several axes is a list of [`AxisFit`]s, put in X, Y, Z order by
//! their names (one axis of them alone goes where its name puts it, the others at zero); a
//! single axis without a name goes into X, and the file says so.

pub mod ardupilot;
pub mod numbers;
pub mod polynomial;
pub mod px4;

pub use polynomial::{MAX_ORDER, TempPolynomial, static_polynomial};

use crate::models::fitted::DriftModel;

/// A model fitted on one axis of an IMU.
#[derive(Debug, Clone, Copy)]
pub struct AxisFit<'a> {
    /// The axis's name (`gyro_x`, `gx`, `x`, `accel_z_m_s2`): its x, y or z places it; empty
    /// for a calibration that names no axis.
    pub axis: &'a str,
    /// The fitted model.
    pub model: &'a DriftModel,
}

/// The models of one IMU to export.
#[derive(Debug, Clone, Default)]
pub struct ImuFits<'a> {
    /// Gyro axes, each a model of the rate in °/h (driftlab's unit).
    pub gyro: Vec<AxisFit<'a>>,
    /// Accelerometer axes, each a model fitted on a log whose rate column held that axis in
    /// m/s² (so its predictions are in m/s²).
    pub accel: Vec<AxisFit<'a>>,
}

/// A parameter file and what the user must know about it.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightFile {
    /// The file's text.
    pub text: String,
    /// What was chosen on the user's behalf (also written as comments in the file).
    pub notes: Vec<String>,
    /// What the firmware will not correct as driftlab does: terms left out, a curve held
    /// where driftlab extrapolates (also written as comments in the file).
    pub warnings: Vec<String>,
}

impl FlightError {
    /// The refusal itself, under the axes it was found on.
    pub fn innermost(&self) -> &FlightError {
        match self {
            FlightError::OnAxis { source, .. } => source.innermost(),
            other => other,
        }
    }
}

/// Why a calibration cannot be written for a flight controller.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlightError {
    /// The model's static part is not a polynomial in T the firmware evaluates.
    #[error("{0}")]
    NotPolynomial(String),
    /// Vakhrameev's K0 is a curve of knots (piecewise-linear, spline) rather than a polynomial
    /// in T; a parabolic or linear K0, or a polynomial model, would do.
    #[error(
        "model {model}: K0 is a {kind} curve; PX4 and ArduPilot evaluate a polynomial in T of \
         degree 3 at most: calibrate with a parabolic (or linear) K0, or with the poly-t model \
         or a custom model of 1,T,T^2,T^3"
    )]
    K0NotPolynomial {
        /// The model's name.
        model: String,
        /// The kind of K0's curve.
        kind: String,
    },
    /// A refusal about one axis of a sensor.
    #[error("{sensor} axis {axis}: {source}")]
    OnAxis {
        /// The sensor (`gyro`, `accelerometer`).
        sensor: String,
        /// The axis: X, Y or Z.
        axis: &'static str,
        /// What is wrong with the axis's model.
        source: Box<FlightError>,
    },
    /// PX4 finds a gyro by its device id, which neither the export nor the calibration gives.
    #[error(
        "PX4 finds the gyro by its device_id (TC_G0_ID): give the export the gyro's device id, \
         or make it the calibration's gyro id (driftlab inspect LOG lists each gyro's)"
    )]
    NoGyroDeviceId,
    /// The accelerometer's device id for PX4 (`TC_A{n}_ID`) is not the gyro's, and the one
    /// given (or none) is not it: the export's accelerometer id gives it.
    #[error("{0}")]
    AccelDeviceId(String),
    /// The IMU a file is for cannot be told (models fitted on different IMUs), or is one the
    /// firmware does not calibrate: the export's IMU number chooses it.
    #[error("{0}")]
    ImuNumber(String),
    /// The axes cannot be put in X, Y, Z order.
    #[error("{0}")]
    Axes(String),
    /// Something the firmware needs that the calibration does not say.
    #[error("{0}")]
    Missing(String),
    /// A number the firmware cannot hold.
    #[error("{0}")]
    Number(String),
}

/// Which sensor a set of axes is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sensor {
    Gyro,
    Accel,
}

impl Sensor {
    fn name(self) -> &'static str {
        match self {
            Sensor::Gyro => "gyro",
            Sensor::Accel => "accelerometer",
        }
    }

    /// From the unit the models predict in to the firmware's (rad/s, m/s²).
    fn to_si(self) -> f64 {
        match self {
            Sensor::Gyro => 1.0 / crate::log::ingest::RateUnit::RadPerSec.to_dph_factor(),
            Sensor::Accel => 1.0,
        }
    }
}

/// The place (0 = x, 1 = y, 2 = z) an axis's name gives it: a word `x`, `y` or `z`, or a
/// two-letter word ending in one (`gx`, `ay`, `wz`), among the name's words.
pub fn axis_index(name: &str) -> Option<usize> {
    let lower = name.to_ascii_lowercase();
    lower
        .split(|c: char| !c.is_ascii_alphanumeric())
        .find_map(|w| {
            let b = w.as_bytes();
            let last = match b {
                [c] => *c,
                [a, c] if a.is_ascii_alphabetic() => *c,
                _ => return None,
            };
            match last {
                b'x' => Some(0),
                b'y' => Some(1),
                b'z' => Some(2),
                _ => None,
            }
        })
}

/// One sensor's axes as polynomials in the firmware's unit, in X, Y, Z order, over the range
/// all of them were fitted on.
#[derive(Debug, Clone)]
pub(crate) struct Axes3 {
    pub polys: [Option<TempPolynomial>; 3],
    pub t_min: f64,
    pub t_max: f64,
}

/// Puts `fits` in X, Y, Z order, their polynomials in the firmware's unit; notes what was
/// chosen (a single unnamed axis as X, missing axes at zero, a range narrowed to the one
/// every axis covers) and warns of what was left out.
pub(crate) fn axes3(
    fits: &[AxisFit<'_>],
    sensor: Sensor,
    notes: &mut Vec<String>,
    warnings: &mut Vec<String>,
) -> Result<Option<Axes3>, FlightError> {
    if fits.is_empty() {
        return Ok(None);
    }
    let mut polys: [Option<TempPolynomial>; 3] = [None, None, None];
    for fit in fits {
        let k = match axis_index(fit.axis) {
            Some(k) => k,
            None if fits.len() == 1 => {
                notes.push(format!(
                    "a single-axis {} calibration{}: written as the X axis; Y and Z are left \
                     at zero",
                    sensor.name(),
                    if fit.axis.is_empty() {
                        " that names no axis".to_string()
                    } else {
                        format!(" of axis \"{}\"", fit.axis)
                    }
                ));
                0
            }
            None => {
                return Err(FlightError::Axes(format!(
                    "the {} axis \"{}\" names no x, y or z: the firmware's X, Y, Z cannot be \
                     told",
                    sensor.name(),
                    fit.axis
                )));
            }
        };
        if polys[k].is_some() {
            return Err(FlightError::Axes(format!(
                "two {} models for axis {}",
                sensor.name(),
                ["X", "Y", "Z"][k]
            )));
        }
        let p = static_polynomial(fit.model).map_err(|e| FlightError::OnAxis {
            sensor: sensor.name().to_string(),
            axis: ["X", "Y", "Z"][k],
            source: Box::new(e),
        })?;
        for w in &p.warnings {
            warnings.push(format!("{} {}: {w}", sensor.name(), ["X", "Y", "Z"][k]));
        }
        if p.extrapolates {
            warnings.push(format!(
                "{} {}: driftlab evaluates this curve beyond {} .. {} degC, the firmware holds \
                 it at the ends",
                sensor.name(),
                ["X", "Y", "Z"][k],
                p.t_min,
                p.t_max
            ));
        }
        polys[k] = Some(p.scaled(sensor.to_si()));
    }
    let missing: Vec<&str> = (0..3)
        .filter(|&k| polys[k].is_none())
        .map(|k| ["X", "Y", "Z"][k])
        .collect();
    // A single axis its name places (one axis of a unit written alone) is said too: the file
    // corrects that axis only. A single axis written as X has said so above.
    let placed_by_name = fits.len() == 1 && axis_index(fits[0].axis).is_some();
    if !missing.is_empty() && (fits.len() > 1 || placed_by_name) {
        notes.push(format!(
            "no {} model for axis {}: its coefficients are written as zero",
            sensor.name(),
            missing.join(", ")
        ));
    }
    let given = polys.iter().flatten();
    let t_min = given
        .clone()
        .map(|p| p.t_min)
        .fold(f64::NEG_INFINITY, f64::max);
    let t_max = given.clone().map(|p| p.t_max).fold(f64::INFINITY, f64::min);
    // NaN ends count as no range.
    if t_min.partial_cmp(&t_max) != Some(std::cmp::Ordering::Less) {
        return Err(FlightError::Missing(format!(
            "the {} axes share no temperature range (their fits cover {}): the firmware holds \
             one range for all three",
            sensor.name(),
            given
                .map(|p| format!("{} .. {} degC", p.t_min, p.t_max))
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    if polys
        .iter()
        .flatten()
        .any(|p| p.t_min != t_min || p.t_max != t_max)
    {
        notes.push(format!(
            "the {} axes were fitted over different temperatures: the file's range is the one \
             all cover, {t_min} .. {t_max} degC",
            sensor.name()
        ));
    }
    Ok(Some(Axes3 {
        polys,
        t_min,
        t_max,
    }))
}

/// Where a model came from, for the file's comments: its name and source log.
pub(crate) fn provenance(fits: &ImuFits<'_>) -> Vec<String> {
    fits.gyro
        .iter()
        .map(|f| ("gyro", f))
        .chain(fits.accel.iter().map(|f| ("accelerometer", f)))
        .map(|(what, f)| {
            let axis = if f.axis.is_empty() {
                String::new()
            } else {
                format!(" {}", f.axis)
            };
            comment(&format!(
                "{what}{axis}: model {} fitted on {}{}",
                f.model.name(),
                f.model.source().name,
                if f.model.gyro_id().is_empty() {
                    String::new()
                } else {
                    format!(" (gyro {})", f.model.gyro_id())
                }
            ))
        })
        .collect()
}

/// The comment lines of a file's notes and warnings.
pub(crate) fn comments(notes: &[String], warnings: &[String]) -> String {
    let mut text = String::new();
    for w in warnings {
        text.push_str(&format!("# warning: {}\n", comment(w)));
    }
    for n in notes {
        text.push_str(&format!("# note: {}\n", comment(n)));
    }
    text
}

/// `s` as one line of printable ASCII for a `#` comment: the signs driftlab's messages use
/// spelled out (`±` as `+-`, `·` as `*`, `°` as `deg`), others as `?`.
pub(crate) fn comment(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '±' => out.push_str("+-"),
            '·' | '×' => out.push('*'),
            '°' => out.push_str("deg"),
            '−' | '–' | '—' => out.push('-'),
            c if c.is_ascii_graphic() || c == ' ' => out.push(c),
            c if c.is_whitespace() => out.push(' '),
            _ => out.push('?'),
        }
    }
    out
}

/// A finite number, or an error naming it.
pub(crate) fn finite(v: f64, what: &str) -> Result<f64, FlightError> {
    if v.is_finite() && v.abs() < f64::from(f32::MAX) {
        Ok(v)
    } else {
        Err(FlightError::Number(format!(
            "{what} is {v}: not a number a float32 parameter holds"
        )))
    }
}
