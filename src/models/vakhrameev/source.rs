//! The identity of the log a calibration was made from: its name, bytes' hash, length and a
//! sketch of its samples, and the one rule every face asks to call a log in-sample or held out.

use crate::error::Invalid;
use crate::log::run_sketch::{RunSketch, Shared};
use crate::log::{DroneGyro, Log};
use serde::{Deserialize, Serialize};

/// Identity of the log a calibration was made from.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceInfo {
    /// File name (or label) of the log.
    pub name: String,
    /// SHA-256 of the file's bytes, hex; empty when not made from a file.
    pub sha256: String,
    /// Samples used.
    pub samples: usize,
    /// Duration, s.
    pub duration_s: f64,
    /// The run's fingerprint ([`Log::run_fingerprint`]), as files written before
    /// `samples_sketch` hold it (it tells the whole run under other bytes, not a part of it);
    /// empty in newer files and in files older than it.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub run: String,
    /// A sketch of the run's samples ([`RunSketch`], hexadecimal): what tells the
    /// calibration's own samples from another run's, in any file and in any part of the run;
    /// empty in files written before it was recorded.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub samples_sketch: String,
    /// The gyro of a drone or robot log it was fitted on (a DataFlash log's `IMU` instance
    /// among it): a log of several IMUs does not say by its name which one, and a flight
    /// controller's parameters must go to that one. `None` for a CSV, and in files written
    /// before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<DroneGyro>,
    /// The runs of a campaign it was fitted on ([`crate::models::campaign`]), with each
    /// run's plateaus and this axis's bias on them; empty for a calibration of one run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub runs: Vec<crate::models::campaign::RunRecord>,
    /// Within what two plateaus of the runs share a temperature, °C, as the fit grouped them
    /// (`--temp-tolerance`): what the report groups them by unless told otherwise. `None` for
    /// a calibration of one run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temp_tolerance_c: Option<f64>,
}

impl SourceInfo {
    /// The identity of `log` as far as the log itself knows it (the file's SHA-256 is filled
    /// in by whoever reads the file).
    pub fn of(log: &Log) -> SourceInfo {
        SourceInfo {
            name: log.source.clone(),
            sha256: String::new(),
            samples: log.len(),
            // A campaign's: the joined time axis's, which its plateaus are placed on (each
            // run's own duration is in its record).
            duration_s: log.duration_s(),
            run: String::new(),
            samples_sketch: RunSketch::of(log).to_text(),
            instance: log.info.instance.clone(),
            runs: Vec::new(),
            temp_tolerance_c: None,
        }
    }

    /// How much of `log` is this calibration's run, by its samples' sketch; `None` for a
    /// file written before sketches were kept.
    pub fn shared_with(&self, log: &Log) -> Option<Shared> {
        let sketch = RunSketch::from_text(&self.samples_sketch).filter(|s| !s.is_empty())?;
        Some(sketch.shared_with(log, self.samples))
    }

    /// Whether `log`, read from a file whose bytes hash to `file_sha256` and named
    /// `file_name`, holds the run this calibration was fitted on: the same file (its
    /// SHA-256), or samples of the run under other bytes or another name, the whole run or a
    /// part of it (the samples' sketch; in older files, the whole run's fingerprint). Only a
    /// file recorded with none of them is known by its name alone. Every face asks this one
    /// rule before it calls figures in-sample or held out.
    pub fn is_run_of(&self, log: &Log, file_name: &str, file_sha256: &str) -> bool {
        self.judge_run(log, file_name, file_sha256).0
    }

    /// [`SourceInfo::is_run_of`] with what the sketch found ([`SourceInfo::shared_with`]),
    /// measured once.
    pub fn judge_run(
        &self,
        log: &Log,
        file_name: &str,
        file_sha256: &str,
    ) -> (bool, Option<Shared>) {
        // Another gyro of the same file is another sensor's samples: held out, however
        // the file is named or hashed.
        if let (Some(fitted), Some(read)) = (&self.instance, &log.info.instance)
            && !fitted.same_gyro(read)
        {
            return (false, None);
        }
        let same_file = !file_sha256.is_empty()
            && std::iter::once(self.sha256.as_str())
                .chain(self.runs.iter().map(|r| r.sha256.as_str()))
                .any(|s| !s.is_empty() && file_sha256.eq_ignore_ascii_case(s));
        let shared = self.shared_with(log);
        let same_run = match shared {
            Some(shared) => shared.in_sample(),
            None => !self.run.is_empty() && self.run == log.run_fingerprint(),
        };
        let by_name = self.sha256.is_empty()
            && self.run.is_empty()
            && self.samples_sketch.is_empty()
            && file_name == self.name;
        (same_file || same_run || by_name, shared)
    }

    /// Checks what a calibration file says of the log it was fitted on: a log that lasted
    /// (no calibration is fitted on a single instant), at least the two samples that make a
    /// duration, a SHA-256 that is printable text, and the record of a campaign's runs
    /// ([`crate::models::campaign::validate_runs`]), its tolerance only beside them.
    ///
    /// # Errors
    /// An [`Invalid`] naming the field (`source.duration_s`).
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        let d = self.duration_s;
        if !(d.is_finite() && d > 0.0) {
            return Err(Invalid::new(
                "source.duration_s",
                format!(
                    "must be a duration in seconds, got {}: a calibration is fitted on a log \
                     that lasts",
                    crate::number::readable(d)
                ),
            ));
        }
        if self.samples < 2 {
            return Err(Invalid::new(
                "source.samples",
                format!(
                    "is {}, and a log of {} s has at least two",
                    self.samples,
                    crate::number::readable(d)
                ),
            ));
        }
        // Their digits are not checked (a file whose hash was damaged still corrects; the
        // report then finds no log with that hash), but they are printed as they stand.
        if !self.samples_sketch.is_empty()
            && let Err(why) = RunSketch::parse(&self.samples_sketch)
        {
            return Err(Invalid::new(
                "source.samples_sketch",
                format!(
                    "is not a sketch of a run's samples: {why} (version 2: `2;` the \
                     temperature's and the rate's resolutions, a step, `f32@UNIT` or `-`, \
                     each then `;`, then two parts separated by `;`, each empty or `T0:WIDTH:` \
                     a byte a bin of temperature `:` samples per hash `:` at most {n} \
                     ascending hashes of 16 hexadecimal digits; version 1: at most {n} such \
                     hashes, then optionally `+`, `T0:WIDTH:` and a byte a bin, `+` and as \
                     many hashes more)",
                    n = crate::log::run_sketch::SKETCH_LEN
                ),
            ));
        }
        for (field, text) in [("source.sha256", &self.sha256), ("source.run", &self.run)] {
            if let Some(c) = text.chars().find(|&c| crate::text::is_unprintable(c)) {
                return Err(Invalid::new(
                    field,
                    format!(
                        "holds {}: a hash is printable text",
                        crate::text::unprintable_named(c)
                    ),
                ));
            }
        }
        if let Some(t) = self.temp_tolerance_c {
            crate::models::campaign::check_tolerance("source.temp_tolerance_c", t)?;
        }
        if self.temp_tolerance_c.is_some() && self.runs.is_empty() {
            return Err(Invalid::new(
                "source.temp_tolerance_c",
                "is given, and there are no runs: it is the tolerance a campaign's plateaus \
                 were grouped by, recorded beside its runs (source.runs)",
            ));
        }
        crate::models::campaign::validate_runs(&self.runs)
    }
}
