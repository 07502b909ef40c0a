//! A gyro sample's temperature from the readings of a ROS Temperature topic around it: the
//! straight line between the reading before the sample and the reading after, by whichever
//! clock `ros_clocks` pairs them by.
//!
//! A Temperature topic is often slower than the gyro (a chamber's or a board's sensor read
//! once a second, or once a minute, beside an IMU at 100 Hz). Given the nearest reading, a
//! sample between two readings 60 s apart would take one held up to 30 s, and the written
//! temperature would be a staircase: 0.75 °C off on a chamber's sine, steps a rate model reads
//! as Tdot, and flats `inspect` can take for plateaus. The temperature between two readings is
//! the straight line between them instead; a sample taken with a reading (the same time on the
//! pairing's clock) keeps that reading's value bit for bit, so a topic as dense as the gyro and
//! stamped with it is paired as before.
//!
//! A straight line is trusted only between readings at most [`LINEAR_AT_MOST_NS`] apart.
//! Further apart, a chamber profile's corner (a ramp turning into a soak) can fall between
//! them unseen, and neither the line nor a held reading is the temperature: the samples there
//! are given none ([`Reading`] `None`, their temp_c NaN, dropped by `convert` for that
//! reason), told with the topic's reading interval. A sample before the first reading or after
//! the last, or beside such a gap, keeps the nearest reading only within `hold` (the pairing's
//! tolerance), and never more than [`HOLD_AT_MOST_NS`].

/// The furthest apart two readings may be and the temperature between them still be taken as
/// the straight line between them: 120 s. A chamber ramping at 1 °C/min (a brisk one) that
/// turns into a soak between two readings 120 s apart leaves the line at most a quarter of the
/// 2 °C it moved off at the corner, 0.5 °C; a gyro's package lags the air by minutes, so its
/// own temperature bends more gently still. On a smooth profile (20 °C swinging over 80 min)
/// the line is within 0.06 °C. Two minutes also passes a chamber logger's reading every
/// 100 s, which the pairing of another clock's readings was built for.
pub(crate) const LINEAR_AT_MOST_NS: i128 = 120_000_000_000;

/// The furthest a reading is held beside a sample no line reaches (before the first reading,
/// after the last, beside a gap wider than [`LINEAR_AT_MOST_NS`]): 10 s, the pairing's
/// tolerance when less. A reading held 10 s on a brisk ramp (1 °C/min) is 0.17 °C off; held
/// a sparse topic's half step (150 s of a reading every 300 s) it would be 2.5 °C off, a flat
/// stretch the temperature never had.
pub(crate) const HOLD_AT_MOST_NS: i128 = 10_000_000_000;

/// Where a sample's temperature comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Reading {
    /// Reading `i`'s value, as it stands: taken with the sample, or the nearest one held.
    At(usize),
    /// The straight line from reading `.0` to reading `.1`, a fraction `.2` of the way.
    Between(usize, usize, f64),
}

impl Reading {
    /// The temperature, from each reading's value (`celsius(i)`, °C).
    pub(crate) fn celsius(self, celsius: impl Fn(usize) -> f64) -> f64 {
        match self {
            Reading::At(i) => celsius(i),
            Reading::Between(a, b, w) => {
                let (ca, cb) = (celsius(a), celsius(b));
                ca + (cb - ca) * w
            }
        }
    }
}

/// What [`readings`] gives each sample, and why some have none.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Readings {
    /// Each sample's reading, or none.
    pub each: Vec<Option<Reading>>,
    /// Samples between two readings more than [`LINEAR_AT_MOST_NS`] apart, none within the
    /// hold: how many, the first (0-based), and the widest such gap (ns).
    pub too_far: usize,
    pub first_too_far: Option<usize>,
    pub widest_ns: i128,
    /// The other samples without a reading (before the first, after the last, beyond the
    /// hold): how many and the first.
    pub beyond: usize,
    pub first_beyond: Option<usize>,
}

/// Each of `times` (ns, the samples') given its temperature among readings taken at
/// `candidates` (ns, any order, on the same clock), as the module says; `hold` is the
/// pairing's tolerance, which [`HOLD_AT_MOST_NS`] bounds.
pub(crate) fn readings(times: &[i128], candidates: &[i128], hold: i128) -> Readings {
    let hold = hold.min(HOLD_AT_MOST_NS);
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by_key(|&i| candidates[i]);
    let mut out = Readings::default();
    for (k, &t) in times.iter().enumerate() {
        let j = order.partition_point(|&i| candidates[i] < t);
        let before = j.checked_sub(1).map(|p| order[p]);
        let after = order.get(j).copied();
        let reading = match (before, after) {
            (_, Some(b)) if candidates[b] == t => Some(Reading::At(b)),
            (Some(a), Some(b)) if candidates[b] - candidates[a] <= LINEAR_AT_MOST_NS => {
                let (ta, tb) = (candidates[a], candidates[b]);
                Some(Reading::Between(a, b, (t - ta) as f64 / (tb - ta) as f64))
            }
            _ => {
                let near = [before, after]
                    .into_iter()
                    .flatten()
                    .map(|i| (i, (candidates[i] - t).abs()))
                    .filter(|&(_, d)| d <= hold)
                    .min_by_key(|&(_, d)| d);
                if near.is_none() {
                    if let (Some(a), Some(b)) = (before, after) {
                        out.too_far += 1;
                        out.first_too_far.get_or_insert(k);
                        out.widest_ns = out.widest_ns.max(candidates[b] - candidates[a]);
                    } else {
                        out.beyond += 1;
                        out.first_beyond.get_or_insert(k);
                    }
                }
                near.map(|(i, _)| Reading::At(i))
            }
        };
        out.each.push(reading);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: i128 = 1_000_000_000;

    /// The temperatures of `r` from readings valued `c`, NaN where none.
    fn temps(r: &Readings, c: &[f64]) -> Vec<f64> {
        r.each
            .iter()
            .map(|x| x.map_or(f64::NAN, |x| x.celsius(|i| c[i])))
            .collect()
    }

    #[test]
    fn a_sample_between_two_readings_is_on_the_line_between_them() {
        // Readings every 4 s (in reverse order: any order serves), samples every second.
        let cand = [8 * S, 4 * S, 0];
        let c = [28.0, 24.0, 20.0];
        let times: Vec<i128> = (0..=9).map(|k| k * S).collect();
        let r = readings(&times, &cand, 4 * S);
        let got = temps(&r, &c);
        // 0..8 s on the line (20 + t); 9 s past the last reading, held within the tolerance.
        let want = [20.0, 21.0, 22.0, 23.0, 24.0, 25.0, 26.0, 27.0, 28.0, 28.0];
        assert_eq!(got, want);
        assert_eq!((r.too_far, r.beyond), (0, 0));
    }

    #[test]
    fn a_sample_taken_with_a_reading_keeps_its_value_bit_for_bit() {
        let cand = [0, S, 2 * S];
        let c = [0.1, 0.7, 0.2];
        let r = readings(&cand, &cand, S);
        assert_eq!(
            r.each,
            [Reading::At(0), Reading::At(1), Reading::At(2)].map(Some)
        );
        assert_eq!(temps(&r, &c), c);
    }

    #[test]
    fn readings_too_far_apart_give_no_line_and_no_held_plateau() {
        // Readings 2000 s apart, samples every 10 s: within 10 s of a reading it is held,
        // further no temperature at all (not 1000 s of a held reading).
        let cand = [0, 2000 * S, 4000 * S];
        let times: Vec<i128> = (0..=400).map(|k| k * 10 * S).collect();
        let r = readings(&times, &cand, 2000 * S);
        let held = r.each.iter().filter(|x| x.is_some()).count();
        // 0 and 10 s, 1990..2010 s, 3990 and 4000 s.
        assert_eq!(held, 2 + 3 + 2);
        assert_eq!(r.too_far, 401 - held);
        assert_eq!(r.first_too_far, Some(2));
        assert_eq!(r.widest_ns, 2000 * S);
        assert_eq!(r.beyond, 0);
    }

    #[test]
    fn past_the_last_reading_a_reading_is_held_only_within_the_tolerance() {
        let cand = [0, S];
        let times: Vec<i128> = (0..5).map(|k| k * S).collect();
        let r = readings(&times, &cand, S);
        assert_eq!(
            r.each,
            [
                Some(Reading::At(0)),
                Some(Reading::At(1)),
                Some(Reading::At(1)),
                None,
                None
            ]
        );
        assert_eq!((r.beyond, r.first_beyond, r.too_far), (2, Some(3), 0));
    }
}
