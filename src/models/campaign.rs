//! A unit calibrated on a campaign: several chamber runs of one gyro, joined into one log
//! ([`crate::log::campaign::join`]) and fitted by the one [`calibrate`](super::calibrate) path.
//!
//! What a campaign adds to that path is small and kept here:
//! - each run's record (its file, time span and plateaus, with every axis's bias on each),
//!   written into the calibration's source so that repeatability and hysteresis can be read
//!   from the file alone ([`crate::judge::campaign`]);
//! - on request, each run's **turn-on offset**: a constant of that run that no temperature
//!   explains (a FOG's bias shifts from one turn-on to the next). It is estimated from the
//!   plateaus jointly with K0(T) (K0 in the recipe's approximation; the offsets sum to zero
//!   over the runs, so K0 keeps the campaign's mean level), taken out of each run's Ω before
//!   the fit, and recorded. It is never applied to another log: a new turn-on has its own.
//!
//! A campaign of one run is the single-run calibration, bit for bit: no record is made and no
//! offset taken.

use super::unit::{Keep, calibrate_keeping};
use super::{AxisPlan, CalibratedAxis};
use crate::error::{Invalid, Result};
use crate::judge::metrics::MeritOptions;
use crate::log::Log;
use crate::signal::plateau::{self, PlateauStats};
use serde::{Deserialize, Serialize};

mod check;
mod unit_runs;
pub use check::{
    MAX_RUN_DURATION_S, MAX_RUN_NAME_CHARS, MAX_RUN_PLATEAUS, MAX_RUN_START_S, check_same_runs,
    validate_runs,
};
pub use unit_runs::{JoinedRuns, UnitFit, UnitPlan, calibrate_runs};

/// Two plateaus share a temperature when they are within this of each other's group, °C, by
/// default ([`CampaignOptions::tolerance_c`]).
pub const DEFAULT_TOLERANCE_C: f64 = 1.0;

/// The widest tolerance two plateaus may share a temperature within, °C: wider, plateaus at
/// unlike temperatures would be compared as one.
pub const MAX_TOLERANCE_C: f64 = 10.0;

/// The narrowest tolerance, °C: below a hundredth of a degree no chamber holds a set point
/// (nor reads it), so plateaus would share no temperature and a run's start would be told
/// heating or cooling by its sensor's last digit.
pub const MIN_TOLERANCE_C: f64 = 0.01;

/// Checks a tolerance plateaus share a temperature within (`field`: the setting or option
/// that gave it, named in the refusal with the value as given, every digit).
///
/// # Errors
/// A tolerance that is not a number from [`MIN_TOLERANCE_C`] to [`MAX_TOLERANCE_C`].
pub fn check_tolerance(field: &str, tolerance_c: f64) -> std::result::Result<(), Invalid> {
    if tolerance_c.is_finite() && (MIN_TOLERANCE_C..=MAX_TOLERANCE_C).contains(&tolerance_c) {
        return Ok(());
    }
    Err(Invalid::new(
        field,
        format!(
            "is {tolerance_c:?}: the temperatures two plateaus share are within a tolerance from \
             {MIN_TOLERANCE_C} °C (a chamber's steadiness) to {MAX_TOLERANCE_C} °C"
        ),
    ))
}

/// The most rounds of the joint K0 and offsets estimate; it stops sooner when the offsets
/// move less than [`OFFSET_SETTLED_DPH`].
const OFFSET_ROUNDS: usize = 500;

/// The offsets are settled when no run's moves more than this in a round, °/h.
const OFFSET_SETTLED_DPH: f64 = 1e-12;

/// How a campaign is fitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CampaignOptions {
    /// Estimate each run's turn-on offset and keep it out of K0.
    pub per_run_offset: bool,
    /// Two plateaus share a temperature within this, °C (repeatability, hysteresis, and the
    /// runs that tie the offsets together).
    pub tolerance_c: f64,
}

impl Default for CampaignOptions {
    fn default() -> Self {
        CampaignOptions {
            per_run_offset: false,
            tolerance_c: DEFAULT_TOLERANCE_C,
        }
    }
}

/// How a plateau's temperature was reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Approach {
    /// From below.
    Heating,
    /// From above.
    Cooling,
    /// The run started there (its first plateau, within the tolerance of the run's first
    /// temperature): approached from neither side.
    Start,
}

/// One plateau of a run, on the run's own time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunPlateau {
    /// Its start on the run's own time, s.
    pub start_s: f64,
    /// Its end on the run's own time, s.
    pub end_s: f64,
    /// Its mean temperature, °C.
    pub temp_c: f64,
    /// The axis's mean raw output over it, °/h (its turn-on offset included).
    pub bias_dph: f64,
    /// How its temperature was reached: from the previous plateau of the run (or the run's
    /// first temperature).
    pub approach: Approach,
}

/// One run of a campaign, as the calibration records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    /// The run's file name.
    pub name: String,
    /// SHA-256 of the run's file, hex; empty when not read from a file.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub sha256: String,
    /// Samples of the run.
    pub samples: usize,
    /// Its first time stamp, on its own time, s.
    pub start_s: f64,
    /// Its duration, s.
    pub duration_s: f64,
    /// Its plateaus, in time order.
    pub plateaus: Vec<RunPlateau>,
    /// Its turn-on offset, °/h, when one was estimated (`--per-run-offset`): taken out of the
    /// run's output before the fit, never applied to another log.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_on_offset_dph: Option<f64>,
}

/// A campaign's fit: every axis as [`calibrate`](super::calibrate) fits it, and each axis's
/// record of the runs (empty for a log of one run).
#[derive(Debug, Clone)]
pub struct CampaignFit {
    /// The axes, fitted.
    pub axes: Vec<CalibratedAxis>,
    /// For each axis, in the same order, its record of every run.
    pub runs: Vec<Vec<RunRecord>>,
}

/// Fits `plans` on the campaign `log` ([`crate::log::campaign::join`]); a log of one run is
/// fitted as [`calibrate`](super::calibrate) fits it, with no record.
///
/// # Errors
/// What [`calibrate`](super::calibrate) refuses; for a campaign, a run with no plateau, and
/// with `per_run_offset` a run whose plateaus share no temperature with another run's (its
/// offset could not be told from K0's shape).
pub fn calibrate_campaign(
    log: &mut Log,
    plans: &[AxisPlan],
    merit: &MeritOptions,
    options: &CampaignOptions,
) -> Result<CampaignFit> {
    calibrate_campaign_keeping(log, plans, merit, options, Keep::Figures)
}

/// [`calibrate_campaign`], keeping each axis's corrected rate when `keep` says so
/// ([`CalibratedAxis::corrected`](crate::models::CalibratedAxis::corrected)).
///
/// # Errors
/// What [`calibrate_campaign`] refuses.
pub fn calibrate_campaign_keeping(
    log: &mut Log,
    plans: &[AxisPlan],
    merit: &MeritOptions,
    options: &CampaignOptions,
    keep: Keep,
) -> Result<CampaignFit> {
    check_tolerance("tolerance_c", options.tolerance_c)?;
    if log.runs().len() < 2 {
        if options.per_run_offset {
            return Err(Invalid::new(
                "per_run_offset",
                format!(
                    "{} is one run: a turn-on offset is told apart from K0 only between two \
                     runs or more",
                    log.source
                ),
            )
            .into());
        }
        let axes = calibrate_keeping(log, plans, merit, keep)?;
        let runs = vec![Vec::new(); axes.len()];
        return Ok(CampaignFit { axes, runs });
    }
    let first = plans
        .first()
        .ok_or(crate::error::Error::Internal("a campaign fit without axes"))?;
    let (ranges, plateau_runs) = run_plateaus(log, &first.recipe)?;
    let names = if plans.len() == 1 && plans[0].name.is_empty() {
        vec![log.axis.clone()]
    } else {
        plans.iter().map(|p| p.name.clone()).collect()
    };
    let mut records = Vec::with_capacity(plans.len());
    // The raw rates of the axes whose offsets are taken out, put back after the fit: the
    // calibration's sketch of its samples is the files' (a run given again is told by it),
    // and the caller's log ends as it was read.
    let mut raw: Vec<(String, Vec<f64>)> = Vec::new();
    for (plan, name) in plans.iter().zip(&names) {
        let stats = axis_stats(log, name, &ranges)?;
        let offsets = if options.per_run_offset {
            Some(turn_on_offsets(
                &stats,
                &plateau_runs,
                log.runs().len(),
                plan,
                options.tolerance_c,
                &log.runs()
                    .iter()
                    .map(|r| r.name.as_str())
                    .collect::<Vec<_>>(),
            )?)
        } else {
            None
        };
        records.push(record(
            log,
            &stats,
            &plateau_runs,
            offsets.as_deref(),
            options,
        ));
        if let Some(offsets) = offsets {
            let spans: Vec<_> = log.runs().iter().map(|r| r.samples.clone()).collect();
            let omega = axis_rate_mut(log, name);
            raw.push((name.clone(), omega.clone()));
            for (span, c) in spans.into_iter().zip(offsets) {
                for w in &mut omega[span] {
                    *w -= c;
                }
            }
        }
    }
    let fitted = calibrate_keeping(log, plans, merit, keep);
    let first_axis = log.axis.clone();
    for (name, omega) in raw {
        *axis_rate_mut(log, &name) = omega;
    }
    let mut axes = fitted?;
    if options.per_run_offset {
        for a in &mut axes {
            a.calibrated.warnings.push(
                "the in-sample figures are of each run's rates less its turn-on offset, as \
                 the model was fitted on them"
                    .into(),
            );
        }
        let order = log.axis_names();
        for (a, name) in axes.iter_mut().zip(&names) {
            log.select_axis(name);
            a.calibrated.model.source_mut().samples_sketch =
                super::vakhrameev::SourceInfo::of(log).samples_sketch;
        }
        log.select_axis(&first_axis);
        log.order_axes_as(&order);
    }
    Ok(CampaignFit {
        axes,
        runs: records,
    })
}

/// The plateaus of the campaign `log` as `recipe` finds them, each with its run (detection
/// never crosses a run's end; a range given by hand that does is no plateau of either).
///
/// # Errors
/// What the T stages refuse, and a run with no plateau: each run needs one, for its bias to
/// be set beside the others' (`calibrate` and `compare` refuse it alike).
pub fn run_plateaus(
    log: &Log,
    recipe: &crate::models::CheckedRecipe,
) -> Result<(Vec<plateau::PlateauRange>, Vec<usize>)> {
    let ranges = super::vakhrameev::Pipeline::new(log, recipe)?
        .ranges()
        .to_vec();
    runs_of(log, ranges)
}

/// The run each plateau of `ranges` lies in, `None` for one that crosses a run's end (a range
/// placed by hand over the gap between two runs: a plateau of neither).
pub fn run_of_each(log: &Log, ranges: &[plateau::PlateauRange]) -> Vec<Option<usize>> {
    ranges
        .iter()
        .map(|r| {
            let (lo, hi) = r.index_range(&log.time_s);
            log.runs()
                .iter()
                .position(|s| lo >= s.samples.start && hi <= s.samples.end && lo < hi)
        })
        .collect()
}

/// `ranges` less those that cross a run's end, each with its run; refused when a run is left
/// with no plateau.
fn runs_of(
    log: &Log,
    ranges: Vec<plateau::PlateauRange>,
) -> Result<(Vec<plateau::PlateauRange>, Vec<usize>)> {
    let (ranges, plateau_runs): (Vec<plateau::PlateauRange>, Vec<usize>) =
        run_of_each(log, &ranges)
            .into_iter()
            .zip(ranges)
            .filter_map(|(k, r)| Some((r, k?)))
            .unzip();
    if let Some(k) = (0..log.runs().len()).find(|k| !plateau_runs.contains(k)) {
        return Err(Invalid::new(
            format!("run {}", log.runs()[k].name),
            "has no plateau: each run of a campaign needs one, for its bias to be set beside \
             the other runs' (and its turn-on told apart); hold the chamber steady in it, or \
             leave it out",
        )
        .into());
    }
    Ok((ranges, plateau_runs))
}

/// Each run's record of the axis named `name` (the log's first axis for `""`), from the
/// plateaus `ranges` a fit used (detected or placed by hand on the joined time): the faces
/// that fit a campaign stage by stage (the workbench) record it as [`calibrate_campaign`]
/// does, with no turn-on offset. Empty for a log of one run.
///
/// # Errors
/// A run with no plateau among `ranges` (as [`run_plateaus`] refuses it).
pub fn run_records(
    log: &Log,
    name: &str,
    ranges: &[plateau::PlateauRange],
    options: &CampaignOptions,
) -> Result<Vec<RunRecord>> {
    if log.runs().len() < 2 {
        return Ok(Vec::new());
    }
    let (ranges, plateau_runs) = runs_of(log, ranges.to_vec())?;
    let stats = axis_stats(log, name, &ranges)?;
    Ok(record(log, &stats, &plateau_runs, None, options))
}

/// The statistics of axis `name` (the log's first for `""` or a name it lacks) on each of
/// `ranges`, every one of a run ([`runs_of`]).
///
/// # Errors
/// None but the internal one of a range without samples: each range holds samples of its
/// run (`run_of_each` found them there), so the statistics stay beside their runs.
fn axis_stats(
    log: &Log,
    name: &str,
    ranges: &[plateau::PlateauRange],
) -> Result<Vec<PlateauStats>> {
    let omega = log.axis_rate(name).unwrap_or(&log.omega_dph);
    let stats: Vec<PlateauStats> = ranges
        .iter()
        .filter_map(|r| plateau::stats(&log.time_s, &log.temp_c, omega, *r))
        .collect();
    if stats.len() != ranges.len() {
        return Err(crate::error::Error::Internal(
            "a campaign plateau without samples",
        ));
    }
    Ok(stats)
}

/// Writes a campaign's record into a fitted model's source: `runs` and the tolerance its
/// plateaus were grouped by (nothing for a calibration of one run, whose `runs` is empty).
/// The one stamp the command line and the workbench put on a campaign's calibration.
pub fn stamp_runs(
    source: &mut super::vakhrameev::SourceInfo,
    runs: Vec<RunRecord>,
    tolerance_c: f64,
) {
    if !runs.is_empty() {
        source.temp_tolerance_c = Some(tolerance_c);
    }
    source.runs = runs;
}

/// The rate column of axis `name`, to take the offsets out.
fn axis_rate_mut<'a>(log: &'a mut Log, name: &str) -> &'a mut Vec<f64> {
    if log.axis == name {
        return &mut log.omega_dph;
    }
    match log.other_axes.iter().position(|a| a.name == name) {
        Some(k) => &mut log.other_axes[k].omega_dph,
        None => &mut log.omega_dph,
    }
}

/// Each run's record of one axis: its span, its plateaus with the axis's bias on each.
fn record(
    log: &Log,
    stats: &[PlateauStats],
    plateau_runs: &[usize],
    offsets: Option<&[f64]>,
    options: &CampaignOptions,
) -> Vec<RunRecord> {
    log.runs()
        .iter()
        .enumerate()
        .map(|(k, span)| {
            let shift = span.time_shift_s;
            let t = &log.time_s[span.samples.clone()];
            let plateaus = stats
                .iter()
                .zip(plateau_runs)
                .filter(|(_, r)| **r == k)
                .map(|(p, _)| {
                    let (lo, _) = p.range.index_range(&log.time_s);
                    let approach =
                        approach_to(&log.temp_c[span.samples.start..lo], p.temp_c, options);
                    RunPlateau {
                        start_s: p.range.start_s - shift,
                        end_s: p.range.end_s - shift,
                        temp_c: p.temp_c,
                        bias_dph: p.omega_dph,
                        approach,
                    }
                })
                .collect();
            RunRecord {
                name: span.name.clone(),
                sha256: span.sha256.clone(),
                samples: span.samples.len(),
                start_s: t.first().map_or(0.0, |t0| t0 - shift),
                duration_s: match (t.first(), t.last()) {
                    (Some(a), Some(b)) => b - a,
                    _ => 0.0,
                },
                plateaus,
                turn_on_offset_dph: offsets.map(|o| o[k]),
            }
        })
        .collect()
}

/// How a plateau at `temp_c` was reached, from the run's temperatures before it (`before`):
/// walking back from its start to the last temperature more than the tolerance away, below
/// it (heating) or above it (cooling); none so far from it since the run's start: the run
/// started there. How the temperature arrived, whatever lay between (a dwell too short to
/// be a plateau, a plateau at the same temperature split in two).
fn approach_to(before: &[f64], temp_c: f64, options: &CampaignOptions) -> Approach {
    before
        .iter()
        .rev()
        .find(|t| (**t - temp_c).abs() > options.tolerance_c)
        .map_or(Approach::Start, |t| {
            if *t < temp_c {
                Approach::Heating
            } else {
                Approach::Cooling
            }
        })
}

/// Each run's turn-on offset for one axis: the least-squares joint estimate of K0(T), in the
/// axis's K0 approximation, and one constant per run, summing to zero, from the plateau
/// points (`plateau_runs[i]` the run of `stats[i]`). Solved by alternating the two (K0 on the
/// points less their run's offset; each offset the mean of its run's residuals, then centred),
/// which reaches the joint least squares for a linear approximation.
///
/// # Errors
/// A run whose plateaus share no temperature with another run's (within `tolerance_c`): its
/// offset and K0's shape could not be told apart.
fn turn_on_offsets(
    stats: &[PlateauStats],
    plateau_runs: &[usize],
    runs: usize,
    plan: &AxisPlan,
    tolerance_c: f64,
    names: &[&str],
) -> Result<Vec<f64>> {
    check_tied(stats, plateau_runs, runs, tolerance_c, names)?;
    let mut offsets = vec![0.0; runs];
    let mut warnings = Vec::new();
    for _ in 0..OFFSET_ROUNDS {
        let less: Vec<PlateauStats> = stats
            .iter()
            .zip(plateau_runs)
            .map(|(p, &r)| PlateauStats {
                omega_dph: p.omega_dph - offsets[r],
                ..*p
            })
            .collect();
        let k0 = super::vakhrameev::fit_k0(&less, &plan.recipe.k0, &mut warnings)?;
        let mut sum = vec![0.0; runs];
        let mut count = vec![0usize; runs];
        for (p, &r) in stats.iter().zip(plateau_runs) {
            sum[r] += p.omega_dph - k0.eval(p.temp_c);
            count[r] += 1;
        }
        let mut next: Vec<f64> = sum
            .iter()
            .zip(&count)
            .map(|(s, &n)| s / n.max(1) as f64)
            .collect();
        let mean = next.iter().sum::<f64>() / runs as f64;
        for c in &mut next {
            *c -= mean;
        }
        let moved = next
            .iter()
            .zip(&offsets)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        offsets = next;
        if moved < OFFSET_SETTLED_DPH {
            break;
        }
    }
    if offsets.iter().any(|c| !c.is_finite()) {
        return Err(Invalid::new(
            "per_run_offset",
            "the turn-on offsets could not be estimated (the plateau points give no finite \
             solution)",
        )
        .into());
    }
    Ok(offsets)
}

/// Refuses offsets that the plateaus cannot tell from K0: every run must be tied to the
/// others through temperatures their plateaus share.
fn check_tied(
    stats: &[PlateauStats],
    plateau_runs: &[usize],
    runs: usize,
    tolerance_c: f64,
    names: &[&str],
) -> Result<()> {
    // Runs joined when two of their plateaus are within the tolerance; all must be one group.
    let mut group: Vec<usize> = (0..runs).collect();
    fn root(group: &mut [usize], mut k: usize) -> usize {
        while group[k] != k {
            group[k] = group[group[k]];
            k = group[k];
        }
        k
    }
    for (i, p) in stats.iter().enumerate() {
        for (j, q) in stats.iter().enumerate().skip(i + 1) {
            if (p.temp_c - q.temp_c).abs() <= tolerance_c {
                let (a, b) = (
                    root(&mut group, plateau_runs[i]),
                    root(&mut group, plateau_runs[j]),
                );
                group[a] = b;
            }
        }
    }
    let first = root(&mut group, 0);
    if let Some(k) = (1..runs).find(|&k| root(&mut group, k) != first) {
        return Err(Invalid::new(
            "per_run_offset",
            format!(
                "run {} shares no plateau temperature (within {} °C) with run {} or the runs \
                 tied to it: its turn-on offset cannot be told from the shape of K0(T); give it \
                 a plateau at a temperature another run holds, or fit without per-run offsets",
                names.get(k).copied().unwrap_or("?"),
                crate::number::readable(tolerance_c),
                names.first().copied().unwrap_or("?"),
            ),
        )
        .into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plateau_is_reached_as_the_temperature_arrived() {
        let o = CampaignOptions::default();
        // 20 °C, up to 60 °C for a dwell too short to be a plateau, down to 40 °C.
        let mut before: Vec<f64> = vec![20.0; 10];
        before.extend((0..40).map(|k| 20.0 + k as f64));
        before.extend([60.0; 5]);
        before.extend((0..20).map(|k| 60.0 - k as f64));
        before.push(40.5);
        assert_eq!(approach_to(&before, 40.0, &o), Approach::Cooling);
        // A plateau split in two at 60 °C, reached heating: the second half too.
        let mut split: Vec<f64> = (0..40).map(|k| 20.0 + k as f64).collect();
        split.extend([60.0, 60.1, 59.9, 60.0]);
        assert_eq!(approach_to(&split, 60.0, &o), Approach::Heating);
        // The run started at the plateau's temperature, within the tolerance.
        assert_eq!(approach_to(&[20.3, 19.8, 20.0], 20.0, &o), Approach::Start);
        assert_eq!(approach_to(&[], 20.0, &o), Approach::Start);
    }
}
