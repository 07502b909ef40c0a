//! The corrected CSV of every sample log, under every preset (and the three-axis unit), kept
//! byte-identical through restructuring: `calibrate` then `apply` on the log itself and on its
//! held-out partner, each output's SHA-256 against the one recorded in
//! `tests/cli/output_hashes.txt` before the code was moved.
//!
//! The record was made by this test with `DRIFTLAB_RECORD_HASHES=1` at the commit that added
//! it; an outcome that changes (a new hash, or a model that now fails or now fits) fails here.
//! Re-record only for a change that is meant to alter the numbers, and say so in the commit.

use crate::common::run::driftlab;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The sample logs, each with the held-out log its calibration is also applied to.
const LOGS: [(&str, &str); 10] = [
    ("calibration.csv", "validation.csv"),
    ("validation.csv", "calibration.csv"),
    ("imu3-calibration.csv", "imu3-validation.csv"),
    ("imu3-validation.csv", "imu3-calibration.csv"),
    ("laser-gyro.csv", "laser-gyro-2.csv"),
    ("laser-gyro-2.csv", "laser-gyro.csv"),
    ("yan-full-range.csv", "yan-steps-mid.csv"),
    ("yan-steps-low.csv", "yan-full-range.csv"),
    ("yan-steps-mid.csv", "yan-full-range.csv"),
    ("yan-steps-high.csv", "yan-full-range.csv"),
];

const MODELS: [&str; 8] = [
    "vakhrameev",
    "ieee952",
    "yan-cross",
    "yan-delayed",
    "sukhanov",
    "poly-t",
    "pwl-t",
    "coil-lag",
];

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

fn record_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cli/output_hashes.txt")
}

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// `calibrate LOG --model MODEL`, then `apply` on LOG and on its partner: one line per apply,
/// `LOG MODEL TARGET HASH`, or `LOG MODEL - calibrate-fails` when the model does not fit.
fn outcomes(dir: &Path, log: &str, partner: &str, model: &str) -> Vec<(String, String)> {
    let cal = dir.join(format!("{log}-{model}.json"));
    let key = |target: &str| format!("{log} {model} {target}");
    let out = driftlab(&[
        "calibrate",
        sample(log).to_str().unwrap(),
        "--model",
        model,
        "--out",
        cal.to_str().unwrap(),
    ]);
    if !out.status.success() {
        return vec![(key("-"), "calibrate-fails".to_string())];
    }
    [log, partner]
        .iter()
        .map(|target| {
            let csv = dir.join(format!("{log}-{model}-on-{target}"));
            let out = driftlab(&[
                "apply",
                cal.to_str().unwrap(),
                sample(target).to_str().unwrap(),
                "--out",
                csv.to_str().unwrap(),
            ]);
            let value = if out.status.success() {
                sha256_hex(&std::fs::read(&csv).expect("apply wrote its output"))
            } else {
                "apply-fails".to_string()
            };
            (key(target), value)
        })
        .collect()
}

#[test]
fn corrected_csv_of_every_sample_log_and_preset_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let mut seen = BTreeMap::new();
    for (log, partner) in LOGS {
        for model in MODELS {
            seen.extend(outcomes(dir.path(), log, partner, model));
        }
    }
    let text: String = seen.iter().map(|(k, v)| format!("{k} {v}\n")).collect();
    if std::env::var_os("DRIFTLAB_RECORD_HASHES").is_some() {
        std::fs::write(record_path(), &text).unwrap();
        return;
    }
    let recorded = std::fs::read_to_string(record_path()).expect("the recorded hashes are kept");
    let recorded: BTreeMap<&str, &str> = recorded
        .lines()
        .map(|l| l.rsplit_once(' ').expect("KEY HASH"))
        .collect();
    let changed: Vec<String> = seen
        .iter()
        .filter(|(k, v)| recorded.get(k.as_str()) != Some(&v.as_str()))
        .map(|(k, v)| format!("{k}: now {v}, was {:?}", recorded.get(k.as_str())))
        .collect();
    assert_eq!(seen.len(), recorded.len(), "the set of outcomes changed");
    assert!(
        changed.is_empty(),
        "outputs changed:\n{}",
        changed.join("\n")
    );
    // Most pairs fit: the record is not a list of failures.
    let fitted = seen.values().filter(|v| v.len() == 64).count();
    assert!(
        fitted > seen.len() / 2,
        "only {fitted} of {} fitted",
        seen.len()
    );
}
