//! The calibration file: versioned JSON that names its format, its version, its units and the
//! log it came from, so that a calibration found on a test-stand PC years later can still be
//! read and checked against its source.
//!
//! One writer and one loader, over a unit ([`save_unit`], [`load_unit`]): which version a
//! unit is written as is a choice of serialization made here. A unit of one unnamed axis (a
//! single-axis calibration) is a version-1 file (`version1`: one model's body, tagged with
//! the model), byte for byte as driftlab has always written it; a unit of named axes (an IMU)
//! is a version-2 file (`version2`: every axis's body under `axes`, with what the axes share
//! written once). The single-model calls ([`save_model`], [`load_model`], [`save`], [`load`])
//! are that one path for a unit of one.
//!
//! `model` tags each body: a reader that does not know a model says so by name instead of
//! misreading it.
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
use crate::models::unit::UnitCalibration;
use crate::models::vakhrameev::Calibration;
use serde::Deserialize;
use sha2::{Digest, Sha256};
use std::io::Read;
use std::path::Path;

/// The format name written into every calibration file.
pub const FORMAT: &str = "driftlab-calibration";
/// The newest format version this build writes and reads: a unit of several axes.
pub const VERSION: u32 = 2;
/// The version of a single-axis calibration, which driftlab writes as it always has.
pub const VERSION_SINGLE_AXIS: u32 = 1;

mod twice;
mod version1;
mod version2;

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
    version1::to_json(&DriftModel::Vakhrameev(Box::new(cal.clone())))
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

/// Reads any model from JSON text (a version-1 file: a unit of one unnamed axis); `path`
/// names the file in messages.
pub fn model_from_json(path: &Path, text: &str) -> Result<DriftModel> {
    if version(path, text)? != VERSION_SINGLE_AXIS {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: version2::not_single(path, text),
        });
    }
    version1::from_json(path, text)
}

/// The unit as the JSON text of its calibration file: version 2 for a unit of named axes,
/// the version-1 file of its one model otherwise.
///
/// # Errors
/// [`Error::Invalid`] when the axes disagree on what the file holds once (gyro, source log,
/// T settings).
pub fn unit_to_json(unit: &UnitCalibration) -> Result<String> {
    if unit.is_unit() {
        version2::to_json(unit)
    } else {
        Ok(version1::to_json(unit.first()?))
    }
}

/// Reads a calibration file of either version as a unit (a version-1 file is a unit of its one
/// unnamed axis); `path` names the file in messages.
///
/// # Errors
/// As [`model_from_json`], each axis's message naming it (`axes[gy].calibration...`).
pub fn unit_from_json(path: &Path, text: &str) -> Result<UnitCalibration> {
    if version(path, text)? == VERSION_SINGLE_AXIS {
        version1::from_json(path, text).map(UnitCalibration::single)
    } else {
        version2::from_json(path, text)
    }
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

/// The checks loading runs on what a file holds: each model (and, for a unit of named axes,
/// the unit as a whole, each axis named) and the history its corrector would hold.
fn check(unit: &UnitCalibration) -> std::result::Result<(), String> {
    if !unit.is_unit() {
        let model = unit.first().map_err(|e| e.to_string())?;
        model.validate().map_err(|e| e.to_string())?;
        return check_windows(windows(model));
    }
    unit.validate().map_err(|e| e.to_string())?;
    for a in &unit.axes {
        check_windows(windows(&a.model)).map_err(|m| format!("axes[{}].{m}", a.name))?;
    }
    Ok(())
}

/// The text of `unit`'s file, if this build would read it back: the checks loading runs, on
/// the unit and then on the text itself (a number that is not finite is written by JSON as
/// `null`, which no reader takes). The error says why nothing was written.
pub(crate) fn checked_text(path: &Path, unit: &UnitCalibration) -> Result<String> {
    let not_written = |message: String| Error::File {
        path: path.to_path_buf(),
        message: format!("not written: {message}"),
    };
    check(unit).map_err(not_written)?;
    let text = unit_to_json(unit).map_err(|e| not_written(e.to_string()))?;
    unit_from_json(path, &text).map_err(|e| match e {
        Error::File { message, .. } => not_written(message),
        other => not_written(other.to_string()),
    })?;
    Ok(text)
}

/// Writes a calibration file atomically, after the checks loading would run (the text is
/// read back first: a file driftlab writes is a file driftlab reads): version 1 for a unit of
/// one unnamed axis, version 2 for a unit of named axes.
///
/// # Errors
/// A unit that would not read back (nothing is written then), or the write's error.
pub fn save_unit(path: &Path, unit: &UnitCalibration) -> Result<()> {
    let text = checked_text(path, unit)?;
    crate::files::atomic::write_bytes(path, text.as_bytes()).map_err(|e| Error::io(path, e))
}

/// Stages `unit`'s calibration file in `batch`, after the checks [`save_unit`] runs: it is
/// put in place with the batch's other files, or not at all.
///
/// # Errors
/// As [`save_unit`]; nothing is in place yet either way.
pub fn stage_unit(
    batch: &mut crate::files::atomic::Batch,
    path: &Path,
    unit: &UnitCalibration,
) -> Result<()> {
    let text = checked_text(path, unit)?;
    batch.stage_bytes(path, text.as_bytes())
}

/// Reads a calibration file of either version as a unit.
///
/// # Errors
/// As [`unit_from_json`], and an unreadable file.
pub fn load_unit(path: &Path) -> Result<UnitCalibration> {
    unit_from_json(path, &read_text(path)?)
}

/// Any model as the JSON text of a calibration file (version 1).
pub fn model_to_json(model: &DriftModel) -> String {
    version1::to_json(model)
}

/// Writes any model's calibration file ([`save_unit`] for a unit of one unnamed axis).
///
/// # Errors
/// A model that would not read back (nothing is written then), or the write's error.
pub fn save_model(path: &Path, model: &DriftModel) -> Result<()> {
    save_unit(path, &UnitCalibration::single(model.clone()))
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

/// The largest calibration or recipe file read, bytes. A unit of
/// [`MAX_UNIT_AXES`](crate::models::unit::MAX_UNIT_AXES) axes with 64-knot curves takes well
/// under a megabyte; a larger file is another kind of file, or made to exhaust memory.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

fn read_text(path: &Path) -> Result<String> {
    read_json_text(
        path,
        MAX_FILE_BYTES,
        "which no calibration or recipe is: is it a log?",
    )
}

/// A small JSON file's text, read through at most `max_bytes` (a pipe or a device states no
/// length and is cut there, whatever it would go on giving): UTF-8, a byte-order mark left out,
/// no key twice in one object. `too_large` ends the message of a larger file.
///
/// # Errors
/// The read's, a file over `max_bytes`, text that is not UTF-8, a key given twice.
pub(crate) fn read_json_text(path: &Path, max_bytes: u64, too_large: &str) -> Result<String> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut bytes = Vec::new();
    file.take(max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > max_bytes {
        let size = if max_bytes >= 1 << 20 {
            format!("{} MiB", max_bytes >> 20)
        } else {
            format!("{max_bytes} bytes")
        };
        return Err(Error::File {
            path: path.to_path_buf(),
            message: format!("larger than {size}, {too_large}"),
        });
    }
    let mut text = String::from_utf8(bytes).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: format!("not UTF-8 text: {e}"),
    })?;
    // Some Windows editors save UTF-8 with a byte-order mark, which JSON does not allow (RFC
    // 8259 §8.1) but which says nothing but "UTF-8": read the text after it (line and column
    // in messages are then those an editor shows, which hides the mark).
    if text.starts_with(BOM) {
        text.drain(..BOM.len_utf8());
    }
    twice::no_key_twice(&text).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(text)
}

/// What a JSON value is, in words, for a message.
pub(crate) fn json_kind(value: &serde_json::Value) -> &'static str {
    match value {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "true or false",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::String(_) => "a string",
        serde_json::Value::Array(_) => "an array",
        serde_json::Value::Object(_) => "an object",
    }
}

/// The byte-order mark a text file may start with.
const BOM: char = '\u{feff}';

/// Reads a recipe file, or the recipe inside a Vakhrameev calibration file: a single-axis
/// one, or a unit's of one axis (one axis is a unit of one, so the file `calibrate --axes gy`
/// writes gives its recipe back as the file of an unnamed axis does). The two are told apart
/// by the file's `format` field (a recipe has none), not by searching its text.
///
/// # Errors
/// An unreadable file, malformed JSON (with line and column), a calibration without a recipe
/// (a regression model's), or a unit of several axes (which holds one recipe per axis:
/// [`read_axis_recipe`] takes one of them).
pub fn read_recipe(path: &Path) -> Result<Recipe> {
    let text = read_text(path)?;
    let err = |e: serde_json::Error| Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let value: serde_json::Value = serde_json::from_str(&text).map_err(err)?;
    // serde reads a struct from an array field by field, in order: `[]` would be the
    // defaults, `[600]` a filter, and no key named anywhere.
    if !value.is_object() {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: format!(
                "a recipe is a JSON object of choices ({{\"filter_s\": 600, …}}), not {}",
                json_kind(&value)
            ),
        });
    }
    if value.get("format").is_none() {
        return serde_json::from_str(&text).map_err(err);
    }
    if version(path, &text)? == VERSION_SINGLE_AXIS {
        return from_json(path, &text).map(|c| c.recipe);
    }
    let unit = version2::from_json(path, &text)?;
    match unit.axes.as_slice() {
        [one] => axis_recipe(path, &unit, &one.name),
        _ => Err(Error::File {
            path: path.to_path_buf(),
            message: version2::not_single(path, &text),
        }),
    }
}

/// The recipe of axis `axis` for a calibration of a unit: the recipe of that axis when `path`
/// is the version-2 file of a unit (its knots placed and set by hand among its choices, so that
/// the workbench's unit file reproduces each axis), else [`read_recipe`] of the file.
///
/// # Errors
/// As [`read_recipe`]; a unit file without that axis, or whose axis is no Vakhrameev
/// calibration, names the axes it holds.
pub fn read_axis_recipe(path: &Path, axis: &str) -> Result<Recipe> {
    let text = read_text(path)?;
    let is_unit = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .and_then(|v| v.get("version")?.as_u64())
        .is_some_and(|v| v != VERSION_SINGLE_AXIS as u64);
    if !is_unit {
        return read_recipe(path);
    }
    let unit = unit_from_json(path, &text)?;
    axis_recipe(path, &unit, axis)
}

/// The recipe of the axis `axis` of `unit`, read from the file at `path`.
///
/// # Errors
/// A unit without that axis, or whose axis is no Vakhrameev calibration, naming the axes it
/// holds.
fn axis_recipe(path: &Path, unit: &UnitCalibration, axis: &str) -> Result<Recipe> {
    match unit.axes.iter().find(|a| a.name == axis).map(|a| &a.model) {
        Some(DriftModel::Vakhrameev(c)) => Ok(c.recipe.clone()),
        found => Err(Error::File {
            path: path.to_path_buf(),
            message: format!(
                "{} (the file holds axes {})",
                if found.is_some() {
                    format!("axis {axis} is not a Vakhrameev calibration, which has no recipe")
                } else {
                    format!("holds no axis {axis}")
                },
                unit.axis_names().join(", ")
            ),
        }),
    }
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
