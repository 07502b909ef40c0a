//! The section of one log in a report: its temperature program, its drift before and after
//! correction and its Allan deviation drawn, its figures of merit computed. Apart from the
//! writers because every model's report judges its logs the same way.

use super::figures::{self, AllanLine, TimeSeries};
use super::{AllanCurves, LogReport, allan_curves, figure};
use crate::error::Result;
use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::Log;
use crate::models::vakhrameev::correct::Correction;
use crate::signal;
use std::path::{Path, PathBuf};

/// One log to judge, with its correction.
pub(super) struct LogSection<'a> {
    pub(super) path: &'a Path,
    /// The log's name as the page shows it: its file name, with as many of its folders as
    /// tell it apart from another log of the same file name ([`super::names_apart`]).
    pub(super) name: &'a str,
    /// What the axis measures: the unit of its drift and Allan figures.
    pub(super) kind: crate::log::AxisKind,
    pub(super) log: &'a Log,
    pub(super) sha: &'a str,
    pub(super) in_sample: bool,
    /// What the model's sketch found of it (`None`: no sketch kept).
    pub(super) share: Option<crate::log::run_sketch::Shared>,
    pub(super) correction: Correction,
    /// The model's terms left out for want of points, named beside the share of samples
    /// outside its ranges.
    pub(super) left_out: crate::models::vakhrameev::LeftOut,
    /// Plateaus to shade in its temperature program, (start, end) s.
    pub(super) plateaus: &'a [(f64, f64)],
    /// Allan curves given by the caller (`None`: computed here).
    pub(super) allan: Option<Option<AllanCurves>>,
}

/// The figures and figures of merit of one log (any model's correction); the files drawn go
/// to `files`. Also says whether an Allan figure was drawn.
pub(super) fn log_report(
    out_dir: &Path,
    section: LogSection<'_>,
    merit: &MeritOptions,
    taken: &mut Vec<String>,
    files: &mut Vec<PathBuf>,
) -> Result<(LogReport, bool)> {
    let LogSection {
        path,
        name,
        kind,
        log,
        sha,
        in_sample,
        share,
        correction,
        left_out,
        plateaus,
        allan,
    } = section;
    let mut drew_allan = false;
    // As the page shows it: a character that would reorder or forge the text around the
    // name written as its escape.
    let name = crate::text::escaped(name, false).into_owned();
    let stem = unique_stem(path, taken);
    let label = crate::judge::verify::sample_kind(in_sample, share);
    let cannot_tell = share.filter(|_| !in_sample).and_then(|s| s.cannot_tell());
    let evaluation = Evaluation {
        left_out,
        ..Evaluation::of_correction(log, &correction, merit)
    };
    let mut log_figures = Vec::new();

    // Temperature program.
    let mut temps = vec![TimeSeries {
        label: "calibration temperature T",
        values: &log.temp_c,
        width: 3,
        faint: false,
    }];
    for ch in &log.extra {
        let u = ch.unit.to_lowercase();
        if ch.name.to_lowercase().contains("temp") || u.contains("°c") || u == "degc" {
            temps.push(TimeSeries {
                label: &ch.name,
                values: &ch.values,
                width: 2,
                faint: false,
            });
        }
    }
    let f = figures::temperature_program(
        &out_dir.join(format!("temperature-{stem}")),
        &format!("Temperature program: {name} ({label})"),
        &log.time_s,
        &temps,
        plateaus,
    )?;
    files.extend(f.iter().cloned());
    log_figures.push(figure(
        format!("Temperature program, {name}"),
        if plateaus.is_empty() {
            "The calibration temperature and every other temperature column of the log.".into()
        } else {
            "The calibration temperature and every other temperature column of the log; \
             shaded: the plateaus K0 was taken from."
                .into()
        },
        f,
    ));
    drop(temps);

    // Drift.
    let dt = log.nominal_dt_s();
    let window = signal::seconds_to_samples(merit.filter_s, dt);
    // Averaged within each segment: no average reaches across a gap (docs/method.md §5).
    let segments = log.timing().segments;
    let raw_f = signal::moving_average_centered_in(&log.omega_dph, window, &segments);
    let cor_f = signal::moving_average_centered_in(&correction.cor_dph, window, &segments);
    let filter_label = format!("raw, {:.0}-s moving average", merit.filter_s);
    let cor_label = format!("corrected, {:.0}-s moving average", merit.filter_s);
    let (raw_label, y_desc, quantity) = match kind {
        crate::log::AxisKind::Gyro => ("raw rate (every sample)", "gyro rate Ω, °/h", "rate"),
        crate::log::AxisKind::Accel => (
            "raw reading (every sample)",
            "accelerometer reading about its kept mean, m/s²",
            "reading",
        ),
    };
    let series = [
        TimeSeries {
            label: raw_label,
            values: &log.omega_dph,
            width: 1,
            faint: true,
        },
        TimeSeries {
            label: &filter_label,
            values: &raw_f,
            width: 2,
            faint: false,
        },
        TimeSeries {
            label: "predicted thermal drift",
            values: &correction.pred_dph,
            width: 2,
            faint: false,
        },
        TimeSeries {
            label: &cor_label,
            values: &cor_f,
            width: 2,
            faint: false,
        },
    ];
    let f = figures::drift(
        &out_dir.join(format!("drift-{stem}")),
        &format!("Drift before and after correction: {name} ({label})"),
        y_desc,
        &log.time_s,
        &series,
    )?;
    files.extend(f.iter().cloned());
    let c = &evaluation.comparison;
    log_figures.push(figure(
        format!("Drift, {name}"),
        format!(
            "Raw {quantity} (grey, every sample as min/max per pixel column), its {:.0}-s \
             moving average, the drift the calibration predicts, and the corrected {quantity} \
             filtered the same way. Peak-to-peak of the filtered drift {} → {} {}.",
            merit.filter_s,
            super::html::fmt_in(c.raw.p2p_dph, kind.unit()),
            super::html::fmt_in(c.corrected.p2p_dph, kind.unit()),
            kind.unit()
        ),
        f,
    ));
    drop((raw_f, cor_f));

    // Allan deviation.
    let curves = match allan {
        Some(given) => given,
        None => allan_curves(log, &correction),
    };
    if let Some(curves) = curves.filter(|c| !c.is_empty()) {
        drew_allan = true;
        let lines: Vec<AllanLine> = curves
            .iter()
            .map(|c| AllanLine {
                label: &c.label,
                tau_s: &c.tau_s,
                adev_dph: &c.adev_dph,
            })
            .collect();
        let f = figures::allan(
            &out_dir.join(format!("allan-{stem}")),
            &format!("Allan deviation before and after correction: {name} ({label})"),
            &lines,
            kind.unit(),
        )?;
        files.extend(f.iter().cloned());
        log_figures.push(figure(
            format!("Allan deviation, {name}"),
            format!("Allan deviation of the {quantity} before and after correction, log-log."),
            f,
        ));
    }

    let (t_lo, t_hi) = min_max(&log.temp_c);
    Ok((
        LogReport {
            name,
            path: path.to_path_buf(),
            sha256: sha.to_string(),
            in_sample,
            kind: label,
            cannot_tell,
            evaluation,
            samples: log.len(),
            duration_s: log.duration_s(),
            temp_range_c: (t_lo, t_hi),
            figures: log_figures,
            unit: kind.unit(),
            index: 0,
        },
        drew_allan,
    ))
}

/// A file-name-safe stem for a log, unique among `taken`.
fn unique_stem(path: &Path, taken: &mut Vec<String>) -> String {
    let raw = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    safe_unique_name(&raw, 60, "log", taken)
}

/// `raw` as a file name (ASCII letters, digits, `-` and `_`, others as `_`, at most `max`
/// characters; `fallback` when nothing is left), made unique among `taken` with `-2`, `-3`…
/// and added to them.
pub(super) fn safe_unique_name(
    raw: &str,
    max: usize,
    fallback: &str,
    taken: &mut Vec<String>,
) -> String {
    let mut stem: String = raw
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .take(max)
        .collect();
    if stem.is_empty() {
        stem = fallback.into();
    }
    let mut candidate = stem.clone();
    let mut k = 2;
    while taken.contains(&candidate) {
        candidate = format!("{stem}-{k}");
        k += 1;
    }
    taken.push(candidate.clone());
    candidate
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}
