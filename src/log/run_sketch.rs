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
//! sketch, so among a log's samples hashed that low, the share found in the sketch is the
//! share of the log's samples that are the run's: all of them for any part of the run, in
//! any file; none for another run, since its noise differs at every sample. The share is of
//! samples, not of distinct values: a log that repeats another run twice after the
//! calibration run is a third the run's.
//!
//! **Values are hashed at the run's own resolution.** The sketch records the step the run's
//! temperatures and rates are written with (the smallest step between its distinct values,
//! when every value is a multiple of it: 0.001 °C and 0.0001 °/h for a log written with
//! three and four decimals), and every log's values are rounded to the nearest multiple of
//! those steps before they are hashed. A copy converted to another unit and back, or stored
//! as float32 rad/s as PX4, ArduPilot and ROS store a rate, or written with 9 significant
//! digits, is the same numbers at that resolution, and is found whole. A copy whose every
//! value is moved by a step or more (an offset of one LSB, 0.001 °C added) holds other numbers
//! at that resolution and is not found: the sketch cannot tell such an edit from another
//! run, whose values differ by a step or more too. A run whose values are multiples of no
//! step (float32 samples of a drone log) is hashed as before: each value rounded to 32 bits
//! of mantissa.
//!
//! Two sketches, for two ways a copy of a run differs from it:
//! - **Runs of eight** consecutive samples: a log written with few digits (a rate in
//!   0.1 °/h, a temperature in 0.1 °C) repeats each sample's pair of values many times, and
//!   another run of the same gyro holds the same pairs (two thirds of one were found in
//!   another); eight in a row rarely agree by chance. But a copy that dropped rows (thinned to
//!   every other row, rows without a temperature left out) keeps none of the runs.
//! - **Single samples**, kept beside the runs: a thinned copy keeps its samples.
//!
//! **Each is corrected for chance.** How often a value (or a run of eight) recurs by chance
//! depends on where the run is: on a ramp no temperature repeats, on a plateau held at
//! 20.000 °C a rate written with four decimals meets its like in half the samples, and a
//! rate written in 2 °/h on a 0.1 °C temperature holds the same eight values for minutes. So
//! the chance is measured on the run itself, per degree of temperature (its odd samples'
//! values among its even samples', as a second run of the same program would meet them),
//! and only what a log shares beyond the chance of the temperatures it holds counts;
//! temperatures where values recur too often tell nothing and are not looked at, and a run
//! where they do everywhere keeps no sketch (its copies are known by their bytes alone).
//!
//! **A limit.** The hash is public: one who crafts a copy from it can leave out the few rows
//! whose hashes would be found and pass a copy of the run as held out. The sketch guards
//! against accidents (another file, another unit, a part of the run), not against that.
//! What it says stays consistent: the share of the run a log is said to hold never
//! contradicts the share of its samples it is said to be the run's and its length.
//!
//! The files: this one holds the sketch, its text and the measure of a log against it;
//! `values.rs` what is hashed (the values at the log's steps, a sample's and a run's hash,
//! the same-instant test); `chance.rs` how often values recur by chance per temperature.

mod chance;
mod values;

use super::Log;
use chance::{ChanceByTemperature, chance_by_temperature};
use std::collections::HashMap;
#[cfg(test)]
use values::mix;
use values::{NO_HASH, like_a_twin, quantum, run_hashes, single_hashes};

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

/// The chance that a value recurs, past which samples at that temperature tell nothing of a
/// log: a log written with so few digits, or held so long at one temperature, that another
/// run of the program meets half of its values there. Below it, a log sharing the run's
/// values in excess of chance by [`IN_SAMPLE_SHARE`] is at least a quarter of the way from
/// chance to all, many standard errors of a 128-value sketch away from another run.
const MAX_CHANCE: f64 = 0.5;

/// Standard errors beyond chance the sketch's hashes found must be for a log to share any
/// samples with the run.
const SIGNIFICANT: f64 = 3.0;

/// Values looked at to measure the chance of a recurring value: enough for a share known to
/// a few tenths of a percent, few enough that a million-sample log is sketched in
/// milliseconds.
const CHANCE_VALUES: usize = 1 << 16;

/// Temperature bins the chance is measured in, at most: a degree each over a chamber's
/// whole range (−60 … +150 °C), wider beyond it.
const MAX_BINS: usize = 256;

/// Samples a bin of temperature must hold for its chance to be measured: fewer (the edge of
/// a ramp) tell too little of how often values recur there, and are not looked at.
const MIN_BIN_SAMPLES: usize = 64;

/// A log's values below the sketch's largest hash that single samples must see before they
/// judge it: fewer (a short log, or one held where values recur) leave it to the runs.
const MIN_SEEN: usize = 8;

/// Samples whose values one hash of the runs sketch covers (see the module's doc).
const RUN_OF: usize = 8;

/// The version tag of the sketch's text since values are hashed at the run's resolution
/// (texts without it are version 1: exact values, runs not corrected for chance).
const VERSION_2: &str = "2";

/// The steps the run's temperatures and rates are written with; `None` for a column whose
/// values are multiples of no step (hashed by their bits, 32 of mantissa).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Quanta {
    temp: Option<f64>,
    rate: Option<f64>,
}

/// The smallest hashes of a run's runs of samples and of its single samples, each where it
/// tells the run from another; the steps its values were hashed at.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunSketch {
    /// Read from a version-1 text: values hashed exactly, runs not corrected for chance.
    version1: bool,
    quanta: Quanta,
    runs: Option<Part>,
    singles: Option<Part>,
}

/// One sketch (of runs of eight, or of single samples): its hashes, ascending, and how often
/// the run's values recur by chance.
#[derive(Debug, Clone, PartialEq)]
struct Part {
    hashes: Vec<u64>,
    /// The chance per temperature; `None` in a version-1 runs sketch (taken as none).
    chance: Option<ChanceByTemperature>,
    /// The run's samples per sketched hash (a value held by several samples counts each);
    /// `None` in version-1 texts (taken as 1).
    per_hash: Option<f64>,
}

/// How much of a log is a run's samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shared {
    /// The sketch's hashes found among the log's samples.
    pub found: usize,
    /// The hashes in the sketch.
    pub of: usize,
    /// The share of the log's samples that are the run's beyond chance, estimated (0 to 1).
    pub share_of_log: f64,
    /// The log's samples.
    pub log_samples: usize,
    /// The run's samples.
    pub run_samples: usize,
    /// Whether the hashes found are beyond what chance finds in another run.
    beyond_chance: bool,
    /// How many times the log repeats each of the run's samples it holds, against the run
    /// itself (at least 1).
    repeats: f64,
}

impl Shared {
    /// Nothing shared (nothing looked at, or nothing tells).
    fn none(of: usize, log_samples: usize, run_samples: usize) -> Shared {
        Shared {
            found: 0,
            of,
            share_of_log: 0.0,
            log_samples,
            run_samples,
            beyond_chance: false,
            repeats: 1.0,
        }
    }

    /// Whether the log holds the run's samples at all (beyond two other runs' chance
    /// agreement).
    fn found_any(&self) -> bool {
        self.beyond_chance
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
    /// the run's, counted (exact when no sample of the log repeats another). When that count
    /// is beyond what the sketch found by more than its error, the log either repeats the
    /// run's samples (a part of the run written many times: the count is divided by how many
    /// times the log repeats each), or lacks just the rows the sketch holds (a copy crafted
    /// from the public hash: the count stands, so that the two shares never contradict each
    /// other and the log's length).
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
            (self.share_of_log * self.log_samples as f64 / self.repeats / self.run_samples as f64)
                .min(1.0)
        }
    }
}

impl RunSketch {
    /// The sketch of `log`'s samples as they are (its selected axis's rate).
    pub fn of(log: &Log) -> RunSketch {
        let quanta = Quanta {
            temp: quantum(&log.temp_c),
            rate: quantum(&log.omega_dph),
        };
        let singles = single_hashes(log, quanta);
        let runs = run_hashes(&singles);
        let twin = like_a_twin(log, quanta);
        // A run of eight meets its twin when each of its samples does.
        let mut alike = 0;
        let runs_twin: Vec<bool> = twin
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                alike = if t { alike + 1 } else { 0 };
                i + 1 >= RUN_OF && alike >= RUN_OF
            })
            .collect();
        RunSketch {
            version1: false,
            quanta,
            runs: part_of(log, &runs, &runs_twin),
            singles: part_of(log, &singles, &twin),
        }
    }

    /// Whether the sketch holds nothing (a file written before sketches were kept, or a run
    /// whose values recur everywhere).
    pub fn is_empty(&self) -> bool {
        self.runs.is_none() && self.singles.is_none()
    }

    /// How much of `log` is the run's samples (`run_samples` of them): by its runs of samples
    /// or by its single samples, whichever finds more beyond chance (single samples find a
    /// thinned copy, a copy less the rows its reader left out).
    pub fn shared_with(&self, log: &Log, run_samples: usize) -> Shared {
        let singles = single_hashes(log, self.quanta);
        let runs = run_hashes(&singles);
        let by_runs = self
            .runs
            .as_ref()
            .and_then(|p| measure(p, log, &runs, 1, run_samples));
        let by_singles = self
            .singles
            .as_ref()
            .and_then(|p| measure(p, log, &singles, MIN_SEEN, run_samples));
        let of = self
            .runs
            .as_ref()
            .or(self.singles.as_ref())
            .map_or(0, |p| p.hashes.len());
        match (by_runs, by_singles) {
            (Some(r), Some(s)) => {
                let told = |x: &Shared| if x.found_any() { x.share_of_log } else { -1.0 };
                if told(&s) > told(&r) { s } else { r }
            }
            (Some(one), None) | (None, Some(one)) => one,
            (None, None) => Shared::none(of, log.len(), run_samples),
        }
    }

    /// The sketch as calibration files hold it, version 2: `2;` the temperature's and the
    /// rate's steps (`-` for none) each followed by `;`, then the runs' part, `;`, the single
    /// samples' part. A part is empty where nothing tells, else `T0:WIDTH:BYTES:PER:HASHES`:
    /// the chance of a recurring value per bin of temperature (whole °C, a byte a bin in
    /// 255ths), the run's samples per sketched hash, and the hashes in 16 hexadecimal digits
    /// each, ascending. A version-1 sketch (read from an older file) is written as it was
    /// read: the runs' hashes, then optionally `+`, the single samples' chance, `+`, hashes.
    pub fn to_text(&self) -> String {
        if self.version1 {
            let runs = self.runs.as_ref().map_or(String::new(), |p| hex(&p.hashes));
            return match &self.singles {
                Some(Part {
                    hashes,
                    chance: Some(chance),
                    ..
                }) => format!("{runs}+{}+{}", chance.to_text(), hex(hashes)),
                _ => runs,
            };
        }
        let step = |q: Option<f64>| q.map_or("-".to_string(), |q| format!("{q}"));
        let part = |p: &Option<Part>| match p {
            Some(Part {
                hashes,
                chance: Some(chance),
                per_hash,
            }) => format!(
                "{}:{}:{}",
                chance.to_text(),
                per_hash.map_or("1".to_string(), |m| format!("{m:.4}")),
                hex(hashes)
            ),
            _ => String::new(),
        };
        format!(
            "{VERSION_2};{};{};{};{}",
            step(self.quanta.temp),
            step(self.quanta.rate),
            part(&self.runs),
            part(&self.singles)
        )
    }

    /// A sketch from [`RunSketch::to_text`]'s text, of either version; `None` when it is not
    /// that.
    pub fn from_text(text: &str) -> Option<RunSketch> {
        if text.contains(';') {
            Self::from_text_2(text)
        } else {
            Self::from_text_1(text)
        }
    }

    fn from_text_2(text: &str) -> Option<RunSketch> {
        let fields: Vec<&str> = text.split(';').collect();
        let [version, temp, rate, runs, singles] = fields[..] else {
            return None;
        };
        if version != VERSION_2 {
            return None;
        }
        let step = |s: &str| -> Option<Option<f64>> {
            if s == "-" {
                return Some(None);
            }
            let q: f64 = s.parse().ok()?;
            (q.is_finite() && q > 0.0).then_some(Some(q))
        };
        let part = |s: &str| -> Option<Option<Part>> {
            if s.is_empty() {
                return Some(None);
            }
            let f: Vec<&str> = s.split(':').collect();
            let [t0, width, bytes, per, hashes] = f[..] else {
                return None;
            };
            let chance = ChanceByTemperature::from_parts(t0, width, bytes)?;
            let per: f64 = per.parse().ok()?;
            if !(per.is_finite() && (1.0..1e12).contains(&per)) {
                return None;
            }
            let hashes = hashes_from_hex(hashes)?;
            if hashes.is_empty() {
                return None;
            }
            Some(Some(Part {
                hashes,
                chance: Some(chance),
                per_hash: Some(per),
            }))
        };
        Some(RunSketch {
            version1: false,
            quanta: Quanta {
                temp: step(temp)?,
                rate: step(rate)?,
            },
            runs: part(runs)?,
            singles: part(singles)?,
        })
    }

    fn from_text_1(text: &str) -> Option<RunSketch> {
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
                Some(Part {
                    hashes,
                    chance: Some(chance),
                    per_hash: None,
                })
            }
            _ => return None,
        };
        let runs = (!runs.is_empty()).then_some(Part {
            hashes: runs,
            chance: None,
            per_hash: None,
        });
        Some(RunSketch {
            version1: true,
            quanta: Quanta::default(),
            runs,
            singles,
        })
    }
}

fn hex(hashes: &[u64]) -> String {
    hashes.iter().map(|h| format!("{h:016x}")).collect()
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

/// The sketch of `hashes` (one per sample of `log`, [`NO_HASH`] where a sample has none): the
/// [`SKETCH_LEN`] smallest at the temperatures where they rarely recur, with the chance per
/// temperature and the samples per hash; `None` when no temperature tells.
fn part_of(log: &Log, hashes: &[u64], twin: &[bool]) -> Option<Part> {
    let chance = chance_by_temperature(log, hashes, twin).filter(ChanceByTemperature::tells_any)?;
    let telling = |i: usize| chance.at(log.temp_c[i]).is_some_and(|c| c <= MAX_CHANCE);
    let told = || {
        hashes
            .iter()
            .enumerate()
            .filter_map(|(i, &h)| (h != NO_HASH && telling(i)).then_some(h))
    };
    let kept = smallest(told());
    let top = *kept.last()?;
    let low = told().filter(|&h| h <= top).count();
    Some(Part {
        per_hash: Some(low as f64 / kept.len() as f64),
        hashes: kept,
        chance: Some(chance),
    })
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

/// How much of a log's samples are a sketch's run's, beyond chance: among the log's samples
/// whose hashes (`hashes`, one per sample) are no larger than the sketch's largest (every
/// run value hashed that low is in the sketch), at temperatures where the run's values
/// rarely recur, the share found in it, less the share the chance of their temperatures
/// would find, scaled to 0 to 1. `None` when fewer than `min_seen` distinct values are
/// looked at.
fn measure(
    part: &Part,
    log: &Log,
    hashes: &[u64],
    min_seen: usize,
    run_samples: usize,
) -> Option<Shared> {
    let top = *part.hashes.last()?;
    // Per distinct value looked at: its chance, whether the sketch holds it, its samples.
    let mut low: HashMap<u64, (f64, bool, usize)> = HashMap::new();
    for (i, h) in hashes.iter().enumerate() {
        let h = *h;
        if h == NO_HASH || h > top {
            continue;
        }
        let c = match &part.chance {
            None => 0.0,
            Some(chance) => match chance.at(log.temp_c[i]) {
                Some(c) if c <= MAX_CHANCE => c,
                _ => continue,
            },
        };
        low.entry(h)
            .or_insert_with(|| (c, part.hashes.binary_search(&h).is_ok(), 0))
            .2 += 1;
    }
    if low.len() < min_seen.max(1) {
        return None;
    }
    let (mut samples, mut hit_samples, mut chance_sum) = (0usize, 0usize, 0.0);
    let (mut found, mut chance_distinct) = (0usize, 0.0);
    for &(c, hit, n) in low.values() {
        samples += n;
        chance_sum += c * n as f64;
        chance_distinct += c;
        if hit {
            hit_samples += n;
            found += 1;
        }
    }
    let share = hit_samples as f64 / samples as f64;
    let expected = chance_sum / samples as f64;
    let beyond = ((share - expected) / (1.0 - expected)).clamp(0.0, 1.0);
    // Chance finds each distinct value with its temperature's chance: the hashes found must
    // be beyond that count by [`SIGNIFICANT`] standard errors.
    let seen = low.len() as f64;
    let p0 = chance_distinct / seen;
    let beyond_chance = found >= MIN_FOUND
        && found as f64 - seen * p0 > SIGNIFICANT * (seen * p0 * (1.0 - p0)).sqrt()
        && beyond > 0.0;
    let repeats = if found == 0 {
        1.0
    } else {
        (hit_samples as f64 / found as f64 / part.per_hash.unwrap_or(1.0)).max(1.0)
    };
    Some(Shared {
        found,
        of: part.hashes.len(),
        share_of_log: beyond,
        log_samples: log.len(),
        run_samples,
        beyond_chance,
        repeats,
    })
}

#[cfg(test)]
mod tests;
