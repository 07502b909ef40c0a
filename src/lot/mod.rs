//! A lot: every unit of a day's production calibrated, judged against the product's
//! acceptance spec, and compared with the others.
//!
//! A lot is a driver above the unit. Each unit is read, joined, fitted and stamped through the
//! one path `driftlab calibrate` takes ([`crate::models::campaign::calibrate_runs`]), and its
//! calibration written by the one writer ([`crate::files::calibration::save_unit`]) into its
//! own folder; what the lot adds is the figures it is judged by ([`figures`]), the spec's check
//! ([`verdict`]), the outliers of the lot ([`outliers`]) and one table ([`table`]).
//!
//! A unit that cannot be read or fitted is an outcome with its message ([`Status::Error`]),
//! never an abort: the other units go on. What stops a lot before any unit is what would make
//! every unit wrong: a spec or shared recipe that cannot be read, folders that cannot be
//! listed or hold no unit, an output folder among the inputs.

pub mod cache;
pub mod figures;
pub mod lock;
pub mod open;
pub mod outliers;
pub mod page;
pub mod read_back;
mod run;
pub mod shard;
pub mod spec;
pub mod table;
mod unit;
pub mod units;
pub mod verdict;

pub use figures::{AxisFigures, Figure};
pub use outliers::{Outlier, Spread};
pub use run::{Lot, Progress, run};
pub use shard::{Shard, merge};
pub use spec::Spec;
pub use units::{UnitJob, find_units, folder_of};

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Why a lot could not be run at all.
#[derive(Debug, thiserror::Error)]
pub enum LotError {
    /// The spec cannot be read or holds a key or value it may not.
    #[error("{}: {message}", path.display())]
    Spec {
        /// The spec file.
        path: PathBuf,
        /// What is wrong, naming the key.
        message: String,
    },
    /// The recipe every unit shares cannot be read.
    #[error("{}: {message}", path.display())]
    Recipe {
        /// The recipe file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A folder or file given cannot be listed or read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The folders given hold no unit.
    #[error(
        "no unit in {}: a unit is a log file, or a folder of logs (files not ending in .json \
         nor hidden)",
        paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    NoUnits {
        /// The folders given.
        paths: Vec<PathBuf>,
    },
    /// One unit found twice: a folder or a file given twice.
    #[error(
        "{} and {} are one unit found twice (a folder or a file given twice): give each once",
        first.display(),
        second.display()
    )]
    UnitTwice {
        /// Where it was found first.
        first: PathBuf,
        /// Where it was found again.
        second: PathBuf,
    },
    /// The output folder lies among the inputs, or an input inside it: the next lot would
    /// take the outputs for units.
    #[error(
        "{}: the lot's output folder and the folder of units {} lie one inside the other: the \
         outputs would be read as units by the next lot; give an output folder apart",
        out.display(),
        input.display()
    )]
    OutAmongInputs {
        /// The output folder.
        out: PathBuf,
        /// The folder of units.
        input: PathBuf,
    },
    /// Another lot (or a merge, or the same shard) is writing the output folder.
    #[error(
        "{}: {why}; wait for it to end, or give another output folder (two lots writing one \
         folder would leave one's table beside the other's calibrations)",
        out.display()
    )]
    Busy {
        /// The output folder.
        out: PathBuf,
        /// Who holds it.
        why: String,
    },
    /// The shards' tables in a folder cannot be merged into one lot.
    #[error("{}: {message}", out.display())]
    Merge {
        /// The folder of the shards' tables.
        out: PathBuf,
        /// Why not.
        message: String,
    },
    /// A shard's table holds a unit's outcome the lot does not compute: a figure or axis it
    /// has not, one given twice, a run's path that is not the run's.
    #[error(transparent)]
    ReadBack(#[from] read_back::ReadBack),
    /// An output of the lot could not be written.
    #[error(transparent)]
    Write(#[from] crate::Error),
    /// A unit's calibration could not be written: the output's fault (a full disk, a quota, a
    /// folder that cannot be written), not the unit's. The lot stops before its tables, and no
    /// unit is made an error for it, so no earlier lot's calibration is removed.
    #[error(
        "unit {unit}: its calibration could not be written: {source}: the lot stopped before its \
         tables, and lot.csv, lot.json and lot.html are as the last lot left them; no unit's \
         earlier files were removed (the units written before it keep their new calibration and \
         record, and a lot run again takes them from there)"
    )]
    Unwritten {
        /// The unit whose calibration could not be written.
        unit: String,
        /// Why.
        source: crate::Error,
    },
}

/// How a unit came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Calibrated, and within every limit of the spec.
    Pass,
    /// Calibrated, and outside at least one limit (each named in its reasons).
    Fail,
    /// Not calibrated: its files could not be read, joined or fitted, or its calibration
    /// written (the message is its reason).
    Error,
}

impl Status {
    /// The word the table writes.
    pub fn word(self) -> &'static str {
        match self {
            Status::Pass => "pass",
            Status::Fail => "fail",
            Status::Error => "error",
        }
    }
}

/// One unit of the lot as it came out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitOutcome {
    /// The unit's name.
    pub unit: String,
    /// Its folder in the output folder.
    pub folder: String,
    /// Pass, fail or error.
    pub status: Status,
    /// Every limit it breaks (fail), or why it could not be calibrated (error).
    pub reasons: Vec<String>,
    /// Its runs' files, as given.
    pub runs: Vec<String>,
    /// Its runs' files as absolute paths, in the same order: where a face opening the unit
    /// from elsewhere than the lot was run (the workbench, [`open`]) finds them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub runs_at: Vec<String>,
    /// The recipe it was calibrated with: its own file, the shared one, or none (the
    /// defaults).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub recipe: Option<String>,
    /// Its calibration file, relative to the output folder; none for an error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<String>,
    /// Its report's page, relative to the output folder, when one was asked for and written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub report: Option<String>,
    /// Each axis's figures; none for an error.
    pub axes: Vec<AxisFigures>,
    /// What reading and fitting told (they did not stop it).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Taken from the record of an earlier lot: its runs, recipe and spec unchanged, it was
    /// not calibrated again ([`cache`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cached: bool,
}

impl UnitOutcome {
    /// The outcome read back from `file` in `OUT` (a unit's record on a cache hit, a shard's
    /// table in a merge) settled by what the lot itself knows, never by what the file says:
    /// its runs, axes and figures checked against what the lot computes ([`read_back`]), its
    /// folder made from its name, its status and reasons judged again from its figures against
    /// `spec`, its calibration and report linked where the lot writes them and only when they
    /// are there. An edited record or table can then neither pass a unit that fails, nor link
    /// out of `OUT`, nor put a name of its own (or a control character) into the lot's files.
    ///
    /// # Errors
    /// The outcome holds what the lot does not compute ([`read_back::ReadBack`]).
    pub fn settled(
        mut self,
        spec: &Spec,
        out: &std::path::Path,
        file: &std::path::Path,
    ) -> Result<UnitOutcome, read_back::ReadBack> {
        read_back::runs(&self, file)?;
        self.folder = folder_of(&self.unit);
        let folder = std::path::Path::new(&self.folder);
        self.report = None;
        if self.status == Status::Error {
            self.calibration = None;
            self.axes.clear();
            return Ok(self);
        }
        let calibration = folder.join(cache::CALIBRATION);
        let errored = |mut this: UnitOutcome, reason: String| {
            this.status = Status::Error;
            this.reasons = vec![reason];
            this.calibration = None;
            this.axes.clear();
            this
        };
        if !out.join(&calibration).is_file() {
            let reason = format!(
                "its calibration {} is not in the output folder",
                calibration.display()
            );
            return Ok(errored(self, reason));
        }
        let own_axes: Vec<String> =
            match crate::files::calibration::load_unit(&out.join(&calibration)) {
                Ok(unit) => unit.axes.into_iter().map(|a| a.name).collect(),
                Err(e) => {
                    let reason = format!("its calibration cannot be read: {e}");
                    return Ok(errored(self, reason));
                }
            };
        read_back::axes(&self, spec, &own_axes, file)?;
        self.calibration = Some(calibration.display().to_string());
        let report = folder.join(unit::REPORT_PAGE);
        if out.join(&report).is_file() {
            self.report = Some(report.display().to_string());
        }
        self.reasons = verdict::reasons(spec, &self.axes);
        self.status = if self.reasons.is_empty() {
            Status::Pass
        } else {
            Status::Fail
        };
        Ok(self)
    }
}

/// A lot as it came out: every unit in order, and the outliers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LotOutcome {
    /// The spec the units were held to.
    pub spec: Spec,
    /// Every unit, in the order found.
    pub units: Vec<UnitOutcome>,
    /// Every figure of a unit far from the lot's median.
    pub outliers: Vec<Outlier>,
}

impl LotOutcome {
    /// The units of each status: pass, fail, error.
    pub fn counts(&self) -> [usize; 3] {
        let n = |s: Status| self.units.iter().filter(|u| u.status == s).count();
        [n(Status::Pass), n(Status::Fail), n(Status::Error)]
    }

    /// The lot's status: an error if any unit is one, else a failure if any unit fails, else
    /// a pass.
    pub fn status(&self) -> Status {
        match self.counts() {
            [_, _, e] if e > 0 => Status::Error,
            [_, f, _] if f > 0 => Status::Fail,
            _ => Status::Pass,
        }
    }

    /// The outliers found in `units` by `spec`'s number of robust standard deviations.
    pub fn find_outliers(spec: &Spec, units: &[UnitOutcome]) -> Vec<Outlier> {
        let judged: Vec<(&str, &[AxisFigures])> = units
            .iter()
            .filter(|u| u.status != Status::Error)
            .map(|u| (u.unit.as_str(), u.axes.as_slice()))
            .collect();
        outliers::outliers(&judged, spec.outlier_sigmas())
    }
}
