//! The two clocks of a ROS log, and which of them pairs a gyro's samples with the readings of
//! a Temperature topic.
//!
//! Every message has two times: its `header.stamp`, set by the driver that published it, and
//! the time the log recorded it (the bag's record time, MCAP's `log_time`). Within a log the
//! record times are one clock; the stamps are each driver's: an IMU driver may stamp by the
//! sensor's clock from boot, a temperature node by the wall clock, or not at all. Stamps are
//! read as stamped, and a gyro paired with its temperature by them, unless they cannot be:
//!
//! - a topic whose stamps never advance ([`stuck`], a driver that leaves them 0) has no time
//!   of its own, and is timed by the record time instead;
//! - a topic (Imu or Temperature) whose stamps change clock within the log, stepped once
//!   or switching back and forth ([`super::ros_clock_changes`]): no one offset stands for
//!   it, and paired by stamp the messages after the step would find no reading, or the
//!   wrong one. The two are paired by record time instead, with a note naming the topic, the
//!   message where its stamps change clock and by how much. An Imu topic's samples are then
//!   timed by the record time too, one clock throughout ([`Pairing::gyro_by_record_time`],
//!   with or without a Temperature topic): by its stamps, a step back would run the clock
//!   twice over the same times (half the log dropped as a restart, or the rest spliced on
//!   early) and a step forward would leave a gap that never was;
//! - a Temperature topic whose stamps stand on another clock than the gyro's: each topic's
//!   offset from the record time (stamp minus record time, the median of the messages) is
//!   known, and when the two offsets differ by more than [`ANOTHER_CLOCK_STEPS`] steps of the
//!   pairing, at least [`ANOTHER_CLOCK_AT_LEAST_NS`] and at most [`ANOTHER_CLOCK_AT_MOST_NS`]
//!   (the limit does not grow with a slow topic's step: minutes between two clocks are no
//!   transport's delay at any rate), a pairing by stamp would give each sample a reading
//!   taken that much earlier or later, or none. They are paired by record time instead,
//!   with a note naming both topics and both offsets.
//!
//! Pairing by record time lags each message by its transport's delay and jitter (a few ms),
//! which is why stamps are preferred whenever they share a clock. By either clock a sample's
//! temperature is the line between the readings around it ([`super::ros_readings`]). Samples
//! left without a reading are told with the reason (no reading within the pairing's
//! tolerance, or readings too far apart to draw a line between), so that the temp_c they
//! lack is not taken for a NaN in the log.

use super::recording::{Problem, RosTime, median_step};
use super::ros_clock_changes::{Change, change, seconds};
use super::ros_readings::{HOLD_AT_MOST_NS, LINEAR_AT_MOST_NS, Reading, readings};

/// How many steps of the pairing (the larger median step of the two topics) two topics'
/// offsets from the record time may differ by and still be paired by stamp: transport delays
/// of a few steps are the same clock; ten steps or more are another clock (a reading that
/// far from its sample would be paired with the wrong one, or with none).
pub(crate) const ANOTHER_CLOCK_STEPS: i128 = 10;

/// The least difference of offsets taken as another clock, however fast the topics: 1 s, far
/// more than a transport's delay, less than a temperature drifts by in a real log.
pub(crate) const ANOTHER_CLOCK_AT_LEAST_NS: i128 = 1_000_000_000;

/// The most: 10 s, however slow the topics. Ten steps of a topic published every 100 s are
/// 1000 s, and clocks 900 s apart are no transport's delay at any rate: paired by stamp, a
/// slow chamber's reading would be given to the samples 900 s after it.
pub(crate) const ANOTHER_CLOCK_AT_MOST_NS: i128 = 10_000_000_000;

/// How many messages an offset is the median of, evenly spaced over the topic: enough to
/// pass over a few messages stamped apart, without a copy of a million messages' offsets.
const OFFSET_SAMPLES: usize = 1025;

/// True when a topic of two messages or more stamps every one alike (`header.stamp` left 0
/// by a driver that does not fill it, or set once): its samples have no time of their own,
/// and read by it every one but the first would repeat the first's stamp.
pub(crate) fn stuck(stamps: impl IntoIterator<Item = RosTime>) -> bool {
    let mut stamps = stamps.into_iter();
    let Some(first) = stamps.next() else {
        return false;
    };
    let mut n = 1;
    for s in stamps {
        if s != first {
            return false;
        }
        n += 1;
    }
    n > 1
}

/// True when the log times (ns) are not all one: a clock that can time the samples.
pub(crate) fn advances(log_times: &[u64]) -> bool {
    log_times.iter().any(|&t| t != log_times[0])
}

/// A log time (ns since the epoch) as a ROS time stamp.
pub(crate) fn log_stamp(ns: u64) -> RosTime {
    RosTime {
        sec: (ns / 1_000_000_000) as i64,
        nsec: (ns % 1_000_000_000) as u32,
    }
}

/// A topic's stamps minus its record times (ns) at the fifth of its messages least delayed:
/// the upper quintile over at most [`OFFSET_SAMPLES`] messages evenly spaced; `None` without
/// messages. A transport's delay only ever makes a record time later, so the offsets of one
/// clock spread below the clock's own; the median would take a delay's median (13 s for
/// messages delivered 0 to 20 s late) for an offset between clocks, the upper quintile takes
/// the messages that came through at once, and still passes over a few stray stamps.
pub(crate) fn offset(stamps: &[RosTime], log_times: &[u64]) -> Option<i128> {
    let n = stamps.len().min(log_times.len());
    if n == 0 {
        return None;
    }
    let m = n.min(OFFSET_SAMPLES);
    let mut d: Vec<i128> = (0..m)
        .map(|j| {
            let i = if m == 1 { 0 } else { j * (n - 1) / (m - 1) };
            stamps[i].nanos() - i128::from(log_times[i])
        })
        .collect();
    d.sort_unstable();
    Some(d[(m - 1) * 4 / 5])
}

/// One side of a pairing: a topic's (or a frame's) messages, by stamp and by record time.
pub(crate) struct Side<'a> {
    /// What messages name it by: the topic, or the gyro's label.
    pub name: &'a str,
    /// Each message's `header.stamp`.
    pub stamps: &'a [RosTime],
    /// Each message's record time (ns).
    pub log_times: &'a [u64],
}

/// How a gyro's samples are timed and given their temperature.
#[derive(Debug, PartialEq)]
pub(crate) struct Pairing {
    /// Each sample's reading of the Temperature topic (indices into its messages), or none:
    /// every one none without a Temperature topic.
    pub readings: Vec<Option<Reading>>,
    /// The gyro's own stamps change clock within the log: its samples are timed by the
    /// record time instead, one clock throughout (told).
    pub gyro_by_record_time: bool,
}

/// For each sample of `gyro` its reading of `temp` (the line between the two around it, or
/// one reading, as [`readings`] gives them), by stamp or by record time as the module says;
/// `gyro_by_clock` when the gyro's own stamps never advance (its samples timed by the record
/// time, already told). Without a Temperature topic (`temp` `None`) the gyro's clock is still
/// checked. `clock` names the record time as the format does ("the bag's record time"). A
/// choice other than the stamps is told in `problems`, and so are samples left without a
/// reading (their temp_c NaN, dropped later), with the reason: no reading of `temp` within
/// the tolerance, or readings too far apart to pair.
pub(crate) fn paired(
    gyro: &Side<'_>,
    temp: Option<&Side<'_>>,
    gyro_by_clock: bool,
    clock: &str,
    problems: &mut Vec<Problem>,
) -> Pairing {
    let Some(temp) = temp else {
        let restamped = !gyro_by_clock && own_clock_changes(gyro, clock, problems);
        return Pairing {
            readings: vec![None; gyro.stamps.len()],
            gyro_by_record_time: restamped,
        };
    };
    let c = chosen(gyro, temp, gyro_by_clock, clock, problems);
    let r = readings(&c.gyro, &c.temp, c.tol);
    let n = r.each.len();
    if r.too_far > 0 {
        let first = r.first_too_far.unwrap_or(0) + 1;
        let why = format!(
            "where neither the straight line between two readings nor a reading held is the \
             temperature (a chamber's ramp can turn between them unseen, and a held reading \
             reads as a plateau the temperature never held): their temp_c is NaN, a reading \
             held only within {} s of a sample",
            seconds(c.tol.min(HOLD_AT_MOST_NS))
        );
        let sparse = median_step(&c.temp).filter(|&s| s > LINEAR_AT_MOST_NS);
        problems.push(Problem::note(match sparse {
            Some(step) => format!(
                "{} has one reading every {} s: too sparse to pair with a {} Hz gyro ({}); {} \
                 of {n} samples fall between two readings more than {} s apart (first at \
                 sample {first}), {why}; to calibrate, record the temperature at least every {} \
                 s",
                temp.name,
                seconds(step),
                hertz(median_step(&c.gyro)),
                gyro.name,
                r.too_far,
                seconds(LINEAR_AT_MOST_NS),
                seconds(LINEAR_AT_MOST_NS),
            ),
            None => format!(
                "{}: {} of {n} samples fall between two readings of {} more than {} s apart \
                 (first at sample {first}, the widest gap {} s), {why}",
                gyro.name,
                r.too_far,
                temp.name,
                seconds(LINEAR_AT_MOST_NS),
                seconds(r.widest_ns),
            ),
        }));
    }
    if r.beyond > 0 && !temp.stamps.is_empty() {
        problems.push(Problem::note(format!(
            "{}: {} of {n} samples have no reading of {} within {} s of their {} (first at \
             sample {}): their temp_c is NaN",
            gyro.name,
            r.beyond,
            temp.name,
            seconds(c.tol.min(HOLD_AT_MOST_NS)),
            c.by,
            r.first_beyond.unwrap_or(0) + 1
        )));
    }
    Pairing {
        readings: r.each,
        gyro_by_record_time: c.gyro_by_record_time,
    }
}

/// A rate for a message, from a median step (ns): `1`, `100`, `0.5` (Hz); `?` without one.
fn hertz(step_ns: Option<i128>) -> String {
    match step_ns {
        Some(s) if s > 0 => seconds(1_000_000_000_000_000_000 / s),
        _ => "?".into(),
    }
}

/// How far two topics' offsets may stand apart, and one topic's offsets spread, on one
/// clock: [`ANOTHER_CLOCK_STEPS`] steps of the pairing (`tol`), at least
/// [`ANOTHER_CLOCK_AT_LEAST_NS`] and at most [`ANOTHER_CLOCK_AT_MOST_NS`].
fn another_clock_limit(tol: i128) -> i128 {
    (ANOTHER_CLOCK_STEPS * tol).clamp(ANOTHER_CLOCK_AT_LEAST_NS, ANOTHER_CLOCK_AT_MOST_NS)
}

/// Every message's stamp minus its record time, ns.
fn offsets(side: &Side<'_>) -> Vec<i128> {
    side.stamps
        .iter()
        .zip(side.log_times)
        .map(|(s, &t)| s.nanos() - i128::from(t))
        .collect()
}

/// Where `side`'s stamps change clock within the log, against `limit` (ns); `None` when they
/// keep one, or the record time stands still (nothing to tell two clocks by).
fn clock_change(side: &Side<'_>, limit: i128) -> Option<Change> {
    if !advances(side.log_times) {
        return None;
    }
    let stamps: Vec<i128> = side.stamps.iter().map(|s| s.nanos()).collect();
    change(&offsets(side), &stamps, limit)
}

/// What a gyro whose stamps change clock is timed by, for its note: by the stamps, the
/// samples on the other clock would stand a gap that never was away from the others, or,
/// where the stamps step back, be dropped as a clock run twice or spliced onto the others.
fn restamped_told(gyro: &str, clock: &str) -> String {
    format!(
        "{gyro}'s samples are timed by {clock} instead, one clock throughout (by the stamps, \
         the samples on the other clock would stand apart by a gap that never was, or, where \
         the stamps step back, be dropped or spliced onto the others)"
    )
}

/// A gyro without a Temperature topic: whether its stamps change clock (told, with its
/// samples timed by `clock` instead), against the limit of its own step.
fn own_clock_changes(gyro: &Side<'_>, clock: &str, problems: &mut Vec<Problem>) -> bool {
    let g: Vec<i128> = gyro.stamps.iter().map(|s| s.nanos()).collect();
    let limit = another_clock_limit(median_step(&g).unwrap_or(0));
    let Some(c) = clock_change(gyro, limit) else {
        return false;
    };
    problems.push(Problem::note(format!(
        "{}; {}, which lags each by the transport's delay and jitter; to time them by the \
         sensor, have the driver keep one clock",
        c.told(gyro.name, clock, limit),
        restamped_told(gyro.name, clock)
    )));
    true
}

/// The clock [`paired`] pairs by: both sides' times on it (ns), what it is ("stamps",
/// "record times"), its tolerance (ns), and whether the gyro is timed by the record time.
struct Chosen {
    gyro: Vec<i128>,
    temp: Vec<i128>,
    by: &'static str,
    tol: i128,
    gyro_by_record_time: bool,
}

/// [`paired`]'s clock, as the module says.
fn chosen(
    gyro: &Side<'_>,
    temp: &Side<'_>,
    gyro_by_clock: bool,
    clock: &str,
    problems: &mut Vec<Problem>,
) -> Chosen {
    let by_log = |problems: &mut Vec<Problem>, notes: Vec<String>, restamped: bool| {
        problems.extend(notes.into_iter().map(Problem::note));
        let g: Vec<i128> = gyro.log_times.iter().map(|&x| i128::from(x)).collect();
        let t: Vec<i128> = temp.log_times.iter().map(|&x| i128::from(x)).collect();
        let tol = median_step(&t)
            .unwrap_or(0)
            .max(median_step(&g).unwrap_or(0));
        Chosen {
            gyro: g,
            temp: t,
            by: "record times",
            tol,
            gyro_by_record_time: restamped,
        }
    };
    // Both by the log's clock when either's stamps never advance: the stamps of one beside
    // the log times of the other would be two clocks.
    let temp_stuck = stuck(temp.stamps.iter().copied());
    if gyro_by_clock {
        return by_log(problems, Vec::new(), false);
    }
    if temp_stuck {
        let told = advances(temp.log_times).then(|| {
            format!(
                "{}: header.stamp never advances (all {} messages are stamped {} s, as a \
                 driver that does not fill it leaves them): its readings are paired with {}'s \
                 samples by {clock} instead",
                temp.name,
                temp.stamps.len(),
                temp.stamps[0].seconds(),
                gyro.name
            )
        });
        return by_log(problems, told.into_iter().collect(), false);
    }
    let g: Vec<i128> = gyro.stamps.iter().map(|s| s.nanos()).collect();
    let t: Vec<i128> = temp.stamps.iter().map(|s| s.nanos()).collect();
    let tol = median_step(&t)
        .unwrap_or(0)
        .max(median_step(&g).unwrap_or(0));
    let limit = another_clock_limit(tol);
    let log_advances = advances(gyro.log_times) && advances(temp.log_times);
    // A topic whose stamps change clock within the log: no one offset stands for it. A
    // gyro's own is timed by the record time too.
    if log_advances {
        let gyro_change = clock_change(gyro, limit);
        let restamped = gyro_change.is_some();
        let mut notes: Vec<String> = gyro_change
            .map(|c| {
                format!(
                    "{}; {}",
                    c.told(gyro.name, clock, limit),
                    restamped_told(gyro.name, clock)
                )
            })
            .into_iter()
            .chain(clock_change(temp, limit).map(|c| c.told(temp.name, clock, limit)))
            .collect();
        if let Some(last) = notes.last_mut() {
            last.push_str(&format!(
                "; {}'s readings are paired with {}'s samples by {clock} instead (one clock \
                 throughout), which lags each by the transport's delay and jitter; to pair \
                 them by stamp, have each driver keep one clock",
                temp.name, gyro.name
            ));
            return by_log(problems, notes, restamped);
        }
    }
    if let (Some(go), Some(to)) = (
        offset(gyro.stamps, gyro.log_times),
        offset(temp.stamps, temp.log_times),
    ) && (to - go).abs() > limit
    {
        let apart = format!(
            "{}: header.stamp stands {} s from {clock} (its least delayed messages), {}'s \
             {} s: the two topics are stamped by clocks {} s apart, more than {} s \
             ({ANOTHER_CLOCK_STEPS} steps of either, at least {} s and at most {} s, whatever \
             the rate), and paired by stamp each sample would take a reading that much older \
             or newer",
            temp.name,
            seconds(to),
            gyro.name,
            seconds(go),
            seconds((to - go).abs()),
            seconds(limit),
            seconds(ANOTHER_CLOCK_AT_LEAST_NS),
            seconds(ANOTHER_CLOCK_AT_MOST_NS),
        );
        if log_advances {
            let note = format!(
                "{apart}; its readings are paired with {}'s samples by {clock} instead, which \
                 lags each by the transport's delay and jitter; to pair them by stamp, have \
                 both drivers stamp by one clock",
                gyro.name
            );
            return by_log(problems, vec![note], false);
        }
        // A log whose own clock stands still has nothing else to pair by: said, not silent.
        problems.push(Problem::note(format!(
            "{apart}; {clock} does not advance, so they are paired by stamp all the same: have \
             both drivers stamp by one clock"
        )));
    }
    Chosen {
        gyro: g,
        temp: t,
        by: "stamps",
        tol,
        gyro_by_record_time: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(s: &[i64]) -> Vec<RosTime> {
        s.iter().map(|&sec| RosTime { sec, nsec: 0 }).collect()
    }

    #[test]
    fn an_offset_is_the_upper_quintile_and_passes_over_a_stray_stamp() {
        let log: Vec<u64> = (0..5).map(|k| (100 + k) * 1_000_000_000).collect();
        // Stamps 3 s ahead of the record time, but one.
        let stamps = at(&[103, 104, 900, 106, 107]);
        assert_eq!(offset(&stamps, &log), Some(3_000_000_000));
        assert_eq!(offset(&[], &[]), None);
        // Recorded late by 0 to 20 s from the 34th of 100 messages on (in order): the
        // offset is that of the messages that came through at once, 0.
        let stamps: Vec<RosTime> = (0..100u64).map(|k| log_stamp(k * 1_000_000_000)).collect();
        let mut last = 0;
        let log: Vec<u64> = (0..100u64)
            .map(|k| {
                let delay = if k >= 34 {
                    (k * 7919 % 21) * 1_000_000_000
                } else {
                    0
                };
                last = (k * 1_000_000_000 + delay).max(last);
                last
            })
            .collect();
        assert_eq!(offset(&stamps, &log), Some(0));
    }

    #[test]
    fn offsets_a_few_steps_apart_are_one_clock_and_paired_by_stamp() {
        // 10 Hz, the temperature stamped 0.3 s (3 steps) later than the gyro against the
        // record time: one clock with a delay; each sample takes the reading stamped with it.
        let log: Vec<u64> = (0..20).map(|k| k * 100_000_000).collect();
        let g: Vec<RosTime> = log.iter().map(|&x| log_stamp(x)).collect();
        let t: Vec<RosTime> = log.iter().map(|&x| log_stamp(x + 300_000_000)).collect();
        let tlog: Vec<u64> = log.iter().map(|&x| x + 600_000_000).collect();
        let mut problems = Vec::new();
        let pick = paired(
            &Side {
                name: "g",
                stamps: &g,
                log_times: &log,
            },
            Some(&Side {
                name: "t",
                stamps: &t,
                log_times: &tlog,
            }),
            false,
            "the log time",
            &mut problems,
        );
        // The two samples stamped before the first reading less a step have none, told.
        let told: Vec<&str> = problems.iter().map(|p| p.message.as_str()).collect();
        assert_eq!(
            told,
            [
                "g: 2 of 20 samples have no reading of t within 0.1 s of their stamps (first at \
              sample 1): their temp_c is NaN"
            ]
        );
        // Sample k is stamped k/10 s; reading j is stamped j/10 + 0.3 s: j = k - 3; sample 2
        // (0.2 s) is one step from reading 0, within the pairing's tolerance.
        let want: Vec<Option<Reading>> = (0..20)
            .map(|k: usize| k.checked_sub(3).or((k == 2).then_some(0)))
            .map(|j| j.map(Reading::At))
            .collect();
        assert_eq!(pick.readings, want);
        assert!(!pick.gyro_by_record_time);
    }

    #[test]
    fn another_clock_in_a_log_whose_clock_stands_still_is_told_and_paired_by_stamp() {
        // Every message recorded at 0 (a writer that leaves the log time 0): nothing to pair
        // by but the stamps, 1000 s apart, so no sample has a reading within a step.
        let log = vec![0u64; 10];
        let g = at(&(0..10).collect::<Vec<i64>>());
        let t = at(&(1000..1010).collect::<Vec<i64>>());
        let mut problems = Vec::new();
        let side = |name, stamps| Side {
            name,
            stamps,
            log_times: &log,
        };
        let pick = paired(
            &side("g", &g),
            Some(&side("t", &t)),
            false,
            "the log time",
            &mut problems,
        );
        assert_eq!(pick.readings, vec![None; 10]);
        assert_eq!(problems.len(), 2);
        assert!(
            problems[1]
                .message
                .starts_with("g: 10 of 10 samples have no reading of t within 1 s of their stamps"),
            "{problems:?}"
        );
        assert!(
            problems[0]
                .message
                .contains("the two topics are stamped by clocks 1000 s apart")
                && problems[0]
                    .message
                    .contains("the log time does not advance, so they are paired by stamp"),
            "{problems:?}"
        );
    }
}
