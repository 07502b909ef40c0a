//! Writing what the workbench made: PNG pictures (the window, or one plot cropped out of a
//! window screenshot), the calibration file, the corrected log and the session. Every file is
//! written atomically; every failure comes back as a message naming the file.

use crate::gui::jobs::Loaded;
use crate::log::Log;
use crate::models::vakhrameev::{Calibration, SourceInfo};
use crate::signal::plateau::PlateauRange;
use eframe::egui::{ColorImage, Rect};
use std::path::{Path, PathBuf};

/// Writes `image` as PNG, cropped to `crop` (points) when given; `pixels_per_point` converts
/// the crop to pixels.
pub fn save_png(
    path: &Path,
    image: &ColorImage,
    crop: Option<Rect>,
    pixels_per_point: f32,
) -> Result<PathBuf, String> {
    let [w, h] = image.size;
    let (x0, y0, x1, y1) = match crop {
        Some(r) => {
            let ppp = pixels_per_point.max(0.1);
            let x0 = ((r.min.x * ppp).floor().max(0.0) as usize).min(w);
            let y0 = ((r.min.y * ppp).floor().max(0.0) as usize).min(h);
            let x1 = ((r.max.x * ppp).ceil().max(0.0) as usize).clamp(x0, w);
            let y1 = ((r.max.y * ppp).ceil().max(0.0) as usize).clamp(y0, h);
            (x0, y0, x1, y1)
        }
        None => (0, 0, w, h),
    };
    if x1 <= x0 || y1 <= y0 {
        return Err(format!(
            "{}: nothing to save (empty picture)",
            path.display()
        ));
    }
    // Opaque RGB, best compression: pictures for reports stay small.
    let mut rgb = Vec::with_capacity((x1 - x0) * (y1 - y0) * 3);
    for y in y0..y1 {
        for p in &image.pixels[y * w + x0..y * w + x1] {
            let [r, g, b, _] = p.to_array();
            rgb.extend_from_slice(&[r, g, b]);
        }
    }
    let mut bytes = Vec::new();
    {
        use image::ImageEncoder as _;
        use image::codecs::png::{CompressionType, FilterType, PngEncoder};
        PngEncoder::new_with_quality(&mut bytes, CompressionType::Best, FilterType::Adaptive)
            .write_image(
                &rgb,
                (x1 - x0) as u32,
                (y1 - y0) as u32,
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    crate::files::atomic::write_bytes(path, &bytes)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path.to_path_buf())
}

/// Writes the calibration file, naming its source log and the log's SHA-256 (a campaign's
/// runs, each with its own, and their plateaus: [`stamp_source`]).
pub fn save_calibration(path: &Path, cal: &Calibration, log: &Loaded) -> Result<PathBuf, String> {
    let cal = stamped(cal, log)?;
    crate::files::calibration::save(path, &cal).map_err(|e| e.to_string())?;
    Ok(path.to_path_buf())
}

/// The calibration with its source filled in as files record it ([`stamp_source`]).
pub fn stamped(cal: &Calibration, log: &Loaded) -> Result<Calibration, String> {
    let mut cal = cal.clone();
    let ranges: Vec<_> = cal.plateaus.iter().map(|p| p.range).collect();
    stamp_source(&mut cal.source, log, &ranges)?;
    Ok(cal)
}

/// Fills in a fitted model's source as the command line's `calibrate` does: the log's file
/// name and SHA-256; for a campaign, the runs' names joined, no hash of its own, and each
/// run's record (its name, SHA-256, span and its plateaus among `ranges`, with the axis's bias
/// on each) at the default tolerance, through the engine's one stamp
/// ([`crate::models::campaign::stamp_runs`]).
///
/// # Errors
/// The log's file cannot be hashed; a run of the campaign has no plateau (the command line
/// refuses the same campaign).
pub fn stamp_source(
    source: &mut SourceInfo,
    log: &Loaded,
    ranges: &[PlateauRange],
) -> Result<(), String> {
    use crate::models::campaign;
    if log.log.runs().len() > 1 {
        let options = campaign::CampaignOptions::default();
        let runs =
            campaign::run_records(&log.log, "", ranges, &options).map_err(|e| e.to_string())?;
        source.name = log.log.source.clone();
        source.sha256 = String::new();
        campaign::stamp_runs(source, runs, options.tolerance_c);
        return Ok(());
    }
    source.name = log
        .path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| log.path.display().to_string());
    source.sha256 = match &log.sha256 {
        Some(s) => s.clone(),
        None => crate::files::calibration::sha256_file(&log.path).map_err(|e| e.to_string())?,
    };
    Ok(())
}

/// Writes the test report of `cal` on `logs` into the folder `dir` (the engine's report, as
/// `driftlab report` writes it); returns the HTML page.
pub fn write_report(
    dir: &Path,
    cal: &Calibration,
    logs: &[(PathBuf, Log)],
) -> Result<PathBuf, String> {
    let summary = crate::export::report::write(
        cal,
        logs,
        dir,
        &crate::export::report::ReportOptions::default(),
    )
    .map_err(|e| e.to_string())?;
    Ok(summary.html)
}

/// Writes the test report of every axis of `unit` on `logs` (each holding every axis) into
/// the folder `dir`, as `driftlab report` writes a unit's; returns the HTML page.
pub fn write_unit_report(
    dir: &Path,
    unit: &crate::models::UnitCalibration,
    mut logs: Vec<(PathBuf, Log)>,
) -> Result<PathBuf, String> {
    let merit = crate::export::report::UnitMerit {
        filter_s: None,
        window_s: crate::judge::metrics::MeritOptions::default().window_s,
    };
    crate::export::report::write_unit(
        unit,
        &mut logs,
        dir,
        merit,
        None,
        crate::models::campaign::DEFAULT_TOLERANCE_C,
    )
    .map(|s| s.html)
    .map_err(|e| e.to_string())
}

/// Writes any fitted model's calibration file (the engine's format, atomically), its source
/// stamped as [`stamp_source`] does with the plateaus `ranges` the workbench's fit used.
pub fn save_model(
    path: &Path,
    model: &crate::models::fitted::DriftModel,
    log: &Loaded,
    ranges: &[PlateauRange],
) -> Result<PathBuf, String> {
    let mut model = model.clone();
    stamp_source(model.source_mut(), log, ranges)?;
    crate::files::calibration::save_model(path, &model).map_err(|e| e.to_string())?;
    Ok(path.to_path_buf())
}

/// Writes a unit's calibration file (version 2, every axis; the engine's
/// [`crate::files::calibration::save_unit`]).
pub fn save_unit(path: &Path, unit: &crate::models::UnitCalibration) -> Result<PathBuf, String> {
    crate::files::calibration::save_unit(path, unit).map_err(|e| e.to_string())?;
    Ok(path.to_path_buf())
}

/// Writes the corrected log as `driftlab apply` does, with the engine's one writer: the one
/// axis of a single-axis calibration as `omega_*` columns, or every axis of a unit side by
/// side in the calibration's order, each predicted batch by batch from `log`.
pub fn write_corrected_csv(
    path: &Path,
    log: &Log,
    unit: &crate::models::UnitCalibration,
) -> Result<PathBuf, String> {
    crate::files::corrected_csv::correct_and_write(path, log, unit, &|_| {})
        .map_err(|e| e.to_string())?;
    Ok(path.to_path_buf())
}

/// A file name next to the log: `run7.csv` → `run7-<suffix>`; never a word twice
/// (`calibration.csv` → `calibration.json`, not `calibration-calibration.json`), and never
/// the log's own name.
pub fn suggested_name(log_path: Option<&Path>, suffix: &str) -> String {
    let stem = log_path
        .and_then(|p| p.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "driftlab".into());
    let (word, ext) = match suffix.split_once('.') {
        Some((w, e)) => (w, Some(e)),
        None => (suffix, None),
    };
    let with_ext = |base: &str| match ext {
        Some(e) => format!("{base}.{e}"),
        None => base.to_string(),
    };
    let repeats = stem == word || stem.ends_with(&format!("-{word}"));
    let own = log_path
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned());
    match repeats {
        true if own.as_deref() != Some(with_ext(&stem).as_str()) => with_ext(&stem),
        true => with_ext(&format!("{stem}-new")),
        false => format!("{stem}-{suffix}"),
    }
}
