//! Two recorders' rows interleaved in one log: the rows switch back and forth between two
//! clocks that each keep time of their own (one gyro's rows at 0, 1, 2 s, another's at
//! 5000.5, 5001.5, 5002.5 s, written in turn). The one rule both readers (CSV and the drone
//! logs) refuse such a log by.
//!
//! No reading of the stamps as one clock holds: the rows of one clock look like stray stamps
//! between the rows of the other ([`super::timing::stray_stamps`]), so half the log would be
//! dropped as a glitch repeated thousands of times, and the other clock's last row kept as a
//! segment of its own past a gap that is only the offset between the clocks. The samples of
//! the two clocks are two logs, often of two gyros: which one is wanted only the user knows,
//! so the reader refuses and names the first place the rows switch clock.
//!
//! A switch is told from a glitch by what comes after it: a glitch stamps a row or two far out
//! of line and the rows return to their clock; the second clock's rows come back again and
//! again, and their stamps rise at the pace of the first clock's (both count real time). One
//! stray stamp, a few in several places (each its own value), a clock set back, a logger's
//! restart and a block sent twice make one backward step each, not a run of
//! [`MIN_SWITCHES`] such returns side by side.
//!
//! A second clock close to the first (less than [`GAP_FACTOR`] of its step away: 1.5 s at a
//! 1 s step) stands among the first's rows as rows swapped in pairs or a jittered clock's
//! do, and its stamps alone cannot tell it. What does is the rows before it, on one clock:
//! from the first switch on, the first clock keeps that step a row of its own while the rows
//! come thicker, the second clock standing the same offset from it each time
//! ([`follows_close`], [`two_clocks_in`]). Read by time order instead, the rows kept would
//! switch from one recorder to the other at the first step back. A second clock less than a
//! step away never steps back: the rows read as one clock at twice the rate.

use super::timing::GAP_FACTOR;

/// The fewest returns to the first clock in a row, each with the second clock's rows in
/// between and rising at the first clock's pace, for a log to hold two recorders' rows
/// interleaved ([`interleaved_clocks`]): a clock glitch garbles a row or two in a few places,
/// not sixteen in a row, each a step on from the one before.
pub const MIN_SWITCHES: usize = 16;

/// Where the rows of a log first switch between two clocks ([`interleaved_clocks`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interleaved {
    /// Index of the last sample on the first clock before the first switch.
    pub before: usize,
    /// Index of the first sample on the second clock: where the rows first switch.
    pub away: usize,
    /// Index of the sample where they come back to the first clock.
    pub back: usize,
    /// The stamps of those three samples, s.
    pub before_s: f64,
    /// See `before_s`.
    pub away_s: f64,
    /// See `before_s`.
    pub back_s: f64,
    /// How many times in a row the rows come back to the first clock from the second.
    pub returns: usize,
}

impl Interleaved {
    /// What a reader says when it refuses the log: `noun` is what it calls a sample ("row",
    /// "sample"), `place(i)` where sample `i` stands ("line 3"), `advice` how the user parts
    /// the two recorders in the reader's words. Both readers word it through this, so that a
    /// log says the same in a CSV and a drone log.
    pub fn message(&self, noun: &str, place: impl Fn(usize) -> String, advice: &str) -> String {
        let offset = self.away_s - self.before_s;
        let side = if offset > 0.0 { "ahead of" } else { "behind" };
        format!(
            "the {noun}s alternate between two clocks from {} on: its time {} s stands {} s \
             {side} the {noun}s around it ({} s at {}, {} s at {}), and the {noun}s switch to \
             that clock and back {} times in a row, each clock keeping time of its own: the log \
             holds two recorders' {noun}s interleaved; {advice}",
            place(self.away),
            stamp(self.away_s),
            crate::number::readable(offset.abs()),
            stamp(self.before_s),
            place(self.before),
            stamp(self.back_s),
            place(self.back),
            self.returns
        )
    }
}

/// A stamp in a message: ten significant digits, so that stamps a step apart differ.
fn stamp(t: f64) -> String {
    crate::number::significant(t, 10)
}

/// One return to the first clock: the samples `away..back` stand on the second clock between
/// `before` and `back` on the first; `far` when they stand more than [`GAP_FACTOR`] of the
/// first clock's step ahead of `back`.
#[derive(Debug, Clone, Copy)]
struct Return {
    before: usize,
    away: usize,
    back: usize,
    far: bool,
}

/// The return to a first clock at `back` (a step back from the sample before it), if the
/// samples just before it rise on a clock of their own ahead of it: a run that rises, all
/// stamps ahead of `back`'s, after a sample behind it (`before`, the first clock's last).
fn return_at(time_s: &[f64], back: usize) -> Option<Return> {
    let t = time_s[back];
    let last = time_s[back - 1];
    if !(t.is_finite() && last.is_finite() && last > t) {
        return None;
    }
    let mut away = back - 1;
    while away > 0 && time_s[away - 1] > t && time_s[away - 1] < time_s[away] {
        away -= 1;
    }
    let before = away.checked_sub(1)?;
    let step = t - time_s[before];
    (step > 0.0).then_some(Return {
        before,
        away,
        back,
        far: time_s[away] - t > GAP_FACTOR * step,
    })
}

/// Whether `next` follows `prev` as the next return of two interleaved clocks: the first
/// clock runs on between them, and the second clock's first stamp rises from the one return to
/// the next at the pace of the first clock (within [`GAP_FACTOR`] either way), past the
/// previous run's last stamp.
fn follows(time_s: &[f64], prev: &Return, next: &Return) -> bool {
    if next.before < prev.back || next.far != prev.far {
        return false;
    }
    let second = time_s[next.away] - time_s[prev.away];
    let first = time_s[next.back] - time_s[prev.back];
    time_s[next.away] > time_s[prev.back - 1]
        && first > 0.0
        && second > 0.0
        && second <= GAP_FACTOR * first
        && first <= GAP_FACTOR * second
}

/// How many steps of the rows before a run of close returns tell the first clock's step.
const LEAD_STEPS: usize = 8;

/// How far (relative) a close return may stray from the lead's step and the first return's
/// offset ([`follows_close`]).
const CLOSE_TOLERANCE: f64 = 0.25;

/// The step of the first clock before a return at `before` whose second clock stands close
/// (within [`GAP_FACTOR`] steps): the median of the [`LEAD_STEPS`] steps up to `before`, when
/// they all rise. A second clock that stands close cannot be told by its stamps alone from
/// rows swapped in pairs or a jittered clock's: what tells it is the rows before it, on one
/// clock, whose step the first clock keeps while the rows come twice as thick.
fn lead_step(time_s: &[f64], before: usize) -> Option<f64> {
    let start = before.checked_sub(LEAD_STEPS)?;
    let mut steps: Vec<f64> = time_s[start..=before]
        .windows(2)
        .map(|w| w[1] - w[0])
        .collect();
    if !steps.iter().all(|d| d.is_finite() && *d > 0.0) {
        return None;
    }
    steps.sort_by(f64::total_cmp);
    Some(steps[steps.len() / 2])
}

/// The lead's step of a close streak just broken, for a close return `r` that comes right
/// after it: when the second clock stands *behind* the first, the first return takes the
/// first clock's last row before the switch for a row of the second (both stand ahead of the
/// step back), so its offset is not the ones after it and the streak breaks at the second
/// return. The rows from there on are no longer on one clock, so the lead is the broken
/// streak's, read from the rows before it, while `r` stands within [`LEAD_STEPS`] rows of it.
fn inherited_lead(broken: Option<&Streak>, r: &Return) -> Option<f64> {
    match broken {
        Some((_, last, _, Some(lead_s)))
            if r.before >= last.before && r.before - last.back < LEAD_STEPS =>
        {
            Some(*lead_s)
        }
        _ => None,
    }
}

/// Whether close return `next` follows `prev` ([`follows`]) as a second clock interleaved
/// with a first of step `lead_s`: the first clock's rows between them rise at `lead_s` a row
/// (rows swapped in pairs rise two steps a row), and the second clock stands the same offset
/// from the first each time (a jittered stamp stands out by whatever its jitter was).
fn follows_close(time_s: &[f64], prev: &Return, next: &Return, lead_s: f64) -> bool {
    if !follows(time_s, prev, next) {
        return false;
    }
    let rise = time_s[next.back] - time_s[prev.back];
    let first_rows = (next.away - prev.back) as f64;
    let offset = |r: &Return| time_s[r.away] - time_s[r.back];
    (rise / first_rows - lead_s).abs() <= CLOSE_TOLERANCE * lead_s
        && (offset(next) - offset(prev)).abs() <= CLOSE_TOLERANCE * lead_s
}

/// A streak of returns: the first, the last, how many, and for close returns the lead's step.
type Streak = (Return, Return, usize, Option<f64>);

/// Whether `streak` is two clocks interleaved: [`MIN_SWITCHES`] switches or more and, for
/// close returns, rows thicker over it than the lead's, the second clock's a quarter of them
/// or more. A jittered clock's rows, the ones stamped out of line among them, come one a
/// step: their steps back can line up as returns, never thicken the rows.
fn two_clocks_in(time_s: &[f64], (first, last, k, lead): &Streak) -> bool {
    let thicker = match lead {
        None => true,
        Some(lead_s) => {
            let rise = time_s[last.back] - time_s[first.back];
            let rows = (last.back - first.back) as f64;
            rise <= (1.0 - CLOSE_TOLERANCE) * lead_s * rows
        }
    };
    thicker && switches(time_s, first, *k) >= MIN_SWITCHES
}

/// The switches a streak of `returns` returns from `first` on counts: one more when the rows
/// stepped back onto the first clock at its first row too (the second clock ahead of the
/// first from the log's start, or behind it: the first switch is then a step back with no
/// row of the first clock before it, and the count is the same whichever clock is ahead).
fn switches(time_s: &[f64], first: &Return, returns: usize) -> usize {
    let stepped_in = first.before > 0 && time_s[first.before] < time_s[first.before - 1];
    returns + usize::from(stepped_in)
}

/// The first place where the rows of `time_s` (the stamps as read, before any is dropped for
/// time order) switch between two clocks [`MIN_SWITCHES`] times in a row or more, `None` when
/// they do not. Each switch is a return to the first clock (a step back) from a run of samples
/// rising on a second clock far from it; the returns follow each other with no other step
/// back between them, the second clock's stamps rising from one to the next at the first
/// clock's pace. Whichever clock is behind is the first. One pass: each sample is looked at a
/// bounded number of times.
pub fn interleaved_clocks(time_s: &[f64]) -> Option<Interleaved> {
    // Whichever way finds the rows switching clock first.
    match (switching_clocks(time_s), alternating(time_s)) {
        (Some(a), Some(b)) => Some(if b.away < a.away { b } else { a }),
        (a, b) => a.or(b),
    }
}

/// [`interleaved_clocks`] by streaks of returns to the first clock from a second that keeps
/// its own time (far, or close at a fixed offset).
fn switching_clocks(time_s: &[f64]) -> Option<Interleaved> {
    let mut streak: Option<Streak> = None;
    let mut found: Option<(Return, usize)> = None;
    for i in 1..time_s.len() {
        let (a, b) = (time_s[i - 1], time_s[i]);
        // A step on or a repeat leaves the streak as it is; any other step back is a return
        // that follows the last, or breaks the streak.
        if b >= a {
            continue;
        }
        let here = return_at(time_s, i);
        let follows_last = |(_, last, _, lead): &Streak, r: &Return| match lead {
            None => follows(time_s, last, r),
            Some(lead_s) => follows_close(time_s, last, r, *lead_s),
        };
        streak = match (streak, here) {
            (Some(s), Some(r)) if follows_last(&s, &r) => Some((s.0, r, s.2 + 1, s.3)),
            (_, r) => {
                if let Some(s) = streak
                    && two_clocks_in(time_s, &s)
                {
                    found = Some((s.0, s.2));
                    break;
                }
                // A far return starts a streak; a close one only after rows on one clock, or
                // right after a close streak whose lead it inherits.
                r.and_then(|r| {
                    if r.far {
                        Some((r, r, 1, None))
                    } else {
                        lead_step(time_s, r.before)
                            .or_else(|| inherited_lead(streak.as_ref(), &r))
                            .map(|lead_s| (r, r, 1, Some(lead_s)))
                    }
                })
            }
        };
    }
    let (first, returns) = match (found, streak) {
        (Some(f), _) => f,
        (None, Some(s)) if two_clocks_in(time_s, &s) => (s.0, s.2),
        _ => return None,
    };
    Some(Interleaved {
        before: first.before,
        away: first.away,
        back: first.back,
        before_s: time_s[first.before],
        away_s: time_s[first.away],
        back_s: time_s[first.back],
        returns: switches(time_s, &first, returns),
    })
}

/// A second clock whose stamps jitter about an offset less than [`GAP_FACTOR`] steps from the
/// first's: its rows, one after each of the first clock's, step back and on in turn, but stand
/// no fixed offset away, so [`follows_close`] finds no streak. What tells them is the same as
/// for a close clock that keeps its offset: after rows on one clock (its step the lead's),
/// the steps go back and on [`MIN_SWITCHES`] times in a row or more, and the rows come
/// thicker, rising a quarter less than the lead's step a row or more. Rows swapped in pairs
/// go back and on too, but rise the lead's step a row; a jittered clock's steps back come
/// here and there, never in a row.
fn alternating(time_s: &[f64]) -> Option<Interleaved> {
    let mut start: Option<usize> = None; // the first step back of the run
    let mut backs = 0;
    for i in 1..time_s.len() {
        let (a, b) = (time_s[i - 1], time_s[i]);
        if !(a.is_finite() && b.is_finite()) {
            start = None;
            backs = 0;
            continue;
        }
        let back = b < a;
        match start {
            None if back => {
                start = Some(i);
                backs = 1;
            }
            None => {}
            Some(s) => {
                // The run goes on while the steps go back and on in turn.
                let want_back = (i - s) % 2 == 0;
                if back == want_back && b != a {
                    backs += usize::from(back);
                } else {
                    start = back.then_some(i);
                    backs = usize::from(back);
                    continue;
                }
            }
        }
        let Some(s) = start else { continue };
        if backs < MIN_SWITCHES || s < 2 {
            continue;
        }
        let before = s - 1;
        let Some(lead_s) = lead_step(time_s, before) else {
            // No rows on one clock before the run: nothing to tell its pace by.
            start = None;
            backs = 0;
            continue;
        };
        let rows = (i - before) as f64;
        let rise = time_s[i] - time_s[before];
        if rise <= (1.0 - CLOSE_TOLERANCE) * lead_s * rows {
            return Some(Interleaved {
                before,
                away: s,
                back: s + 1,
                before_s: time_s[before],
                away_s: time_s[s],
                back_s: time_s[s + 1],
                returns: count_backs(time_s, s),
            });
        }
    }
    None
}

/// How many steps back the run from `start` (a step back) holds, the steps going back and on
/// in turn.
fn count_backs(time_s: &[f64], start: usize) -> usize {
    let mut n = 0;
    let mut i = start;
    while i < time_s.len() && time_s[i] < time_s[i - 1] {
        n += 1;
        i += 1;
        if i >= time_s.len() || time_s[i] <= time_s[i - 1] {
            break;
        }
        i += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers uniform in [0, 1) from `seed`, the same each run (a linear congruential
    /// generator: the tests need spread, not quality).
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn at_one_s(n: usize) -> Vec<f64> {
        (0..n).map(|i| i as f64).collect()
    }

    /// `n` rows of a clock from 0 s at 1 s, each followed by `every`-th a row of a second clock
    /// `offset_s` away.
    fn two_clocks(n: usize, every: usize, offset_s: f64) -> Vec<f64> {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(i as f64);
            if i % every == every - 1 {
                t.push(i as f64 + offset_s);
            }
        }
        t
    }

    #[test]
    fn rows_alternating_between_two_clocks_are_found_at_the_first_switch() {
        let t = two_clocks(1000, 1, 5000.5);
        let got = interleaved_clocks(&t).expect("two clocks");
        assert_eq!((got.before, got.away, got.back), (0, 1, 2));
        assert_eq!((got.before_s, got.away_s, got.back_s), (0.0, 5000.5, 1.0));
        assert_eq!(got.returns, 999);
        // The second clock behind the first: the first switch is found where its rows have
        // a row of their own before them.
        let t = two_clocks(1000, 1, -5000.5);
        let got = interleaved_clocks(&t).expect("two clocks");
        assert_eq!((got.before, got.away, got.back), (1, 2, 3));
        // One row of the second clock every ten of the first's.
        let t = two_clocks(1000, 10, 1e6);
        let got = interleaved_clocks(&t).expect("two clocks");
        assert_eq!((got.before, got.away, got.back), (9, 10, 11));
        assert_eq!(got.returns, 99);
    }

    #[test]
    fn glitches_restarts_and_resent_blocks_are_no_second_clock() {
        let n = 3000;
        // Stray stamps in many places, each of its own value (or the same value each time).
        for stray in [|_: usize| 1e9, |k: usize| 1e9 * (k % 7) as f64] {
            let mut t = at_one_s(n);
            for (k, at) in (100..n).step_by(100).enumerate() {
                t[at] = stray(k);
            }
            assert_eq!(interleaved_clocks(&t), None);
        }
        // A logger restarting every 500 s.
        let t: Vec<f64> = (0..n).map(|i| (i % 500) as f64).collect();
        assert_eq!(interleaved_clocks(&t), None);
        // A block sent twice, a few rows out of order, newest first.
        let mut t = at_one_s(n);
        let block = t[1900..2000].to_vec();
        t.splice(2000..2000, block);
        assert_eq!(interleaved_clocks(&t), None);
        let mut t = at_one_s(n);
        t[1000..1010].rotate_left(5);
        assert_eq!(interleaved_clocks(&t), None);
        let t: Vec<f64> = at_one_s(n).into_iter().rev().collect();
        assert_eq!(interleaved_clocks(&t), None);
        // Rows swapped in pairs stand a step apart, not on a clock of their own.
        let t: Vec<f64> = (0..n).map(|i| (i ^ 1) as f64).collect();
        assert_eq!(interleaved_clocks(&t), None);
    }

    #[test]
    fn fewer_switches_than_the_least_are_no_second_clock() {
        let mut t = at_one_s(1000);
        // MIN_SWITCHES - 1 rows of a second clock among the first's, then the first alone.
        let mut mixed = two_clocks(MIN_SWITCHES - 1, 1, 5000.5);
        mixed.extend(t.drain(MIN_SWITCHES - 1..));
        assert_eq!(interleaved_clocks(&mixed), None);
        let mut mixed = two_clocks(MIN_SWITCHES + 1, 1, 5000.5);
        mixed.extend(at_one_s(1000).drain(MIN_SWITCHES + 1..));
        assert!(interleaved_clocks(&mixed).is_some());
    }

    /// Clock A at 0, 1, 2 … s alone for `lead` rows, then each of its rows followed by one of
    /// clock B, `offset_s` away, for `n` rows more.
    fn after_a_lead(lead: usize, n: usize, offset_s: f64) -> Vec<f64> {
        let mut t = at_one_s(lead);
        for i in lead..lead + n {
            t.extend([i as f64, i as f64 + offset_s]);
        }
        t
    }

    #[test]
    fn a_second_clock_close_to_the_first_is_found_after_rows_on_one_clock() {
        // B less than 2.5 steps from A: its rows stand close among A's, yet the rows come
        // twice as thick as before, A's keeping its own step.
        for offset_s in [1.1, 1.5, 2.4, 3.0, 3.5] {
            let t = after_a_lead(1000, 2000, offset_s);
            let got = interleaved_clocks(&t).unwrap_or_else(|| panic!("{offset_s} s"));
            // A's rows 0..=1000 at indices 0..=1000, B's first at 1001, A's next at 1002.
            assert_eq!(
                (got.before, got.away, got.back),
                (1000, 1001, 1002),
                "{offset_s}"
            );
            assert!(
                (got.away_s - got.before_s - offset_s).abs() < 1e-9,
                "{offset_s}"
            );
            assert_eq!(got.returns, 1999, "{offset_s} s");
        }
        // Fewer switches than the least: not refused.
        let t = after_a_lead(1000, MIN_SWITCHES - 1, 1.5);
        let mut t = t;
        t.extend((1000 + MIN_SWITCHES - 1..3000).map(|i| i as f64));
        assert_eq!(interleaved_clocks(&t), None);
    }

    #[test]
    fn a_second_clock_close_behind_the_first_is_found_too() {
        // B 1.1 to 2.4 steps behind A: the mirror of the cases above, refused alike.
        for offset_s in [-0.6, -1.1, -1.5, -2.4] {
            let t = after_a_lead(1000, 2000, offset_s);
            let got = interleaved_clocks(&t).unwrap_or_else(|| panic!("{offset_s} s"));
            // Found within a row or two of where B's rows begin (index 1001).
            assert!((1000..=1004).contains(&got.away), "{offset_s}: {got:?}");
            assert!(
                (got.away_s - got.before_s).abs() > 0.5 && got.returns >= 1990,
                "{offset_s}: {got:?}"
            );
        }
    }

    #[test]
    fn a_second_clock_close_behind_and_jittering_is_found() {
        // B 1.5 s behind A, its stamps jittering by up to ±0.3 s: no fixed offset, yet the
        // steps go back and on in turn and the rows come twice as thick.
        let mut draw = uniform(99);
        for offset_s in [-1.5, -1.1, 1.5] {
            let mut t: Vec<f64> = (0..1000).map(|i| i as f64).collect();
            for i in 1000..3000 {
                t.extend([i as f64, i as f64 + offset_s + 0.6 * (draw() - 0.5)]);
            }
            let got = interleaved_clocks(&t).unwrap_or_else(|| panic!("{offset_s} s"));
            assert!((999..=1004).contains(&got.away), "{offset_s}: {got:?}");
            assert!(got.returns >= MIN_SWITCHES, "{offset_s}: {got:?}");
        }
    }

    #[test]
    fn rows_swapped_in_pairs_after_rows_in_order_are_no_second_clock() {
        // Their stamps are those of a second clock 1.5 steps ahead; but the rows swapped rise
        // two of the lead's steps a row, where a second clock's leave the first's at one.
        let mut t = at_one_s(1000);
        t.extend((1000..3000).map(|i| (i ^ 1) as f64));
        assert_eq!(interleaved_clocks(&t), None);
        // A clock whose stamps jitter by up to ±0.8 steps: many steps back, none of a second
        // clock.
        let mut draw = uniform(12345);
        let t: Vec<f64> = (0..20_000)
            .map(|i| i as f64 + 1.6 * (draw() - 0.5))
            .collect();
        assert!(t.windows(2).filter(|w| w[1] < w[0]).count() > 1000);
        assert_eq!(interleaved_clocks(&t), None);
    }

    #[test]
    fn a_second_clock_behind_takes_as_many_switches_as_one_ahead() {
        // MIN_SWITCHES rows of B among A's, then A alone: refused with B ahead or behind.
        for offset_s in [5000.5, -5000.5] {
            let mut t = two_clocks(MIN_SWITCHES, 1, offset_s);
            t.extend((MIN_SWITCHES..1000).map(|i| i as f64));
            let got = interleaved_clocks(&t).unwrap_or_else(|| panic!("{offset_s}"));
            assert_eq!(got.returns, MIN_SWITCHES, "{offset_s}");
            let mut t = two_clocks(MIN_SWITCHES - 1, 1, offset_s);
            t.extend((MIN_SWITCHES - 1..1000).map(|i| i as f64));
            assert_eq!(interleaved_clocks(&t), None, "{offset_s}");
        }
    }

    #[test]
    fn blocks_of_a_second_clock_between_the_firsts_rows_are_found() {
        // A at 1 s; after every 2000 of its rows a block of 1000 rows of B, whose clock is
        // 1.5 s ahead, covering A's last 1000 s: 20 blocks.
        let mut t = Vec::new();
        for i in 0..40_000usize {
            t.push(i as f64);
            if i % 2000 == 1999 {
                t.extend((i + 1 - 1000..=i).map(|k| k as f64 + 1.5));
            }
        }
        assert!(interleaved_clocks(&t).is_some());
    }
}
