//! Whether one topic's stamps keep one clock through the log: a driver whose clock is stepped
//! mid-log (an NTP or PTP step, a restart on another clock), or two nodes publishing one
//! topic each by its own clock, leave stamps that stand one offset from the record time for a
//! while and another after.
//!
//! Each message's offset (stamp minus record time) is the transport's delay on one clock,
//! spread by its jitter. Sorted, the offsets of one clock lie close together; those of two
//! clocks fall in two groups with a gap between them wider than any delay ([`change`] takes
//! the width as `limit`). A group of one message is a stray stamp, left to the glitch filters;
//! two groups of several messages each are two clocks, and no one offset, the median
//! [`super::ros_clocks`] compares, stands for the topic: paired by stamp, the messages of the
//! other clock would be given readings (or samples) that much older or newer, or none.
//!
//! Record times that do not keep pace with the stamps (a bag written all at once by a script,
//! its record times seconds apart over hours of stamps) make every message a group of its
//! own: no clock is found there, and the stamps are kept.

/// Where a topic's stamps change clock, and how often.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Change {
    /// How many messages the topic has.
    pub messages: usize,
    /// The last message (0-based) on the first clock before the stamps first change clock.
    pub before: usize,
    /// The first message (0-based) on another clock.
    pub at: usize,
    /// The offsets (stamp minus record time, ns) of `before` and `at`.
    pub before_ns: i128,
    /// See `before_ns`.
    pub at_ns: i128,
    /// How many messages stand on another clock than the first's.
    pub elsewhere: usize,
    /// How many times the messages change clock, one to the next (stray stamps passed over).
    pub switches: usize,
    /// How many clocks the messages stand on (groups of two messages or more).
    pub clocks: usize,
}

impl Change {
    /// What the change is, for a note on topic `name` whose record time is `clock` ("the
    /// bag's record time"): where it first changes and by how much, and whether it stays or
    /// switches back and forth.
    pub(crate) fn told(&self, name: &str, clock: &str, limit_ns: i128) -> String {
        let how = if self.switches == 1 {
            format!(
                "the messages from there on ({} of {}) stay on that clock",
                self.elsewhere, self.messages
            )
        } else {
            format!(
                "the messages alternate between {} clocks, changing {} times ({} of {} away from \
                 the first message's)",
                self.clocks, self.switches, self.elsewhere, self.messages
            )
        };
        format!(
            "{name}: header.stamp changes clock at message {}: it stands {} s from {clock} \
             there, against {} s at message {} (a step of {} s, more than the {} s a \
             transport's delay would explain), and {how}",
            self.at + 1,
            seconds(self.at_ns),
            seconds(self.before_ns),
            self.before + 1,
            signed_seconds(self.at_ns - self.before_ns),
            seconds(limit_ns),
        )
    }
}

/// Seconds for a message, from ns: to the millisecond, trailing zeros dropped.
pub(crate) fn seconds(ns: i128) -> String {
    let s = format!("{:.3}", ns as f64 * 1e-9);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// As [`seconds`], with its sign: `+3600`, `-0.5`.
fn signed_seconds(ns: i128) -> String {
    let s = seconds(ns);
    if s.starts_with('-') || s == "0" {
        s
    } else {
        format!("+{s}")
    }
}

/// Where the offsets `offsets_ns` (stamp minus record time of each message, in log order)
/// stand on more than one clock: groups of two messages or more, their sorted offsets more
/// than `limit_ns` apart, and the stamps `stamps_ns` themselves breaking their step where
/// the messages pass from one group to another. `None` when they stand on one (stray stamps
/// aside), when fewer than half the messages stand in a group of two or more (record times
/// that do not keep pace with the stamps: no clock to tell), or when the stamps keep their
/// step across every passage: then only the record times moved, a transport's delay (a
/// burst of messages delivered late, in order), and the stamps are one clock.
pub(crate) fn change(offsets_ns: &[i128], stamps_ns: &[i128], limit_ns: i128) -> Option<Change> {
    let n = offsets_ns.len();
    if n < 4 || stamps_ns.len() != n {
        return None;
    }

    if one_grid(stamps_ns, limit_ns) {
        return None;
    }
    let mut sorted = offsets_ns.to_vec();
    sorted.sort_unstable();
    // The groups: the lowest offset of each, and how many messages it holds.
    let mut lows: Vec<i128> = vec![sorted[0]];
    let mut sizes: Vec<usize> = vec![1];
    for w in sorted.windows(2) {
        if w[1] - w[0] > limit_ns {
            lows.push(w[1]);
            sizes.push(1);
        } else {
            *sizes.last_mut()? += 1;
        }
    }
    let clocks = sizes.iter().filter(|&&s| s > 1).count();
    let grouped: usize = sizes.iter().filter(|&&s| s > 1).sum();
    if clocks < 2 || 2 * grouped < n {
        return None;
    }
    let group = |o: i128| lows.partition_point(|&l| l <= o) - 1;
    // The stamps' step a message, read within the largest group (one clock): between two
    // messages of it, the stamps rise by the step times the messages between them.
    let largest = (0..sizes.len()).max_by_key(|&g| sizes[g])?;
    let members: Vec<usize> = (0..n)
        .filter(|&i| group(offsets_ns[i]) == largest)
        .collect();
    let mut steps: Vec<i128> = members
        .windows(2)
        .map(|w| (stamps_ns[w[1]] - stamps_ns[w[0]]) / (w[1] - w[0]) as i128)
        .collect();
    if steps.is_empty() {
        return None;
    }
    steps.sort_unstable();
    let step = steps[steps.len() / 2];
    // Whether the stamps from message `j` to `i` break that step by more than the limit.
    let stamps_break = |j: usize, i: usize| {
        let expected = step * (i - j) as i128;
        (stamps_ns[i] - stamps_ns[j] - expected).abs() > limit_ns
    };
    // Walk the messages in order over the clocks, stray stamps (groups of one) passed over.
    let mut first: Option<(usize, usize)> = None;
    let mut last: Option<(usize, usize)> = None;
    let mut change: Option<(usize, usize)> = None;
    let mut switches = 0;
    let mut elsewhere = 0;
    for (i, &o) in offsets_ns.iter().enumerate() {
        let g = group(o);
        if sizes[g] < 2 {
            continue;
        }
        let (_, g0) = *first.get_or_insert((i, g));
        if g != g0 {
            elsewhere += 1;
        }
        if let Some((j, h)) = last
            && h != g
            && stamps_break(j, i)
        {
            switches += 1;
            change.get_or_insert((j, i));
        }
        last = Some((i, g));
    }
    let (before, at) = change?;
    Some(Change {
        messages: n,
        before,
        at,
        before_ns: offsets_ns[before],
        at_ns: offsets_ns[at],
        elsewhere,
        switches,
        clocks,
    })
}

/// Whether the stamps, put in their own order, are one clock's: no two alike and every step
/// within `limit_ns`, and a tenth, of their median step. Then whatever the record times do (messages
/// delivered late, out of order, as a transport retries them), the stamps are one clock's
/// samples; a second clock's would fall between them off the step, or on them.
fn one_grid(stamps_ns: &[i128], limit_ns: i128) -> bool {
    let mut sorted = stamps_ns.to_vec();
    sorted.sort_unstable();
    let mut steps: Vec<i128> = sorted.windows(2).map(|w| w[1] - w[0]).collect();
    if steps.is_empty() || steps.contains(&0) {
        return false;
    }
    steps.sort_unstable();
    let median = steps[steps.len() / 2];
    // Within the limit and within a tenth of the step: a second clock's stamps interleaved
    // with the first's halve the steps somewhere, which the limit alone (a step, at 1 Hz)
    // would pass.
    let off = limit_ns.min(median / 10);
    steps.first().is_some_and(|&lo| median - lo <= off)
        && steps.last().is_some_and(|&hi| hi - median <= off)
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: i128 = 1_000_000_000;

    /// Offsets of `n` messages with a jitter of up to 20 ms, `f(i)` s each.
    fn offsets(n: usize, f: impl Fn(usize) -> i128) -> Vec<i128> {
        (0..n)
            .map(|i| f(i) * S - (i as i128 * 7919 % 20) * 1_000_000)
            .collect()
    }

    /// The stamps of messages a second apart on clocks whose offsets from the record time are
    /// `offsets` (recorded at i s, no delay): the stamp moves with the offset.
    fn stamped(offsets: &[i128]) -> Vec<i128> {
        offsets
            .iter()
            .enumerate()
            .map(|(i, o)| i as i128 * S + o)
            .collect()
    }

    #[test]
    fn one_clock_with_jitter_and_a_stray_stamp_is_no_change() {
        let mut o = offsets(100, |_| 0);
        o[40] = 3600 * S;
        assert_eq!(change(&o, &stamped(&o), S), None);
    }

    #[test]
    fn a_jump_that_stays_is_named_where_it_happens() {
        let o = offsets(100, |i| if i >= 60 { 3600 } else { 0 });
        let c = change(&o, &stamped(&o), S).unwrap();
        assert_eq!(
            (c.before, c.at, c.switches, c.elsewhere, c.clocks),
            (59, 60, 1, 40, 2)
        );
        let told = c.told("/t", "the log time", S);
        assert!(
            told.contains("changes clock at message 61")
                && told.contains("a step of +3600")
                && told.contains("(40 of 100) stay on that clock"),
            "{told}"
        );
    }

    #[test]
    fn two_clocks_in_turn_are_told_as_alternating() {
        let o = offsets(100, |i| 300 * (i % 2) as i128);
        let c = change(&o, &stamped(&o), S).unwrap();
        assert_eq!((c.before, c.at, c.switches, c.elsewhere), (0, 1, 99, 50));
        assert!(
            c.told("/t", "the log time", S)
                .contains("alternate between 2 clocks")
        );
    }

    #[test]
    fn a_transport_delay_moves_the_record_times_not_the_stamps() {
        // Stamps a second apart throughout; from message 40 on each recorded 0 to 20 s late
        // (in order): the offsets fall into groups, the stamps keep their step.
        let stamps: Vec<i128> = (0..200).map(|i| i * S).collect();
        let mut recorded = 0;
        let o: Vec<i128> = stamps
            .iter()
            .enumerate()
            .map(|(i, &st)| {
                let delay = if i >= 40 {
                    (i as i128 * 7919 % 21) * S
                } else {
                    0
                };
                recorded = (st + delay).max(recorded);
                st - recorded
            })
            .collect();
        assert!(
            o.iter().any(|&x| x < -10 * S),
            "the delays reach past the limit"
        );
        assert_eq!(change(&o, &stamps, S), None);
    }

    #[test]
    fn readings_delivered_late_out_of_order_are_one_clock() {
        // A reading every 60 s, stamped on the grid; every 4th recorded 90 s late, after
        // the one that follows it: in record order the stamps go back, yet they are one grid.
        let mut msgs: Vec<(i128, i128)> = (0..80)
            .map(|i| {
                let stamp = i * 60 * S;
                let late = if i % 4 == 3 { 90 * S } else { 0 };
                (stamp + late, stamp)
            })
            .collect();
        msgs.sort_unstable();
        let stamps: Vec<i128> = msgs.iter().map(|m| m.1).collect();
        let o: Vec<i128> = msgs.iter().map(|m| m.1 - m.0).collect();
        assert_eq!(change(&o, &stamps, 10 * S), None);
        // The same topic with every 4th message on a clock 90 s behind: its stamps fall off
        // the grid, told as two clocks.
        let stamps: Vec<i128> = (0..80)
            .map(|i| i * 60 * S - if i % 4 == 3 { 90 * S } else { 0 })
            .collect();
        let o: Vec<i128> = stamps
            .iter()
            .enumerate()
            .map(|(i, st)| st - i as i128 * 60 * S)
            .collect();
        assert!(change(&o, &stamps, 10 * S).is_some());
    }

    #[test]
    fn record_times_that_do_not_keep_pace_tell_no_clock() {
        // Stamps 100 s apart, all recorded within a second: every offset a group of its own.
        let o: Vec<i128> = (0..50).map(|i| i * 100 * S - i * 10_000_000).collect();
        assert_eq!(change(&o, &stamped(&o), S), None);
    }
}
