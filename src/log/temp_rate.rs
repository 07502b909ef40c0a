//! Stretches where the temperature moves faster than any chamber moves a gyro's: the one rule
//! both readers (CSV and drone logs) tell them by.
//!
//! A log whose time is read in the wrong unit shows it first here: a chamber controller's
//! time column counting minutes, unitless and so read as seconds, makes an 11-hour run 11
//! minutes long and its 1 °C/min ramps 60 °C/min. Every figure computed from such a log is
//! wrong (Ṫ and T̈ 60 and 3600 times too large, an Allan τ 60 times too short) without any
//! figure looking wrong on its own, so the reader says it. Rows out of order (a log put
//! together from blocks in the wrong order) show the same way: a step between blocks that no
//! chamber makes.
//!
//! The rate is taken between the medians of neighbouring blocks of samples (each at least
//! [`BLOCK_SAMPLES`] samples and [`BLOCK_S`] long), so that a sensor's noise, its quantum and
//! a bad read of a few samples do not make a rate; and a stretch is told only when the
//! temperature moves over it by at least what a glitch stands out by ([`GLITCH_LEAST_C`], or
//! [`GLITCH_NOISE_FACTOR`] typical steps of a noisier column). The samples are kept: the
//! numbers may be right and their time wrong, and which is the user knows.

use crate::log::temp_glitch::{GLITCH_LEAST_C, GLITCH_NOISE_FACTOR, typical_step};

/// The fastest a gyro's temperature moves for a stretch, °C/s: 30 °C a minute. The fastest
/// chambers (for stress screening) ramp their air at 15 to 30 °C/min, and a gyro, lagging its
/// air, moves slower still; calibration ramps are 0.5 to 2 °C/min, which a time in minutes read
/// as seconds makes 30 to 120 °C/min. Half of
/// [`FASTEST_CHAMBER_C_PER_S`](crate::log::temp_glitch::FASTEST_CHAMBER_C_PER_S), the bound of
/// one step, which a chamber does not reach at all, let alone hold.
pub const FASTEST_SUSTAINED_C_PER_S: f64 = 0.5;

/// The fewest samples of a block whose median gives the temperature a rate is taken from: a
/// bad read of up to two samples does not move the median of five off the others.
pub const BLOCK_SAMPLES: usize = 5;

/// The shortest block, s: a rate is measured between two blocks' middles, over at least this
/// long (and at least [`BLOCK_SAMPLES`] samples), so a fast-sampled sensor's noise averages out.
pub const BLOCK_S: f64 = 2.5;

/// The stretches of a temperature moving faster than [`FASTEST_SUSTAINED_C_PER_S`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FastStretches {
    /// Index of the sample where the first stretch starts (the middle of its first block).
    pub first: usize,
    /// How many stretches.
    pub count: usize,
    /// The fastest rate between two blocks, °C/s (its magnitude).
    pub fastest_c_per_s: f64,
    /// How long the stretches last in all, s.
    pub lasting_s: f64,
}

impl FastStretches {
    /// The problem's words, the first stretch at `place` ("line 1003"), with `advice` (what to
    /// check, which unit the time may be in) after a semicolon.
    pub fn message(&self, place: &str, advice: &str) -> String {
        let r = |v: f64| crate::number::significant(v, 3);
        let (n, s) = (self.count, if self.count == 1 { "" } else { "es" });
        format!(
            "the temperature moves at up to {} °C/s ({} °C/min) for {} s in all, {n} \
             stretch{s} (first at {place}): faster than any chamber moves a gyro's temperature \
             ({FASTEST_SUSTAINED_C_PER_S} °C/s, {} °C/min, at most); {advice}",
            r(self.fastest_c_per_s),
            r(60.0 * self.fastest_c_per_s),
            r(self.lasting_s),
            r(60.0 * FASTEST_SUSTAINED_C_PER_S),
        )
    }
}

/// A block: its middle sample, its median temperature (`None` when half its samples or more
/// are not finite) and its middle's time.
struct Block {
    mid: usize,
    temp_c: Option<f64>,
    time_s: f64,
}

/// The stretches where `temp_c` sampled at `time_s` (same length, time increasing) moves
/// faster than [`FASTEST_SUSTAINED_C_PER_S`], `None` when there is none: runs of neighbouring
/// blocks each faster than that one way, over which the temperature moves by at least
/// [`GLITCH_LEAST_C`] and [`GLITCH_NOISE_FACTOR`] typical steps.
pub(crate) fn find(time_s: &[f64], temp_c: &[f64]) -> Option<FastStretches> {
    let n = temp_c.len().min(time_s.len());
    let least_move = GLITCH_LEAST_C.max(GLITCH_NOISE_FACTOR * typical_step(&temp_c[..n]));
    let blocks = blocks(&time_s[..n], &temp_c[..n]);
    // The signed rate between each block and the next, NaN where either has no median.
    let rates: Vec<f64> = blocks
        .windows(2)
        .map(|w| match (w[0].temp_c, w[1].temp_c) {
            (Some(a), Some(b)) => (b - a) / (w[1].time_s - w[0].time_s),
            _ => f64::NAN,
        })
        .collect();
    let fast = |r: f64| r.abs() > FASTEST_SUSTAINED_C_PER_S; // false for NaN
    let mut found: Option<FastStretches> = None;
    let mut k = 0;
    while k < rates.len() {
        if !fast(rates[k]) {
            k += 1;
            continue;
        }
        // The stretch: pairs k..end, each fast and the same way.
        let sign = rates[k].signum();
        let mut end = k + 1;
        while end < rates.len() && fast(rates[end]) && rates[end].signum() == sign {
            end += 1;
        }
        let (a, b) = (&blocks[k], &blocks[end]);
        let moved = match (a.temp_c, b.temp_c) {
            (Some(x), Some(y)) => (y - x).abs(),
            _ => 0.0,
        };
        if moved >= least_move {
            let fastest = rates[k..end].iter().fold(0.0f64, |m, r| m.max(r.abs()));
            let f = found.get_or_insert(FastStretches {
                first: a.mid,
                count: 0,
                fastest_c_per_s: 0.0,
                lasting_s: 0.0,
            });
            f.count += 1;
            f.fastest_c_per_s = f.fastest_c_per_s.max(fastest);
            f.lasting_s += b.time_s - a.time_s;
        }
        k = end;
    }
    found
}

/// The series cut into blocks of at least [`BLOCK_SAMPLES`] samples spanning at least
/// [`BLOCK_S`], from the first sample on; the samples after the last whole block are left out.
fn blocks(time_s: &[f64], temp_c: &[f64]) -> Vec<Block> {
    let n = temp_c.len();
    let mut out = Vec::new();
    let mut scratch = Vec::new();
    let mut start = 0;
    while start < n {
        // Long enough, false for a NaN time (which no block then ends at).
        let long = |end: usize| time_s[end - 1] - time_s[start] >= BLOCK_S;
        let mut end = start + BLOCK_SAMPLES;
        while end <= n && !long(end) {
            end += 1;
        }
        if end > n {
            break;
        }
        scratch.clear();
        scratch.extend(temp_c[start..end].iter().copied().filter(|v| v.is_finite()));
        let temp = (2 * scratch.len() > end - start).then(|| {
            let mid = scratch.len() / 2;
            *scratch.select_nth_unstable_by(mid, f64::total_cmp).1
        });
        let mid = start + (end - start) / 2;
        out.push(Block {
            mid,
            temp_c: temp,
            time_s: time_s[mid],
        });
        start = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(n: usize, step_s: f64, temp: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64 * step_s).collect();
        let temp = t.iter().map(|&t| temp(t)).collect();
        (t, temp)
    }

    /// A calibration program: 20 °C held, a ramp at `rate` °C/s to 60 °C, held; time in s.
    fn program(rate: f64) -> impl Fn(f64) -> f64 {
        move |t: f64| {
            let ramp_s = 40.0 / rate;
            20.0 + 40.0 * ((t - 3600.0) / ramp_s).clamp(0.0, 1.0)
        }
    }

    #[test]
    fn a_ramp_of_a_degree_a_minute_with_its_time_in_minutes_read_as_seconds_is_told() {
        // The program at 1 °C/min sampled each second, its time in minutes read as seconds:
        // each "second" is a minute, so the ramp reads as 1 °C/s.
        let real = program(1.0 / 60.0);
        let (t, temp) = series(3 * 3600, 1.0 / 60.0, |t| real(60.0 * t));
        let f = find(&t, &temp).expect("a fast stretch");
        assert_eq!(f.count, 1);
        assert!((f.fastest_c_per_s - 1.0).abs() < 0.01, "{f:?}");
        // The ramp lasts 40 min: 40 "s", within a block (2.5 "s") at each end.
        assert!((35.0..=45.0).contains(&f.lasting_s), "{f:?}");
        // It starts at 60 "s" (3600 s), where the ramp does.
        let at = t[f.first];
        assert!((57.0..=61.0).contains(&at), "{at}");
        // Read in seconds it is the chamber's.
        let (t, temp) = series(3 * 3600, 1.0, real);
        assert_eq!(find(&t, &temp), None);
    }

    #[test]
    fn rows_put_together_out_of_order_are_told() {
        // Blocks of 600 samples of the ramp, swapped in pairs: a step of 10 °C at each joint.
        let (t, temp) = series(6000, 1.0, |t| 20.0 + 0.01 * t);
        let shuffled: Vec<f64> = (0..6000)
            .map(|i| {
                let (block, k) = (i / 600, i % 600);
                temp[(block ^ 1) * 600 + k]
            })
            .collect();
        let f = find(&t, &shuffled).expect("steps");
        assert!(f.count >= 5, "{f:?}");
        assert!(f.fastest_c_per_s > 1.0, "{f:?}");
    }

    #[test]
    fn chamber_programs_noise_and_short_bad_reads_are_none() {
        // Ramps at 2 °C/min and 20 °C/min (a stress-screening chamber), at 1 Hz and 1 kHz.
        for (rate, step_s) in [(2.0 / 60.0, 1.0), (20.0 / 60.0, 1.0), (2.0 / 60.0, 1e-3)] {
            let (t, temp) = series(20_000, step_s, program(rate));
            assert_eq!(find(&t, &temp), None, "{rate} °C/s at {step_s} s");
        }
        // A MEMS sensor at 1 kHz: noise of 0.5 °C and a 1 °C quantum flickering.
        let (t, temp) = series(20_000, 1e-3, |t| {
            45.0 + ((t * 1e3) as usize % 2) as f64 + 0.5 * (t * 7919.0).sin()
        });
        assert_eq!(find(&t, &temp), None);
        // Two bad reads in a row at 127.996 °C on a plateau at 1 Hz.
        let (t, mut temp) = series(600, 1.0, |_| 20.0);
        temp[300] = 127.996;
        temp[301] = 127.996;
        assert_eq!(find(&t, &temp), None);
        // Raw counts with a noise of ±20 a sample: a counts column is no fast temperature.
        let (t, temp) = series(3000, 1.0, |t| 4000.0 + [0.0, 20.0, -20.0][t as usize % 3]);
        assert_eq!(find(&t, &temp), None);
        // Too short for two blocks; NaN throughout.
        let (t, temp) = series(8, 1.0, |t| 100.0 * t);
        assert_eq!(find(&t, &temp), None);
        let (t, temp) = series(100, 1.0, |_| f64::NAN);
        assert_eq!(find(&t, &temp), None);
    }

    #[test]
    fn the_message_says_the_rate_in_both_units_and_the_bound() {
        let f = FastStretches {
            first: 3,
            count: 2,
            fastest_c_per_s: 1.1,
            lasting_s: 80.0,
        };
        let m = f.message("line 3602", "check it");
        assert!(
            m.contains(
                "moves at up to 1.1 °C/s (66 °C/min) for 80 s in all, 2 stretches (first at \
                 line 3602): faster than any chamber moves a gyro's temperature (0.5 °C/s, \
                 30 °C/min, at most); check it"
            ),
            "{m}"
        );
    }
}
