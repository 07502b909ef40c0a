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
//! the same sampling step, with the temperature of one sensor, from the same drone-log gyro.
//! Anything else is refused, saying what differs, as are a file given twice, two files that
//! hold one run's samples, and a run that holds a part of another's. A run that records no
//! drone-log gyro (a CSV) beside one that does is joined, saying that which gyro it is could
//! not be checked. Runs are named by their files ([`run_names`]).

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

/// The share of a run's samples another run may hold, beyond chance, before the two are
/// refused ([`CampaignError::SharesSamples`]): about a plateau's worth (a 15-minute dwell of
/// an 11-hour run is 2.3 %). Two runs of a chamber share none (their noise differs at every
/// sample, and the sketch counts only what is shared beyond chance: the simulated campaigns'
/// runs share 0 %); a run whose first 400 of 40,000 samples are another's is found at 1.1 %,
/// the 2,000 of a 33-minute plateau at 5 %.
pub const MAX_SHARED: f64 = 0.02;

/// The share of a run's samples that are another run's from which it is that run's samples
/// again ([`CampaignError::SameRun`]: the run under other bytes, or a part of it), rather than
/// a run that holds a part of another ([`CampaignError::SharesSamples`]).
const SAME_RUN_SHARE: f64 = 0.9;

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
    /// A run that holds a part of another run's samples (beyond chance), too large a part to
    /// be two runs of one program meeting by chance.
    #[error(
        "{second} holds samples of {first}: about {} % of its samples ({samples} of them) are \
         {first}'s, {} % of {first}'s; each run of a campaign is given once, whole and alone: \
         give each run's own samples (a plateau of both would count twice, and the \
         repeatability be read from a plateau and its own copy)",
        (.share * 100.0).round(),
        (.share_of_first * 100.0).round()
    )]
    SharesSamples {
        /// The run given first.
        first: String,
        /// The run that holds some of its samples.
        second: String,
        /// The share of `second`'s samples that are `first`'s (0 to 1), estimated.
        share: f64,
        /// The share of `first`'s samples that `second` holds (0 to 1), estimated.
        share_of_first: f64,
        /// The samples of `second` that are `first`'s, estimated.
        samples: usize,
    },
    /// The runs are not one gyro logged alike.
    #[error(
        "{run} is not a run of the gyro of {first}: its {what} ({theirs}), where {first} has \
         {ours}; a campaign joins runs of one gyro logged alike ({})",
        what_to_do(.what)
    )]
    Differs {
        /// The first run (for a drone-log gyro, the first run that records one).
        first: String,
        /// The run that differs.
        run: String,
        /// What differs: "gyro axes", "rate units", "temperature unit", "temperature column",
        /// "sampling step", "drone-log gyro".
        what: &'static str,
        /// The first run's.
        ours: String,
        /// The other run's.
        theirs: String,
    },
}

/// What to do about runs that differ in `what` ([`CampaignError::Differs`]).
fn what_to_do(what: &str) -> &'static str {
    match what {
        "temperature column" => {
            "the temperature of one sensor in every run: choose the gyro's own with temp_col \
             where a run has it, or calibrate the others apart"
        }
        _ => "calibrate the others apart",
    }
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
    let mut log = joined(&runs);
    log.info.problems.extend(unchecked_gyros(&runs));
    Ok(log)
}

/// The runs whose drone-log gyro could not be checked: they record none (a CSV, one `convert`
/// wrote of a drone log among them), where another run does. Said once, naming them, with
/// the gyro the campaign is taken to be.
fn unchecked_gyros(runs: &[RunInput]) -> Option<Problem> {
    let (known, gyro) = runs
        .iter()
        .find_map(|r| r.log.info.instance.as_ref().map(|g| (&r.log, g)))?;
    let unknown: Vec<&str> = runs
        .iter()
        .filter(|r| r.log.info.instance.is_none())
        .map(|r| r.log.source.as_str())
        .collect();
    let one = unknown.len() == 1;
    (!unknown.is_empty()).then(|| Problem {
        line: 0,
        column: None,
        kind: super::ProblemKind::Unchecked,
        count: unknown.len(),
        message: format!(
            "{} record{} no drone-log gyro (a CSV records none, one `convert` wrote too), so \
             which gyro {} cannot be checked against {}'s {}: the campaign is taken as that \
             gyro's; make sure {} of it",
            unknown.join(", "),
            if one { "s" } else { "" },
            if one { "it is" } else { "they are" },
            known.source,
            gyro.describe(),
            if one { "the run is" } else { "the runs are" },
        ),
    })
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
        axis_kind: first.axis_kind,
        other_axes: first
            .other_axes
            .iter()
            .map(|a| super::Axis {
                name: a.name.clone(),
                omega_dph: Vec::with_capacity(total),
                kind: a.kind,
            })
            .collect(),
        info: LogInfo {
            runs: Vec::with_capacity(runs.len()),
            problems: Vec::new(),
            rows_read: 0,
            // The one gyro the runs that record one are (a run of a CSV records none).
            instance: runs.iter().find_map(|r| r.log.info.instance.clone()),
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
        axis_kind: log.axis_kind,
        other_axes: log
            .other_axes
            .iter()
            .map(|a| super::Axis {
                name: a.name.clone(),
                omega_dph: a.omega_dph[r.clone()].to_vec(),
                kind: a.kind,
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
            check_shared(&earlier.log, log)?;
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
        if let (Some(ours), Some(theirs)) = (temp_column(first), temp_column(log))
            && super::ingest::temperature_sensor(ours) != super::ingest::temperature_sensor(theirs)
        {
            let named = |c: &str| crate::text::escaped(c, false).into_owned();
            return Err(differs(
                log,
                "temperature column",
                named(ours),
                named(theirs),
            ));
        }
        // Drone-log gyros are compared where both runs record one: a CSV records none, and
        // is joined with a warning ([`unchecked_gyros`]).
        let recorded = runs[..k]
            .iter()
            .find_map(|r| r.log.info.instance.as_ref().map(|g| (&r.log, g)));
        if let (Some((known, a)), Some(b)) = (recorded, &log.info.instance)
            && !a.same_gyro(b)
        {
            return Err(CampaignError::Differs {
                first: known.source.clone(),
                run: log.source.clone(),
                what: "drone-log gyro",
                ours: a.describe(),
                theirs: b.describe(),
            });
        }
    }
    Ok(())
}

/// The name of the column `log`'s temperature was read from, when its reader recorded it.
fn temp_column(log: &Log) -> Option<&str> {
    log.info
        .columns
        .iter()
        .find(|c| c.role == super::ColumnRole::Temperature)
        .map(|c| c.name.as_str())
}

/// Refuses `log` when it holds samples of `earlier`'s run beyond chance and more than
/// [`MAX_SHARED`] of either run (by the sketch [`Log::run_shared`] compares with, 4096
/// hashes of `earlier`): nearly all of it, as the same run ([`CampaignError::SameRun`]),
/// else as a run holding a part of another ([`CampaignError::SharesSamples`]).
fn check_shared(earlier: &Log, log: &Log) -> Result<(), CampaignError> {
    let shared = earlier.run_shared(log);
    if shared.in_sample() && shared.share_of_log >= SAME_RUN_SHARE {
        return Err(CampaignError::SameRun {
            first: earlier.source.clone(),
            second: log.source.clone(),
        });
    }
    let of_log = if shared.in_sample() || shared.partly().is_some() {
        shared.share_of_log
    } else {
        0.0
    };
    let of_earlier = shared.share_of_run();
    if of_log.max(of_earlier) > MAX_SHARED {
        return Err(CampaignError::SharesSamples {
            first: earlier.source.clone(),
            second: log.source.clone(),
            share: of_log,
            share_of_first: of_earlier,
            samples: (of_log * log.len() as f64).round() as usize,
        });
    }
    Ok(())
}

/// The names of runs read from `paths`, as every face names them (the runs' record in a
/// calibration, its repeatability lines, leave-one-run-out, the report): each file's name,
/// or where files share a name (`day1/run.csv`, `day2/run.csv`), the fewest of its path's
/// last parts that tell it from every other path (`day1/run.csv`). A path given twice keeps
/// its whole path (the files are then refused as one file given twice).
pub fn run_names<P: AsRef<std::path::Path>>(paths: &[P]) -> Vec<String> {
    use std::path::Component;
    let parts: Vec<Vec<String>> = paths
        .iter()
        .map(|p| {
            p.as_ref()
                .components()
                .filter_map(|c| match c {
                    Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
                    Component::ParentDir => Some("..".to_string()),
                    Component::CurDir | Component::RootDir | Component::Prefix(_) => None,
                })
                .collect()
        })
        .collect();
    // The last `k` parts of a path (all of them for a shorter one).
    let last = |p: &[String], k: usize| p[p.len().saturating_sub(k)..].to_vec();
    // How many paths end in each run of last parts, for each count of parts: a path is told
    // by its fewest last parts that no other path ends in (counted once, not path by path:
    // a lot lists ten thousand units).
    let longest = parts.iter().map(Vec::len).max().unwrap_or(0).max(1);
    let mut ends: Vec<std::collections::HashMap<Vec<String>, usize>> = (0..=longest)
        .map(|_| std::collections::HashMap::with_capacity(parts.len()))
        .collect();
    for own in &parts {
        for (k, counts) in ends.iter_mut().enumerate().skip(1) {
            *counts.entry(last(own, k)).or_insert(0) += 1;
        }
    }
    parts
        .iter()
        .enumerate()
        .map(|(i, own)| {
            let told = (1..=own.len().max(1)).find(|&k| ends[k][&last(own, k)] == 1);
            let name = match told {
                Some(k) => last(own, k).join("/"),
                None => own.join("/"),
            };
            let name = if name.is_empty() {
                paths[i].as_ref().display().to_string()
            } else {
                name
            };
            // A file's name may hold a control character (an escape sequence): the run's
            // name is written with it escaped, as a calibration records it and every face
            // shows it, never refused after the fit.
            crate::text::escaped(&name, false).into_owned()
        })
        .collect()
}
