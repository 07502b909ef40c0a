//! The lot's driver: the units found, each read, calibrated, judged and written on one of a
//! few worker threads, the outliers found over the whole, and the table written.
//!
//! Memory is bounded by the units in flight: each worker holds one unit's log at a time and
//! hands back its outcome (a few figures and sentences), so a lot of ten thousand units needs
//! the memory of `jobs` units.

use super::figures::axis_figures;
use super::shard::{Placed, Shard, ShardTable};
use super::units::UnitJob;
use super::{LotError, LotOutcome, Spec, Status, UnitOutcome, cache, table, verdict};
use crate::files::calibration;
use crate::log::campaign::RunInput;
use crate::log::ingest::ReadOptions;
use crate::log::read::{FormatChoice, read_any};
use crate::models::campaign::{CampaignOptions, JoinedRuns, UnitPlan, calibrate_runs};
use crate::models::{CheckedRecipe, ModelChoice, Preset, Recipe};
use std::path::{Path, PathBuf};

/// What a lot is run on.
#[derive(Debug, Clone)]
pub struct Lot {
    /// The folders of units (or unit files).
    pub inputs: Vec<PathBuf>,
    /// The spec every unit is held to.
    pub spec: Spec,
    /// The output folder.
    pub out: PathBuf,
    /// The recipe every unit without its own is calibrated with; the defaults when `None`.
    pub recipe: Option<PathBuf>,
    /// Units calibrated at once (at least 1).
    pub jobs: usize,
    /// The one shard of the lot to calibrate ([`super::shard`]); the whole lot when `None`.
    pub shard: Option<Shard>,
}

/// How far a lot has come, told after each unit.
#[derive(Debug, Clone, Copy)]
pub struct Progress<'a> {
    /// Units done.
    pub done: usize,
    /// Units in all.
    pub total: usize,
    /// The unit just done.
    pub unit: &'a UnitOutcome,
}

/// Runs the lot: every unit calibrated into `OUT/<unit>/calibration.json`, judged against
/// the spec, the outliers found, and `OUT/lot.csv` and `OUT/lot.json` written. `progress` is
/// called after each unit, from the calling thread. With a shard, its units alone, and its
/// table written as `OUT/lot-shard-I-of-N.json` for [`super::merge`] (no outliers: they are
/// the whole lot's).
///
/// # Errors
/// What stops the lot before any unit ([`LotError`]), and the table that cannot be written. A
/// unit that cannot be read, fitted or written is an [`Status::Error`] outcome instead.
pub fn run(lot: &Lot, progress: &mut dyn FnMut(Progress<'_>)) -> Result<LotOutcome, LotError> {
    refuse_out_among_inputs(&lot.out, &lot.inputs)?;
    let shared = match &lot.recipe {
        Some(p) => Some(load_recipe(p).map_err(|message| LotError::Recipe {
            path: p.clone(),
            message,
        })?),
        None => None,
    };
    let jobs = super::find_units(&lot.inputs)?;
    std::fs::create_dir_all(&lot.out).map_err(|e| LotError::Io {
        path: lot.out.clone(),
        source: e,
    })?;
    let context = Context {
        spec: &lot.spec,
        temps_c: lot.spec.reference_temps(),
        shared: lot.recipe.as_deref().zip(shared.as_ref()),
        out: &lot.out,
    };
    let Some(shard) = lot.shard else {
        let units = in_parallel(&jobs, lot.jobs, &context, progress);
        let outliers = LotOutcome::find_outliers(&lot.spec, &units);
        let outcome = LotOutcome {
            spec: lot.spec.clone(),
            units,
            outliers,
        };
        table::write(&lot.out, &outcome)?;
        return Ok(outcome);
    };
    let (positions, mine): (Vec<usize>, Vec<UnitJob>) = jobs
        .iter()
        .enumerate()
        .filter(|(_, j)| shard.holds(&j.name))
        .map(|(k, j)| (k, j.clone()))
        .unzip();
    let units = in_parallel(&mine, lot.jobs, &context, progress);
    super::shard::write(
        &lot.out,
        &ShardTable {
            shard,
            spec: lot.spec.clone(),
            lot_units: jobs.len(),
            lot_fingerprint: super::shard::fingerprint(jobs.iter().map(|j| j.name.as_str())),
            units: positions
                .into_iter()
                .zip(&units)
                .map(|(position, outcome)| Placed {
                    position,
                    outcome: outcome.clone(),
                })
                .collect(),
        },
    )?;
    Ok(LotOutcome {
        spec: lot.spec.clone(),
        units,
        outliers: Vec::new(),
    })
}

/// What every unit is calibrated and judged with.
struct Context<'a> {
    spec: &'a Spec,
    temps_c: Vec<f64>,
    shared: Option<(&'a Path, &'a CheckedRecipe)>,
    out: &'a Path,
}

/// Every job's outcome, in the jobs' order, from `workers` threads each taking the next job
/// when done with its last; `progress` told on this thread as each arrives.
fn in_parallel(
    jobs: &[UnitJob],
    workers: usize,
    context: &Context<'_>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Vec<UnitOutcome> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut slots: Vec<Option<UnitOutcome>> = vec![None; jobs.len()];
    let (send, receive) = std::sync::mpsc::channel::<(usize, UnitOutcome)>();
    std::thread::scope(|scope| {
        for _ in 0..workers.clamp(1, jobs.len().max(1)) {
            let send = send.clone();
            let next = &next;
            scope.spawn(move || {
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(job) = jobs.get(k) else { break };
                    if send.send((k, guarded(job, context))).is_err() {
                        break;
                    }
                }
            });
        }
        drop(send);
        for (done, (k, outcome)) in receive.into_iter().enumerate() {
            progress(Progress {
                done: done + 1,
                total: jobs.len(),
                unit: &outcome,
            });
            slots[k] = Some(outcome);
        }
    });
    jobs.iter()
        .zip(slots)
        .map(|(job, slot)| {
            slot.unwrap_or_else(|| {
                errored(
                    job,
                    None,
                    "internal: the unit's worker stopped (please report this)",
                )
            })
        })
        .collect()
}

/// [`calibrate_unit`], with a defect of driftlab that panics made that unit's error rather
/// than the end of the lot.
fn guarded(job: &UnitJob, context: &Context<'_>) -> UnitOutcome {
    let run = std::panic::AssertUnwindSafe(|| calibrate_unit(job, context));
    let mut outcome = std::panic::catch_unwind(run).unwrap_or_else(|_| {
        errored(
            job,
            None,
            "internal: the unit's calibration stopped on a defect of driftlab (please report \
             this)",
        )
    });
    if outcome.status == Status::Error {
        let left = cache::forget(&context.out.join(&job.folder));
        outcome.warnings.extend(left);
    }
    outcome
}

/// One unit read, calibrated, judged and its calibration written.
fn calibrate_unit(job: &UnitJob, context: &Context<'_>) -> UnitOutcome {
    let recipe_file = job
        .recipe
        .as_deref()
        .or(context.shared.map(|(p, _)| p))
        .map(|p| p.display().to_string());
    let fail = |message: String| errored(job, recipe_file.clone(), &message);
    if let Some(problem) = &job.problem {
        return fail(problem.clone());
    }
    let recipe = match (&job.recipe, context.shared) {
        (Some(own), _) => match load_recipe(own) {
            Ok(r) => r,
            Err(e) => return fail(format!("{}: {e}", own.display())),
        },
        (None, Some((_, shared))) => shared.clone(),
        (None, None) => match Recipe::default().checked() {
            Ok(r) => r,
            Err(e) => return fail(e.to_string()),
        },
    };
    let folder = context.out.join(&job.folder);
    let key = match cache::key(&job.runs, recipe.recipe(), context.spec) {
        Ok(k) => k,
        Err(e) => return fail(e),
    };
    if let Some(outcome) = cache::recorded(&folder, &key) {
        return outcome;
    }
    let mut warnings = job.notes.clone();
    let mut runs = Vec::with_capacity(job.runs.len());
    for (path, run) in job.runs.iter().zip(&key.runs) {
        match read_run(path, run.sha256.clone(), &mut warnings) {
            Ok(run) => runs.push(run),
            Err(e) => return fail(e),
        }
    }
    let mut joined = match JoinedRuns::join(runs, &job.runs) {
        Ok(j) => j,
        Err(e) => return fail(e.to_string()),
    };
    let plan = UnitPlan::every_axis(
        &joined.log,
        ModelChoice::Preset(Preset::Vakhrameev),
        recipe,
        CampaignOptions::default(),
    );
    let fitted = match calibrate_runs(&mut joined, &plan) {
        Ok(f) => f,
        Err(e) => return fail(about(&joined.log.source, &e)),
    };
    warnings.extend(fitted.warnings.iter().cloned());
    warnings.extend(fitted.settings_told.iter().map(|i| i.to_string()));
    let mut axes = Vec::with_capacity(fitted.fit.axes.len());
    for axis in &fitted.fit.axes {
        let on = if axis.name.is_empty() {
            String::new()
        } else {
            format!("axis {}: ", axis.name)
        };
        warnings.extend(axis.calibrated.warnings.iter().map(|w| format!("{on}{w}")));
        axes.push(axis_figures(&mut joined.log, axis, &context.temps_c));
    }
    drop(joined);
    let file = Path::new(&job.folder).join(cache::CALIBRATION);
    let written = std::fs::create_dir_all(&folder)
        .map_err(|e| crate::Error::io(&folder, e))
        .and_then(|()| calibration::save_unit(&context.out.join(&file), &fitted.unit));
    if let Err(e) = written {
        return fail(format!("its calibration could not be written: {e}"));
    }
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
        recipe: recipe_file,
        calibration: Some(file.display().to_string()),
        axes,
        warnings,
        cached: false,
    };
    // Without its record the unit is calibrated again next time: said, not an error.
    match cache::record(&folder, &key, &outcome) {
        Ok(()) => outcome,
        Err(e) => {
            let mut outcome = outcome;
            outcome.warnings.push(format!(
                "its record was not written, so the next lot calibrates it again: {e}"
            ));
            outcome
        }
    }
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
fn load_recipe(path: &Path) -> Result<CheckedRecipe, String> {
    calibration::read_recipe(path)
        .map_err(|e| e.to_string())?
        .checked()
        .map_err(|e| e.to_string())
}

/// A unit that could not be calibrated, with `message`.
fn errored(job: &UnitJob, recipe: Option<String>, message: &str) -> UnitOutcome {
    UnitOutcome {
        unit: job.name.clone(),
        folder: job.folder.clone(),
        status: Status::Error,
        reasons: vec![message.to_string()],
        runs: run_files(job),
        recipe,
        calibration: None,
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

/// Refuses an output folder inside a folder of units, or one that holds a folder of units or
/// a unit's file given alone.
fn refuse_out_among_inputs(out: &Path, inputs: &[PathBuf]) -> Result<(), LotError> {
    let resolved = |p: &Path| -> Option<PathBuf> {
        // The output folder may not exist yet: resolve the nearest folder that does.
        let mut tail = Vec::new();
        let mut at = p.to_path_buf();
        loop {
            if let Ok(r) = std::fs::canonicalize(&at) {
                return Some(tail.iter().rev().fold(r, |acc: PathBuf, t| acc.join(t)));
            }
            tail.push(at.file_name()?.to_os_string());
            at = match at.parent() {
                Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
                _ => PathBuf::from("."),
            };
        }
    };
    let Some(out_r) = resolved(out) else {
        return Ok(());
    };
    for input in inputs {
        let Ok(input_r) = std::fs::canonicalize(input) else {
            continue;
        };
        let overlaps = if input_r.is_dir() {
            out_r.starts_with(&input_r) || input_r.starts_with(&out_r)
        } else {
            input_r.starts_with(&out_r)
        };
        if overlaps {
            return Err(LotError::OutAmongInputs {
                out: out.to_path_buf(),
                input: input.clone(),
            });
        }
    }
    Ok(())
}
