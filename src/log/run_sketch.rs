//! Which samples of a log are another's: a sketch of a run's samples small enough for a
//! calibration file to carry, and the share of a log's samples it finds there.
//!
//! Figures judged on the samples a calibration was fitted on are in-sample, whatever file
//! they come in. A whole-run fingerprint told one run from another, but not a part of it:
//! the calibration log less its first row, or its first 30,000 rows, read as "held out",
//! and another gyro's rate beside the same time and temperature read as "in-sample". The
//! sketch is a bottom-k sample of the run (Broder, "On the resemblance and containment of
//! documents", 1997): values of the run are hashed, and the [`SKETCH_LEN`] smallest distinct
//! hashes kept. Every value of the run whose hash is at most the sketch's largest is in the
//! sketch, so among a log's values hashed that low, the share found in the sketch is the
//! share of the log's values that are the run's: all of them for any part of the run, in
//! any file; none for another run, since its noise differs at every sample.
//!
//! Two sketches, for two ways a copy of a run differs from it:
//! - **Runs of eight** consecutive samples: a log written with few digits (a rate in
//!   0.1 °/h, a temperature in 0.1 °C) repeats each sample's pair of values many times, and
//!   another run of the same gyro holds the same pairs (two thirds of one were found in
//!   another); eight in a row agreeing by chance is as unlikely as the noise of two runs
//!   agreeing for eight samples. But a copy that dropped rows (thinned to every other row,
//!   rows without a temperature left out) keeps none of the runs.
//! - **Single samples**, kept beside the runs: a thinned copy keeps its samples. How often a
//!   value recurs by chance depends on where the run is: on a ramp no temperature repeats,
//!   on a plateau held at 20.000 °C a rate written with four decimals meets its like in
//!   half the samples. So the chance is measured on the run itself, per degree of
//!   temperature (its odd samples' values among its even samples', as a second run of the
//!   same program would meet them), and only what a log shares beyond the chance of the
//!   temperatures it holds counts; temperatures where values recur too often tell nothing
//!   and are not looked at.

use super::Log;
use std::collections::HashSet;

/// Hashes a sketch keeps: a log holding 3 % of a run's samples is found in it (about four
/// of them), and the sketch is 2 KiB of hexadecimal in a calibration file.
pub const SKETCH_LEN: usize = 128;

/// Sketch hashes a log must hold to be called the run's: one could be two other runs'
/// samples that happen to agree in every bit kept (a plateau's temperature, a rate of few
/// digits, the same time stamp).
const MIN_FOUND: usize = 2;

/// The share of a log's samples that makes its figures in-sample: most of them. A log that
/// shares less with the run (two simulated runs of one seed share their first hour) is held
/// out, and the faces say how much it shares ([`Shared::partly`]).
const IN_SAMPLE_SHARE: f64 = 0.5;

/// The chance that a value recurs, past which single samples at that temperature tell
/// nothing of a log: a log written with so few digits, or held so long at one temperature,
/// that another run of the program meets half of its values there. Below it, a log sharing
/// the run's values in excess of chance by [`IN_SAMPLE_SHARE`] is at least a quarter of the
/// way from chance to all, many standard errors of a 128-value sketch away from another run.
const MAX_CHANCE: f64 = 0.5;

/// Values looked at to measure the chance of a recurring value: enough for a share known to
/// a few tenths of a percent, few enough that a million-sample log is sketched in
/// milliseconds.
const CHANCE_VALUES: usize = 1 << 16;

/// Temperature bins the chance is measured in, at most: a degree each over a chamber's
/// whole range (−60 … +150 °C), wider beyond it.
const MAX_BINS: usize = 256;

/// A log's values below the sketch's largest hash that single samples must see before they
/// judge it: fewer (a short log, or one held where values recur) leave it to the runs.
const MIN_SEEN: usize = 8;

/// Samples whose values one hash of the runs sketch covers (see the module's doc).
const RUN_OF: usize = 8;

/// The smallest hashes of a run's runs of samples, and of its single samples when they
/// tell runs apart; each ascending.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunSketch {
    runs: Vec<u64>,
    singles: Option<Singles>,
}

/// The single samples' sketch and how often the run's values recur by chance.
#[derive(Debug, Clone, PartialEq)]
struct Singles {
    hashes: Vec<u64>,
    chance: ChanceByTemperature,
}

/// The share of the run's odd samples whose values its even samples hold, per bin of
/// temperature, as a second run of the program would meet them among all the run's.
#[derive(Debug, Clone, PartialEq)]
struct ChanceByTemperature {
    /// The lower edge of the first bin, °C (whole).
    t0: f64,
    /// The bins' width, °C (whole, at least 1).
    width: f64,
    /// Each bin's chance in 255ths; 255 where nothing was measured.
    chance: Vec<u8>,
}

impl ChanceByTemperature {
    /// The chance of a value at `temp_c` recurring in the run: 0 outside the run's
    /// temperatures (no value there is the run's); `None` for no temperature.
    fn at(&self, temp_c: f64) -> Option<f64> {
        if !temp_c.is_finite() {
            return None;
        }
        let b = ((temp_c - self.t0) / self.width).floor();
        if b < 0.0 || b >= self.chance.len() as f64 {
            return Some(0.0);
        }
        Some(f64::from(self.chance[b as usize]) / 255.0)
    }

    /// Whether some temperature of the run tells its values from another run's.
    fn tells_any(&self) -> bool {
        self.chance
            .iter()
            .any(|&c| f64::from(c) / 255.0 <= MAX_CHANCE)
    }

    fn to_text(&self) -> String {
        let bytes: String = self.chance.iter().map(|c| format!("{c:02x}")).collect();
        format!("{}:{}:{bytes}", self.t0, self.width)
    }

    fn from_text(text: &str) -> Option<ChanceByTemperature> {
        let mut parts = text.split(':');
        let (t0, width, bytes) = (parts.next()?, parts.next()?, parts.next()?);
        if parts.next().is_some() {
            return None;
        }
        let (t0, width): (f64, f64) = (t0.parse().ok()?, width.parse().ok()?);
        let whole = |v: f64| v.is_finite() && v.fract() == 0.0 && v.abs() < 1e6;
        if !whole(t0) || !whole(width) || width < 1.0 {
            return None;
        }
        if bytes.is_empty() || !bytes.len().is_multiple_of(2) || bytes.len() > 2 * MAX_BINS {
            return None;
        }
        let chance: Option<Vec<u8>> = (0..bytes.len() / 2)
            .map(|k| u8::from_str_radix(bytes.get(2 * k..2 * k + 2)?, 16).ok())
            .collect();
        Some(ChanceByTemperature {
            t0,
            width,
            chance: chance?,
        })
    }
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
    /// The log's samples.
    pub log_samples: usize,
    /// The run's samples.
    pub run_samples: usize,
}

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

    /// The share of the run's samples the log holds, estimated (0 to 1): its samples that are
    /// the run's, counted (exact when no sample of the log repeats another), unless that count
    /// is beyond what the sketch found by more than its error (a log repeating a part of the
    /// run many times), when the sketch's own estimate is taken.
    pub fn share_of_run(&self) -> f64 {
        if self.of == 0 || self.run_samples == 0 {
            return 0.0;
        }
        let sketched = self.found as f64 / self.of as f64;
        let counted =
            (self.share_of_log * self.log_samples as f64 / self.run_samples as f64).min(1.0);
        // The sketch's standard error, at the larger of the two (a fair bound for both).
        let p = sketched.max(counted);
        let error = (p * (1.0 - p) / self.of as f64).sqrt();
        if (counted - sketched).abs() <= 3.0 * error + 1.0 / self.of as f64 {
            counted
        } else {
            sketched
        }
    }
}

impl RunSketch {
    /// The sketch of `log`'s samples as they are (its selected axis's rate).
    pub fn of(log: &Log) -> RunSketch {
        let runs = smallest(run_hashes(log));
        let chance = chance_by_temperature(log);
        // Only the values at temperatures that tell: those a log is judged by.
        let singles = chance
            .filter(ChanceByTemperature::tells_any)
            .map(|chance| Singles {
                hashes: smallest(single_hashes(log).enumerate().filter_map(|(i, h)| {
                    chance
                        .at(log.temp_c[i])
                        .is_some_and(|c| c <= MAX_CHANCE)
                        .then_some(h)
                })),
                chance,
            });
        RunSketch { runs, singles }
    }

    /// Whether the sketch holds nothing (a file written before sketches were kept).
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// How much of `log` is the run's samples (`run_samples` of them): by its runs of samples,
    /// or by its single samples when they say most of it is the run's (a thinned copy, a copy
    /// less the rows its reader left out).
    pub fn shared_with(&self, log: &Log, run_samples: usize) -> Shared {
        let counts = |found, of, share_of_log| Shared {
            found,
            of,
            share_of_log,
            log_samples: log.len(),
            run_samples,
        };
        let by_runs = {
            let (found, of, share) = containment(&self.runs, run_hashes(log));
            counts(found, of, share)
        };
        let by_singles = self
            .singles
            .as_ref()
            .and_then(|s| containment_beyond_chance(s, log))
            .map(|(found, of, share)| counts(found, of, share))
            .filter(Shared::in_sample);
        match by_singles {
            Some(s) if s.share_of_log > by_runs.share_of_log || !by_runs.found_any() => s,
            _ => by_runs,
        }
    }

    /// The sketch as calibration files hold it: each hash of the runs in 16 hexadecimal
    /// digits, joined; then, when single samples are sketched, `+`, the chance of a
    /// recurring value per bin of temperature (`T0:WIDTH:` and a byte a bin, 255ths), `+`
    /// and the single samples' hashes.
    pub fn to_text(&self) -> String {
        let hex =
            |hashes: &[u64]| -> String { hashes.iter().map(|h| format!("{h:016x}")).collect() };
        match &self.singles {
            None => hex(&self.runs),
            Some(s) => format!(
                "{}+{}+{}",
                hex(&self.runs),
                s.chance.to_text(),
                hex(&s.hashes)
            ),
        }
    }

    /// A sketch from [`RunSketch::to_text`]'s text; `None` when it is not that.
    pub fn from_text(text: &str) -> Option<RunSketch> {
        let mut parts = text.split('+');
        let runs = hashes_from_hex(parts.next()?)?;
        let singles = match (parts.next(), parts.next(), parts.next()) {
            (None, _, _) => None,
            (Some(chance), Some(hashes), None) => {
                let chance = ChanceByTemperature::from_text(chance)?;
                let hashes = hashes_from_hex(hashes)?;
                if hashes.is_empty() {
                    return None;
                }
                Some(Singles { hashes, chance })
            }
            _ => return None,
        };
        Some(RunSketch { runs, singles })
    }
}

/// Ascending hashes of at most [`SKETCH_LEN`] digits groups; `None` when `text` is not that.
fn hashes_from_hex(text: &str) -> Option<Vec<u64>> {
    if !text.len().is_multiple_of(16) || !text.is_ascii() || text.len() > 16 * SKETCH_LEN {
        return None;
    }
    let hashes: Option<Vec<u64>> = (0..text.len() / 16)
        .map(|k| u64::from_str_radix(&text[16 * k..16 * k + 16], 16).ok())
        .collect();
    let hashes = hashes?;
    hashes.windows(2).all(|w| w[0] < w[1]).then_some(hashes)
}

/// The [`SKETCH_LEN`] smallest distinct values of `hashes`, ascending.
fn smallest(hashes: impl Iterator<Item = u64>) -> Vec<u64> {
    let mut heap = std::collections::BinaryHeap::with_capacity(SKETCH_LEN + 1);
    for h in hashes {
        let full = heap.len() >= SKETCH_LEN;
        if full && heap.peek().is_some_and(|&top| h >= top) {
            continue;
        }
        // A value already kept (a stuck stretch repeats one) would crowd out another.
        if heap.iter().any(|&k| k == h) {
            continue;
        }
        heap.push(h);
        if heap.len() > SKETCH_LEN {
            heap.pop();
        }
    }
    heap.into_sorted_vec()
}

/// How much of a log's values are a sketch's run's: among the log's distinct hashes no
/// larger than the sketch's largest (every run value hashed that low is in the sketch), the
/// share found in it. The sketch's hashes found, its length, and the share.
fn containment(sketch: &[u64], log: impl Iterator<Item = u64>) -> (usize, usize, f64) {
    let Some(&top) = sketch.last() else {
        return (0, 0, 0.0);
    };
    let low: HashSet<u64> = log.filter(|&h| h <= top).collect();
    let found = low
        .iter()
        .filter(|h| sketch.binary_search(h).is_ok())
        .count();
    let share = if low.is_empty() {
        0.0
    } else {
        found as f64 / low.len() as f64
    };
    (found, sketch.len(), share)
}

/// [`containment`] of the log's single samples, beyond chance: only the values at
/// temperatures where the run's values rarely recur are looked at (the sketch holds only
/// those of the run's), the share the chance of
/// their temperatures would find is taken off, and the rest scaled to 0 to 1. `None` when
/// fewer than [`MIN_SEEN`] values are looked at.
fn containment_beyond_chance(singles: &Singles, log: &Log) -> Option<(usize, usize, f64)> {
    let top = *singles.hashes.last()?;
    let mut low: std::collections::HashMap<u64, f64> = std::collections::HashMap::new();
    for (i, h) in single_hashes(log).enumerate() {
        if h <= top
            && let Some(c) = singles.chance.at(log.temp_c[i])
            && c <= MAX_CHANCE
        {
            low.entry(h).or_insert(c);
        }
    }
    if low.len() < MIN_SEEN {
        return None;
    }
    let found = low
        .keys()
        .filter(|h| singles.hashes.binary_search(h).is_ok())
        .count();
    let seen = low.len() as f64;
    let expected = low.values().sum::<f64>() / seen;
    let share = found as f64 / seen;
    let beyond = ((share - expected) / (1.0 - expected)).clamp(0.0, 1.0);
    Some((found, singles.hashes.len(), beyond))
}

/// The hash of each sample's values: its temperature and rate, each with its last 20 bits
/// of mantissa rounded off, so that a column read through another unit (°/s × 3600) or
/// written back with fewer digits than a double holds is still the same sample. Not its
/// time: the same samples stamped from the epoch, or in another time unit, are the same run.
fn single_hashes(log: &Log) -> impl Iterator<Item = u64> + '_ {
    let n = log.temp_c.len().min(log.omega_dph.len());
    (0..n).map(move |i| {
        let mut h = 0x05ee_d0fd_21f7_u64;
        for v in [log.temp_c[i], log.omega_dph[i]] {
            h = mix(h ^ rounded_bits(v));
        }
        h
    })
}

/// The hash of each run of [`RUN_OF`] consecutive samples (one per sample from the
/// [`RUN_OF`]-th on): their single hashes in their order.
fn run_hashes(log: &Log) -> impl Iterator<Item = u64> + '_ {
    let mut last = [0u64; RUN_OF];
    single_hashes(log).enumerate().filter_map(move |(i, one)| {
        last[i % RUN_OF] = one;
        (i + 1 >= RUN_OF).then(|| {
            // The run's samples in their order, oldest first.
            (0..RUN_OF).fold(0x0dd_ba11_u64, |h, k| mix(h ^ last[(i + 1 + k) % RUN_OF]))
        })
    })
}

/// How often the run's values recur by chance, per bin of temperature: the share of its odd
/// samples' distinct values that its even samples hold, as a second run of the same program
/// would meet them among half of the run; a run twice as long meets about twice as many, so
/// the chance among the whole run is `1 − (1 − c)²`. Only values hashed below a bound are
/// looked at (at most about [`CHANCE_VALUES`] of them): a value is in or out whatever sample
/// holds it, so the share is the same. `None` for a run without temperatures.
fn chance_by_temperature(log: &Log) -> Option<ChanceByTemperature> {
    let n = log.temp_c.len().min(log.omega_dph.len());
    let (lo, hi) = log.temp_c[..n]
        .iter()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    if !(lo.is_finite() && hi.is_finite()) || hi - lo > 1e6 {
        return None;
    }
    let t0 = lo.floor();
    let width = ((hi - t0) / (MAX_BINS - 1) as f64).ceil().max(1.0);
    let bins = ((hi - t0) / width).floor() as usize + 1;
    let bound = match n / (2 * CHANCE_VALUES) {
        0 => u64::MAX,
        k => u64::MAX / (k as u64 + 1),
    };
    // (bin, hash, odd) of every sample hashed low enough, sorted so that each bin's values
    // come together.
    let mut seen: Vec<(usize, u64, bool)> = single_hashes(log)
        .enumerate()
        .filter(|&(i, h)| h <= bound && log.temp_c[i].is_finite())
        .map(|(i, h)| {
            let b = (((log.temp_c[i] - t0) / width).floor() as usize).min(bins - 1);
            (b, h, i % 2 == 1)
        })
        .collect();
    seen.sort_unstable();
    // Per bin: the odd samples' distinct values, and those of them the even samples hold.
    let mut odd = vec![0usize; bins];
    let mut met = vec![0usize; bins];
    for group in seen.chunk_by(|a, b| a.0 == b.0 && a.1 == b.1) {
        let (b, any_odd, any_even) = (
            group[0].0,
            group.iter().any(|g| g.2),
            group.iter().any(|g| !g.2),
        );
        if any_odd {
            odd[b] += 1;
            met[b] += usize::from(any_even);
        }
    }
    let chance = (0..bins)
        .map(|b| {
            if odd[b] == 0 {
                return u8::MAX;
            }
            let half = met[b] as f64 / odd[b] as f64;
            let whole = 1.0 - (1.0 - half) * (1.0 - half);
            // Rounded up: a chance is never told smaller than it is.
            (whole * 255.0).ceil().min(255.0) as u8
        })
        .collect();
    Some(ChanceByTemperature { t0, width, chance })
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
        assert_eq!(sketch.runs.len(), SKETCH_LEN);
        let whole = sketch.shared_with(&cal, 40_000);
        assert_eq!((whole.found, whole.share_of_log), (SKETCH_LEN, 1.0));
        // Less its first sample: still all of it, in-sample.
        let trimmed = sketch.shared_with(&part(&cal, 1..40_000), 40_000);
        assert!(
            trimmed.in_sample() && trimmed.share_of_log > 0.95,
            "{trimmed:?}"
        );
        // Three quarters: about 96 of the 128, all of the part's samples the run's.
        let most = sketch.shared_with(&part(&cal, 0..30_000), 40_000);
        assert!((70..=120).contains(&most.found), "{most:?}");
        assert!(most.in_sample() && most.share_of_log > 0.9, "{most:?}");
        // Another run on the same time and temperature: none of it.
        let other = sketch.shared_with(&run(40_000, 2), 40_000);
        assert!(!other.in_sample() && other.found == 0, "{other:?}");
        assert_eq!(other.partly(), None);
        // A tenth of the run beside nine tenths of another: held out, partly the run's.
        let mut mixed = run(40_000, 2);
        mixed.omega_dph[..4_000].copy_from_slice(&cal.omega_dph[..4_000]);
        let some = sketch.shared_with(&mixed, 40_000);
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
        let shared = RunSketch::of(&a).shared_with(&b, 40_000);
        assert!(
            !shared.in_sample() && shared.partly().is_none(),
            "{shared:?}"
        );
        assert!(RunSketch::of(&a).shared_with(&a, 40_000).in_sample());
    }

    #[test]
    fn the_same_samples_stamped_otherwise_are_the_same_run() {
        let cal = run(5_000, 5);
        let sketch = RunSketch::of(&cal);
        let mut epoch = cal.clone();
        for t in &mut epoch.time_s {
            *t += 1.7e9;
        }
        assert_eq!(sketch.shared_with(&epoch, 5_000).found, SKETCH_LEN);
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
        let shared = sketch.shared_with(&converted, 5_000);
        assert!(shared.found >= SKETCH_LEN - 2, "{shared:?}");
    }

    #[test]
    fn the_file_text_reads_back_and_nothing_else_does() {
        let sketch = RunSketch::of(&run(1_000, 4));
        let text = sketch.to_text();
        // The runs', then the chance by temperature and the single samples'.
        let parts: Vec<&str> = text.split('+').collect();
        assert_eq!(parts.len(), 3, "{text}");
        assert_eq!(
            (parts[0].len(), parts[2].len()),
            (16 * SKETCH_LEN, 16 * SKETCH_LEN)
        );
        // 1 000 samples between 20 and 21 °C: two bins of a degree, from 20 °C.
        assert!(
            parts[1].starts_with("20:1:") && parts[1].len() == 5 + 4,
            "{}",
            parts[1]
        );
        assert_eq!(RunSketch::from_text(&text), Some(sketch));
        for bad in [
            "abc",
            "zzzzzzzzzzzzzzzz",
            "00000000000000020000000000000001",
        ] {
            assert_eq!(RunSketch::from_text(bad), None, "{bad}");
        }
    }

    /// `log` less the rows `keep` says no to.
    fn kept(log: &Log, keep: impl Fn(usize) -> bool) -> Log {
        let pick = |v: &[f64]| -> Vec<f64> {
            v.iter()
                .enumerate()
                .filter(|(i, _)| keep(*i))
                .map(|(_, x)| *x)
                .collect()
        };
        Log::from_columns(
            "kept.csv",
            pick(&log.time_s),
            pick(&log.omega_dph),
            pick(&log.temp_c),
        )
    }

    /// `log` with its rate written with `digits` decimals, its temperature with 3.
    fn written(mut log: Log, digits: i32) -> Log {
        let round = |x: f64, d: i32| (x * 10f64.powi(d)).round() / 10f64.powi(d);
        for w in &mut log.omega_dph {
            *w = round(*w, digits);
        }
        for t in &mut log.temp_c {
            *t = round(*t, 3);
        }
        log
    }

    #[test]
    fn a_copy_less_some_rows_is_the_run_and_all_its_samples_are() {
        let cal = run(40_000, 8);
        let sketch = RunSketch::of(&cal);
        // Thinned to every other row (a 10 Hz log kept at 5 Hz): no run of eight survives,
        // every sample does.
        let thinned = sketch.shared_with(&kept(&cal, |i| i % 2 == 0), 40_000);
        assert!(thinned.in_sample(), "{thinned:?}");
        assert_eq!(thinned.share_of_log, 1.0);
        assert!(
            (0.35..0.65).contains(&thinned.share_of_run()),
            "{thinned:?}"
        );
        // One row in eight left out (its temperature was blank), and one in fifty.
        for every in [8, 50] {
            let holed = sketch.shared_with(&kept(&cal, |i| i % every != 3), 40_000);
            assert!(holed.in_sample(), "{every}: {holed:?}");
            assert_eq!(holed.share_of_log, 1.0, "{every}");
        }
        // The first half, untouched: all of its samples are the run's, exactly; it is about
        // half of the run.
        let half = sketch.shared_with(&part(&cal, 0..20_000), 40_000);
        assert_eq!(half.share_of_log, 1.0);
        assert!((0.35..0.65).contains(&half.share_of_run()), "{half:?}");
        // Another run thinned the same way is still another run.
        let other = sketch.shared_with(&kept(&run(40_000, 9), |i| i % 2 == 0), 40_000);
        assert!(!other.in_sample() && other.partly().is_none(), "{other:?}");
    }

    #[test]
    fn values_that_recur_count_only_beyond_their_chance() {
        // A rate of ±0.1 °/h noise written with four decimals, a temperature with three:
        // another run of the program meets some of the run's values by chance, and the run
        // measures how many.
        let (a, b) = (written(run(40_000, 10), 4), written(run(40_000, 11), 4));
        let sketch = RunSketch::of(&a);
        let chance = sketch.singles.as_ref().map(|s| s.chance.chance.clone());
        assert!(
            chance
                .as_ref()
                .is_some_and(|c| c.iter().any(|&c| c > 2 && c < 128)),
            "{chance:?}"
        );
        let other = sketch.shared_with(&b, 40_000);
        assert!(!other.in_sample() && other.partly().is_none(), "{other:?}");
        let thinned = sketch.shared_with(&kept(&a, |i| i % 2 == 1), 40_000);
        assert!(thinned.in_sample(), "{thinned:?}");
        // Written with one decimal, most values recur: single samples tell nothing and are
        // not sketched; runs of eight still tell the run from another.
        let (c, d) = (written(run(40_000, 12), 1), written(run(40_000, 13), 1));
        let coarse = RunSketch::of(&c);
        assert_eq!(coarse.singles, None);
        assert!(coarse.shared_with(&c, 40_000).in_sample());
        assert!(!coarse.shared_with(&d, 40_000).in_sample());
    }

    #[test]
    fn a_stuck_stretch_is_one_value_of_the_sketch() {
        let mut cal = run(10_000, 14);
        for i in 2_000..6_000 {
            cal.omega_dph[i] = 0.5;
            cal.temp_c[i] = 22.0;
        }
        let sketch = RunSketch::of(&cal);
        assert_eq!(sketch.runs.len(), SKETCH_LEN);
        assert!(sketch.runs.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn the_text_with_single_samples_reads_back_and_nothing_else_does() {
        let sketch = RunSketch::of(&run(2_000, 15));
        assert!(sketch.singles.is_some());
        let text = sketch.to_text();
        assert_eq!(RunSketch::from_text(&text), Some(sketch));
        let runs = &text[..16 * SKETCH_LEN];
        let singles = &text[text.rfind('+').unwrap_or(0) + 1..];
        for bad in [
            format!("{runs}+0.7+{singles}"),
            format!("{runs}+x+{singles}"),
            format!("{runs}+0.1+"),
            format!("{runs}+0.1+{singles}+0.1"),
            format!("{runs}+0.1"),
            format!("{runs}+20:0:00+{singles}"),
            format!("{runs}+20.5:1:00+{singles}"),
            format!("{runs}+20:1:0+{singles}"),
            format!("{runs}+20:1:+{singles}"),
            format!("{runs}+20:1:00:00+{singles}"),
        ] {
            assert_eq!(
                RunSketch::from_text(&bad),
                None,
                "{}",
                &bad[bad.len() - 40..]
            );
        }
    }

    #[test]
    fn a_hold_of_another_run_is_not_the_run_however_its_values_recur() {
        // Two hours held at 20.000 °C, then a ramp; the rate written with four decimals. On
        // the hold half the values recur by chance, on the ramp none: a part of another run
        // held at 20 °C meets the run's values by the hold's chance, not the whole run's.
        let held = |seed| {
            let mut log = written(run(30_000, seed), 4);
            for (i, t) in log.temp_c.iter_mut().enumerate() {
                *t = if i < 7_200 {
                    20.0
                } else {
                    20.0 + 0.001 * (i - 7_200) as f64
                };
            }
            log
        };
        let cal = held(16);
        let sketch = RunSketch::of(&cal);
        for (seed, len) in [(17, 1_500), (18, 6_000), (19, 7_000), (20, 3_000)] {
            let other = part(&held(seed), 0..len);
            let shared = sketch.shared_with(&other, cal.len());
            assert!(!shared.in_sample(), "seed {seed}, {len}: {shared:?}");
        }
        // The run thinned is still the run, by its ramp's samples.
        let thinned = sketch.shared_with(&kept(&cal, |i| i % 2 == 0), cal.len());
        assert!(thinned.in_sample(), "{thinned:?}");
        assert!((thinned.share_of_run() - 0.5).abs() < 1e-3, "{thinned:?}");
    }
}
