//! Time order: which samples a reader keeps so that the stamps rise, the one rule of the CSV
//! reader and of the drone logs' readers.
//!
//! A stamp that repeats the last kept one is dropped. A stamp behind the last kept one leaves
//! two readings: the samples after it are late (the clock jumped back, and they are to go until
//! it passes the last kept stamp again), or the samples kept just before it are early (the
//! clock jumped ahead for a while, and the log goes on from where it was before the jump). The
//! reading that drops fewer samples is taken; on a tie, the samples after. Read the first way
//! only, three rows stamped +10,000 s in a log at 1 s kept those three and dropped the 9,999
//! good rows after them; [`super::timing::stray_stamps`] takes one or two such rows with a
//! message of their own, and this rule takes a longer run.

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
}

impl Backwards {
    /// What a reader says: `noun` is what it calls a sample ("row"), `count` how many it
    /// drops, `place` where the first stands ("line 20003").
    pub fn message(&self, noun: &str, place: &str) -> String {
        format!(
            "{}: time went backwards (first at {place}: {} s after {} s)",
            dropped(self.tally.count, noun),
            crate::number::readable(self.first_s),
            crate::number::readable(self.after_s)
        )
    }
}

impl Ahead {
    /// What a reader says: `noun` is what it calls a sample ("row"), `place` where the first
    /// stands ("line 8947"), `resumed` where the log goes on ("line 8950").
    pub fn message(&self, noun: &str, place: &str, resumed: &str) -> String {
        format!(
            "{}: stamped ahead of the {noun}s after them, which go on from the {noun}s before \
             them (first at {place}: {} s; the log goes on at {resumed} with {} s)",
            dropped(self.tally.count, noun),
            crate::number::readable(self.first_s),
            crate::number::readable(self.resumed_s)
        )
    }
}

/// "1 row dropped", "3 rows dropped".
fn dropped(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun} dropped")
    } else {
        format!("{n} {noun}s dropped")
    }
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
}

impl TimeOrder {
    /// How many samples go back in time: those behind and those ahead.
    pub fn out_of_order(&self) -> usize {
        self.backwards.map_or(0, |b| b.tally.count) + self.ahead.map_or(0, |a| a.tally.count)
    }

    /// The first backward step, for a refusal: the index of the sample that stands behind,
    /// its stamp and the stamp before it (for a run dropped as ahead, the sample the log goes
    /// on with and the run's first stamp). `None` when every sample is in order.
    pub fn first_step_back(&self) -> Option<(usize, f64, f64)> {
        let behind = self
            .backwards
            .map(|b| (b.tally.first, b.first_s, b.after_s));
        let ahead = self.ahead.map(|a| (a.resumed, a.resumed_s, a.first_s));
        match (behind, ahead) {
            (Some(b), Some(a)) if a.0 < b.0 => Some(a),
            (Some(x), _) | (None, Some(x)) => Some(x),
            (None, None) => None,
        }
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
    let n = time_s.len();
    let mut out = TimeOrder::default();
    let mut kept: Vec<usize> = Vec::with_capacity(n);
    // The kept stamp behind which the samples from a backward step on were judged late: until
    // a sample passes it, the ones behind it are dropped without counting again.
    let mut late_behind: Option<f64> = None;
    let mut repeated = None;
    let mut backwards: Option<Backwards> = None;
    let mut ahead: Option<Ahead> = None;
    for i in 0..n {
        if skip(i) {
            continue;
        }
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
        // Count side by side: `early` kept samples at or ahead of `t`, `late` samples from
        // `i` on at or behind `last`, until one count is known to be the smaller.
        let (mut early, mut late) = (0usize, 0usize);
        let mut fwd = i;
        let early_wins = loop {
            let more_early = early < kept.len() && time_s[kept[kept.len() - 1 - early]] >= t;
            if more_early {
                early += 1;
            }
            let more_late = loop {
                if fwd >= n {
                    break false;
                }
                let k = fwd;
                fwd += 1;
                if skip(k) {
                    continue;
                }
                break time_s[k] <= last;
            };
            if more_late {
                late += 1;
            } else {
                // The first sample past `last` (or the end): no more late ones.
                fwd = n;
            }
            match (more_early, more_late) {
                (false, _) if early < late => break true,
                (_, false) if late <= early => break false,
                (false, false) => break early < late,
                _ => {}
            }
        };
        if early_wins {
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

    #[test]
    fn a_clock_set_back_halfway_drops_the_shorter_part_and_the_later_on_a_tie() {
        // 0..600 s, then the clock restarts at 0 for 400 samples: the restart's 400 go.
        let mut t = at_one_s(600);
        t.extend(at_one_s(400));
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, (600..1000).collect::<Vec<_>>());
        // 400 then 600: 400 go either way (the first part, or the restart's samples up to
        // 399 s), and the tie drops the later ones.
        let mut t = at_one_s(400);
        t.extend(at_one_s(600));
        let o = time_order(&t, |_| false);
        assert_eq!(o.dropped, (400..800).collect::<Vec<_>>());
        // A tie: the later part goes, as before this rule.
        let mut t = at_one_s(300);
        t.extend(at_one_s(300));
        assert_eq!(
            time_order(&t, |_| false).dropped,
            (300..600).collect::<Vec<_>>()
        );
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
