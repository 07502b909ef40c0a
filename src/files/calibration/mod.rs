//! The calibration file: versioned JSON that names its format, its version, its units and the
//! log it came from, so that a calibration found on a test-stand PC years later can still be
//! read and checked against its source.
//!
//! ```json
//! { "format": "driftlab-calibration", "version": 1, "model": "vakhrameev",
//!   "calibration": { "gyro_id": ..., "source": {...}, "recipe": {...}, "k0": {...}, ... } }
//! { "format": "driftlab-calibration", "version": 1, "model": "regression",
//!   "calibration": { "gyro_id": ..., "source": {...}, "model": { "spec": {...},
//!                    "coefficients": [...], "ranges": {...}, ... } } }
//! ```
//!
//! `model` tags the body: a reader that does not know a model says so by name instead of
//! misreading it.
//!
//! A unit of several gyro axes (an IMU) is a version-2 file (`unit`): every axis's body as
//! above under `axes`, with what the axes share (gyro, source log, date, T settings) once. A
//! single-axis calibration is written as version 1, as it always was.
//!
//! Loading checks the format name and version before anything else, then reads the body with
//! every unknown field rejected and every approximation validated (finite numbers, ordered
//! knots), then the model as a whole ([`DriftModel::validate`]: names that match the terms,
//! sane sizes and spacings, delays and lags that fit the log, coefficients that predict a
//! drift a gyro could have over their ranges), so a hand-edited file fails with a message
//! that names the field and says why. Saving runs the same checks and reads the text back
//! before it writes: a file driftlab writes is a file driftlab reads.

use crate::error::{Error, Result};
use crate::models::fitted::DriftModel;
use crate::models::recipe::Recipe;
use crate::models::regression::RegressionCalibration;
use crate::models::vakhrameev::Calibration;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::io::Read;
use std::path::Path;

/// The format name written into every calibration file.
pub const FORMAT: &str = "driftlab-calibration";
/// The newest format version this build writes and reads: a unit of several axes.
pub const VERSION: u32 = 2;
/// The version of a single-axis calibration, which driftlab writes as it always has.
pub const VERSION_SINGLE_AXIS: u32 = 1;

mod unit;
pub use unit::{load_unit, save_unit, unit_from_json, unit_to_json};

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CalFile {
    format: String,
    version: u32,
    model: String,
    calibration: Calibration,
}

/// A file whose body is a regression model.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RegressionFile {
    format: String,
    version: u32,
    model: String,
    calibration: RegressionCalibration,
}

/// Only the header, read first so that a file of another kind or version is named as such
/// instead of failing on its first unexpected field.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u64>,
    model: Option<String>,
}

/// The calibration as the JSON text of a calibration file.
pub fn to_json(cal: &Calibration) -> String {
    let file = CalFile {
        format: FORMAT.into(),
        version: VERSION_SINGLE_AXIS,
        model: "vakhrameev".into(),
        calibration: cal.clone(),
    };
    // Serialising plain data with string keys cannot fail.
    serde_json::to_string_pretty(&file).unwrap_or_default() + "\n"
}

/// Checks the format name and returns the version (1 or 2).
fn version(path: &Path, text: &str) -> Result<u32> {
    let err = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let header: Header =
        serde_json::from_str(text).map_err(|e| err(format!("not a calibration file: {e}")))?;
    match header.format.as_deref() {
        Some(FORMAT) => {}
        Some(other) => {
            return Err(err(format!("format is \"{other}\", expected \"{FORMAT}\"")));
        }
        None => return Err(err(format!("no \"format\" field: not a {FORMAT} file"))),
    }
    match header.version {
        Some(v) if (1..=VERSION as u64).contains(&v) => Ok(v as u32),
        Some(v) if v > VERSION as u64 => Err(err(format!(
            "version {v} is newer than this driftlab reads (versions 1 to {VERSION}); use a \
             newer driftlab"
        ))),
        Some(v) => Err(err(format!(
            "version {v} was never written by driftlab (versions start at 1)"
        ))),
        None => Err(err("no \"version\" field".into())),
    }
}

/// Checks the header of a single-axis (version 1) file and returns the model tag.
fn header(path: &Path, text: &str) -> Result<String> {
    let err = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    if version(path, text)? != VERSION_SINGLE_AXIS {
        return Err(err(unit::not_single(path, text)));
    }
    let header: Header =
        serde_json::from_str(text).map_err(|e| err(format!("not a calibration file: {e}")))?;
    model_tag(header.model.as_deref()).map_err(err)
}

/// The model tag of a body, checked against the models this build knows.
fn model_tag(model: Option<&str>) -> std::result::Result<String, String> {
    match model {
        Some(m @ ("vakhrameev" | "regression")) => Ok(m.to_string()),
        Some(other) => Err(format!(
            "model \"{other}\" is not known to this driftlab (it knows vakhrameev and \
             regression)"
        )),
        None => Err("no \"model\" field".into()),
    }
}

/// Reads a Vakhrameev calibration from JSON text; `path` names the file in messages.
pub fn from_json(path: &Path, text: &str) -> Result<Calibration> {
    match model_from_json(path, text)? {
        DriftModel::Vakhrameev(c) => Ok(*c),
        DriftModel::Regression(r) => Err(Error::File {
            path: path.to_path_buf(),
            message: format!(
                "holds the regression model \"{}\", and this needs a Vakhrameev calibration",
                r.model.spec.name
            ),
        }),
    }
}

/// Reads any model from JSON text; `path` names the file in messages.
pub fn model_from_json(path: &Path, text: &str) -> Result<DriftModel> {
    let err = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let model = if header(path, text)? == "regression" {
        let file: RegressionFile = serde_json::from_str(text).map_err(|e| err(e.to_string()))?;
        DriftModel::Regression(Box::new(file.calibration))
    } else {
        let file: CalFile = serde_json::from_str(text).map_err(|e| err(e.to_string()))?;
        DriftModel::Vakhrameev(Box::new(file.calibration))
    };
    model.validate().map_err(|e| err(e.to_string()))?;
    check_windows(windows(&model)).map_err(err)?;
    Ok(model)
}

/// The longest window (T smoothing, derivative step, delay, lag) a calibration file may ask
/// for, in samples at its own sampling step. A corrector holds that much history, so a file
/// asking for more (a hand-edited `1e28`) would exhaust memory instead of correcting; no
/// chamber run needs it (10 million samples are 30 hours at 93 Hz).
const MAX_WINDOW_SAMPLES: f64 = crate::signal::MAX_HISTORY_SAMPLES as f64;

/// The windows of a model that set how much history its corrector holds, with the sampling
/// step they are counted in.
fn windows(model: &DriftModel) -> (f64, Vec<(&'static str, f64)>) {
    match model {
        DriftModel::Vakhrameev(c) => calibration_windows(c),
        DriftModel::Regression(r) => {
            let m = &r.model;
            (
                m.dt_s,
                vec![
                    ("spec.smoothing_s", m.spec.smoothing_s),
                    ("spec.step_h_s", m.spec.step_h_s),
                    ("delay", m.delay.max_s()),
                    ("lag_s", m.lag_s.unwrap_or(0.0)),
                ],
            )
        }
    }
}

fn calibration_windows(c: &Calibration) -> (f64, Vec<(&'static str, f64)>) {
    let r = &c.resolved;
    (
        r.dt_s,
        vec![
            ("resolved.smooth_samples", r.smooth_samples as f64 * r.dt_s),
            ("resolved.step_samples", r.step_samples as f64 * r.dt_s),
        ],
    )
}

fn check_windows(
    (dt_s, windows): (f64, Vec<(&'static str, f64)>),
) -> std::result::Result<(), String> {
    for (name, seconds) in windows {
        if seconds / dt_s > MAX_WINDOW_SAMPLES {
            return Err(format!(
                "{name} spans {} s, more than {MAX_WINDOW_SAMPLES:e} samples of {} s: no \
                 corrector can hold that much history",
                crate::number::readable(seconds),
                crate::number::readable(dt_s)
            ));
        }
    }
    Ok(())
}

/// The text of `model`'s file, if this build would read it back: the checks loading runs,
/// on the model and then on the text itself (a number that is not finite is written by JSON as
/// `null`, which no reader takes). The error says why nothing was written.
fn checked_text(path: &Path, model: &DriftModel) -> Result<String> {
    let not_written = |message: String| Error::File {
        path: path.to_path_buf(),
        message: format!("not written: {message}"),
    };
    model.validate().map_err(|e| not_written(e.to_string()))?;
    check_windows(windows(model)).map_err(not_written)?;
    let text = model_to_json(model);
    model_from_json(path, &text).map_err(|e| match e {
        Error::File { message, .. } => not_written(message),
        other => not_written(other.to_string()),
    })?;
    Ok(text)
}

/// Any model as the JSON text of a calibration file.
pub fn model_to_json(model: &DriftModel) -> String {
    let text = match model {
        DriftModel::Vakhrameev(c) => return to_json(c),
        DriftModel::Regression(r) => serde_json::to_string_pretty(&RegressionFile {
            format: FORMAT.into(),
            version: VERSION_SINGLE_AXIS,
            model: "regression".into(),
            calibration: (**r).clone(),
        }),
    };
    text.unwrap_or_default() + "\n"
}

/// Writes any model's calibration file atomically, after the checks loading would run.
///
/// # Errors
/// A model that would not read back (nothing is written then), or the write's error.
pub fn save_model(path: &Path, model: &DriftModel) -> Result<()> {
    let text = checked_text(path, model)?;
    crate::files::atomic::write_bytes(path, text.as_bytes()).map_err(|e| Error::io(path, e))
}

/// Reads any model's calibration file.
pub fn load_model(path: &Path) -> Result<DriftModel> {
    model_from_json(path, &read_text(path)?)
}

/// Writes a calibration file atomically, as [`save_model`] does.
///
/// # Errors
/// As [`save_model`].
pub fn save(path: &Path, cal: &Calibration) -> Result<()> {
    save_model(path, &DriftModel::Vakhrameev(Box::new(cal.clone())))
}

/// Reads a calibration file.
pub fn load(path: &Path) -> Result<Calibration> {
    from_json(path, &read_text(path)?)
}

fn read_text(path: &Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: format!("not UTF-8 text: {e}"),
    })
}

/// Reads a recipe file, or the recipe inside a Vakhrameev calibration file. The two are told
/// apart by the file's `format` field (a recipe has none), not by searching its text.
///
/// # Errors
/// An unreadable file, malformed JSON (with line and column), or a calibration without a
/// recipe (a regression model's).
pub fn read_recipe(path: &Path) -> Result<Recipe> {
    let text = read_text(path)?;
    let err = |e: serde_json::Error| Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let value: serde_json::Value = serde_json::from_str(&text).map_err(err)?;
    if value.get("format").is_some() {
        return from_json(path, &text).map(|c| c.recipe);
    }
    serde_json::from_str(&text).map_err(err)
}

/// SHA-256 of a file's bytes as lowercase hex, read in blocks (logs can be gigabytes).
///
/// # Errors
/// An unreadable file, or one that is not a regular file: a FIFO or a device gives its bytes
/// once, to whoever read the log from it, and opening it again would wait for a writer that
/// never comes ([`sha256_input`] hashes the bytes that were read).
pub fn sha256_file(path: &Path) -> Result<String> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => {
            return Err(Error::File {
                path: path.to_path_buf(),
                message: "not a regular file: its bytes can be read only once".into(),
            });
        }
        _ => {}
    }
    let mut f = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = f.read(&mut buf).map_err(|e| Error::io(path, e))?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
    }
    Ok(hex(hasher))
}

/// SHA-256 of the bytes a log was read from: the file's, or the stream's as it was read.
///
/// # Errors
/// As [`sha256_file`].
pub fn sha256_input(input: &crate::log::ingest::Input) -> Result<String> {
    match input {
        crate::log::ingest::Input::Path(p) => sha256_file(p),
        crate::log::ingest::Input::Bytes { bytes, .. } => {
            let mut hasher = Sha256::new();
            hasher.update(bytes);
            Ok(hex(hasher))
        }
    }
}

fn hex(hasher: Sha256) -> String {
    hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}
