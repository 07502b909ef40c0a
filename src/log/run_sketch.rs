//! Which samples of a log are another's: a sketch of a run's samples small enough for a
//! calibration file to carry, and the share of a log's samples it finds there.
//!
//! Figures judged on the samples a calibration was fitted on are in-sample, whatever file
//! they come in. A whole-run fingerprint told one run from another, but not a part of it:
//! the calibration log less its first row, or its first 30,000 rows, read as "held out",
//! and another gyro's rate beside the same time and temperature read as "in-sample". The
//! sketch is a bottom-k sample of the run (Broder, "On the resemblance and containment of
//! documents", 1997): every run of eight consecutive samples' temperatures and rates is
//! hashed, and the [`SKETCH_LEN`] smallest hashes kept. A log holding a share `s` of the run's samples
//! holds about `s·SKETCH_LEN` of them, whatever part of the run it holds and in whatever
//! file; another run holds none, since its noise differs at every sample.

use super::Log;

/// Hashes a sketch keeps: a log holding 3 % of a run's samples is found in it (about four
/// of them), and the sketch is 2 KiB of hexadecimal in a calibration file.
pub const SKETCH_LEN: usize = 128;

/// Sketch hashes a log must hold to be called the run's: one could be two other runs'
/// samples that happen to agree in every bit kept (a plateau's temperature, a rate of few
/// digits, the same time stamp).
const MIN_FOUND: usize = 2;

/// The smallest hashes of a run's samples, ascending.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RunSketch {
    hashes: Vec<u64>,
}

/// How much of a log is a run's samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shared {
    /// The sketch's hashes found among the log's samples.
    pub found: usize,
    /// The hashes in the sketch.
    pub of: usize,
    /// The share of the log's samples that are the run's, estimated (0 to 1).
    pub share_of_log: f64,
}

/// The share of a log's samples that makes its figures in-sample: most of them. A log that
/// shares less with the run (two simulated runs of one seed share their first hour) is held
/// out, and the faces say how much it shares ([`Shared::partly`]).
const IN_SAMPLE_SHARE: f64 = 0.5;

impl Shared {
    /// Whether the log holds the run's samples at all (beyond two other runs' chance
    /// agreement).
    fn found_any(&self) -> bool {
        self.found >= MIN_FOUND.min(self.of)
    }

    /// Whether most of the log's samples are the run's: its figures are in-sample.
    pub fn in_sample(&self) -> bool {
        self.found_any() && self.share_of_log >= IN_SAMPLE_SHARE
    }

    /// The share of the log's samples that are the run's when some are but not most: the
    /// log is held out, and its figures are partly the run's own.
    pub fn partly(&self) -> Option<f64> {
        (self.found_any() && !self.in_sample()).then_some(self.share_of_log)
    }
}

impl RunSketch {
    /// The sketch of `log`'s samples as they are (its selected axis's rate).
    pub fn of(log: &Log) -> RunSketch {
        let mut heap = std::collections::BinaryHeap::with_capacity(SKETCH_LEN + 1);
        for h in sample_hashes(log) {
            if heap.len() < SKETCH_LEN {
                heap.push(h);
            } else if heap.peek().is_some_and(|&top| h < top) {
                heap.pop();
                heap.push(h);
            }
        }
        let mut hashes = heap.into_vec();
        hashes.sort_unstable();
        hashes.dedup();
        RunSketch { hashes }
    }

    /// Whether the sketch holds nothing (a file written before sketches were kept).
    pub fn is_empty(&self) -> bool {
        self.hashes.is_empty()
    }

    /// How much of `log` is the run's samples; `run_samples` is the run's sample count.
    pub fn shared_with(&self, log: &Log, run_samples: usize) -> Shared {
        let mut found = vec![false; self.hashes.len()];
        for h in sample_hashes(log) {
            if let Ok(k) = self.hashes.binary_search(&h) {
                found[k] = true;
            }
        }
        let found = found.iter().filter(|&&f| f).count();
        let of = self.hashes.len();
        // `found/of` of the run's samples are in the log; as a share of the log's own.
        let share_of_log = if of == 0 || log.is_empty() {
            0.0
        } else {
            // Runs of samples, each log's: one fewer than RUN_OF fewer than its samples.
            let runs = |samples: usize| samples.saturating_sub(RUN_OF - 1).max(1) as f64;
            (found as f64 / of as f64 * runs(run_samples) / runs(log.len())).min(1.0)
        };
        Shared {
            found,
            of,
            share_of_log,
        }
    }

    /// The sketch as calibration files hold it: each hash in 16 hexadecimal digits, joined.
    pub fn to_hex(&self) -> String {
        self.hashes.iter().map(|h| format!("{h:016x}")).collect()
    }

    /// A sketch from [`RunSketch::to_hex`]'s text; `None` when it is not that.
    pub fn from_hex(text: &str) -> Option<RunSketch> {
        if !text.len().is_multiple_of(16) || !text.is_ascii() || text.len() > 16 * SKETCH_LEN {
            return None;
        }
        let hashes: Option<Vec<u64>> = (0..text.len() / 16)
            .map(|k| u64::from_str_radix(&text[16 * k..16 * k + 16], 16).ok())
            .collect();
        let hashes = hashes?;
        hashes
            .windows(2)
            .all(|w| w[0] < w[1])
            .then_some(RunSketch { hashes })
    }
}

/// Samples whose values one hash covers: a run of consecutive samples, not one. A log written
/// with few digits (a rate in 0.1 °/h, a temperature in 0.1 °C) repeats each sample's pair of
/// values many times over, and another run of the same gyro holds the same pairs (two thirds
/// of one were found in another); eight in a row agreeing by chance is as unlikely as the
/// noise of two runs agreeing for eight samples.
const RUN_OF: usize = 8;

/// The hash of each run of [`RUN_OF`] consecutive samples (one per sample from the
/// [`RUN_OF`]-th on): their temperatures and rates, each with its last 20 bits of mantissa
/// rounded off, so that a column read through another unit (°/s × 3600) or written back with
/// fewer digits than a double holds is still the same sample. Not their time: the same
/// samples stamped from the epoch, or in another time unit, are the same run.
fn sample_hashes(log: &Log) -> impl Iterator<Item = u64> + '_ {
    let n = log.temp_c.len().min(log.omega_dph.len());
    let one = move |i: usize| {
        let mut h = 0x05ee_d0fd_21f7_u64;
        for v in [log.temp_c[i], log.omega_dph[i]] {
            h = mix(h ^ rounded_bits(v));
        }
        h
    };
    let mut last = [0u64; RUN_OF];
    (0..n).filter_map(move |i| {
        last[i % RUN_OF] = one(i);
        (i + 1 >= RUN_OF).then(|| {
            // The run's samples in their order, oldest first.
            (0..RUN_OF).fold(0x0dd_ba11_u64, |h, k| mix(h ^ last[(i + 1 + k) % RUN_OF]))
        })
    })
}

/// The bits of `v` rounded to 32 bits of mantissa (about 9.6 significant digits); one value
/// for every NaN, and for 0 and −0.
fn rounded_bits(v: f64) -> u64 {
    const DROPPED: u32 = 20;
    if v.is_nan() {
        return u64::MAX;
    }
    if v == 0.0 {
        return 0;
    }
    let bits = v.to_bits();
    // Round half up on the magnitude; a carry into the exponent is the next power of two,
    // as it should be.
    (bits + (1 << (DROPPED - 1))) >> DROPPED
}

/// SplitMix64's finaliser (Steele, Lea and Flood, 2014): a fixed, well-mixed 64-bit hash
/// that no Rust release changes, as the files that hold its values need.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run of `n` samples at 1 Hz whose rate is noise drawn from `seed`.
    fn run(n: usize, seed: u64) -> Log {
        let mut s = seed;
        let omega: Vec<f64> = (0..n)
            .map(|_| {
                s = mix(s);
                ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5).mul_add(0.2, 0.01)
            })
            .collect();
        Log::from_columns(
            "run.csv",
            (0..n).map(|i| i as f64).collect(),
            omega,
            (0..n).map(|i| 20.0 + (i / 600) as f64).collect(),
        )
    }

    fn part(log: &Log, range: std::ops::Range<usize>) -> Log {
        Log::from_columns(
            "part.csv",
            log.time_s[range.clone()].to_vec(),
            log.omega_dph[range.clone()].to_vec(),
            log.temp_c[range].to_vec(),
        )
    }

    #[test]
    fn a_part_of_the_run_is_found_in_proportion_and_another_run_is_not() {
        let cal = run(40_000, 1);
        let sketch = RunSketch::of(&cal);
        assert_eq!(sketch.hashes.len(), SKETCH_LEN);
        let whole = sketch.shared_with(&cal, cal.len());
        assert_eq!((whole.found, whole.share_of_log), (SKETCH_LEN, 1.0));
        // Less its first sample: still all of it, in-sample.
        let trimmed = sketch.shared_with(&part(&cal, 1..40_000), cal.len());
        assert!(
            trimmed.in_sample() && trimmed.share_of_log > 0.95,
            "{trimmed:?}"
        );
        // Three quarters: about 96 of the 128, all of the part's samples the run's.
        let most = sketch.shared_with(&part(&cal, 0..30_000), cal.len());
        assert!((70..=120).contains(&most.found), "{most:?}");
        assert!(most.in_sample() && most.share_of_log > 0.9, "{most:?}");
        // Another run on the same time and temperature: none of it.
        let other = sketch.shared_with(&run(40_000, 2), cal.len());
        assert!(!other.in_sample() && other.found == 0, "{other:?}");
        assert_eq!(other.partly(), None);
        // A tenth of the run beside nine tenths of another: held out, partly the run's.
        let mut mixed = run(40_000, 2);
        mixed.omega_dph[..4_000].copy_from_slice(&cal.omega_dph[..4_000]);
        let some = sketch.shared_with(&mixed, cal.len());
        assert!(!some.in_sample(), "{some:?}");
        assert!(
            some.partly().is_some_and(|s| (0.02..0.25).contains(&s)),
            "{some:?}"
        );
    }

    #[test]
    fn two_runs_written_with_few_digits_are_not_one() {
        // Rates of ±1 °/h noise written in 0.1 °/h, on a temperature written in whole °C:
        // the same pairs of values recur in both runs (a pair in twenty), eight in a row do
        // not.
        let coarse = |seed| {
            let mut log = run(40_000, seed);
            for w in &mut log.omega_dph {
                *w = (*w * 100.0).round() / 10.0;
            }
            log
        };
        let (a, b) = (coarse(6), coarse(7));
        let shared = RunSketch::of(&a).shared_with(&b, a.len());
        assert!(
            !shared.in_sample() && shared.partly().is_none(),
            "{shared:?}"
        );
        assert!(RunSketch::of(&a).shared_with(&a, a.len()).in_sample());
    }

    #[test]
    fn the_same_samples_stamped_otherwise_are_the_same_run() {
        let cal = run(5_000, 5);
        let sketch = RunSketch::of(&cal);
        let mut epoch = cal.clone();
        for t in &mut epoch.time_s {
            *t += 1.7e9;
        }
        assert_eq!(sketch.shared_with(&epoch, cal.len()).found, SKETCH_LEN);
    }

    #[test]
    fn the_same_samples_through_another_unit_are_the_same_run() {
        let cal = run(5_000, 3);
        let sketch = RunSketch::of(&cal);
        // The rate read in °/s and converted back: a few ulps off.
        let mut converted = cal.clone();
        for w in &mut converted.omega_dph {
            *w = *w / 3600.0 * 3600.0;
        }
        let shared = sketch.shared_with(&converted, cal.len());
        assert!(shared.found >= SKETCH_LEN - 2, "{shared:?}");
    }

    #[test]
    fn the_file_text_reads_back_and_nothing_else_does() {
        let sketch = RunSketch::of(&run(1_000, 4));
        let text = sketch.to_hex();
        assert_eq!(text.len(), 16 * SKETCH_LEN);
        assert_eq!(RunSketch::from_hex(&text), Some(sketch));
        for bad in [
            "abc",
            "zzzzzzzzzzzzzzzz",
            "00000000000000020000000000000001",
        ] {
            assert_eq!(RunSketch::from_hex(bad), None, "{bad}");
        }
    }
}
