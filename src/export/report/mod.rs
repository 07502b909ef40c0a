//! The test report of a calibration: figures (PNG and SVG) and one self-contained HTML page.
//!
//! [`write()`] takes a calibration and the logs to judge it on and writes, into one folder:
//!
//! * `temperature-LOG` and `drift-LOG` for every log: the temperature program, and the raw
//!   drift with its filtered version, the predicted drift and the corrected drift;
//! * `k0`, `k1`, `k2`: the fitted coefficients over their variables, with the plateau points
//!   and (when the calibration's own log is among the logs) the pointwise K1± and K2± values
//!   they were fitted to;
//! * `campaign`, for a calibration fitted on several runs: every run's plateau biases over
//!   temperature beside K0(T); the page then has a campaign section (`campaign_section.rs`);
//! * `allan-LOG`: Allan deviation before and after correction, when curves are given or the
//!   Allan hook ([`allan_curves`]) provides them;
//! * `report.html`: the gyro's identity, the recipe, the coefficients with their ranges, the
//!   figures of merit of every log (in-sample or held out) and every figure, inline.
//!
//! [`write_model`] takes any model of a calibration file; for a regression model
//! ([`write_regression`]) the calibration's figures are replaced by `costs`, the cost curves of
//! its searches for λ, τd and the lag (when it searched), and the page lists its terms with
//! coefficients ± standard errors instead of the recipe, plateaus and K curves.
//!
//! A single-axis calibration is a unit of one axis: [`write_model`] and [`write_unit`] draw
//! each axis's figures with the same builder and write `report.html` with the same page writer
//! (`page.rs`), which lays a unit of one unnamed axis out as the single-axis page and a unit of
//! several with a summary of every axis and a section per axis.
//!
//! A log is *in-sample* when it is the calibration's own run ([`SourceInfo::is_run_of`]: the
//! same file's SHA-256, the same samples under other bytes, or, for a calibration that records
//! neither, the same file name) and *held out* otherwise.
//!
//! [`SourceInfo::is_run_of`]: crate::models::vakhrameev::SourceInfo::is_run_of
//! Nothing here depends on a user interface: the command line and the workbench call the same
//! function.

mod axis_summary;
mod campaign_section;
pub mod figures;
mod folder;
pub mod html;
mod log_section;
mod model_figures;
mod page;
mod regression_section;
mod unit;
mod vakhrameev_section;

pub use folder::MARKER;
pub use unit::{AxisReport, UnitMerit, UnitReportSummary, write_unit};

use crate::error::{Error, Result};
use crate::files::calibration;
use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::Log;
use crate::models::fitted::DriftModel;
use crate::models::regression::RegressionCalibration;
use crate::models::vakhrameev::Calibration;
use crate::models::vakhrameev::correct::Correction;
use folder::{Relocate, moved};
use log_section::{LogSection, log_report};
use model_figures::ModelFigures;
use page::PageAxis;
use std::path::{Path, PathBuf};

/// One Allan-deviation curve, computed elsewhere (`allan/`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AllanCurve {
    /// Legend text, e.g. "raw" or "corrected".
    pub label: String,
    /// Averaging times τ, s.
    pub tau_s: Vec<f64>,
    /// Allan deviation at each τ, °/h.
    pub adev_dph: Vec<f64>,
}

/// The Allan curves of one log (typically raw and corrected).
pub type AllanCurves = Vec<AllanCurve>;

/// Choices of a report.
#[derive(Debug, Clone, Default)]
pub struct ReportOptions {
    /// How the figures of merit are computed; `None`: the calibration's own Ω filter and
    /// 10-minute windows, as `driftlab evaluate` does.
    pub merit: Option<MeritOptions>,
    /// Allan curves already computed, one entry per log in the order of the logs. `None`: the
    /// report asks [`allan_curves`] for each log.
    pub allan: Option<Vec<Option<AllanCurves>>>,
    /// SHA-256 of each log's bytes, in the order of the logs, when the caller has them: a log
    /// read from a pipe cannot be opened again to be hashed. `None`: each log is hashed from
    /// its path.
    pub sha256: Option<Vec<String>>,
    /// What the axis reported measures: the unit of its figures, columns and coefficients.
    pub kind: crate::log::AxisKind,
}

/// One figure of the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title, also the figure's caption in the page.
    pub title: String,
    /// What the reader sees in it.
    pub caption: String,
    /// The PNG file.
    pub png: PathBuf,
    /// The SVG file.
    pub svg: PathBuf,
}

/// Whether a log is the model's own, with what the model's sketch found of it
/// ([`crate::models::vakhrameev::SourceInfo::judge_run`]).
pub type Told = (bool, Option<crate::log::run_sketch::Shared>);

/// One log judged by the calibration.
#[derive(Debug, Clone)]
pub struct LogReport {
    /// File name of the log.
    pub name: String,
    /// The path it was read from.
    pub path: PathBuf,
    /// SHA-256 of the file (empty when it could not be read again).
    pub sha256: String,
    /// True for the calibration's own log.
    pub in_sample: bool,
    /// What its figures are, in the words every face uses: "in-sample", "held out", or
    /// "cannot tell" when the calibration's sketch cannot tell whether it is its own log
    /// ([`crate::judge::verify::sample_kind`]).
    pub kind: &'static str,
    /// Why the sketch cannot tell, when it cannot.
    pub cannot_tell: Option<String>,
    /// Raw against corrected, as `metrics::Evaluation::of` computes them.
    pub evaluation: Evaluation,
    /// Samples and duration of the log.
    pub samples: usize,
    /// Duration, s.
    pub duration_s: f64,
    /// Range of the calibration temperature, °C.
    pub temp_range_c: (f64, f64),
    /// Its figures (temperature program, drift, Allan deviation when available).
    pub figures: Vec<Figure>,
    /// The unit of its figures of merit: `°/h`, `m/s²` for an accelerometer axis.
    pub unit: &'static str,
    /// Its place among the logs given, counted from 0 (a log left out takes its place too).
    pub index: usize,
}

/// A log left out of an axis's tables: its readings of that axis are none a figure can take
/// ([`crate::models::check_axis_readings`]: held at one value, more readings beyond any
/// sensor's than glitches, most samples missing), so any figure of it is 10³⁸ or rounding.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOutLog {
    /// Its name as the page shows it.
    pub name: String,
    /// Its place among the logs given, counted from 0.
    pub index: usize,
    /// Why, the words `evaluate` refuses it with.
    pub reason: String,
}

/// What [`write()`] wrote.
#[derive(Debug, Clone)]
pub struct ReportSummary {
    /// The HTML page.
    pub html: PathBuf,
    /// Every file written, the page last (the folder's [`MARKER`] aside).
    pub files: Vec<PathBuf>,
    /// The calibration's figures (K0, K1±, K2±).
    pub figures: Vec<Figure>,
    /// Every log judged, in the order given.
    pub logs: Vec<LogReport>,
    /// The logs left out, with why, in the order given.
    pub left_out: Vec<LeftOutLog>,
    /// The merit options used.
    pub merit: MeritOptions,
    /// Things the reader should know (no in-sample log given, no Allan curves, ...).
    pub notes: Vec<String>,
    /// The unit of the axis's figures of merit and coefficients: `°/h`, `m/s²`.
    pub unit: &'static str,
}

impl Relocate for Figure {
    fn relocate(&mut self, from: &Path, to: &Path) {
        self.png = moved(&self.png, from, to);
        self.svg = moved(&self.svg, from, to);
    }
}

impl Relocate for ReportSummary {
    /// The report's own files; the logs' paths are where they were read from.
    fn relocate(&mut self, from: &Path, to: &Path) {
        self.html = moved(&self.html, from, to);
        for f in &mut self.files {
            *f = moved(f, from, to);
        }
        let log_figures = self.logs.iter_mut().flat_map(|l| &mut l.figures);
        for f in self.figures.iter_mut().chain(log_figures) {
            f.relocate(from, to);
        }
    }
}

/// Allan deviation of `log`'s raw rate and of its `correction`, for the
/// report's "before and after" figure: the octave overlapping deviation of the raw and the
/// corrected rate over the same samples (after the correction's warm-up), or `None` when the
/// log is too short for one.
pub fn allan_curves(log: &Log, correction: &Correction) -> Option<AllanCurves> {
    let opts = crate::judge::allan::AllanOptions {
        tau0_s: log.nominal_dt_s(),
        ..crate::judge::allan::AllanOptions::default()
    };
    let skip = correction.ready_from.min(correction.cor_dph.len());
    let curve = |label: &str, rate: &[f64]| {
        crate::judge::allan::allan(rate, &opts)
            .ok()
            .map(|d| AllanCurve {
                label: label.to_string(),
                tau_s: d.points.iter().map(|p| p.tau_s).collect(),
                adev_dph: d.points.iter().map(|p| p.adev).collect(),
            })
    };
    let raw = curve("raw", &log.omega_dph[skip.min(log.omega_dph.len())..])?;
    let cor = curve("corrected", &correction.cor_dph[skip..])?;
    Some(vec![raw, cor])
}

/// The merit options a report of any model uses by default: a Vakhrameev calibration's own Ω
/// filter, the default filter for a regression model (which has none); 10-minute windows.
pub fn default_merit_for(model: &DriftModel) -> MeritOptions {
    match model {
        DriftModel::Vakhrameev(cal) => default_merit(cal),
        DriftModel::Regression(_) => MeritOptions::default(),
    }
}

/// The merit options a report uses by default: the calibration's Ω filter, 10-minute windows.
pub fn default_merit(cal: &Calibration) -> MeritOptions {
    MeritOptions {
        filter_s: cal.recipe.filter_s,
        ..MeritOptions::default()
    }
}

/// The logs' names as a page shows them: each its file name, and where two share one, with
/// as many of their folders as tell them apart (`d1/run.csv`, `d2/run.csv`); two paths to
/// one name all the way up keep their whole paths.
pub(super) fn names_apart(paths: &[&Path]) -> Vec<String> {
    let parts: Vec<Vec<String>> = paths
        .iter()
        .map(|p| {
            p.components()
                .rev()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect()
        })
        .collect();
    let name = |k: usize, depth: usize| {
        let mut c: Vec<&str> = parts[k].iter().take(depth).map(String::as_str).collect();
        c.reverse();
        c.join("/")
    };
    let mut depth = vec![1usize; paths.len()];
    loop {
        let names: Vec<String> = (0..paths.len()).map(|k| name(k, depth[k])).collect();
        let mut grew = false;
        for k in 0..paths.len() {
            let clash = (0..paths.len()).any(|j| j != k && names[j] == names[k]);
            if clash && depth[k] < parts[k].len() {
                depth[k] += 1;
                grew = true;
            }
        }
        if !grew {
            return names
                .into_iter()
                .zip(paths)
                .map(|(n, p)| {
                    if n.is_empty() {
                        p.display().to_string()
                    } else {
                        n
                    }
                })
                .collect();
        }
    }
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

fn figure(title: String, caption: String, files: Vec<PathBuf>) -> Figure {
    let pick = |ext: &str| {
        files
            .iter()
            .find(|p| p.extension().is_some_and(|e| e == ext))
            .cloned()
            .unwrap_or_default()
    };
    Figure {
        title,
        caption,
        png: pick("png"),
        svg: pick("svg"),
    }
}

/// Writes the report of any model judged on `logs` (each with the path it was read from) into
/// the folder `out_dir`: the model's own figures (a Vakhrameev calibration's `k0`, `k1`, `k2`;
/// a regression model's `costs`), each log's figures, and `report.html`, the page of a unit of
/// one axis. The report is written beside `out_dir` and then put in its place whole
/// (`folder.rs`): a failure leaves `out_dir` as it was, and a report replacing an earlier one
/// leaves none of the earlier one's files. `out_dir` must be new, empty or a report.
///
/// # Errors
/// Figures of merit without a positive filter or window, a log lacking a channel the model
/// reads, a figure that cannot be drawn, a file that cannot be written, an `out_dir` that is
/// a file or a folder holding other things than a report.
pub fn write_model(
    model: &DriftModel,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    let refused = refusals(logs);
    folder::replace(out_dir, |dir| {
        let mut summary = build(model, (logs, &refused), dir, opts, None)?;
        let axis = PageAxis {
            name: "",
            rate_column: "",
            model,
            summary: &summary,
            kind: opts.kind,
            kept_mean: None,
        };
        page::write(
            &[axis],
            &summary.html,
            crate::models::campaign::DEFAULT_TOLERANCE_C,
            None,
        )?;
        summary.files.push(summary.html.clone());
        Ok(summary)
    })
}

/// Writes the report of a regression model judged on `logs` into `out_dir`, as
/// [`write_model`] does.
///
/// # Errors
/// As [`write_model`].
pub fn write_regression(
    cal: &RegressionCalibration,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    write_model(
        &DriftModel::Regression(Box::new(cal.clone())),
        logs,
        out_dir,
        opts,
    )
}

/// Writes the report of a Vakhrameev calibration judged on `logs` into `out_dir`, as
/// [`write_model`] does.
///
/// # Errors
/// As [`write_model`].
pub fn write(
    cal: &Calibration,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    write_model(
        &DriftModel::Vakhrameev(Box::new(cal.clone())),
        logs,
        out_dir,
        opts,
    )
}

/// Why each log's selected axis can take no figure, `None` for one that can
/// ([`crate::models::check_axis_readings`], on the readings as read).
pub(super) fn refusals(logs: &[(PathBuf, Log)]) -> Vec<Option<String>> {
    logs.iter()
        .map(|(_, log)| {
            crate::models::check_axis_readings(log)
                .err()
                .map(|e| e.to_string())
        })
        .collect()
}

/// The figures and figures of merit of one axis's report, without its page: the folder made
/// (an axis's, inside a unit's staging folder), the model's own figures, then a section for
/// every log. A log `refused` gives a reason for (its readings as read, before an
/// accelerometer's mean is taken off) is left out of the figures, with that reason, in the
/// summary's `left_out`.
/// `in_sample`: whether each log is the model's own, with what the model's sketch found of it,
/// when the caller settled it (a unit's axes, together); `None`: each log judged by the
/// model's source alone.
fn build(
    model: &DriftModel,
    (logs, refused): (&[(PathBuf, Log)], &[Option<String>]),
    out_dir: &Path,
    opts: &ReportOptions,
    in_sample: Option<&[Told]>,
) -> Result<ReportSummary> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let merit = opts.merit.unwrap_or_else(|| default_merit_for(model));
    for (setting, seconds) in [("filter_s", merit.filter_s), ("window_s", merit.window_s)] {
        if seconds.is_nan() || seconds <= 0.0 {
            return Err(Error::Invalid(crate::error::Invalid::new(
                setting,
                format!(
                    "the figures of merit need a positive number of seconds, got {}",
                    crate::number::readable(seconds)
                ),
            )));
        }
    }
    let hashes: Vec<String> = match &opts.sha256 {
        Some(h) if h.len() == logs.len() => h.clone(),
        _ => logs
            .iter()
            .map(|(p, _)| calibration::sha256_file(p).unwrap_or_default())
            .collect(),
    };
    let told: Vec<Told> = match in_sample {
        Some(given) if given.len() == logs.len() => given.to_vec(),
        _ => logs
            .iter()
            .zip(&hashes)
            .map(|((p, log), h)| model.source().judge_run(log, &file_name(p), h))
            .collect(),
    };
    // A log left out is no model's own: its figures are none.
    let is_refused = |i: usize| refused.get(i).is_some_and(Option::is_some);
    let in_sample: Vec<bool> = told
        .iter()
        .enumerate()
        .map(|(i, t)| t.0 && !is_refused(i))
        .collect();
    let ModelFigures {
        mut taken,
        mut files,
        mut notes,
        figures,
    } = model_figures::draw(model, logs, &in_sample, out_dir)?;

    let mut reports = Vec::new();
    let mut left_out = Vec::new();
    let mut any_allan = false;
    let names = names_apart(&logs.iter().map(|(p, _)| p.as_path()).collect::<Vec<_>>());
    for (i, ((path, log), sha)) in logs.iter().zip(&hashes).enumerate() {
        if let Some(Some(reason)) = refused.get(i) {
            left_out.push(LeftOutLog {
                name: names[i].clone(),
                index: i,
                reason: reason.clone(),
            });
            continue;
        }
        let (correction, plateaus) = correct(model, in_sample[i], sha, path, log)?;
        let section = LogSection {
            path,
            name: &names[i],
            kind: opts.kind,
            log,
            sha,
            in_sample: in_sample[i],
            share: told[i].1,
            correction,
            left_out: model.left_out(),
            plateaus: &plateaus,
            allan: opts
                .allan
                .as_ref()
                .map(|given| given.get(i).cloned().flatten()),
        };
        let (mut report, drew_allan) =
            log_report(out_dir, section, &merit, &mut taken, &mut files)?;
        report.index = i;
        any_allan |= drew_allan;
        reports.push(report);
    }
    if !any_allan && !reports.is_empty() {
        notes.push(ALLAN_NOTE.into());
    }
    Ok(ReportSummary {
        html: out_dir.join("report.html"),
        files,
        figures,
        logs: reports,
        left_out,
        merit,
        notes,
        unit: opts.kind.unit(),
    })
}

/// The correction of `log` (read from `path`, its bytes hashing to `sha256`) by `model`, and
/// the plateaus to shade in its temperature program: a Vakhrameev calibration's, on its own
/// log only; of a campaign's, the plateaus of the run the log is (on the run's own time),
/// since the calibration's are on the campaign's joined time.
fn correct(
    model: &DriftModel,
    own: bool,
    sha256: &str,
    path: &Path,
    log: &Log,
) -> Result<(Correction, Vec<(f64, f64)>)> {
    match model {
        DriftModel::Vakhrameev(cal) if !cal.source.runs.is_empty() => {
            let run = campaign_section::run_of(&cal.source.runs, sha256);
            let plateaus = match run {
                Some(k) if own => cal.source.runs[k - 1]
                    .plateaus
                    .iter()
                    .map(|p| (p.start_s, p.end_s))
                    .collect(),
                _ => Vec::new(),
            };
            Ok((cal.correct(log), plateaus))
        }
        DriftModel::Vakhrameev(cal) => {
            let plateaus = if own {
                cal.plateaus
                    .iter()
                    .map(|p| (p.range.start_s, p.range.end_s))
                    .collect()
            } else {
                Vec::new()
            };
            Ok((cal.correct(log), plateaus))
        }
        DriftModel::Regression(reg) => {
            let correction = reg.model.correct(log).map_err(|e| match e {
                Error::Fit(e) => Error::Fit(e.on_file(path)),
                other => other,
            })?;
            Ok((correction, Vec::new()))
        }
    }
}

const ALLAN_NOTE: &str = "Allan deviation: not computed in this build (the report's Allan hook \
                          returned no curves).";

#[cfg(test)]
mod names_apart_tests {
    use super::names_apart;
    use std::path::Path;

    #[test]
    fn logs_of_one_file_name_are_told_apart_by_their_folders() {
        let p = |s: &'static str| Path::new(s);
        assert_eq!(
            names_apart(&[p("/a/d1/run.csv"), p("/a/d2/run.csv"), p("/a/cal.csv")]),
            ["d1/run.csv", "d2/run.csv", "cal.csv"]
        );
        // Apart only higher up.
        assert_eq!(
            names_apart(&[p("x/same/run.csv"), p("y/same/run.csv")]),
            ["x/same/run.csv", "y/same/run.csv"]
        );
        // One file given twice keeps its path: nothing tells the two apart.
        assert_eq!(
            names_apart(&[p("d/run.csv"), p("d/run.csv")]),
            ["d/run.csv", "d/run.csv"]
        );
    }
}
