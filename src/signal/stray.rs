//! Stray time stamps: a clock glitch that stamps a row or two far out of line with the rows
//! around them (1e6 s, 1e300 s, or 0 in the middle of a run that keeps time), and a sample or
//! two alone at an end of the log past a gap far longer than the rest of it. Both readers (CSV
//! and the drone logs) drop them by these rules and say so with their lines, so that one bad
//! stamp neither makes every later row "go backwards" nor stretches the log's duration.

use super::timing::{GAP_FACTOR, Timing, rough_step};
use std::ops::Range;

/// How many times longer than the body of a log the gap before (or after) a lone sample at
/// its end must be for that sample to be a stray stamp ([`Timing::stray_end`]).
pub const STRAY_FACTOR: f64 = 100.0;

/// The most samples side by side that are taken for stray stamps ([`stray_stamps`],
/// [`Timing::stray_end`]): a clock glitch garbles a row's stamp, or a couple of rows'. A
/// longer run that keeps to a step of its own is data with a time base of its own (another
/// recorder's rows, a clock set wrong for a while), not a glitch, and is left to the checks
/// of time order and gaps, which say what they drop. Short runs that come back again and
/// again, rising at the pace of the rows around them, are another recorder's rows too: the
/// readers refuse them before looking for stray stamps ([`super::interleaved`]).
pub const MAX_STRAY_RUN: usize = 2;

/// The largest share of a log's samples that an end segment past a gap far longer than the
/// rest of the log may hold and be dropped as stray ([`Timing::stray_end`]): rows stamped
/// before a logger's clock was set (0, 0.5, 0.7 s, then Unix time) are a handful, and kept as
/// a segment of their own they made a 10-hour log "55 years" long. A larger end segment, however
/// far, is data of its own, kept and told as a gap.
pub const STRAY_END_SHARE: f64 = 0.01;

/// The most samples an end segment of a log of `n` samples may hold and be stray: at least
/// [`MAX_STRAY_RUN`], else [`STRAY_END_SHARE`] of the log.
fn max_stray_end(n: usize) -> usize {
    MAX_STRAY_RUN.max((STRAY_END_SHARE * n as f64) as usize)
}

/// An end of a log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The first sample.
    First,
    /// The last sample.
    Last,
}

/// Samples at an end of a log that stand alone past a gap far longer than the rest of it
/// ([`Timing::stray_end`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrayEnd {
    /// Which end.
    pub end: End,
    /// How many samples, 1 to [`max_stray_end`] of the log.
    pub samples: usize,
    /// The span of the body of the log they stand apart from, s.
    pub body_s: f64,
}

impl StrayEnd {
    /// The indices of the stray samples in a log of `n` samples.
    pub fn range(&self, n: usize) -> Range<usize> {
        match self.end {
            End::First => 0..self.samples.min(n),
            End::Last => n.saturating_sub(self.samples)..n,
        }
    }

    /// What a reader says when it drops them: `noun` is what it calls a sample ("row",
    /// "sample"), `place` where they stand ("line 1001"), `dur` how it writes a duration.
    /// Both readers word it alike, so that a stray stamp reads the same in a CSV file and in
    /// a drone log.
    pub fn message(
        &self,
        time_s: &[f64],
        noun: &str,
        place: &str,
        dur: &dyn Fn(f64) -> String,
    ) -> String {
        let r = self.range(time_s.len());
        let stamps = &time_s[r.clone()];
        if stamps.is_empty() {
            return String::new();
        }
        let (step, side) = match self.end {
            End::First => (
                time_s
                    .get(r.end)
                    .map_or(0.0, |t| t - stamps[stamps.len() - 1]),
                "before",
            ),
            End::Last => (
                stamps[0] - r.start.checked_sub(1).map_or(stamps[0], |i| time_s[i]),
                "after",
            ),
        };
        let times: Vec<String> = stamps.iter().map(|&t| crate::number::readable(t)).collect();
        let (subject, what) = match times.as_slice() {
            [one] => (format!("its time {one} s stands"), "a stray time stamp"),
            [a, b] => (
                format!("their times {a} s and {b} s stand"),
                "stray time stamps",
            ),
            [a, .., b] => (
                format!("their times {a} s to {b} s stand"),
                "stray time stamps",
            ),
            [] => (String::new(), ""),
        };
        format!(
            "{} dropped: {subject} alone {} s {side} the rest of the log, more than \
             {STRAY_FACTOR} times the {} s the rest spans: {what} ({place})",
            counted(stamps.len(), noun),
            dur(step),
            dur(self.body_s)
        )
    }
}

/// "1 row", "2 rows": `n` of `noun`.
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

impl Timing {
    /// The samples at an end of the log (the first end when both qualify) that stand alone
    /// past a gap more than [`STRAY_FACTOR`] times longer than the body of the log: a segment
    /// of at most [`max_stray_end`] samples there (two, or a hundredth of the log). `None`
    /// when neither end has one. For a segment of `k` samples the body runs from the first segment of more than `k` samples
    /// to the last one, so that stray stamps side by side (1e299 s, then 1e300 s; or 1e6 s
    /// and 1e6 + 1 s, a step apart) or at both ends do not vouch for each other.
    ///
    /// Such samples carry stray time stamps (a row stamped 1e300 s, or 0 before a clock that
    /// counts from 1970): no window, filter or derivative fits in a segment of a sample or
    /// two, so they add nothing to any analysis but their stamps, and those alone would make
    /// the log's duration, the time axis of every figure and the duration a calibration
    /// stores. A reader drops them and says so with their lines. Samples after an outage of a
    /// few times the run are an outage, and are kept; so is an end segment longer than
    /// [`max_stray_end`], however far.
    pub fn stray_end(&self, time_s: &[f64]) -> Option<StrayEnd> {
        if self.segments.len() < 2 {
            return None;
        }
        let body_s = |run: usize| {
            let first = self.segments.iter().find(|r| r.len() > run)?;
            let last = self.segments.iter().rev().find(|r| r.len() > run)?;
            Some(time_s[last.end - 1] - time_s[first.start])
        };
        let ends = [
            (End::First, &self.segments[0], self.gaps.first()),
            (
                End::Last,
                &self.segments[self.segments.len() - 1],
                self.gaps.last(),
            ),
        ];
        for (end, seg, gap) in ends {
            if seg.len() > max_stray_end(time_s.len()) {
                continue;
            }
            if let (Some(body_s), Some(gap)) = (body_s(seg.len()), gap)
                && gap.step_s > STRAY_FACTOR * body_s
            {
                return Some(StrayEnd {
                    end,
                    samples: seg.len(),
                    body_s,
                });
            }
        }
        None
    }
}

/// Stamps out of line with the samples around them ([`stray_stamps`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StrayStamps {
    /// The runs of stray samples, in order: each of 1 to [`MAX_STRAY_RUN`] samples, with a
    /// sample that is not stray before and after it.
    pub runs: Vec<Range<usize>>,
    /// The step the samples around them keep (a first estimate of the log's step), s.
    pub step_s: f64,
}

impl StrayStamps {
    /// How many samples are stray.
    pub fn count(&self) -> usize {
        self.runs.iter().map(ExactSizeIterator::len).sum()
    }

    /// What a reader says when it drops them, as one problem: `noun` is what it calls a sample
    /// ("row", "sample"), `place` where the first stands ("line 20003"), for `time_s` the
    /// stamps [`stray_stamps`] was given. The first stamp is named with the two it stands
    /// between, so that the glitch can be found and judged in the file.
    pub fn message(&self, time_s: &[f64], noun: &str, place: &str) -> String {
        let Some(first) = self.runs.first() else {
            return String::new();
        };
        let stamp = |i: usize| time_s.get(i).map_or_else(String::new, |&t| stamp_text(t));
        let (before, after) = (stamp(first.start.wrapping_sub(1)), stamp(first.end));
        let n = self.count();
        let step = crate::number::readable(self.step_s);
        // The samples that vouch for the time base: both neighbours, or at an end of the log
        // the ones on its one side.
        let (sides, stamps_around) = match (before.is_empty(), after.is_empty()) {
            (true, _) => ("after", format!("from {after} s on")),
            (_, true) => ("before", format!("up to {before} s")),
            _ => ("before and after", format!("{before} s and {after} s")),
        };
        if self.runs.len() == 1 {
            let stamps: Vec<String> = first.clone().map(stamp).collect();
            let (subject, them, what) = if n == 1 {
                ("its time", "it", "a stray time stamp")
            } else {
                ("their times", "them", "stray time stamps")
            };
            format!(
                "{} dropped: {subject} {} s {} far out of line with the {noun}s {sides} {them} \
                 ({stamps_around}), which keep to the log's step of {step} s: {what} ({place})",
                counted(n, noun),
                stamps.join(" s and "),
                if n == 1 { "stands" } else { "stand" }
            )
        } else {
            format!(
                "{n} {noun}s dropped, in {} places: their times stand far out of line with the \
                 {noun}s around them, which keep to the log's step of {step} s: stray time \
                 stamps (first at {place}: {} s, the {noun}s {sides} it {stamps_around})",
                self.runs.len(),
                stamp(first.start)
            )
        }
    }
}

/// A stamp in a message: ten significant digits, so that the stamps of a clock counting from
/// 1970 still differ from their neighbours.
fn stamp_text(t: f64) -> String {
    crate::number::significant(t, 10)
}

/// The stray stamps of `time_s`, the stamps as read (before any row is dropped for time
/// order): runs of at most [`MAX_STRAY_RUN`] samples, each stamp of which lies more than
/// [`GAP_FACTOR`] steps before the sample before the run or after the sample after it, while
/// those two samples keep the log's step between them (positive, and at most [`GAP_FACTOR`]
/// steps for each step they span). At an end, where one side is missing, the two steps on the
/// other side vouch: a run at the start far ahead of them, a run at the end far behind them.
/// `None` when there is none.
///
/// A clock glitch stamps one row (or two) 1e6 s, 1e300 s or 0 in the middle of a run whose
/// other rows keep time. Read as it is, a stamp far ahead makes every later row "go
/// backwards" until the clock catches up with it (the rest of the log lost), and a stamp far
/// behind is only told as time going backwards. The samples around the run vouch for the
/// time base, so the run is what is wrong: dropping it loses no more rows than the time-order
/// check would, and usually far fewer. Nothing is invented: the samples on either side keep
/// their stamps, and a genuine gap (time going on from the later value) is no stray, as the
/// samples around a run across it do not keep the step. Rising stamps have none, and cost one
/// pass.
pub fn stray_stamps(time_s: &[f64]) -> Option<StrayStamps> {
    let n = time_s.len();
    if n < 3 || time_s.windows(2).all(|w| w[0] < w[1]) {
        return None;
    }
    let dt = rough_step(time_s);
    let far = GAP_FACTOR * dt;
    let is_run = |i: usize, k: usize| {
        let (before, after) = (time_s[i - 1], time_s[i + k]);
        let span = after - before;
        span > 0.0
            && span <= GAP_FACTOR * (k + 1) as f64 * dt
            && time_s[i..i + k]
                .iter()
                .all(|&t| t < before - far || t > after + far)
    };
    // Samples `a` and `b` keep the step between them.
    let keeps_step = |a: usize, b: usize| {
        let span = time_s[b] - time_s[a];
        span > 0.0 && span <= GAP_FACTOR * (b - a) as f64 * dt
    };
    let mut runs = Vec::new();
    // At the start, with only the samples after to vouch: a stamp or two ahead of the two
    // steps that follow (time would go backwards after them, and every later row be dropped
    // until the clock caught up). A first stamp far BEHIND the rest is a gap before the log,
    // told by `Timing::stray_end`.
    let mut i = 1;
    if let Some(k) = (1..=MAX_STRAY_RUN).find(|&k| {
        k + 2 < n && keeps_step(k, k + 2) && time_s[..k].iter().all(|&t| t > time_s[k] + far)
    }) {
        runs.push(0..k);
        i = k + 1;
    }
    while i + 1 < n {
        match (1..=MAX_STRAY_RUN).find(|&k| i + k < n && is_run(i, k)) {
            Some(k) => {
                runs.push(i..i + k);
                // The sample after the run kept time with the one before it: the next run
                // starts after it at the earliest.
                i += k + 1;
            }
            None => i += 1,
        }
    }
    // At the end, likewise: a stamp or two far behind the two steps before them.
    let done = runs.last().map_or(0, |r| r.end);
    if let Some(k) = (1..=MAX_STRAY_RUN).find(|&k| {
        n >= k + 3
            && n - k - 3 >= done
            && keeps_step(n - k - 3, n - k - 1)
            && time_s[n - k..].iter().all(|&t| t < time_s[n - k - 1] - far)
    }) {
        runs.push(n - k..n);
    }
    (!runs.is_empty()).then_some(StrayStamps { runs, step_s: dt })
}
