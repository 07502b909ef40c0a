//! Temperature-stabilisation plateaus: where Ṫ = T̈ = 0, so the mean output is the static bias
//! K0 at that temperature (docs/method.md §2, step 3).
//!
//! The detector looks for long stretches where |Ṫ| stays under a threshold and keeps only their
//! settled tail: after the chamber stops, heat still diffuses into the coil for many minutes and
//! the rate-driven drift dies away slowly, so the start of a hold is not yet static.
//!
//! This is the plateau stage of every model: the ranges a recipe asks for ([`ranges`]), the
//! mask of the samples they cover ([`mask`]) and the K0 points they give ([`stats_of`]).
//! Vakhrameev's model and the regressions fitted on plateaus read them from here.

use crate::error::Invalid;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// A plateau as a time range, s (inclusive).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlateauRange {
    /// Start, s.
    pub start_s: f64,
    /// End, s.
    pub end_s: f64,
}

impl PlateauRange {
    /// Whether `t` lies within the range.
    pub fn contains(&self, t: f64) -> bool {
        t >= self.start_s && t <= self.end_s
    }

    /// Sample index range `[lo, hi)` of a sorted time column covered by the plateau.
    pub fn index_range(&self, time_s: &[f64]) -> (usize, usize) {
        let lo = time_s.partition_point(|&t| t < self.start_s);
        let hi = time_s.partition_point(|&t| t <= self.end_s);
        (lo, hi.max(lo))
    }
}

/// A plateau written as text (`START:END` in seconds) that is not one.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlateauRangeError {
    /// No `:` between a start and an end.
    #[error("plateau \"{text}\" must be START:END in seconds")]
    NotARange {
        /// The text given.
        text: String,
    },
    /// A start or an end that is not a number.
    #[error("plateau \"{text}\": \"{value}\" is not a number of seconds")]
    NotSeconds {
        /// The text given.
        text: String,
        /// The part that is not a number.
        value: String,
    },
    /// A start at or after the end.
    #[error("plateau \"{text}\": the start must come before the end")]
    Reversed {
        /// The text given.
        text: String,
    },
}

impl std::str::FromStr for PlateauRange {
    type Err = PlateauRangeError;
    /// Parses `START:END` in seconds, as a recipe or a face gives it.
    fn from_str(s: &str) -> Result<Self, PlateauRangeError> {
        let text = || s.to_string();
        let (a, b) = s
            .split_once(':')
            .ok_or_else(|| PlateauRangeError::NotARange { text: text() })?;
        // `inf` and `nan` parse as floats, and are no number of seconds either.
        let parse = |v: &str| {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| PlateauRangeError::NotSeconds {
                    text: text(),
                    value: v.to_string(),
                })
        };
        let (start_s, end_s) = (parse(a)?, parse(b)?);
        if start_s >= end_s {
            return Err(PlateauRangeError::Reversed { text: text() });
        }
        Ok(PlateauRange { start_s, end_s })
    }
}

/// Where the plateaus come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "mode", rename_all = "snake_case", deny_unknown_fields)]
pub enum PlateauChoice {
    /// Found by the detector with these options.
    Auto(DetectOptions),
    /// Given by the engineer as time ranges.
    Manual {
        /// The ranges, s.
        ranges: Vec<PlateauRange>,
    },
}

impl Default for PlateauChoice {
    fn default() -> Self {
        PlateauChoice::Auto(DetectOptions::default())
    }
}

impl PlateauChoice {
    /// Whether this is the detector with its default options.
    pub fn is_default(&self) -> bool {
        *self == PlateauChoice::default()
    }
}

/// The plateau ranges `choice` asks for on a log sampled at `time_s` whose temperature rate
/// is `tdot` (°C/s), with full rate history over the `ready` ranges (one per segment).
/// Detected plateaus are found within each segment's ready samples, so a plateau never spans
/// a gap; given ranges are taken as they are.
pub fn ranges(
    choice: &PlateauChoice,
    time_s: &[f64],
    tdot: &[f64],
    ready: &[Range<usize>],
) -> Vec<PlateauRange> {
    match choice {
        PlateauChoice::Auto(opts) => ready
            .iter()
            .flat_map(|r| detect(&time_s[r.clone()], &tdot[r.clone()], 0, opts))
            .collect(),
        PlateauChoice::Manual { ranges } => ranges.clone(),
    }
}

/// Which samples of a log sampled at `time_s` lie inside any of `ranges` (they carry the K0
/// points and no rate information).
pub fn mask(time_s: &[f64], ranges: &[PlateauRange]) -> Vec<bool> {
    let mut mask = vec![false; time_s.len()];
    for r in ranges {
        let (lo, hi) = r.index_range(time_s);
        mask[lo..hi].fill(true);
    }
    mask
}

/// Settings of the automatic plateau detector.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DetectOptions {
    /// |Ṫ| must stay below this, °C/min.
    pub max_rate_c_per_min: f64,
    /// The quiet stretch must last at least this long, s.
    pub min_duration_s: f64,
    /// Fraction of each quiet stretch kept, counted back from its end (the settled tail).
    pub settled_fraction: f64,
    /// Excursions above the threshold shorter than this do not split a stretch, s.
    pub bridge_s: f64,
}

impl Default for DetectOptions {
    fn default() -> Self {
        DetectOptions {
            max_rate_c_per_min: 0.05,
            min_duration_s: 1200.0,
            settled_fraction: 0.5,
            bridge_s: 60.0,
        }
    }
}

impl DetectOptions {
    /// Checks the settings; the message names the one that is wrong.
    pub fn validate(&self) -> Result<(), Invalid> {
        let bad =
            |field: &str, reason: &str| Err(Invalid::new(format!("plateaus.{field}"), reason));
        if !(self.max_rate_c_per_min.is_finite() && self.max_rate_c_per_min > 0.0) {
            return bad("max_rate_c_per_min", "must be positive");
        }
        if self.max_rate_c_per_min > MAX_HOLD_RATE_C_PER_MIN {
            return bad(
                "max_rate_c_per_min",
                "is at most 0.5 °C/min (ten times the default): beyond it a chamber's ramps, \
                 about 1 °C/min, pass for temperature holds",
            );
        }
        if self.bridge_s > MAX_BRIDGE_S {
            return bad(
                "bridge_s",
                "is at most 3600 s: an excursion of more than an hour is a ramp between two \
                 holds, not a glitch inside one",
            );
        }
        if !(self.min_duration_s.is_finite() && self.min_duration_s >= 0.0) {
            return bad("min_duration_s", "must be non-negative");
        }
        if !(self.settled_fraction >= MIN_SETTLED_FRACTION && self.settled_fraction <= 1.0) {
            // Less keeps a sample or two of each hold: K0 through single readings.
            return bad(
                "settled_fraction",
                "must be from 0.05 to 1: the share of each quiet stretch kept as its plateau",
            );
        }
        if !(self.bridge_s.is_finite() && self.bridge_s >= 0.0) {
            return bad("bridge_s", "must be non-negative");
        }
        Ok(())
    }
}

/// The smallest share of a quiet stretch kept as its plateau ([`DetectOptions::validate`]):
/// a 20-minute stretch keeps a minute.
pub const MIN_SETTLED_FRACTION: f64 = 0.05;

/// The loosest |Ṫ| a plateau may be detected under, °C/min ([`DetectOptions::validate`]).
pub const MAX_HOLD_RATE_C_PER_MIN: f64 = 0.5;

/// The longest excursion the detector may bridge inside a plateau, s.
pub const MAX_BRIDGE_S: f64 = 3600.0;

/// Finds plateaus from the temperature rate `tdot` (°C/s) sampled at `time_s`.
///
/// Samples before `ready_from` (no derivative history yet) are never part of a plateau.
pub fn detect(
    time_s: &[f64],
    tdot: &[f64],
    ready_from: usize,
    opts: &DetectOptions,
) -> Vec<PlateauRange> {
    let n = time_s.len().min(tdot.len());
    let limit = opts.max_rate_c_per_min / 60.0;
    let quiet = |i: usize| i >= ready_from && tdot[i].abs() < limit;
    // Quiet runs as index ranges [a, b).
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut i = 0;
    while i < n {
        if !quiet(i) {
            i += 1;
            continue;
        }
        let a = i;
        while i < n && quiet(i) {
            i += 1;
        }
        match runs.last_mut() {
            Some(last) if time_s[a] - time_s[last.1 - 1] <= opts.bridge_s => last.1 = i,
            _ => runs.push((a, i)),
        }
    }
    // Inside each long quiet stretch, the ends where the rate is above a fifth of the limit are
    // a ramp still fading out or already creeping in: the plateau ends before them.
    let strict = limit / 5.0;
    runs.into_iter()
        .filter(|&(a, b)| time_s[b - 1] - time_s[a] >= opts.min_duration_s && b - a >= 2)
        .filter_map(|(a, b)| {
            let b = (a..b)
                .rev()
                .find(|&i| tdot[i].abs() < strict)
                .map(|i| i + 1)?;
            let end = time_s[b - 1];
            let start = end - (end - time_s[a]) * opts.settled_fraction;
            (end > start).then_some(PlateauRange {
                start_s: start,
                end_s: end,
            })
        })
        .collect()
}

/// What a plateau says about the gyro: the K0 point and how trustworthy it is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, from = "PlateauStatsFile")]
pub struct PlateauStats {
    /// The time range.
    pub range: PlateauRange,
    /// Mean temperature, °C.
    pub temp_c: f64,
    /// Mean output, °/h: the K0 point.
    pub omega_dph: f64,
    /// Standard deviation of the raw output on the plateau, °/h; `None` (`null` in a file)
    /// for a plateau of one sample, whose spread nothing measures.
    pub omega_std_dph: Option<f64>,
    /// Standard error of the mean output, °/h (std/√n: white noise assumed); `None` with the
    /// deviation.
    pub omega_sem_dph: Option<f64>,
    /// Max − min temperature on the plateau, °C: a large value means it was not stable.
    pub temp_spread_c: f64,
    /// Samples in the plateau.
    pub samples: usize,
}

impl PlateauStats {
    /// How fast T moves over the plateau on average, °C/min: its spread over its length (a
    /// lower bound of the fastest |Ṫ| on it); `None` for a plateau of no length or no
    /// finite spread. What [`outside_detector`] and [`unsteady`] hold against the detector's
    /// rate, and what a face shows beside the spread.
    pub fn mean_rate_c_per_min(&self) -> Option<f64> {
        let length_s = self.range.end_s - self.range.start_s;
        (length_s > 0.0 && self.temp_spread_c.is_finite())
            .then(|| self.temp_spread_c / length_s * 60.0)
    }
}

/// [`PlateauStats`] as a file holds them. Files written before the deviation of a one-sample
/// plateau was `null` hold 0 there (and as its standard error): read as `null`, which is what
/// that 0 meant; any other value is left for the calibration's check to refuse.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlateauStatsFile {
    range: PlateauRange,
    temp_c: f64,
    omega_dph: f64,
    omega_std_dph: Option<f64>,
    omega_sem_dph: Option<f64>,
    temp_spread_c: f64,
    samples: usize,
}

impl From<PlateauStatsFile> for PlateauStats {
    fn from(f: PlateauStatsFile) -> PlateauStats {
        let unmeasured = |v: Option<f64>| {
            if f.samples == 1 && v == Some(0.0) {
                None
            } else {
                v
            }
        };
        PlateauStats {
            range: f.range,
            temp_c: f.temp_c,
            omega_dph: f.omega_dph,
            omega_std_dph: unmeasured(f.omega_std_dph),
            omega_sem_dph: unmeasured(f.omega_sem_dph),
            temp_spread_c: f.temp_spread_c,
            samples: f.samples,
        }
    }
}

/// Statistics of each of `ranges` over the given columns, in order; a range without samples
/// is dropped.
pub fn stats_of(
    time_s: &[f64],
    temp_c: &[f64],
    omega_dph: &[f64],
    ranges: &[PlateauRange],
) -> Vec<PlateauStats> {
    ranges
        .iter()
        .filter_map(|r| stats(time_s, temp_c, omega_dph, *r))
        .collect()
}

/// Statistics of `range` over the given columns; `None` when it holds no sample.
pub fn stats(
    time_s: &[f64],
    temp_c: &[f64],
    omega_dph: &[f64],
    range: PlateauRange,
) -> Option<PlateauStats> {
    let (lo, hi) = range.index_range(time_s);
    let n = hi - lo;
    if n == 0 {
        return None;
    }
    let t = &temp_c[lo..hi];
    let w = &omega_dph[lo..hi];
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mt, mw) = (mean(t), mean(w));
    let var = (n > 1).then(|| w.iter().map(|v| (v - mw).powi(2)).sum::<f64>() / (n - 1) as f64);
    let (tmin, tmax) = t
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    Some(PlateauStats {
        range,
        temp_c: mt,
        omega_dph: mw,
        omega_std_dph: var.map(f64::sqrt),
        omega_sem_dph: var.map(|v| (v / n as f64).sqrt()),
        temp_spread_c: tmax - tmin,
        samples: n,
    })
}

/// The plateaus given by hand (`ranges`) that give K0 no point or a point without a spread, each
/// in words: a range that holds no sample of the log (over a gap, or past its end) is left out
/// of the fit, and one that holds a single sample makes its bias one reading, whose noise
/// nothing measures (its standard error, written as 0, is unknown). `stats` are the
/// statistics the fit kept (a range without samples has none).
pub fn too_few_samples(ranges: &[PlateauRange], stats: &[PlateauStats]) -> Vec<String> {
    let shown = |r: &PlateauRange| {
        format!(
            "{}:{} s",
            crate::number::readable(r.start_s),
            crate::number::readable(r.end_s)
        )
    };
    ranges
        .iter()
        .filter_map(|r| match stats.iter().find(|s| s.range == *r) {
            None => Some(format!(
                "plateau {} holds no sample of the log: it gives K0 no point and is left out",
                shown(r)
            )),
            Some(s) if s.samples < 2 => Some(format!(
                "plateau {} holds one sample: its bias is a single reading, whose noise nothing \
                 measures; widen it",
                shown(r)
            )),
            Some(_) => None,
        })
        .collect()
}

/// How many times the detector's tolerance a plateau's mean temperature rate may reach before
/// it is told: a hold the detector would take never moves faster than its limit, so twice that
/// on average is a ramp, not noise.
pub const UNSTEADY_FACTOR: f64 = 2.0;

/// The temperature spread under which a plateau is never told, °C: a sensor's noise and
/// quantisation over a short range (0.001 °C steps, a few hundredths of noise).
pub const UNSTEADY_FLOOR_C: f64 = 0.1;

/// Where a plateau lies outside what the detector (with `opts`) would have kept, each in a
/// few words for a table's mark: T moving on average faster than the detector's rate (its
/// spread over its length, a lower bound of the fastest |Ṫ| on it; spreads under
/// [`UNSTEADY_FLOOR_C`], a sensor's noise, aside), or a plateau shorter than the settled part
/// of the shortest quiet stretch the detector accepts. Empty for a plateau it could have
/// found. (The fit's warning, [`unsteady`], asks for [`UNSTEADY_FACTOR`] times the rate.)
pub fn outside_detector(stats: &PlateauStats, opts: &DetectOptions) -> Vec<String> {
    let n = |v: f64| crate::number::significant(v, 3);
    let mut out = Vec::new();
    let length_s = stats.range.end_s - stats.range.start_s;
    let spread = stats.temp_spread_c;
    if let Some(rate) = stats.mean_rate_c_per_min()
        && spread > UNSTEADY_FLOOR_C
        && rate > opts.max_rate_c_per_min
    {
        out.push(format!(
            "T moves {} °C over it, {} °C/min on average: the detector holds a plateau \
             under {} °C/min",
            n(spread),
            n(rate),
            n(opts.max_rate_c_per_min)
        ));
    }
    let shortest_s = opts.min_duration_s * opts.settled_fraction;
    if length_s < shortest_s {
        out.push(format!(
            "it lasts {} s: a plateau the detector keeps lasts at least {} s",
            n(length_s),
            n(shortest_s)
        ));
    }
    out
}

/// The warning for a plateau over which T moves far more than a plateau the detector finds
/// could: its spread, over its length, is more than [`UNSTEADY_FACTOR`] times the detector's
/// `max_rate_c_per_min` (and above [`UNSTEADY_FLOOR_C`]). Its K0 point then mixes the bias
/// at several temperatures with the rate-driven drift of a ramp (a range given by hand
/// across a 40 °C ramp). `None` for a steady plateau.
pub fn unsteady(stats: &PlateauStats, max_rate_c_per_min: f64) -> Option<String> {
    let spread = stats.temp_spread_c;
    let mean_rate = stats.mean_rate_c_per_min()?;
    if spread <= UNSTEADY_FLOOR_C {
        return None;
    }
    (mean_rate > UNSTEADY_FACTOR * max_rate_c_per_min).then(|| {
        format!(
            "plateau {}:{} s: the temperature spreads {} °C over it ({} °C/min on average), \
             more than {UNSTEADY_FACTOR} times the {} °C/min a plateau the detector finds stays \
             under: it is not a temperature hold, and its K0 point mixes the bias at several \
             temperatures with the drift of a ramp; check the range",
            crate::number::readable(stats.range.start_s),
            crate::number::readable(stats.range.end_s),
            crate::number::significant(spread, 3),
            crate::number::significant(mean_rate, 3),
            crate::number::readable(max_rate_c_per_min)
        )
    })
}
