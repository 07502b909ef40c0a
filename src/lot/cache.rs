//! A unit not calibrated again: when its runs' bytes, the recipe it is calibrated with and the
//! spec are those of the outcome recorded beside its calibration, and the calibration file is
//! the one that was written, that outcome is the unit's.
//!
//! The record is `OUT/<unit>/unit.json`: the key (each run's name and SHA-256, the SHA-256 of
//! the recipe and of the spec as used, the SHA-256 of the calibration file written, and the
//! driftlab version that made them) and the outcome. A day's lot run again after one unit's
//! log was replaced calibrates that unit alone; a lot of ten thousand units stopped half way
//! resumes where it stopped. Only units that were calibrated are recorded: an error is tried
//! again (what made it, a disk full, may be gone).

use super::{Spec, UnitOutcome};
use crate::files::calibration::sha256_file;
use crate::models::Recipe;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The record's file name in the unit's folder.
pub const RECORD: &str = "unit.json";

/// The calibration's file name in the unit's folder.
pub const CALIBRATION: &str = "calibration.json";

/// The largest record read: a unit's outcome is a few kilobytes.
const MAX_RECORD_BYTES: u64 = 4 << 20;

/// One run of a unit as the key holds it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunKey {
    /// The run's file, as found.
    pub file: String,
    /// SHA-256 of its bytes.
    pub sha256: String,
}

/// What a unit's outcome depends on.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitKey {
    /// The driftlab that calibrated it.
    pub driftlab: String,
    /// Its runs.
    pub runs: Vec<RunKey>,
    /// SHA-256 of the recipe it was calibrated with, as JSON.
    pub recipe_sha256: String,
    /// SHA-256 of the spec it was judged by, as JSON.
    pub spec_sha256: String,
    /// Whether its report was written.
    #[serde(default)]
    pub report: bool,
}

/// A unit's recorded outcome and the calibration file it wrote.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Record {
    key: UnitKey,
    calibration_sha256: String,
    outcome: UnitOutcome,
}

/// The key of a unit of `runs`, calibrated with `recipe` and judged by `spec`, with its report
/// or without.
///
/// # Errors
/// A run whose bytes cannot be read, with its message.
pub fn key(
    runs: &[PathBuf],
    recipe: &Recipe,
    spec: &Spec,
    report: bool,
) -> Result<UnitKey, String> {
    let mut keys = Vec::with_capacity(runs.len());
    for path in runs {
        keys.push(RunKey {
            file: path.display().to_string(),
            sha256: sha256_file(path).map_err(|e| e.to_string())?,
        });
    }
    Ok(UnitKey {
        driftlab: env!("CARGO_PKG_VERSION").to_string(),
        runs: keys,
        recipe_sha256: sha256_of_json(recipe),
        spec_sha256: sha256_of_json(spec),
        report,
    })
}

/// The SHA-256 of a recipe as a unit's key holds it: what tells two lots' shared recipes
/// apart.
pub fn recipe_sha256(recipe: &crate::models::Recipe) -> String {
    sha256_of_json(recipe)
}

fn sha256_of_json<T: Serialize>(value: &T) -> String {
    // Serializing plain data to memory cannot fail; an empty text would only miss the cache.
    let text = serde_json::to_string(value).unwrap_or_default();
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The outcome recorded in `folder` (the unit's, in `OUT`) under `key`, when its calibration
/// file is still the one written; `None` otherwise (no record, another key, a record that does
/// not read, a calibration changed or gone).
pub fn recorded(folder: &Path, key: &UnitKey) -> Option<UnitOutcome> {
    let path = folder.join(RECORD);
    if std::fs::metadata(&path).ok()?.len() > MAX_RECORD_BYTES {
        return None;
    }
    let record: Record = serde_json::from_str(&std::fs::read_to_string(&path).ok()?).ok()?;
    if record.key != *key {
        return None;
    }
    let written = sha256_file(&folder.join(CALIBRATION)).ok()?;
    (written == record.calibration_sha256).then_some(UnitOutcome {
        cached: true,
        ..record.outcome
    })
}

/// The runs of the unit recorded in `folder`, as given and as absolute paths, whatever its
/// key: what a face showing `lot.csv` (which does not list them) opens the unit from.
pub fn recorded_runs(folder: &Path) -> Option<(Vec<String>, Vec<String>)> {
    let path = folder.join(RECORD);
    if std::fs::metadata(&path).ok()?.len() > MAX_RECORD_BYTES {
        return None;
    }
    let record: Record = serde_json::from_str(&std::fs::read_to_string(&path).ok()?).ok()?;
    Some((record.outcome.runs, record.outcome.runs_at))
}

/// Records `outcome` under `key` in `folder`, beside the calibration it wrote.
///
/// # Errors
/// The calibration cannot be hashed, or the record written.
pub fn record(folder: &Path, key: &UnitKey, outcome: &UnitOutcome) -> crate::Result<()> {
    let record = Record {
        key: key.clone(),
        calibration_sha256: sha256_file(&folder.join(CALIBRATION))?,
        outcome: UnitOutcome {
            cached: false,
            ..outcome.clone()
        },
    };
    let path = folder.join(RECORD);
    let text = serde_json::to_string_pretty(&record)
        .map_err(|e| crate::Error::io(&path, std::io::Error::other(e)))?
        + "\n";
    crate::files::atomic::write_bytes(&path, text.as_bytes())
        .map_err(|e| crate::Error::io(&path, e))
}

/// Removes what a unit's folder holds from an earlier lot (its calibration, record and
/// report), when the unit is now an error: a station flashing `OUT/<unit>/calibration.json`
/// must not find one its lot no longer stands behind. A report folder is removed only when
/// its marker says a report wrote it. Returns what could not be removed, said.
pub fn forget(folder: &Path) -> Vec<String> {
    let report = folder.join("report");
    let report = report
        .join(crate::export::report::MARKER)
        .is_file()
        .then_some(report);
    [CALIBRATION, RECORD]
        .iter()
        .map(|name| folder.join(name))
        .filter(|path| path.exists())
        .map(|path| (std::fs::remove_file(&path), path))
        .chain(report.map(|r| (std::fs::remove_dir_all(&r), r)))
        .filter_map(|(removed, path)| {
            removed.err().map(|e| {
                format!(
                    "{}: an earlier lot's file, which this one does not stand behind, could not \
                     be removed: {e}",
                    path.display()
                )
            })
        })
        .collect()
}
