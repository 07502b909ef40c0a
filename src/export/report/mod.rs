//! The test report of a calibration: figures (PNG and SVG) and one self-contained HTML page.
//!
//! [`write()`] takes a calibration and the logs to judge it on and writes, into one folder:
//!
//! * `temperature-LOG` and `drift-LOG` for every log: the temperature program, and the raw
//!   drift with its filtered version, the predicted drift and the corrected drift;
//! * `k0`, `k1`, `k2`: the fitted coefficients over their variables, with the plateau points
//!   and (when the calibration's own log is among the logs) the pointwise K1± and K2± values
//!   they were fitted to;
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
//! A log is *in-sample* when it is the calibration's source log (same SHA-256 of the file, or
//! the same file name when the calibration records no hash) and *held out* otherwise.
//! Nothing here depends on a user interface: the command line and the workbench call the same
//! function.

pub mod figures;
pub mod html;
mod log_section;
mod regression_page;
mod unit;
mod unit_page;

pub use unit::{AxisReport, UnitMerit, UnitReportSummary, write_unit};

use crate::error::{Error, Result};
use crate::files::calibration;
use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::Log;
use crate::models::fitted::DriftModel;
use crate::models::regression::RegressionCalibration;
use crate::models::vakhrameev::correct::Correction;
use crate::models::vakhrameev::{Calibration, SourceInfo};
use figures::{PlateauPoint, RateAxes, RateSet};
use log_section::{LogSection, log_report};
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
}

/// What [`write()`] wrote.
#[derive(Debug, Clone)]
pub struct ReportSummary {
    /// The HTML page.
    pub html: PathBuf,
    /// Every file written, the page last.
    pub files: Vec<PathBuf>,
    /// The calibration's figures (K0, K1±, K2±).
    pub figures: Vec<Figure>,
    /// Every log, in the order given.
    pub logs: Vec<LogReport>,
    /// The merit options used.
    pub merit: MeritOptions,
    /// Things the reader should know (no in-sample log given, no Allan curves, ...).
    pub notes: Vec<String>,
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

/// Whether `path` holds the calibration's own log: the file's SHA-256 equals the recorded one,
/// or, for a calibration that records no hash, the file name matches.
pub fn is_in_sample(cal: &Calibration, path: &Path, sha256: &str) -> bool {
    is_source(&cal.source, path, sha256)
}

/// Whether `path` is the log `source` describes (see [`is_in_sample`]).
pub fn is_source(source: &SourceInfo, path: &Path, sha256: &str) -> bool {
    if source.sha256.is_empty() {
        file_name(path) == source.name
    } else {
        !sha256.is_empty() && sha256.eq_ignore_ascii_case(&source.sha256)
    }
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

/// Writes the report of any model judged on `logs` into `out_dir`: a Vakhrameev calibration as
/// [`write()`] does, a regression model as [`write_regression`] does.
pub fn write_model(
    model: &DriftModel,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    match model {
        DriftModel::Vakhrameev(cal) => write(cal, logs, out_dir, opts),
        DriftModel::Regression(r) => write_regression(r, logs, out_dir, opts),
    }
}

/// Writes the report of a regression model judged on `logs` into `out_dir`, creating it:
/// `costs` (the searches for λ, τd and the lag: RMS residual over the values tried, the chosen
/// one marked; only when the model searched), then per log the temperature program, the drift
/// and the Allan deviation as for the Vakhrameev model, and `report.html` with the model's
/// terms, coefficients ± standard errors, λ, τd(T), lag, input ranges and fit statistics.
///
/// # Errors
/// A log lacking a channel the model reads, a file that cannot be written.
pub fn write_regression(
    cal: &RegressionCalibration,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    build_regression(cal, logs, out_dir, opts)
        .and_then(|summary| write_page(summary, |s| html::regression_page(cal, s)))
}

/// The figures and figures of merit of a regression model's report, without its page.
fn build_regression(
    cal: &RegressionCalibration,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    let merit = opts.merit.unwrap_or_default();
    let (hashes, in_sample) = start(out_dir, logs, opts, &merit, |p, h| {
        is_source(&cal.source, p, h)
    })?;
    let m = &cal.model;
    let mut notes = Vec::new();
    let mut files = Vec::new();
    let taken: Vec<String> = ["costs", "report"].iter().map(|s| s.to_string()).collect();
    if !logs.is_empty() && !in_sample.contains(&true) {
        notes.push(format!(
            "The model's own log ({}) is not among the logs: every log is held out.",
            cal.source.name
        ));
    }

    // The searches.
    let mut model_figures = Vec::new();
    let lines: Vec<figures::CostLine> = m
        .searches
        .iter()
        .map(|c| figures::CostLine {
            parameter: &c.parameter,
            x: &c.x,
            rmse: &c.rmse,
            best: c.best,
            log_x: c.parameter == "lambda_s",
        })
        .collect();
    if !lines.is_empty() {
        let f = figures::cost_curves(
            &out_dir.join("costs"),
            &format!(
                "Searches of model {}: RMS residual over the values tried",
                m.spec.name
            ),
            &lines,
        )?;
        files.extend(f.iter().cloned());
        let edge: Vec<&str> = m
            .searches
            .iter()
            .filter(|c| c.at_edge)
            .map(|c| c.parameter.as_str())
            .collect();
        model_figures.push(figure(
            "Search cost curves".into(),
            format!(
                "RMS residual of the least-squares fit at each value tried for the parameters                  the model is not linear in (λ on a logarithmic axis; a delay per temperature                  band for τd(T)); the vertical line marks the value chosen.{}",
                if edge.is_empty() {
                    String::new()
                } else {
                    format!(
                        " At the edge of the searched range (the optimum may lie beyond): {}.",
                        edge.join(", ")
                    )
                }
            ),
            f,
        ));
    }

    let pieces = Pieces {
        hashes,
        in_sample,
        merit,
        taken,
        files,
        notes,
        figures: model_figures,
    };
    finish(out_dir, logs, opts, pieces, |_, path, log| {
        let correction = m.correct(log).map_err(|e| match e {
            Error::Fit(e) => Error::Fit(e.on_file(path)),
            other => other,
        })?;
        Ok((correction, Vec::new()))
    })
}

/// Writes the HTML page of a finished summary (atomically) and lists it among the files.
fn write_page(
    mut summary: ReportSummary,
    page: impl FnOnce(&ReportSummary) -> Result<String>,
) -> Result<ReportSummary> {
    let text = page(&summary)?;
    let path = summary.html.clone();
    crate::files::atomic::write_bytes(&path, text.as_bytes()).map_err(|e| Error::io(&path, e))?;
    summary.files.push(path);
    Ok(summary)
}

/// Writes the report of `cal` judged on `logs` (each with the path it was read from) into
/// `out_dir`, creating it. Every file is written atomically.
pub fn write(
    cal: &Calibration,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    build(cal, logs, out_dir, opts).and_then(|summary| write_page(summary, |s| html::page(cal, s)))
}

/// The figures and figures of merit of any model's report, without its page.
fn build_model(
    model: &DriftModel,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    match model {
        DriftModel::Vakhrameev(cal) => build(cal, logs, out_dir, opts),
        DriftModel::Regression(r) => build_regression(r, logs, out_dir, opts),
    }
}

/// The figures and figures of merit of a Vakhrameev calibration's report, without its page.
fn build(
    cal: &Calibration,
    logs: &[(PathBuf, Log)],
    out_dir: &Path,
    opts: &ReportOptions,
) -> Result<ReportSummary> {
    let merit = opts.merit.unwrap_or_else(|| default_merit(cal));
    let (hashes, in_sample) = start(out_dir, logs, opts, &merit, |p, h| is_in_sample(cal, p, h))?;
    let mut notes = Vec::new();
    let mut files = Vec::new();
    let taken: Vec<String> = ["k0", "k1", "k2", "report"]
        .iter()
        .map(|s| s.to_string())
        .collect();

    // The calibration's figures.
    let mut cal_figures = Vec::new();
    let k0_points: Vec<PlateauPoint> = cal
        .plateaus
        .iter()
        .map(|p| PlateauPoint {
            temp_c: p.temp_c,
            omega_dph: p.omega_dph,
            std_dph: p.omega_std_dph,
        })
        .collect();
    let f = figures::k0(
        &out_dir.join("k0"),
        "Static bias K0(T) from the temperature plateaus",
        &cal.k0,
        &k0_points,
    )?;
    files.extend(f.iter().cloned());
    cal_figures.push(figure(
        "K0(T)".into(),
        format!(
            "Static bias K0 over temperature: the mean rate of each of the {} plateaus (± std of \
             the raw rate) and the {} fit over {:.1} … {:.1} °C, held at its edge value beyond.",
            cal.plateaus.len(),
            cal.k0.kind(),
            cal.k0.x_min(),
            cal.k0.x_max()
        ),
        f,
    ));

    let own = in_sample.iter().position(|&b| b);
    let points = own.map(|i| cal.pointwise(&logs[i].1));
    let source_note = match own {
        Some(i) => format!(
            "Dots: the pointwise values on the calibration log {} (thinned for drawing).",
            file_name(&logs[i].0)
        ),
        None => {
            notes.push(format!(
                "The calibration's own log ({}) is not among the logs: the K1 and K2 figures \
                 show the fitted curves without their points, and every log is held out.",
                cal.source.name
            ));
            "The calibration log was not given, so only the fitted curves are drawn.".into()
        }
    };
    for (k, (name, var, x_desc, y_desc, db, plus, minus)) in [
        (
            "K1",
            "dT/dt",
            "rate of temperature dT/dt, °C/s",
            "K1, (°/h)/(°C/s)",
            cal.resolved.deadband_tdot,
            &cal.k1_plus,
            &cal.k1_minus,
        ),
        (
            "K2",
            "d²T/dt²",
            "second derivative of temperature d²T/dt², °C/s²",
            "K2, (°/h)/(°C/s²)",
            cal.resolved.deadband_tddot,
            &cal.k2_plus,
            &cal.k2_minus,
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let pts = points.as_ref();
        let f = figures::rate_coefficient(
            &out_dir.join(name.to_lowercase()),
            &format!("{name}± over {var}: + set (thermal acceleration) and − set (deceleration)"),
            RateAxes {
                name,
                x_desc,
                y_desc,
                deadband: db,
            },
            [
                RateSet {
                    sign: "+",
                    curve: plus,
                    points: pts.map(|p| &p[2 * k]),
                },
                RateSet {
                    sign: "−",
                    curve: minus,
                    points: pts.map(|p| &p[2 * k + 1]),
                },
            ],
        )?;
        files.extend(f.iter().cloned());
        cal_figures.push(figure(
            format!("{name}±({var})"),
            format!(
                "{name}+ and {name}− over {var}: fitted curves (dashed where held at the edge \
                 value) and the dead-band |{var}| ≤ {:.3e} left out of the fits. {source_note}",
                db
            ),
            f,
        ));
    }
    drop(points);

    let pieces = Pieces {
        hashes,
        in_sample,
        merit,
        taken,
        files,
        notes,
        figures: cal_figures,
    };
    finish(out_dir, logs, opts, pieces, |own, _, log| {
        // The plateaus are shaded on the calibration's own log only.
        let plateaus = if own {
            cal.plateaus
                .iter()
                .map(|p| (p.range.start_s, p.range.end_s))
                .collect()
        } else {
            Vec::new()
        };
        Ok((cal.correct(log), plateaus))
    })
}

/// What both writers start with: the folder made, the figures of merit checked, and each
/// log's hash with whether it is the model's own log (`is_own(path, sha256)`).
fn start(
    out_dir: &Path,
    logs: &[(PathBuf, Log)],
    opts: &ReportOptions,
    merit: &MeritOptions,
    is_own: impl Fn(&Path, &str) -> bool,
) -> Result<(Vec<String>, Vec<bool>)> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    if !(merit.filter_s > 0.0 && merit.window_s > 0.0) {
        return Err(Error::Invalid(crate::error::Invalid::new(
            "merit",
            "the figures of merit need a positive filter and window",
        )));
    }
    let hashes: Vec<String> = match &opts.sha256 {
        Some(h) if h.len() == logs.len() => h.clone(),
        _ => logs
            .iter()
            .map(|(p, _)| calibration::sha256_file(p).unwrap_or_default())
            .collect(),
    };
    let in_sample = logs
        .iter()
        .zip(&hashes)
        .map(|((p, _), h)| is_own(p, h))
        .collect();
    Ok((hashes, in_sample))
}

/// What a writer has gathered when its model's own figures are drawn.
struct Pieces {
    hashes: Vec<String>,
    in_sample: Vec<bool>,
    merit: MeritOptions,
    taken: Vec<String>,
    files: Vec<PathBuf>,
    notes: Vec<String>,
    figures: Vec<Figure>,
}

/// What both writers end with: a section for every log, corrected by `correct(own log?, path,
/// log)`, which also gives the plateaus to shade; the summary the page is written from.
fn finish(
    out_dir: &Path,
    logs: &[(PathBuf, Log)],
    opts: &ReportOptions,
    pieces: Pieces,
    correct: impl Fn(bool, &Path, &Log) -> Result<(Correction, Vec<(f64, f64)>)>,
) -> Result<ReportSummary> {
    let Pieces {
        hashes,
        in_sample,
        merit,
        mut taken,
        mut files,
        mut notes,
        figures,
    } = pieces;
    let mut reports = Vec::new();
    let mut any_allan = false;
    for (i, ((path, log), sha)) in logs.iter().zip(&hashes).enumerate() {
        let (correction, plateaus) = correct(in_sample[i], path, log)?;
        let section = LogSection {
            path,
            log,
            sha,
            in_sample: in_sample[i],
            correction,
            plateaus: &plateaus,
            allan: opts
                .allan
                .as_ref()
                .map(|given| given.get(i).cloned().flatten()),
        };
        let (report, drew_allan) = log_report(out_dir, section, &merit, &mut taken, &mut files)?;
        any_allan |= drew_allan;
        reports.push(report);
    }
    if !any_allan && !logs.is_empty() {
        notes.push(ALLAN_NOTE.into());
    }
    Ok(ReportSummary {
        html: out_dir.join("report.html"),
        files,
        figures,
        logs: reports,
        merit,
        notes,
    })
}

const ALLAN_NOTE: &str = "Allan deviation: not computed in this build (the report's Allan hook \
                          returned no curves).";
