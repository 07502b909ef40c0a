//! An outcome read back from a file of `OUT` (a unit's record on a cache hit, a shard's table
//! in a merge) checked against what the lot itself computes before any of it is taken. Such a
//! file can be edited, and what it holds would otherwise go straight into the lot's files: a
//! figure's name becomes a column of `lot.csv`, an entry of `lot.json` and a heading of
//! `lot.html`, an axis's name the prefix of every column of the axis, and the figures judge
//! the unit. So:
//!
//! - a figure's name is one the lot writes ([`figures::names`], with K0 at the spec's reference
//!   temperatures), each once per axis: no column the lot never computes reaches a table, and
//!   no second value of a figure hides behind the first, which the verdict reads. An axis
//!   holds at most as many figures as there are names, and the names are looked up in a set,
//!   so a table of many figures is refused at once and the check is linear in what it holds;
//! - an axis's name is one of the unit's own calibration's (the `calibration.json` the lot
//!   wrote beside it), each once, and printable by [`crate::text::is_unprintable`]'s rule;
//! - each run, as given and as an absolute path, is printable (the lot writes both escaped),
//!   and its absolute path is the run's path made absolute, as the lot's listing makes it: it
//!   ends with the path as given, so it names no other file.
//!
//! Anything else is refused ([`ReadBack`]), naming the file, the unit and the field, so that no
//! control character of an edited file reaches one the lot writes.

use super::figures::{self, AxisFigures};
use super::{Spec, UnitOutcome};
use std::collections::HashSet;
use std::path::{Component, Path, PathBuf};

/// A unit's outcome read back from a file that does not hold what the lot computes.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{}: unit {}: {field}: {message}; a file the lot writes was edited: run the lot (or that \
     shard) again",
    file.display(),
    crate::text::escaped(unit, false)
)]
pub struct ReadBack {
    /// The file read back.
    pub file: PathBuf,
    /// The unit, as the file names it.
    pub unit: String,
    /// The field that is wrong (`axes[0].figures[17].name`).
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

/// Checks the runs of `outcome`, read back from `file`.
///
/// # Errors
/// A run that is not printable, a count of absolute paths other than the runs', or an
/// absolute path that is not its run's.
pub fn runs(outcome: &UnitOutcome, file: &Path) -> Result<(), ReadBack> {
    let refused = |field: String, message: String| ReadBack {
        file: file.to_path_buf(),
        unit: outcome.unit.clone(),
        field,
        message,
    };
    for (what, list) in [("runs", &outcome.runs), ("runs_at", &outcome.runs_at)] {
        for (k, run) in list.iter().enumerate() {
            if let Some(c) = run.chars().find(|&c| crate::text::is_unprintable(c)) {
                return Err(refused(
                    format!("{what}[{k}]"),
                    format!("holds {}", crate::text::unprintable_named(c)),
                ));
            }
        }
    }
    // An outcome written before the absolute paths were recorded has none.
    if outcome.runs_at.is_empty() {
        return Ok(());
    }
    if outcome.runs_at.len() != outcome.runs.len() {
        return Err(refused(
            "runs_at".into(),
            format!(
                "{} paths for {} runs: one absolute path per run",
                outcome.runs_at.len(),
                outcome.runs.len()
            ),
        ));
    }
    for (k, (run, at)) in outcome.runs.iter().zip(&outcome.runs_at).enumerate() {
        if !is_made_absolute(Path::new(run), Path::new(at)) {
            return Err(refused(
                format!("runs_at[{k}]"),
                format!(
                    "\"{}\" is not run \"{}\" made an absolute path",
                    crate::text::escaped(at, false),
                    crate::text::escaped(run, false)
                ),
            ));
        }
    }
    Ok(())
}

/// Whether `at` is `run` made absolute: `run` itself when absolute, else a path ending with
/// it (`./` before it aside).
fn is_made_absolute(run: &Path, at: &Path) -> bool {
    if !at.is_absolute() {
        return false;
    }
    if run.is_absolute() {
        return run == at;
    }
    let given: PathBuf = run
        .components()
        .skip_while(|c| matches!(c, Component::CurDir))
        .collect();
    !given.as_os_str().is_empty() && at.ends_with(&given)
}

/// Checks the figures of `outcome`, read back from `file`, against those the lot computes for
/// `spec`, and its axes against `calibration_axes`, the axes of its own calibration.
///
/// # Errors
/// An axis that is not the calibration's, or given twice; a figure the lot does not compute,
/// or given twice; an axis of more figures than the lot computes.
pub fn axes(
    outcome: &UnitOutcome,
    spec: &Spec,
    calibration_axes: &[String],
    file: &Path,
) -> Result<(), ReadBack> {
    let refused = |field: String, message: String| ReadBack {
        file: file.to_path_buf(),
        unit: outcome.unit.clone(),
        field,
        message,
    };
    let names = figures::names(&spec.reference_temps());
    let known: HashSet<&str> = names.iter().map(String::as_str).collect();
    let own: HashSet<&str> = calibration_axes.iter().map(String::as_str).collect();
    let mut seen_axes: HashSet<&str> = HashSet::with_capacity(outcome.axes.len());
    for (i, axis) in outcome.axes.iter().enumerate() {
        let field = |rest: &str| format!("axes[{i}]{rest}");
        if let Some(c) = axis.axis.chars().find(|&c| crate::text::is_unprintable(c)) {
            return Err(refused(
                field(".axis"),
                format!("holds {}", crate::text::unprintable_named(c)),
            ));
        }
        if !own.contains(axis.axis.as_str()) {
            return Err(refused(
                field(".axis"),
                format!(
                    "\"{}\" is no axis of its calibration ({})",
                    crate::text::escaped(&axis.axis, false),
                    axes_named(calibration_axes)
                ),
            ));
        }
        if !seen_axes.insert(axis.axis.as_str()) {
            return Err(refused(
                field(".axis"),
                format!(
                    "\"{}\" is given twice",
                    crate::text::escaped(&axis.axis, false)
                ),
            ));
        }
        figures_of(axis, &known, names.len()).map_err(|(j, message)| match j {
            Some(j) => refused(field(&format!(".figures[{j}].name")), message),
            None => refused(field(".figures"), message),
        })?;
    }
    Ok(())
}

/// Checks one axis's figures against the `known` names, `count` of them: the place of the
/// figure that is wrong (none for the whole list) and what is wrong.
fn figures_of(
    axis: &AxisFigures,
    known: &HashSet<&str>,
    count: usize,
) -> Result<(), (Option<usize>, String)> {
    if axis.figures.len() > count {
        return Err((
            None,
            format!(
                "{} figures, more than the {count} the lot computes for an axis",
                axis.figures.len()
            ),
        ));
    }
    let mut seen: HashSet<&str> = HashSet::with_capacity(axis.figures.len());
    for (j, figure) in axis.figures.iter().enumerate() {
        let name = crate::text::escaped(&figure.name, false);
        if !known.contains(figure.name.as_str()) {
            return Err((Some(j), format!("\"{name}\" is no figure the lot computes")));
        }
        if !seen.insert(figure.name.as_str()) {
            return Err((
                Some(j),
                format!("\"{name}\" is given twice: a figure has one value"),
            ));
        }
    }
    Ok(())
}

/// A calibration's axes as a message names them.
fn axes_named(axes: &[String]) -> String {
    if axes.iter().all(String::is_empty) {
        return "one unnamed axis".into();
    }
    axes.iter()
        .map(|a| format!("\"{}\"", crate::text::escaped(a, false)))
        .collect::<Vec<_>>()
        .join(", ")
}
