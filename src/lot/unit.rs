//! One unit of a lot: its recipe, its runs read as `calibrate` reads them, its calibration
//! through the one path (`calibrate_runs`) and the one writer, its figures and verdict, its
//! report on request, and its record for the next lot. Apart from the driver (`run.rs`),
//! which only hands units to workers and gathers their outcomes.

use super::figures::axis_figures;
use super::run::Context;
use super::units::UnitJob;
use super::{LotError, Status, UnitOutcome, cache, verdict};
use crate::files::calibration;
use crate::log::campaign::RunInput;
use crate::log::ingest::ReadOptions;
use crate::log::read::{FormatChoice, read_any};
use crate::models::campaign::{CampaignOptions, JoinedRuns, UnitPlan, calibrate_runs};
use crate::models::{CheckedRecipe, Keep, ModelChoice, Preset, Recipe};
use std::path::{Path, PathBuf};

/// One unit read, calibrated, judged and its calibration written; an error of the unit's (its
/// runs, its recipe, its fit) is its outcome, with the status error.
///
/// # Errors
/// [`LotError::Unwritten`]: its calibration could not be written, which is the output's fault,
/// not the unit's, and stops the lot.
pub(super) fn calibrate_unit(
    job: &UnitJob,
    context: &Context<'_>,
) -> Result<UnitOutcome, LotError> {
    let recipe_file = job
        .recipe
        .as_deref()
        .or(context.shared.map(|(p, _)| p))
        .map(|p| p.display().to_string());
    let fail = |message: String| errored(job, recipe_file.clone(), &message);
    if let Some(problem) = &job.problem {
        return Ok(fail(problem.clone()));
    }
    let recipe = match (&job.recipe, context.shared) {
        (Some(own), _) => match load_recipe(own) {
            Ok(r) => r,
            // A file's error names it already; a value's does not.
            Err(e) if e.starts_with(&format!("{}: ", own.display())) => return Ok(fail(e)),
            Err(e) => return Ok(fail(format!("{}: {e}", own.display()))),
        },
        (None, Some((_, shared))) => shared.clone(),
        (None, None) => match Recipe::default().checked() {
            Ok(r) => r,
            Err(e) => return Ok(fail(e.to_string())),
        },
    };
    let folder = context.out.join(&job.folder);
    let key = match cache::key(&job.runs, recipe.recipe(), context.spec, context.report) {
        Ok(k) => k,
        Err(e) => return Ok(fail(e)),
    };
    // A record that holds what the lot does not compute is no record: the unit is calibrated
    // again, saying why.
    let mut refused_record = None;
    if let Some(recorded) = cache::recorded(&folder, &key) {
        let read_back = UnitOutcome {
            unit: job.name.clone(),
            runs: run_files(job),
            runs_at: runs_at(job),
            recipe: recipe_file.clone(),
            ..recorded
        }
        .settled(context.spec, context.out, &folder.join(cache::RECORD));
        match read_back {
            // A report asked for and gone is made again with its calibration.
            Ok(outcome)
                if outcome.status != Status::Error
                    && (outcome.report.is_some() || !context.report) =>
            {
                return Ok(outcome);
            }
            Ok(_) => {}
            Err(e) => refused_record = Some(format!("{e}; calibrated again")),
        }
    }
    let mut warnings = job.notes.clone();
    warnings.extend(refused_record);
    let mut runs = Vec::with_capacity(job.runs.len());
    for (path, run) in job.runs.iter().zip(&key.runs) {
        match read_run(path, run.sha256.clone(), &mut warnings) {
            Ok(run) => runs.push(run),
            Err(e) => return Ok(fail(e)),
        }
    }
    let mut joined = match JoinedRuns::join(runs, &job.runs) {
        Ok(j) => j,
        Err(e) => return Ok(fail(e.to_string())),
    };
    // Each axis's corrected rate kept from its fit: its Allan figures are read from it,
    // rather than from the log corrected a second time.
    let plan = UnitPlan {
        keep: Keep::Corrected,
        ..UnitPlan::every_axis(
            &joined.log,
            ModelChoice::Preset(Preset::Vakhrameev),
            recipe,
            CampaignOptions::default(),
        )
    };
    let mut fitted = match calibrate_runs(&mut joined, &plan) {
        Ok(f) => f,
        Err(e) => return Ok(fail(about(&joined.log.source, &e))),
    };
    warnings.extend(fitted.warnings.iter().cloned());
    warnings.extend(fitted.settings_told.iter().map(|i| i.to_string()));
    let mut axes = Vec::with_capacity(fitted.fit.axes.len());
    for axis in &mut fitted.fit.axes {
        let on = if axis.name.is_empty() {
            String::new()
        } else {
            format!("axis {}: ", axis.name)
        };
        warnings.extend(axis.calibrated.warnings.iter().map(|w| format!("{on}{w}")));
        axes.push(axis_figures(&mut joined.log, axis, &context.temps_c));
        // Read: its memory goes back before the next axis is judged.
        axis.corrected = None;
    }
    let file = Path::new(&job.folder).join(cache::CALIBRATION);
    let path = context.out.join(&file);
    // A calibration this build would not read back is the unit's error; one that cannot be
    // put on the disk is the output's, and stops the lot.
    let text = match calibration::checked_text(&path, &fitted.unit) {
        Ok(text) => text,
        Err(e) => return Ok(fail(format!("its calibration could not be written: {e}"))),
    };
    let written = std::fs::create_dir_all(&folder)
        .and_then(|()| crate::files::atomic::write_bytes(&path, text.as_bytes()))
        .map_err(|e| crate::Error::io(&path, e));
    if let Err(source) = written {
        return Err(LotError::Unwritten {
            unit: job.name.clone(),
            source,
        });
    }
    let report = if context.report {
        match write_report(job, &key, &joined.log, &fitted.unit, &folder) {
            Ok(()) => Some(
                Path::new(&job.folder)
                    .join(REPORT_PAGE)
                    .display()
                    .to_string(),
            ),
            // The calibration stands without its report: said, not an error.
            Err(e) => {
                warnings.push(format!("its report could not be written: {e}"));
                None
            }
        }
    } else {
        None
    };
    drop(joined);
    let reasons = verdict::reasons(context.spec, &axes);
    let outcome = UnitOutcome {
        unit: job.name.clone(),
        folder: job.folder.clone(),
        status: if reasons.is_empty() {
            Status::Pass
        } else {
            Status::Fail
        },
        reasons,
        runs: run_files(job),
        runs_at: runs_at(job),
        recipe: recipe_file,
        calibration: Some(file.display().to_string()),
        report,
        axes,
        warnings,
        cached: false,
    };
    // Without its record the unit is calibrated again next time: said, not an error.
    Ok(match cache::record(&folder, &key, &outcome) {
        Ok(()) => outcome,
        Err(e) => {
            let mut outcome = outcome;
            outcome.warnings.push(format!(
                "its record was not written, so the next lot calibrates it again: {e}"
            ));
            outcome
        }
    })
}

/// A unit's report page in its folder.
pub(super) const REPORT_PAGE: &str = "report/report.html";

/// The test report of `unit` judged on each of its runs (in-sample), written into
/// `folder/report` as `driftlab report` writes it, with its default figures.
fn write_report(
    job: &UnitJob,
    key: &cache::UnitKey,
    log: &crate::log::Log,
    unit: &crate::models::UnitCalibration,
    folder: &Path,
) -> crate::Result<()> {
    let mut logs: Vec<(PathBuf, crate::log::Log)> = job
        .runs
        .iter()
        .enumerate()
        .filter_map(|(k, path)| Some((path.clone(), log.run_log(k)?)))
        .collect();
    let merit = crate::export::report::UnitMerit {
        filter_s: None,
        window_s: crate::MeritOptions::default().window_s,
    };
    let hashes = key.runs.iter().map(|r| r.sha256.clone()).collect();
    let tolerance_c = unit
        .campaign_tolerance_c()
        .unwrap_or(crate::models::campaign::DEFAULT_TOLERANCE_C);
    crate::export::report::write_unit(
        unit,
        &mut logs,
        &folder.join("report"),
        merit,
        Some(hashes),
        tolerance_c,
    )
    .map(|_| ())
}

/// One run read as `calibrate` reads a log given no option: the calibration columns alone, a
/// drone or robot log's first gyro with a temperature, a log written in bursts reduced to one
/// sample per burst; what the reader noticed added to `warnings`; `sha256` the file's.
fn read_run(path: &Path, sha256: String, warnings: &mut Vec<String>) -> Result<RunInput, String> {
    let opts = ReadOptions {
        skip_extras: true,
        ..ReadOptions::default()
    };
    let any = read_any(path, &opts, &FormatChoice::default()).map_err(|e| e.to_string())?;
    let source = any.log.source.clone();
    if let Some(drone) = &any.drone {
        warnings.extend(drone.problems.iter().map(|p| format!("{source}: {p}")));
        warnings.push(format!("{source}: {}", drone.note));
    }
    warnings.extend(
        any.log
            .info
            .problems
            .iter()
            .map(|p| format!("{source}: {}{}", p.message, p.times())),
    );
    let (log, note) =
        crate::log::resample::prepare(any.log, None).map_err(|e| format!("{source}: {e}"))?;
    warnings.extend(note.map(|n| format!("{source}: {n}")));
    Ok(RunInput { log, sha256 })
}

/// An error about the log `source`, naming it once (a fit's messages already start with it).
fn about(source: &str, e: &crate::Error) -> String {
    let m = e.to_string();
    if m.starts_with(&format!("{source}: ")) {
        m
    } else {
        format!("{source}: {m}")
    }
}

/// A recipe file (or the recipe inside a calibration file), checked.
pub(super) fn load_recipe(path: &Path) -> Result<CheckedRecipe, String> {
    calibration::read_recipe(path)
        .map_err(|e| e.to_string())?
        .checked()
        .map_err(|e| e.to_string())
}

/// A unit that could not be calibrated, with `message`.
pub(super) fn errored(job: &UnitJob, recipe: Option<String>, message: &str) -> UnitOutcome {
    UnitOutcome {
        unit: job.name.clone(),
        folder: job.folder.clone(),
        status: Status::Error,
        reasons: vec![message.to_string()],
        runs: run_files(job),
        runs_at: runs_at(job),
        recipe,
        calibration: None,
        report: None,
        axes: Vec::new(),
        warnings: job.notes.clone(),
        cached: false,
    }
}

fn run_files(job: &UnitJob) -> Vec<String> {
    job.runs
        .iter()
        .map(|p| crate::text::escaped(&p.display().to_string(), false).into_owned())
        .collect()
}

/// The unit's runs as absolute paths (as the system names them, not resolved through links),
/// escaped as [`run_files`] escapes them.
fn runs_at(job: &UnitJob) -> Vec<String> {
    job.runs
        .iter()
        .map(|p| {
            let at = std::path::absolute(p).unwrap_or_else(|_| p.clone());
            crate::text::escaped(&at.display().to_string(), false).into_owned()
        })
        .collect()
}
