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
mod tests;
