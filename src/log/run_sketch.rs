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
//! run, whose values differ by a step or more too. A run whose values are float32 numbers in
//! some unit (a drone log's samples, or `driftlab convert`'s CSV of them, whose shortest
//! decimals are no step of a writer's) is hashed as float32 in that unit, so the binary
//! number and its text are one value; a run of neither is hashed by its bits, rounded to 32
//! bits of mantissa. A judged log written coarser than the run (its rates in 0.001 °/h
//! beside the run's 0.0001) cannot hold the run's values: the sketch says it cannot tell
//! rather than find the tenth of them that happen to be whole multiples of the coarser step.
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
//! **What too few values tell.** A log shorter than the run by far, or thinned to every 20th
//! row, holds only a few values hashed as low as the sketch's (about `128 × its samples /
//! the run's`). From `MIN_SEEN` (8) values on, the share found decides; from fewer, only a
//! count that a log half the run's would rarely reach (five of five found) or rarely fall
//! to (none of five) tells, and otherwise the sketch says it cannot tell, with how many it
//! compared. A unit's axes share their rows, and one that saw too few takes what all the
//! axes' values pooled tell ([`Shared::settle_axes`]).
//!
//! **A limit.** The hash is public: one who crafts a copy from it can leave out the few rows
//! whose hashes would be found and pass a copy of the run as held out. The sketch guards
//! against accidents (another file, another unit, a part of the run), not against that.
//! What it says stays consistent: the share of the run a log is said to hold never
//! contradicts the share of its samples it is said to be the run's and its length.
//!
//! The files: this one holds the sketch and how a log is measured against it; `values.rs`
//! what is hashed (a sample's and a run's hash, the same-instant test); `resolution.rs` the
//! resolution values are hashed at; `chance.rs` how often values recur by chance per
//! temperature; `measure.rs` what a part finds of a log and what few values tell;
//! `shared.rs` the shares and verdicts as the faces read them; `text.rs` the sketch's text.
//! A crafted text or sketch costs no more than a genuine one: the text is bounded before it is
//! split (`text.rs`), and a log compares at most `MAX_COMPARED` values with it (`measure.rs`).

mod chance;
mod measure;
mod resolution;
mod shared;
mod text;
mod values;

use super::Log;
use chance::{ChanceByTemperature, chance_by_temperature};
use measure::measure;
use resolution::{Column, Resolution, coarser, resolution};
pub use shared::Shared;
#[cfg(test)]
use text::hex;
#[cfg(test)]
use values::mix;
use values::{NO_HASH, like_a_twin, run_hashes, single_hashes};

/// Hashes a sketch keeps: a log holding 3 % of a run's samples is found in it (about four
/// of them), and the sketch is 2 KiB of hexadecimal in a calibration file.
pub const SKETCH_LEN: usize = 128;

/// Hashes a sketch keeps when both logs are at hand and nothing is written ([`Log::same_run`]:
/// `compare`, the workbench's validation log): 32 times a file's, so that the run thinned to
/// every 20th row shows about 200 values, not 6, and is told.
const IN_MEMORY_LEN: usize = 4096;

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

/// Values a log must show a part of the sketch for the share found among them to decide,
/// as it is; fewer decide only by a count that rarely happens otherwise (see the module's
/// doc).
const MIN_SEEN: usize = 8;

/// Samples whose values one hash of the runs sketch covers (see the module's doc).
const RUN_OF: usize = 8;

/// The version tag of the sketch's text since values are hashed at the run's resolution
/// (texts without it are version 1: exact values, runs not corrected for chance).
const VERSION_2: &str = "2";

/// The resolutions the run's temperatures and rates are hashed at ([`Resolution::Bits`] in
/// a version-1 sketch).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Quanta {
    temp: Resolution,
    rate: Resolution,
}

/// The smallest hashes of a run's runs of samples and of its single samples, each where it
/// tells the run from another; the resolutions its values were hashed at.
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

impl RunSketch {
    /// The sketch of `log`'s samples as they are (its selected axis's rate).
    pub fn of(log: &Log) -> RunSketch {
        Self::of_len(log, SKETCH_LEN)
    }

    /// The sketch of `log`'s samples for a judging in memory (`IN_MEMORY_LEN` hashes): not
    /// for a file, whose text holds [`SKETCH_LEN`] at most.
    pub fn in_memory(log: &Log) -> RunSketch {
        Self::of_len(log, IN_MEMORY_LEN)
    }

    fn of_len(log: &Log, len: usize) -> RunSketch {
        let quanta = Quanta {
            temp: resolution(&log.temp_c, Column::Temperature),
            rate: resolution(&log.omega_dph, Column::Rate),
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
            runs: part_of(log, &runs, &runs_twin, len),
            singles: part_of(log, &singles, &twin, len),
        }
    }

    /// Whether the sketch holds nothing (a file written before sketches were kept, or a run
    /// whose values recur everywhere).
    pub fn is_empty(&self) -> bool {
        self.runs.is_none() && self.singles.is_none()
    }

    /// How much of `log` is the run's samples (`run_samples` of them): by its runs of samples
    /// or by its single samples, whichever finds more beyond chance (single samples find a
    /// thinned copy, a copy less the rows its reader left out), or both together where each
    /// sees few; or that it cannot tell (too few of its values compared, or a column written
    /// coarser than the run's).
    pub fn shared_with(&self, log: &Log, run_samples: usize) -> Shared {
        let of = self
            .runs
            .as_ref()
            .or(self.singles.as_ref())
            .map_or(0, |p| p.hashes.len());
        let singles = single_hashes(log, self.quanta);
        let runs = run_hashes(&singles);
        let by_runs = self.runs.as_ref().and_then(|p| measure(p, log, &runs));
        let by_singles = self
            .singles
            .as_ref()
            .and_then(|p| measure(p, log, &singles));
        let shared = Shared::of_parts(by_runs, by_singles, of, log.len(), run_samples);
        // Most of its values found, they are the run's, however coarse they look (a ramp of
        // 0.001 °C a sample thinned to every other row is in steps of 0.002). Else a column
        // coarser than the run's could not have shown them: found or not says nothing.
        if shared.in_sample() {
            return shared;
        }
        match self.coarser_column(log) {
            Some((column, own, calibration)) => {
                Shared::coarser(column, own, calibration, of, log.len(), run_samples)
            }
            None => shared,
        }
    }

    /// The first of `log`'s columns written coarser than the run's ([`coarser`]), with its
    /// resolution and the run's; `None` for a version-1 sketch, which recorded none.
    fn coarser_column(&self, log: &Log) -> Option<(Column, Resolution, Resolution)> {
        if self.version1 {
            return None;
        }
        [
            (Column::Temperature, &log.temp_c, self.quanta.temp),
            (Column::Rate, &log.omega_dph, self.quanta.rate),
        ]
        .into_iter()
        .map(|(column, values, calibration)| (column, resolution(values, column), calibration))
        .find(|&(_, own, calibration)| coarser(own, calibration))
    }
}

/// The sketch of `hashes` (one per sample of `log`, [`NO_HASH`] where a sample has none): the
/// `len` smallest at the temperatures where they rarely recur, with the chance per
/// temperature and the samples per hash; `None` when no temperature tells.
fn part_of(log: &Log, hashes: &[u64], twin: &[bool], len: usize) -> Option<Part> {
    let chance = chance_by_temperature(log, hashes, twin).filter(ChanceByTemperature::tells_any)?;
    let telling = |i: usize| chance.at(log.temp_c[i]).is_some_and(|c| c <= MAX_CHANCE);
    let told = || {
        hashes
            .iter()
            .enumerate()
            .filter_map(|(i, &h)| (h != NO_HASH && telling(i)).then_some(h))
    };
    let kept = smallest(told(), len);
    let top = *kept.last()?;
    let low = told().filter(|&h| h <= top).count();
    Some(Part {
        per_hash: Some(low as f64 / kept.len() as f64),
        hashes: kept,
        chance: Some(chance),
    })
}

/// The `len` smallest distinct values of `hashes`, ascending: a value already kept (a stuck
/// stretch repeats one) does not crowd out another.
fn smallest(hashes: impl Iterator<Item = u64>, len: usize) -> Vec<u64> {
    let mut kept = std::collections::BTreeSet::new();
    // The largest kept once `len` are: most values are larger, and cost one comparison.
    let mut top = u64::MAX;
    for h in hashes {
        if h >= top {
            continue;
        }
        kept.insert(h);
        if kept.len() > len {
            kept.pop_last();
        }
        if kept.len() == len {
            top = kept.last().copied().unwrap_or(u64::MAX);
        }
    }
    kept.into_iter().collect()
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_told;
