//! Time order: which samples a reader keeps so that the stamps rise, the one rule of the CSV
//! reader and of the drone logs' readers.
//!
//! A stamp that repeats the last kept one is dropped. A stamp behind the last kept one has
//! three readings:
//!
//! - the samples after it are late (a glitch stamped a few of them behind): they go until the
//!   clock passes the last kept stamp again;
//! - the samples kept just before it are early (a glitch stamped a few of them ahead): they go,
//!   and the log goes on from where it was before them;
//! - the clock went back and ran again over the same times (a logger restarted, whatever its
//!   first stamp after the boot; a clock set back): both of the above would drop a run of
//!   samples and splice the two runs of the clock into one log that is neither (a 10,000-s
//!   run followed by the second run's samples past 10,000 s), so one run is kept whole, the
//!   longer, and the other dropped.
//!
//! A glitch drops few samples one way and many the other; a restart drops about as many
//! either way, and many: the clock goes back over most of the run kept. So when both readings
//! would drop more than [`MIN_RESTART`] samples, neither more than twice the other, and the
//! clock goes back over at least half of the run kept, the step is a restart, unless the
//! samples after it are copies of the ones before (the same stamps and readings: a block sent
//! twice, which loses its second copy). Else the reading that drops fewer is taken (on a tie,
//! the samples after): a clock set back by 50 s late in a long run loses the 50 s of rows
//! behind the time it had reached, not half the log. Read the first
//! way only, three rows stamped +10,000 s in a log at 1 s kept those three and dropped the
//! 9,999 good rows after them; [`super::timing::stray_stamps`] takes one or two such rows with
//! a message of their own.

/// The fewest samples both readings of a backward step must drop for it to be a restart of
/// the clock ([`time_order`]): a host that stamps a few samples out of order is no restart,
/// and dropping a run of a dozen samples to splice is a small harm against dropping a run.
pub const MIN_RESTART: usize = 16;

/// How many samples after a backward step are compared with the ones before it to tell a
/// block sent twice from a restart.
const COPIES_COMPARED: usize = 8;

/// The first occurrence and count of something dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tally {
    /// Index of the first sample (in the stamps given).
    pub first: usize,
    /// How many.
    pub count: usize,
}

impl Tally {
    fn note(t: &mut Option<Tally>, i: usize) {
        match t {
            Some(t) => {
                t.count += 1;
                t.first = t.first.min(i);
            }
            None => *t = Some(Tally { first: i, count: 1 }),
        }
    }
}

/// Samples dropped because they go back: `first_s` is the first one's stamp, `after_s` the
/// stamp kept before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Backwards {
    /// Where and how many.
    pub tally: Tally,
    /// The first dropped sample's stamp, s.
    pub first_s: f64,
    /// The kept stamp it stood behind, s.
    pub after_s: f64,
}

/// Samples dropped because they stand ahead of the samples the log goes on with: `first_s`
/// is the first one's stamp; `resumed` the sample after the run, whose stamp `resumed_s`
/// keeps to the samples before the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ahead {
    /// Where and how many.
    pub tally: Tally,
    /// The first dropped sample's stamp, s.
    pub first_s: f64,
    /// Index of the sample the log goes on with.
    pub resumed: usize,
    /// Its stamp, s.
    pub resumed_s: f64,
    /// The stamp kept before it (the run's last), s.
    pub stepped_from_s: f64,
    /// Whether the run began the samples kept (none before it for the log to go on from).
    pub from_start: bool,
}

/// The clock going back and running again over the same times: one run is kept whole, the
/// longer, and the samples of the other dropped ([`time_order`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Restarts {
    /// The samples dropped: the first and how many.
    pub tally: Tally,
    /// Index of the first sample after the first restart.
    pub at: usize,
    /// Its stamp, s.
    pub to_s: f64,
    /// The stamp kept before it, s.
    pub from_s: f64,
    /// How many restarts.
    pub count: usize,
    /// Whether the run before the first restart was the one dropped (else the samples from
    /// it on).
    pub dropped_before: bool,
    /// Whether the two parts were as long as each other (the later is dropped).
    pub even: bool,
}

impl Backwards {
    /// What a reader says: `noun` is what it calls a sample ("row"), `place` where the first
    /// stands ("line 20003").
    pub fn message(&self, noun: &str, place: &str) -> String {
        format!(
            "{}: time went backwards (first at {place}: {} s after {} s)",
            dropped(self.tally.count, noun),
            stamp(self.first_s),
            stamp(self.after_s)
        )
    }
}

impl Ahead {
    /// What a reader says: `noun` is what it calls a sample ("row"), `place` where the first
    /// stands ("line 8947"), `resumed` where the log goes on ("line 8950").
    pub fn message(&self, noun: &str, place: &str, resumed: &str) -> String {
        let after = if self.from_start {
            format!("stamped ahead of the {noun}s after them, which run on past them")
        } else {
            format!(
                "stamped ahead of the {noun}s after them, which go on from the {noun}s before \
                 them"
            )
        };
        format!(
            "{}: {after} (first at {place}: {} s; the log goes on at {resumed} with {} s, after \
             {} s)",
            dropped(self.tally.count, noun),
            stamp(self.first_s),
            stamp(self.resumed_s),
            stamp(self.stepped_from_s)
        )
    }
}

impl Restarts {
    /// What a reader says: `noun` is what it calls a sample ("row"), `at` where the clock
    /// first goes back ("line 10002"), `first` where the first dropped sample stands.
    pub fn message(&self, noun: &str, at: &str, first: &str) -> String {
        let which = match (self.dropped_before, self.even) {
            (true, _) => format!("the {noun}s before it, the shorter part,"),
            (false, false) => format!("the {noun}s from it on, the shorter part,"),
            (false, true) => format!("the {noun}s from it on, as many as the {noun}s before it,"),
        };
        let (times, split) = match self.count {
            1 => (String::new(), format!("split the log at {at}")),
            2 => (
                ", and once more".to_string(),
                format!("split the log at each restart (the first at {at})"),
            ),
            k => (
                format!(", and {} times more", k - 1),
                format!("split the log at each restart (the first at {at})"),
            ),
        };
        format!(
            "{}: the clock goes back at {at} ({} s after {} s{times}) and runs again over the \
             same times: the log holds runs of a clock that restarted or was set back; {which} \
             dropped (first at {first}) so that one run is kept whole rather than two spliced; \
             to use the other, {split}",
            dropped(self.tally.count, noun),
            stamp(self.to_s),
            stamp(self.from_s)
        )
    }
}

/// A stamp in a message: ten significant digits, so that stamps a step apart differ.
fn stamp(t: f64) -> String {
    crate::number::significant(t, 10)
}

/// "1 row dropped", "3 rows dropped".
fn dropped(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun} dropped")
    } else {
        format!("{n} {noun}s dropped")
    }
}

/// One thing a reader tells of the samples [`time_order`] dropped ([`TimeOrder::told`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Told {
    /// Index of the first sample dropped.
    pub first: usize,
    /// How many.
    pub count: usize,
    /// Whether they repeat a stamp (else they go back in time).
    pub repeated: bool,
    /// The sentence.
    pub message: String,
}

/// What [`time_order`] drops.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TimeOrder {
    /// Indices of the samples dropped, ascending (none of those skipped).
    pub dropped: Vec<usize>,
    /// Stamps equal to the last kept one.
    pub repeated: Option<Tally>,
    /// Stamps behind the last kept one, dropped until the clock passes it again.
    pub backwards: Option<Backwards>,
    /// Runs stamped ahead of the samples after them, dropped because the log goes on from
    /// the time before them.
    pub ahead: Option<Ahead>,
    /// The clock going back and running again: the shorter part dropped.
    pub restarts: Option<Restarts>,
}

impl TimeOrder {
    /// How many samples go back in time: those behind and those ahead.
    pub fn out_of_order(&self) -> usize {
        self.backwards.map_or(0, |b| b.tally.count)
            + self.ahead.map_or(0, |a| a.tally.count)
            + self.restarts.map_or(0, |r| r.tally.count)
    }

    /// What a reader tells of the samples dropped, in the order repeats, behind, restarts,
    /// ahead: `noun` is what it calls a sample ("row"), `place(i)` where sample `i` stands
    /// ("line 12"), `earlier` what a repeated stamp repeats in its words ("value"). Both
    /// readers word them through this, so that a log says the same in a CSV and a drone log.
    pub fn told(&self, noun: &str, place: impl Fn(usize) -> String, earlier: &str) -> Vec<Told> {
        let mut out = Vec::new();
        if let Some(t) = self.repeated {
            out.push(Told {
                first: t.first,
                count: t.count,
                repeated: true,
                message: format!(
                    "{}: time repeats an earlier {earlier} (first at {})",
                    dropped(t.count, noun),
                    place(t.first)
                ),
            });
        }
        if let Some(b) = self.backwards {
            out.push(Told {
                first: b.tally.first,
                count: b.tally.count,
                repeated: false,
                message: b.message(noun, &place(b.tally.first)),
            });
        }
        if let Some(r) = self.restarts {
            out.push(Told {
                first: r.tally.first,
                count: r.tally.count,
                repeated: false,
                message: r.message(noun, &place(r.at), &place(r.tally.first)),
            });
        }
        if let Some(a) = self.ahead {
            out.push(Told {
                first: a.tally.first,
                count: a.tally.count,
                repeated: false,
                message: a.message(noun, &place(a.tally.first), &place(a.resumed)),
            });
        }
        out
    }

    /// The first backward step, for a refusal: the index of the sample that stands behind,
    /// its stamp and the stamp before it (for a run dropped as ahead, the sample the log goes
    /// on with and the stamp before it). `None` when every sample is in order.
    pub fn first_step_back(&self) -> Option<(usize, f64, f64)> {
        [
            self.backwards
                .map(|b| (b.tally.first, b.first_s, b.after_s)),
            self.ahead
                .map(|a| (a.resumed, a.resumed_s, a.stepped_from_s)),
            self.restarts.map(|r| (r.at, r.to_s, r.from_s)),
        ]
        .into_iter()
        .flatten()
        .min_by_key(|s| s.0)
    }
}

/// The samples of `time_s` to drop so that the rest rise strictly, leaving out those for
/// which `skip` is true (dropped already for another reason). Each backward step is read the
/// way that drops fewer samples (see the module's page): the run just kept that stands at or
/// ahead of the new stamp, or the samples from it on that stay at or behind the last kept one.
/// The two are counted side by side and the count stops as soon as one is the smaller, so
/// the whole pass costs a bounded number of looks per sample dropped, on any input. A stamp
/// that is not finite is dropped as going back.
pub fn time_order(time_s: &[f64], skip: impl Fn(usize) -> bool) -> TimeOrder {
    time_order_of(time_s, skip, |_, _| true)
}

/// [`time_order`] of samples whose readings `same(a, b)` compares (every value but the
/// stamp): a block sent twice repeats the readings as well as the stamps, a clock set back
/// into a run it already logged does not. [`time_order`] takes equal stamps for copies.
pub fn time_order_of(
    time_s: &[f64],
    skip: impl Fn(usize) -> bool,
    same: impl Fn(usize, usize) -> bool,
) -> TimeOrder {
    let n = time_s.len();
    let mut out = TimeOrder::default();
    let mut kept: Vec<usize> = Vec::with_capacity(n);
    // The kept stamp behind which the samples from a backward step on were judged late: until
    // a sample passes it, the ones behind it are dropped without counting again.
    let mut late_behind: Option<f64> = None;
    let mut repeated = None;
    let mut backwards: Option<Backwards> = None;
    let mut ahead: Option<Ahead> = None;
    let mut restarts: Option<Restarts> = None;
    // Samples not skipped from the one looked at to the end: the part after a restart.
    let mut remaining = (0..n).filter(|&i| !skip(i)).count();
    for i in 0..n {
        if skip(i) {
            continue;
        }
        remaining -= 1;
        let t = time_s[i];
        let last = kept.last().map_or(f64::NEG_INFINITY, |&j| time_s[j]);
        if !t.is_finite() {
            drop_behind(&mut out, &mut backwards, i, t, last);
            continue;
        }
        if t > last {
            kept.push(i);
            late_behind = None;
            continue;
        }
        if t == last {
            out.dropped.push(i);
            Tally::note(&mut repeated, i);
            continue;
        }
        if late_behind == Some(last) {
            drop_behind(&mut out, &mut backwards, i, t, last);
            continue;
        }
        // `early`: kept samples at or ahead of `t`; `late`: samples from `i` on at or behind
        // `last`. Each counted up to a limit that doubles until one count is known (below
        // it), so that a step costs a few looks per sample the reading taken drops.
        let early_upto = |limit: usize| {
            kept.iter()
                .rev()
                .take(limit)
                .take_while(|&&j| time_s[j] >= t)
                .count()
        };
        let late_upto = |limit: usize| {
            (i..n)
                .filter(|&k| !skip(k))
                .take(limit)
                .take_while(|&k| time_s[k] <= last)
                .count()
        };
        let mut limit = 4;
        let (mut early, mut late) = loop {
            let (e, l) = (early_upto(limit), late_upto(limit));
            if e < limit || l < limit {
                break (e, l);
            }
            limit *= 2;
        };
        // The smaller count is known; the other, when both are runs, up to twice it: a
        // restart drops runs of about the same length either way, a glitch few one way and
        // many the other.
        let small = early.min(late);
        if small > MIN_RESTART {
            if early <= late {
                late = late_upto(2 * small + 1);
            } else {
                early = early_upto(2 * small + 1);
            }
        }
        let early_wins = early < late;
        // A block sent twice: the samples after the step repeat the ones at or ahead of its
        // stamp, stamp and reading, all through the overlap (compared at places spread over
        // it: two runs of one simulator or one chamber program may begin alike).
        let copies = || {
            let early_run = &kept[kept.len() - early..];
            let late_run: Vec<usize> = (i..n).filter(|&k| !skip(k)).take(small).collect();
            let overlap = early_run.len().min(late_run.len());
            (0..COPIES_COMPARED)
                .map(|j| j * overlap.saturating_sub(1) / (COPIES_COMPARED - 1))
                .all(|j| {
                    let (a, b) = (early_run[j], late_run[j]);
                    time_s[a] == time_s[b] && same(a, b)
                })
        };
        if small > MIN_RESTART
            && early.max(late) <= 2 * small
            && 2 * early >= kept.len()
            && !copies()
        {
            // The clock went back and ran again: the longer part is kept whole.
            let after = remaining + 1;
            let dropped_before = after > kept.len();
            let even = after == kept.len();
            let gone = if dropped_before { kept.len() } else { after };
            let first = if dropped_before { kept[0] } else { i };
            match &mut restarts {
                Some(r) => {
                    r.count += 1;
                    r.tally.count += gone;
                }
                None => {
                    restarts = Some(Restarts {
                        tally: Tally { first, count: gone },
                        at: i,
                        to_s: t,
                        from_s: last,
                        count: 1,
                        dropped_before,
                        even,
                    });
                }
            }
            if dropped_before {
                out.dropped.append(&mut kept);
                kept.push(i);
                late_behind = None;
                continue;
            }
            out.dropped.extend((i..n).filter(|&k| !skip(k)));
            break;
        }
        if early_wins {
            let from_start = early == kept.len();
            let run = kept.split_off(kept.len() - early);
            let first = run[0];
            match &mut ahead {
                Some(a) => a.tally.count += run.len(),
                None => {
                    ahead = Some(Ahead {
                        tally: Tally {
                            first,
                            count: run.len(),
                        },
                        first_s: time_s[first],
                        resumed: i,
                        resumed_s: t,
                        stepped_from_s: last,
                        from_start,
                    });
                }
            }
            out.dropped.extend(run);
            kept.push(i);
            late_behind = None;
        } else {
            late_behind = Some(last);
            drop_behind(&mut out, &mut backwards, i, t, last);
        }
    }
    out.dropped.sort_unstable();
    out.repeated = repeated;
    out.backwards = backwards;
    out.ahead = ahead;
    out.restarts = restarts;
    out
}

fn drop_behind(
    out: &mut TimeOrder,
    backwards: &mut Option<Backwards>,
    i: usize,
    t: f64,
    last: f64,
) {
    out.dropped.push(i);
    match backwards {
        Some(b) => b.tally.count += 1,
        None => {
            *backwards = Some(Backwards {
                tally: Tally { first: i, count: 1 },
                first_s: t,
                after_s: last,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at_one_s(n: usize) -> Vec<f64> {
        (0..n).map(|i| i as f64).collect()
    }

    #[test]
    fn rising_stamps_keep_every_sample() {
        let t = at_one_s(100);
        assert_eq!(time_order(&t, |_| false), TimeOrder::default());
    }

    #[test]
    fn a_run_stamped_ahead_is_dropped_not_the_hours_after_it() {
        for run in [3, 10, 200] {
            let mut t = at_one_s(20_000);
            for v in &mut t[8945..8945 + run] {
                *v += 10_000.0;
            }
            let o = time_order(&t, |_| false);
            assert_eq!(
                o.dropped,
                (8945..8945 + run).collect::<Vec<_>>(),
                "run {run}"
            );
            let a = o.ahead.expect("told as ahead");
            assert_eq!(
                a.tally,
                Tally {
                    first: 8945,
                    count: run
                }
            );
            assert_eq!((a.resumed, a.resumed_s), (8945 + run, (8945 + run) as f64));
            assert_eq!(a.first_s, 18_945.0);
            assert!(o.backwards.is_none() && o.repeated.is_none());
        }
    }

    #[test]
    fn a_run_stamped_behind_is_dropped() {
        let mut t = at_one_s(1000);
        for v in &mut t[500..505] {
            *v -= 400.0;
        }
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, (500..505).collect::<Vec<_>>());
        let b = o.backwards.expect("told as behind");
        assert_eq!(
            b.tally,
            Tally {
                first: 500,
                count: 5
            }
        );
        assert_eq!((b.first_s, b.after_s), (100.0, 499.0));
        assert!(o.ahead.is_none());
    }

    #[test]
    fn a_run_at_the_start_stamped_ahead_is_dropped() {
        let mut t = at_one_s(1000);
        for v in &mut t[..3] {
            *v += 100_000.0;
        }
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, vec![0, 1, 2]);
        assert_eq!(o.out_of_order(), 3);
    }

    /// Time order of samples whose readings all differ (a real run's noise).
    fn of_distinct(t: &[f64]) -> TimeOrder {
        time_order_of(t, |_| false, |a, b| a == b)
    }

    #[test]
    fn a_clock_that_restarts_keeps_the_longer_run_whole() {
        // 0..600 s, then the clock restarts at 0 for 400 samples: the restart's 400 go.
        let mut t = at_one_s(600);
        t.extend(at_one_s(400));
        let o = of_distinct(&t);
        assert_eq!(o.dropped, (600..1000).collect::<Vec<_>>());
        let r = o.restarts.expect("a restart");
        assert_eq!((r.at, r.to_s, r.from_s, r.count), (600, 0.0, 599.0, 1));
        assert!(!r.dropped_before);
        // 400 then 600: the first 400 go, whatever the tie of the two readings (either drops
        // 400 and splices the runs: the first run with the second's samples past 399 s).
        let mut t = at_one_s(400);
        t.extend(at_one_s(600));
        let o = of_distinct(&t);
        assert_eq!(o.dropped, (0..400).collect::<Vec<_>>());
        assert!(
            o.restarts
                .is_some_and(|r| r.dropped_before && r.tally.count == 400)
        );
        // A reboot whose clock starts 5 s and 0.4 s into the first run's times, and a clock
        // set back into the middle of the run: no splice either.
        for offset in [5.0, 5.4, 500.0] {
            let mut t = at_one_s(1000);
            t.extend((0..3000).map(|i| offset + f64::from(i)));
            let o = of_distinct(&t);
            assert_eq!(o.dropped, (0..1000).collect::<Vec<_>>(), "{offset}");
            assert!(o.restarts.is_some() && o.backwards.is_none(), "{offset}");
        }
        // A hundred rows sent twice, readings and all: the copy goes, no restart.
        let mut t = at_one_s(3000);
        let block = t[1900..2000].to_vec();
        t.splice(2000..2000, block);
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, (2000..2100).collect::<Vec<_>>());
        assert!(o.restarts.is_none());
        // A few samples stamped out of order by a host are no restart.
        let mut t = at_one_s(3000);
        t[1000..1010].rotate_left(5);
        assert!(of_distinct(&t).restarts.is_none());
        // A block sent twice: its second copy goes, not the log before it.
        let mut t: Vec<f64> = (0..100_000).map(|i| f64::from(i) * 0.01).collect();
        let resent = t[99_995..].to_vec();
        t.extend(resent);
        t.extend((100_000..100_500).map(|i| f64::from(i) * 0.01));
        let o = of_distinct(&t);
        assert_eq!(o.dropped, (100_000..100_005).collect::<Vec<_>>());
        assert!(o.restarts.is_none());
    }

    #[test]
    fn periodic_restarts_keep_the_last_run_and_name_the_first_step() {
        let mut t = Vec::new();
        for _ in 0..8 {
            t.extend(at_one_s(5000));
        }
        t.extend(at_one_s(5201));
        let o = of_distinct(&t);
        assert_eq!(o.dropped, (0..40_000).collect::<Vec<_>>());
        assert_eq!(o.out_of_order(), 40_000);
        // The first step back: 0 s at sample 5000, after 4999 s.
        assert_eq!(o.first_step_back(), Some((5000, 0.0, 4999.0)));
    }

    #[test]
    fn newest_first_drops_all_but_one() {
        let t: Vec<f64> = (0..1000).rev().map(f64::from).collect();
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped.len(), 999);
        assert_eq!(o.out_of_order(), 999);
    }

    #[test]
    fn jitter_drops_the_later_sample_and_repeats_are_told_apart() {
        let t = vec![0.0, 1.0, 2.0, 1.9, 3.0, 3.0, 4.0];
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, vec![3, 5]);
        assert_eq!(o.repeated, Some(Tally { first: 5, count: 1 }));
        assert_eq!(
            o.backwards.map(|b| b.tally),
            Some(Tally { first: 3, count: 1 })
        );
    }

    #[test]
    fn skipped_samples_are_neither_kept_nor_dropped() {
        let mut t = at_one_s(100);
        t[50] = 1e9;
        let o = time_order(&t, |i| i == 50);
        assert!(o.dropped.is_empty());
    }

    #[test]
    fn stamps_that_are_not_finite_are_dropped() {
        let t = vec![f64::NAN, 0.0, 1.0, f64::NAN, 2.0, f64::INFINITY, 3.0];
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, vec![0, 3, 5]);
    }

    #[test]
    fn every_kept_stamp_rises_on_shuffled_input() {
        // A fixed pseudo-random shuffle of rising stamps with repeats: what is kept rises, and
        // every sample is either kept or dropped once.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let t: Vec<f64> = (0..5000)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state % 700) as f64
            })
            .collect();
        let o = time_order(&t, |i| i % 97 == 0);
        let mut dropped = o.dropped.iter().peekable();
        let mut last = f64::NEG_INFINITY;
        for (i, &v) in t.iter().enumerate() {
            if i % 97 == 0 {
                assert!(dropped.peek() != Some(&&i));
                continue;
            }
            if dropped.next_if_eq(&&i).is_some() {
                continue;
            }
            assert!(v > last, "kept {v} after {last} at {i}");
            last = v;
        }
        assert!(dropped.next().is_none());
    }
}
