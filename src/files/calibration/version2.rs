//! The version-2 file: a unit of named gyro axes.
//!
//! ```json
//! { "format": "driftlab-calibration", "version": 2,
//!   "gyro_id": "IMU-7", "source": { "name": "imu.csv", ... }, "created": "...",
//!   "temperature": { "temp_smoothing_s": 60.0, "step_h_s": 30.0, "plateaus": {...} },
//!   "axes": [
//!     { "name": "gx", "rate_column": "gx_dps", "model": "vakhrameev",
//!       "calibration": { "recipe": {...}, "resolved": {...}, "k0": {...}, ... } },
//!     { "name": "gy", ... } ] }
//! ```
//!
//! An accelerometer axis says so, `"kind": "accelerometer"`, with the mean its correction
//! keeps, `"kept_mean_m_s2"` ([`crate::models::accel`]); a gyro axis writes neither, so a file
//! of gyro axes is what it always was.
//!
//! Each axis's `calibration` is the body of a version-1 file of its model, less what the axes
//! share, which the file holds once: the gyro, the source log and the date at the top, and
//! under `temperature` the T settings of the Vakhrameev axes (they were made from one T, so
//! they are processed alike). Loading puts the shared fields back into each body, reads it as
//! a version-1 body is read (unknown fields refused), and checks the unit as a whole
//! ([`UnitCalibration::validate`]) and every axis as a version-1 file is checked.

use super::{FORMAT, VERSION, check_windows, model_tag, windows};
use crate::error::{Error, Result};
use crate::log::AxisKind;
use crate::models::fitted::DriftModel;
use crate::models::unit::{AxisModel, UnitCalibration};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::path::Path;

/// The fields every axis's body has and the file holds once, at the top.
const SHARED: [&str; 3] = ["gyro_id", "source", "created"];
/// The recipe's T settings, held once under `temperature`.
const TEMPERATURE: [&str; 3] = ["temp_smoothing_s", "step_h_s", "plateaus"];

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct UnitFile {
    format: String,
    version: u32,
    gyro_id: String,
    source: Value,
    created: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    temperature: Option<Map<String, Value>>,
    axes: Vec<AxisEntry>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisEntry {
    name: String,
    #[serde(default)]
    rate_column: String,
    /// What the axis measures; written only for an accelerometer.
    #[serde(default, skip_serializing_if = "is_gyro")]
    kind: AxisKind,
    /// The mean an accelerometer axis keeps, m/s².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    kept_mean_m_s2: Option<f64>,
    model: String,
    /// The sketch of this axis's samples (`source.samples_sketch` of its version-1 body):
    /// the axes share the source log, but each has its own rate, so its own sketch.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    samples_sketch: String,
    /// The runs of a campaign as this axis records them (`source.runs` of its version-1 body):
    /// the axes share the runs, but each has its own bias on their plateaus and its own
    /// turn-on offsets.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    runs: Option<Value>,
    calibration: Map<String, Value>,
}

fn is_gyro(kind: &AxisKind) -> bool {
    *kind == AxisKind::Gyro
}

/// The key of an axis's own sketch in its body's `source`.
const SKETCH: &str = "samples_sketch";
/// The key of an axis's own record of a campaign's runs in its body's `source`.
const RUNS: &str = "runs";

/// The message for a version-2 file given where a single-axis calibration is wanted.
/// A broken one is named as a unit file with what is wrong with it.
pub(super) fn not_single(path: &Path, text: &str) -> String {
    match from_json(path, text) {
        Ok(u) => format!(
            "holds a unit of axes {} (version 2); this takes a single-axis calibration",
            u.axis_names().join(", ")
        ),
        Err(Error::File { message, .. }) => {
            format!("version 2, the file of a unit of several axes: {message}")
        }
        Err(e) => format!("version 2, the file of a unit of several axes: {e}"),
    }
}

/// A unit of named axes as the text of a version-2 file.
///
/// # Errors
/// [`Error::Invalid`] when the axes disagree on what the file holds once (gyro, source log,
/// T settings).
pub(super) fn to_json(unit: &UnitCalibration) -> Result<String> {
    let mut shared: Option<Map<String, Value>> = None;
    let mut temperature: Option<Map<String, Value>> = None;
    let mut axes = Vec::with_capacity(unit.axes.len());
    for a in &unit.axes {
        let invalid = |field: &str, reason: &str| {
            Error::Invalid(crate::error::Invalid::new(
                format!("axes[{}].{field}", a.name),
                reason,
            ))
        };
        let mut body = match serde_json::to_value(body_of(&a.model)) {
            Ok(Value::Object(m)) => m,
            _ => return Err(Error::Internal("a calibration body is not a JSON object")),
        };
        let mut mine: Map<String, Value> = SHARED
            .iter()
            .filter_map(|k| body.remove(*k).map(|v| (k.to_string(), v)))
            .collect();
        let (samples_sketch, runs) = match mine.get_mut("source") {
            Some(Value::Object(source)) => (
                match source.remove(SKETCH) {
                    Some(Value::String(s)) => s,
                    _ => String::new(),
                },
                source.remove(RUNS),
            ),
            _ => (String::new(), None),
        };
        match &shared {
            None => shared = Some(mine),
            Some(s) => {
                for k in ["gyro_id", "source"] {
                    if s.get(k) != mine.get(k) {
                        return Err(invalid(
                            k,
                            "differs from the first axis's: a unit is one gyro, calibrated on \
                             one log",
                        ));
                    }
                }
            }
        }
        if let DriftModel::Vakhrameev(_) = a.model
            && let Some(Value::Object(recipe)) = body.get_mut("recipe")
        {
            recipe.remove("gyro_id");
            let mine: Map<String, Value> = TEMPERATURE
                .iter()
                .filter_map(|k| recipe.remove(*k).map(|v| (k.to_string(), v)))
                .collect();
            match &temperature {
                None => temperature = Some(mine),
                Some(t) if *t != mine => {
                    return Err(invalid(
                        "recipe",
                        "its T settings differ from the first axis's: the axes of a unit \
                         share T, and so how it is processed",
                    ));
                }
                Some(_) => {}
            }
        }
        axes.push(AxisEntry {
            name: a.name.clone(),
            rate_column: a.rate_column.clone(),
            kind: a.kind,
            kept_mean_m_s2: a.kept_mean,
            model: a.model.tag().to_string(),
            samples_sketch,
            runs,
            calibration: body,
        });
    }
    let mut shared = shared.unwrap_or_default();
    let mut take_str = |k: &str| match shared.remove(k) {
        Some(Value::String(s)) => s,
        _ => String::new(),
    };
    let file = UnitFile {
        format: FORMAT.into(),
        version: VERSION,
        gyro_id: take_str("gyro_id"),
        created: take_str("created"),
        source: shared.remove("source").unwrap_or(Value::Null),
        temperature,
        axes,
    };
    serde_json::to_string_pretty(&file)
        .map(|t| t + "\n")
        .map_err(|_| Error::Internal("a unit calibration did not serialise"))
}

/// A model's file body as serde sees it.
fn body_of(model: &DriftModel) -> Body<'_> {
    match model {
        DriftModel::Vakhrameev(c) => Body::Vakhrameev(c),
        DriftModel::Regression(r) => Body::Regression(r),
    }
}

#[derive(Serialize)]
#[serde(untagged)]
enum Body<'a> {
    Vakhrameev(&'a crate::models::vakhrameev::Calibration),
    Regression(&'a crate::models::regression::RegressionCalibration),
}

/// Reads a version-2 file (its format and version already checked); `path` names the file in
/// messages.
///
/// # Errors
/// As a version-1 body is refused, each axis's message naming it
/// (`axes[gy].calibration...`); a file of one unnamed axis (a version-1 file's content).
pub(super) fn from_json(path: &Path, text: &str) -> Result<UnitCalibration> {
    let err = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let file: UnitFile = serde_json::from_str(text).map_err(|e| err(e.to_string()))?;
    // Held once at the top, so named there (each axis's body is checked again with them).
    crate::models::fitted::check_identity(&file.gyro_id, &file.created)
        .map_err(|e| err(e.to_string()))?;
    // Checked once, at the top where the file holds it, so that a refusal names its path
    // there rather than the axis body it is copied into.
    if let Some(instance) = file.source.get("instance") {
        crate::log::DroneGyro::from_value(instance).map_err(|e| err(e.to_string()))?;
    }
    let mut axes = Vec::with_capacity(file.axes.len());
    for entry in file.axes {
        let at = |field: &str| format!("axes[{}].{field}", entry.name);
        let tag =
            model_tag(Some(&entry.model)).map_err(|m| err(format!("{}: {m}", at("model"))))?;
        let mut body = entry.calibration;
        for k in SHARED {
            if body.contains_key(k) {
                return Err(err(format!(
                    "{}: the unit gives it once, at the top, not per axis",
                    at(&format!("calibration.{k}"))
                )));
            }
        }
        body.insert("gyro_id".into(), Value::String(file.gyro_id.clone()));
        let mut source = file.source.clone();
        if let Value::Object(s) = &mut source {
            if s.contains_key(SKETCH) {
                return Err(err(format!(
                    "source.{SKETCH}: each axis has its own, beside its name, not at the top"
                )));
            }
            if !entry.samples_sketch.is_empty() {
                s.insert(SKETCH.into(), Value::String(entry.samples_sketch.clone()));
            }
            if s.contains_key(RUNS) {
                return Err(err(format!(
                    "source.{RUNS}: each axis has its own, beside its name, not at the top"
                )));
            }
            if let Some(runs) = &entry.runs {
                s.insert(RUNS.into(), runs.clone());
            }
        }
        body.insert("source".into(), source);
        body.insert("created".into(), Value::String(file.created.clone()));
        let model = if tag == "vakhrameev" {
            let Some(Value::Object(recipe)) = body.get_mut("recipe") else {
                return Err(err(format!("{}: missing", at("calibration.recipe"))));
            };
            let Some(temperature) = &file.temperature else {
                return Err(err(format!(
                    "no \"temperature\" field: axis {} is a vakhrameev calibration, whose T \
                     settings the unit holds there",
                    entry.name
                )));
            };
            for k in TEMPERATURE.iter().chain(&["gyro_id"]) {
                if recipe.contains_key(*k) {
                    return Err(err(format!(
                        "{}: the unit gives it once, not per axis",
                        at(&format!("calibration.recipe.{k}"))
                    )));
                }
            }
            recipe.insert("gyro_id".into(), Value::String(file.gyro_id.clone()));
            for (k, v) in temperature {
                recipe.insert(k.clone(), v.clone());
            }
            let c = serde_json::from_value(Value::Object(body))
                .map_err(|e| err(format!("{}: {e}", at("calibration"))))?;
            DriftModel::Vakhrameev(Box::new(c))
        } else {
            let r = serde_json::from_value(Value::Object(body))
                .map_err(|e| err(format!("{}: {e}", at("calibration"))))?;
            DriftModel::Regression(Box::new(r))
        };
        check_windows(windows(&model)).map_err(|m| err(format!("axes[{}].{m}", entry.name)))?;
        axes.push(AxisModel {
            name: entry.name,
            rate_column: entry.rate_column,
            model,
            kind: entry.kind,
            kept_mean: entry.kept_mean_m_s2,
        });
    }
    let unit = UnitCalibration { axes };
    unit.validate().map_err(|e| err(e.to_string()))?;
    unit.check_rate_columns().map_err(|e| err(e.to_string()))?;
    if !unit.is_unit() {
        return Err(err(
            "a version-2 file holds named axes; a calibration of one unnamed axis is a \
             version-1 file"
                .into(),
        ));
    }
    Ok(unit)
}
