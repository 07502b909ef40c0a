//! The lot's driver: the units found, each read, calibrated, judged and written on one of a
//! few worker threads, the outliers found over the whole, and the table written.
//!
//! Memory is bounded by the units in flight: each worker holds one unit's log at a time and
//! hands back its outcome (a few figures and sentences), so a lot of ten thousand units needs
//! the memory of `jobs` units.

use super::shard::{Placed, Shard, ShardTable};
use super::unit::{calibrate_unit, errored, load_recipe};
use super::units::UnitJob;
use super::{LotError, LotOutcome, Spec, Status, UnitOutcome, cache, table};
use crate::models::CheckedRecipe;
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
    /// Write each calibrated unit's test report, `OUT/<unit>/report/report.html`, judged on
    /// its own runs.
    pub report: bool,
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
    refuse_units_holding_out(&lot.out, &jobs)?;
    // Made and held from here to the table's write.
    let _lock = super::lock::lock(&lot.out, lot.shard)?;
    let context = Context {
        spec: &lot.spec,
        temps_c: lot.spec.reference_temps(),
        shared: lot.recipe.as_deref().zip(shared.as_ref()),
        out: &lot.out,
        report: lot.report,
    };
    let Some(shard) = lot.shard else {
        let units = in_parallel(&jobs, lot.jobs, &context, progress)?;
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
    let units = in_parallel(&mine, lot.jobs, &context, progress)?;
    super::shard::write(
        &lot.out,
        &ShardTable {
            shard,
            spec: lot.spec.clone(),
            lot_units: jobs.len(),
            lot_fingerprint: super::shard::fingerprint(jobs.iter().map(|j| j.name.as_str())),
            recipe_sha256: shared
                .as_ref()
                .map(|r| super::cache::recipe_sha256(r.recipe())),
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
pub(super) struct Context<'a> {
    /// The spec.
    pub spec: &'a Spec,
    /// The reference temperatures of K0.
    pub temps_c: Vec<f64>,
    /// The shared recipe and its file, if one was given.
    pub shared: Option<(&'a Path, &'a CheckedRecipe)>,
    /// The output folder.
    pub out: &'a Path,
    /// Whether each unit's report is written.
    pub report: bool,
}

/// Every job's outcome, in the jobs' order, from `workers` threads each taking the next job
/// when done with its last; `progress` told on this thread as each arrives.
///
/// # Errors
/// The first unit whose calibration could not be written ([`LotError::Unwritten`]): no
/// worker takes a new job after it, and the ones under way finish.
fn in_parallel(
    jobs: &[UnitJob],
    workers: usize,
    context: &Context<'_>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<UnitOutcome>, LotError> {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let mut slots: Vec<Option<UnitOutcome>> = vec![None; jobs.len()];
    let mut unwritten = None;
    let (send, receive) = std::sync::mpsc::channel::<(usize, Result<UnitOutcome, LotError>)>();
    std::thread::scope(|scope| {
        for _ in 0..workers.clamp(1, jobs.len().max(1)) {
            let send = send.clone();
            let (next, stop) = (&next, &stop);
            scope.spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(job) = jobs.get(k) else { break };
                    if send.send((k, guarded(job, context))).is_err() {
                        break;
                    }
                }
            });
        }
        drop(send);
        let mut done = 0;
        for (k, outcome) in receive {
            match outcome {
                Ok(outcome) => {
                    done += 1;
                    progress(Progress {
                        done,
                        total: jobs.len(),
                        unit: &outcome,
                    });
                    slots[k] = Some(outcome);
                }
                Err(e) => {
                    stop.store(true, Ordering::Relaxed);
                    unwritten.get_or_insert(e);
                }
            }
        }
    });
    if let Some(e) = unwritten {
        return Err(e);
    }
    Ok(jobs
        .iter()
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
        .collect())
}

/// [`calibrate_unit`], with a defect of driftlab that panics made that unit's error rather
/// than the end of the lot.
///
/// # Errors
/// [`LotError::Unwritten`], which stops the lot.
fn guarded(job: &UnitJob, context: &Context<'_>) -> Result<UnitOutcome, LotError> {
    let run = std::panic::AssertUnwindSafe(|| calibrate_unit(job, context));
    let mut outcome = std::panic::catch_unwind(run).unwrap_or_else(|_| {
        Ok(errored(
            job,
            None,
            "internal: the unit's calibration stopped on a defect of driftlab (please report \
             this)",
        ))
    })?;
    if outcome.status == Status::Error {
        let left = cache::forget(&context.out.join(&job.folder));
        outcome.warnings.extend(left);
    }
    Ok(outcome)
}

/// Refuses an output folder inside a folder of units, or one that holds a folder of units or
/// a unit's file given alone.
fn refuse_out_among_inputs(out: &Path, inputs: &[PathBuf]) -> Result<(), LotError> {
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

/// `p` resolved: links followed, `.` and `..` taken; a path that does not exist yet (an
/// output folder) resolved up to the nearest folder that does, its `..` taken first
/// (`nothere/../units/out` is `units/out`).
fn resolved(p: &Path) -> Option<PathBuf> {
    if let Ok(r) = std::fs::canonicalize(p) {
        return Some(r);
    }
    let mut tail = Vec::new();
    let mut at = lexically_normal(&std::path::absolute(p).ok()?);
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
}

/// `path` with its `.` and `..` parts taken as written (`a/b/../c` is `a/c`).
fn lexically_normal(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Refuses a unit that is the output folder or holds it (a link among the units to `OUT`, or
/// to a folder above it): the next lot would read the outputs as units.
fn refuse_units_holding_out(out: &Path, jobs: &[UnitJob]) -> Result<(), LotError> {
    let Some(out_r) = resolved(out) else {
        return Ok(());
    };
    for job in jobs {
        if let Ok(unit_r) = std::fs::canonicalize(&job.path)
            && out_r.starts_with(&unit_r)
        {
            return Err(LotError::OutAmongInputs {
                out: out.to_path_buf(),
                input: job.path.clone(),
            });
        }
    }
    Ok(())
}
