//! The version-1 file: one model's body, tagged with the model, for the unit of one unnamed
//! axis (a single-axis calibration), written byte for byte as driftlab has always written it.
//!
//! ```json
//! { "format": "driftlab-calibration", "version": 1, "model": "vakhrameev",
//!   "calibration": { "gyro_id": ..., "source": {...}, "recipe": {...}, "k0": {...}, ... } }
//! { "format": "driftlab-calibration", "version": 1, "model": "regression",
//!   "calibration": { "gyro_id": ..., "source": {...}, "model": { "spec": {...},
//!                    "coefficients": [...], "ranges": {...}, ... } } }
//! ```

use super::{FORMAT, Header, VERSION_SINGLE_AXIS, check_windows, model_tag, windows};
use crate::error::{Error, Result};
use crate::models::fitted::DriftModel;
use crate::models::regression::RegressionCalibration;
use crate::models::vakhrameev::Calibration;
use serde::{Deserialize, Serialize};
use std::path::Path;

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

/// `model` as the text of a version-1 file.
pub(super) fn to_json(model: &DriftModel) -> String {
    // Serialising plain data with string keys cannot fail.
    let text = match model {
        DriftModel::Vakhrameev(c) => serde_json::to_string_pretty(&CalFile {
            format: FORMAT.into(),
            version: VERSION_SINGLE_AXIS,
            model: "vakhrameev".into(),
            calibration: (**c).clone(),
        }),
        DriftModel::Regression(r) => serde_json::to_string_pretty(&RegressionFile {
            format: FORMAT.into(),
            version: VERSION_SINGLE_AXIS,
            model: "regression".into(),
            calibration: (**r).clone(),
        }),
    };
    text.unwrap_or_default() + "\n"
}

/// Reads the body of a version-1 file (its format and version already checked) and checks
/// the model; `path` names the file in messages.
pub(super) fn from_json(path: &Path, text: &str) -> Result<DriftModel> {
    let err = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let header: Header =
        serde_json::from_str(text).map_err(|e| err(format!("not a calibration file: {e}")))?;
    // Checked before the body, whose reader would name a hand-edited record by line and
    // column only.
    if let Ok(v) = serde_json::from_str::<serde_json::Value>(text)
        && let Some(instance) = v.pointer("/calibration/source/instance")
    {
        crate::log::DroneGyro::from_value(instance).map_err(|e| err(e.to_string()))?;
    }
    let model = if model_tag(header.model.as_deref()).map_err(err)? == "regression" {
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
