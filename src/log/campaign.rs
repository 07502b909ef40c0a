//! A campaign: several chamber runs of one gyro (a heating and a cooling run, a repeat on
//! another day, a run at another rate), read as one [`Log`] whose runs are marked.
//!
//! Joining is the whole of what a campaign adds before the fit: the runs' samples one after
//! the other, each run's time moved past the one before it, and the runs' sample ranges kept
//! in [`LogInfo::runs`]. Every stage then reads the runs through [`Log::timing`], whose
//! segments end at each run's end ([`crate::signal::timing::Timing::of_runs`]): no smoothing,
//! derivative or plateau crosses from one run into the next, and the stages that gather
//! points (K0's plateaus, the K1± and K2± sets, a regression's rows) take them from every run.
//! A campaign of one run is that run's log, unchanged.
//!
//! What is joined must be one gyro logged alike: the same axes, read in the same units, at
//! the same sampling step, from the same drone-log gyro. Anything else is refused, saying
//! what differs, as are a file given twice and two files that hold one run's samples.

use super::{Log, LogInfo, Problem};
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// The most runs a campaign may join (each is a whole chamber run held in memory).
pub const MAX_RUNS: usize = 64;

/// The time put between two runs on the joined time axis, s (at least this, and at least
/// [`RUN_GAP_STEPS`] sampling steps): it keeps the joined time strictly increasing and shows
/// the runs apart on a plot. Nothing measures across it: each run is timed on its own.
pub const RUN_GAP_S: f64 = 3600.0;

/// [`RUN_GAP_S`] in sampling steps, for a log sampled slower than once a second.
pub const RUN_GAP_STEPS: f64 = 100.0;

/// Two runs whose sampling steps differ by more than this share were logged differently.
const STEP_TOLERANCE: f64 = 0.02;

/// One run of a campaign's joined log.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSpan {
    /// The run's file name (or label).
    pub name: String,
    /// SHA-256 of the run's file, hex; empty when not read from a file.
    pub sha256: String,
    /// The run's samples in the joined log.
    pub samples: Range<usize>,
    /// What was added to the run's own time stamps to place it on the joined time axis, s:
    /// its own time is the joined time less this.
    pub time_shift_s: f64,
}

/// A run to join: a log read from its file, and the file's SHA-256.
#[derive(Debug, Clone)]
pub struct RunInput {
    /// The run as read.
    pub log: Log,
    /// SHA-256 of its file (hex), empty when not read from a file.
    pub sha256: String,
}

/// Why runs cannot be joined into one campaign.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CampaignError {
    /// No run was given.
    #[error("a campaign needs at least one run")]
    NoRuns,
    /// More runs than [`MAX_RUNS`].
    #[error("{0} runs: a campaign joins at most {MAX_RUNS}")]
    TooManyRuns(usize),
    /// One file given twice (the same bytes).
    #[error(
        "{second} is the same file as {first} (the same bytes): each run of a campaign is given \
         once"
    )]
    SameFile {
        /// The run given first.
        first: String,
        /// The run that repeats it.
        second: String,
    },
    /// Two files that hold one run's samples (under other bytes: another format, separator,
    /// line ending).
    #[error(
        "{second} holds the samples of {first} (the same run under other bytes): each run of \
         a campaign is given once"
    )]
    SameRun {
        /// The run given first.
        first: String,
        /// The run that repeats it.
        second: String,
    },
    /// The runs are not one gyro logged alike.
    #[error(
        "{run} is not a run of the gyro of {first}: its {what} ({theirs}), where {first} has \
         {ours}; a campaign joins runs of one gyro logged alike (calibrate the others apart)"
    )]
    Differs {
        /// The first run.
        first: String,
        /// The run that differs.
        run: String,
        /// What differs: "gyro axes", "rate units", "temperature unit", "sampling step",
        /// "drone-log gyro".
        what: &'static str,
        /// The first run's.
        ours: String,
        /// The other run's.
        theirs: String,
    },
}

impl Log {
    /// The runs of a campaign's joined log, in order; empty for a log of one run.
    pub fn runs(&self) -> &[RunSpan] {
        &self.info.runs
    }

    /// The runs' sample ranges (one range covering the log for a log of one run).
    pub fn run_ranges(&self) -> Vec<Range<usize>> {
        if self.info.runs.is_empty() {
            std::iter::once(0..self.len()).collect()
        } else {
            self.info.runs.iter().map(|r| r.samples.clone()).collect()
        }
    }

    /// Run `k` of a campaign on its own: its samples, on its own time, as it was read (the
    /// leave-one-run-out judge, per-run figures). A log of one run is its own run 0.
    pub fn run_log(&self, k: usize) -> Option<Log> {
        if self.info.runs.is_empty() {
            return (k == 0).then(|| self.clone());
        }
        let span = self.info.runs.get(k)?;
        Some(slice(self, span))
    }

    /// The campaign of every run but `k` (the training of the leave-one-run-out judge);
    /// `None` for a log of one run or `k` out of range.
    pub fn without_run(&self, k: usize) -> Option<Log> {
        if self.info.runs.len() < 2 || k >= self.info.runs.len() {
            return None;
        }
        let runs: Vec<RunInput> = (0..self.info.runs.len())
            .filter(|&j| j != k)
            .map(|j| RunInput {
                log: slice(self, &self.info.runs[j]),
                sha256: self.info.runs[j].sha256.clone(),
            })
            .collect();
        // The runs were checked when the campaign was joined: laid out again, not checked
        // again (the check compares every pair of runs by their samples' sketches).
        Some(match runs.len() {
            1 => runs.into_iter().next()?.log,
            _ => joined(&runs),
        })
    }
}

/// Joins `runs` into one campaign log, in the order given (see the module's words). One run
/// is returned as it was read, its `runs` left empty.
///
/// # Errors
/// A [`CampaignError`]: no run, too many, a file given twice, one run's samples in two
/// files, or runs that are not one gyro logged alike (naming what differs).
pub fn join(mut runs: Vec<RunInput>) -> Result<Log, CampaignError> {
    match runs.len() {
        0 => return Err(CampaignError::NoRuns),
        1 => return Ok(runs.pop().map(|r| r.log).unwrap_or_default()),
        n if n > MAX_RUNS => return Err(CampaignError::TooManyRuns(n)),
        _ => {}
    }
    check_one_gyro(&runs)?;
    Ok(joined(&runs))
}

/// `runs` (two or more, already checked to be one gyro's) laid one after the other.
fn joined(runs: &[RunInput]) -> Log {
    let first = &runs[0].log;
    let dt = first.nominal_dt_s();
    let gap = RUN_GAP_S.max(RUN_GAP_STEPS * dt);
    let total: usize = runs.iter().map(|r| r.log.len()).sum();
    let shared_channels: Vec<(String, String)> = first
        .extra
        .iter()
        .filter(|c| {
            runs[1..].iter().all(|r| {
                r.log
                    .extra
                    .iter()
                    .any(|d| d.name == c.name && d.unit == c.unit)
            })
        })
        .map(|c| (c.name.clone(), c.unit.clone()))
        .collect();
    let mut out = Log {
        source: runs
            .iter()
            .map(|r| r.log.source.as_str())
            .collect::<Vec<_>>()
            .join(" + "),
        time_s: Vec::with_capacity(total),
        omega_dph: Vec::with_capacity(total),
        temp_c: Vec::with_capacity(total),
        extra: first
            .extra
            .iter()
            .filter(|c| {
                shared_channels
                    .iter()
                    .any(|(n, u)| *n == c.name && *u == c.unit)
            })
            .map(|c| super::Channel {
                name: c.name.clone(),
                unit: c.unit.clone(),
                values: Vec::with_capacity(total),
            })
            .collect(),
        axis: first.axis.clone(),
        other_axes: first
            .other_axes
            .iter()
            .map(|a| super::Axis {
                name: a.name.clone(),
                omega_dph: Vec::with_capacity(total),
            })
            .collect(),
        info: LogInfo {
            runs: Vec::with_capacity(runs.len()),
            problems: Vec::new(),
            rows_read: 0,
            ..first.info.clone()
        },
    };
    let mut dropped_channels: Vec<String> = Vec::new();
    for r in runs {
        let log = &r.log;
        let start = out.time_s.len();
        let shift = match (out.time_s.last(), log.time_s.first()) {
            (Some(&end), Some(&t0)) => end + gap - t0,
            _ => 0.0,
        };
        out.time_s.extend(log.time_s.iter().map(|t| t + shift));
        out.temp_c.extend_from_slice(&log.temp_c);
        for name in out.axis_names() {
            let rate = log.axis_rate(&name).unwrap_or(&[]);
            match out.other_axes.iter_mut().find(|a| a.name == name) {
                Some(a) => a.omega_dph.extend_from_slice(rate),
                None => out.omega_dph.extend_from_slice(rate),
            }
        }
        for c in &mut out.extra {
            if let Some(d) = log.channel(&c.name) {
                c.values.extend_from_slice(&d.values);
            }
        }
        for c in &log.extra {
            if !shared_channels
                .iter()
                .any(|(n, u)| *n == c.name && *u == c.unit)
                && !dropped_channels.contains(&c.name)
            {
                dropped_channels.push(c.name.clone());
            }
        }
        out.info.rows_read += log.info.rows_read;
        out.info
            .problems
            .extend(log.info.problems.iter().map(|p| Problem {
                message: format!("{}: {}", log.source, p.message),
                ..p.clone()
            }));
        out.info.runs.push(RunSpan {
            name: log.source.clone(),
            sha256: r.sha256.clone(),
            samples: start..out.time_s.len(),
            time_shift_s: shift,
        });
    }
    if !dropped_channels.is_empty() {
        out.info.problems.push(Problem {
            line: 0,
            column: None,
            kind: super::ProblemKind::LeftOut,
            count: dropped_channels.len(),
            message: format!(
                "the channel{} {} {} not in every run (with one unit) and {} left out of the \
                 campaign: a model that reads {} needs it in every run",
                if dropped_channels.len() == 1 { "" } else { "s" },
                dropped_channels.join(", "),
                if dropped_channels.len() == 1 {
                    "is"
                } else {
                    "are"
                },
                if dropped_channels.len() == 1 {
                    "is"
                } else {
                    "are"
                },
                if dropped_channels.len() == 1 {
                    "it"
                } else {
                    "one"
                },
            ),
        });
    }
    out
}

/// Run `span` of `log` on its own time, with the problems its reader found.
fn slice(log: &Log, span: &RunSpan) -> Log {
    let r = span.samples.clone();
    let prefix = format!("{}: ", span.name);
    Log {
        source: span.name.clone(),
        time_s: log.time_s[r.clone()]
            .iter()
            .map(|t| t - span.time_shift_s)
            .collect(),
        omega_dph: log.omega_dph[r.clone()].to_vec(),
        temp_c: log.temp_c[r.clone()].to_vec(),
        extra: log
            .extra
            .iter()
            .map(|c| super::Channel {
                values: c.values[r.clone()].to_vec(),
                ..c.clone()
            })
            .collect(),
        axis: log.axis.clone(),
        other_axes: log
            .other_axes
            .iter()
            .map(|a| super::Axis {
                name: a.name.clone(),
                omega_dph: a.omega_dph[r.clone()].to_vec(),
            })
            .collect(),
        info: LogInfo {
            runs: Vec::new(),
            problems: log
                .info
                .problems
                .iter()
                .filter_map(|p| {
                    p.message.strip_prefix(&prefix).map(|m| Problem {
                        message: m.to_string(),
                        ..p.clone()
                    })
                })
                .collect(),
            ..log.info.clone()
        },
    }
}

/// Refuses runs that are not one gyro logged alike, or one run given twice.
fn check_one_gyro(runs: &[RunInput]) -> Result<(), CampaignError> {
    let first = &runs[0].log;
    let differs = |run: &Log, what, ours: String, theirs: String| CampaignError::Differs {
        first: first.source.clone(),
        run: run.source.clone(),
        what,
        ours,
        theirs,
    };
    let units = |log: &Log, roles: &[super::ColumnRole]| -> String {
        let u: Vec<String> = log
            .info
            .columns
            .iter()
            .filter(|c| roles.contains(&c.role))
            .map(|c| {
                if c.unit.is_empty() {
                    format!("{} (no unit)", c.name)
                } else {
                    format!("{} in {}", c.name, c.unit)
                }
            })
            .collect();
        u.join(", ")
    };
    let rate_roles = [super::ColumnRole::Rate, super::ColumnRole::OtherAxis];
    let temp_roles = [super::ColumnRole::Temperature];
    let unit_of = |log: &Log, roles: &[super::ColumnRole]| -> Vec<String> {
        log.info
            .columns
            .iter()
            .filter(|c| roles.contains(&c.role))
            .map(|c| c.unit.clone())
            .collect()
    };
    let dt0 = first.nominal_dt_s();
    for (k, r) in runs.iter().enumerate().skip(1) {
        let log = &r.log;
        for earlier in &runs[..k] {
            if !r.sha256.is_empty() && r.sha256.eq_ignore_ascii_case(&earlier.sha256) {
                return Err(CampaignError::SameFile {
                    first: earlier.log.source.clone(),
                    second: log.source.clone(),
                });
            }
            if earlier.log.same_run(log) {
                return Err(CampaignError::SameRun {
                    first: earlier.log.source.clone(),
                    second: log.source.clone(),
                });
            }
        }
        if log.axis_names() != first.axis_names() {
            let names = |l: &Log| {
                let n = l.axis_names();
                if n.len() == 1 && n[0].is_empty() {
                    "one unnamed axis".to_string()
                } else {
                    n.join(", ")
                }
            };
            return Err(differs(log, "gyro axes", names(first), names(log)));
        }
        if unit_of(log, &rate_roles) != unit_of(first, &rate_roles) {
            return Err(differs(
                log,
                "rate units",
                units(first, &rate_roles),
                units(log, &rate_roles),
            ));
        }
        if unit_of(log, &temp_roles) != unit_of(first, &temp_roles) {
            return Err(differs(
                log,
                "temperature unit",
                units(first, &temp_roles),
                units(log, &temp_roles),
            ));
        }
        let dt = log.nominal_dt_s();
        let alike = (dt - dt0).abs() <= STEP_TOLERANCE * dt0;
        if !alike {
            return Err(differs(
                log,
                "sampling step",
                format!("{} s", crate::number::readable(dt0)),
                format!("{} s", crate::number::readable(dt)),
            ));
        }
        match (&first.info.instance, &log.info.instance) {
            (Some(a), Some(b)) if !a.same_gyro(b) => {
                return Err(differs(log, "drone-log gyro", a.describe(), b.describe()));
            }
            (Some(a), None) | (None, Some(a)) => {
                let which = if first.info.instance.is_some() {
                    (a.describe(), "a gyro of no drone log".to_string())
                } else {
                    ("a gyro of no drone log".to_string(), a.describe())
                };
                return Err(differs(log, "drone-log gyro", which.0, which.1));
            }
            _ => {}
        }
    }
    Ok(())
}
