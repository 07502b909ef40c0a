//! A log's columns as a regression model reads them: T through its lag, T's rates, the
//! delayed read of the temperature channels, and the extra channels looked up by name.

use super::{Delay, Inputs, RegressionSpec, lag_at, terms};
use crate::error::Result;
use crate::log::Log;
use crate::models::FitError;
use crate::signal::{self, DerivativeSteps};

pub(crate) fn steps(spec: &RegressionSpec, dt_s: f64) -> DerivativeSteps {
    DerivativeSteps {
        smooth: signal::seconds_to_samples(spec.smoothing_s, dt_s),
        step: signal::seconds_to_samples(spec.step_h_s, dt_s),
    }
}

/// The extra channel that looks most like a second temperature sensor on the gyro: among the
/// columns named or measured as temperatures, one that does not name the chamber's air
/// ([`names_chamber_air`]) before one that does, then the first in the file. The choice does
/// not depend on where the chamber's column stands in the file.
pub fn guess_temp2(log: &Log) -> Option<String> {
    let candidates = log.extra.iter().filter(|c| {
        let n = c.name.to_ascii_lowercase();
        n.contains("temp") || matches!(c.unit.as_str(), "°C" | "degC" | "C")
    });
    candidates
        .clone()
        .find(|c| !names_chamber_air(&c.name))
        .or_else(|| candidates.clone().next())
        .map(|c| c.name.clone())
}

/// True for a column name that says it measures the chamber's air or the room (`chamber`,
/// `air`, `ambient`, `room`, `oven`), not a sensor on the gyro: a difference to it is the
/// chamber's lag, not the gyro's internal gradient.
pub fn names_chamber_air(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    ["chamber", "air", "ambient", "room", "oven"]
        .iter()
        .any(|w| n.contains(w))
}

/// A log's columns as a model reads them: T's rates computed, channels looked up by name.
pub(crate) struct Signals<'a> {
    pub time: &'a [f64],
    pub omega: &'a [f64],
    /// T as the model reads it (through the lag, when there is one).
    pub temp: Vec<f64>,
    pub tdot: Vec<f64>,
    pub tddot: Vec<f64>,
    pub temp2: Option<&'a [f64]>,
    pub channels: Vec<&'a [f64]>,
    pub dt_s: f64,
    pub ready_from: usize,
    /// The samples with full rate history, one range per segment of the log.
    pub ready: Vec<std::ops::Range<usize>>,
    /// The first sample of each segment: no delayed read reaches before its segment's start.
    pub segment_starts: Vec<usize>,
    /// The first sample of each run of a campaign with its time (one run for a log of one):
    /// the self-heating term's clock starts at its run's power-on.
    pub run_starts: Vec<(usize, f64)>,
    /// Lag weights by temperature reading, for [`Signals::relag`].
    alpha_cache: AlphaCache,
}

/// Lag weights by the bits of a temperature reading: a direct-mapped table, whose empty slots
/// hold the weight of 0.0 (whose bits are 0), so that every slot is right for its key.
#[derive(Default)]
struct AlphaCache {
    keys: Vec<u64>,
    alphas: Vec<f64>,
}

const ALPHA_CACHE_BITS: u32 = 16;
const ALPHA_CACHE: usize = 1 << ALPHA_CACHE_BITS;

/// Looks up a channel by name, with a message that lists what the log has.
fn channel<'a>(log: &'a Log, name: &str) -> Result<&'a [f64]> {
    log.extra
        .iter()
        .find(|c| c.name == name)
        .map(|c| c.values.as_slice())
        .ok_or_else(|| FitError::missing_channel(log, name).into())
}

impl<'a> Signals<'a> {
    pub(crate) fn of(
        log: &'a Log,
        spec: &RegressionSpec,
        temp2: Option<&str>,
        lag: Option<(f64, f64)>,
    ) -> Result<Signals<'a>> {
        let timing = log.timing();
        let dt_s = timing.nominal_dt_s;
        let segments = timing.segments;
        // The lag, like the rates, starts afresh in each segment.
        let temp = match lag {
            Some((tau, per_c)) if tau > 0.0 => {
                let mut out = Vec::with_capacity(log.temp_c.len());
                for r in &segments {
                    let mut lag = Lag::new(tau, per_c, dt_s);
                    out.extend(log.temp_c[r.clone()].iter().map(|&t| lag.push(t)));
                }
                out
            }
            _ => log.temp_c.clone(),
        };
        let d = signal::derivatives_in(&temp, steps(spec, dt_s), dt_s, &segments);
        let temp2 = temp2.map(|n| channel(log, n)).transpose()?;
        let channels = terms::channel_names(&spec.terms)
            .iter()
            .map(|n| channel(log, n))
            .collect::<Result<Vec<_>>>()?;
        Ok(Signals {
            time: &log.time_s,
            omega: &log.omega_dph,
            temp,
            tdot: d.tdot,
            tddot: d.tddot,
            temp2,
            channels,
            dt_s,
            ready_from: d.ready_from,
            ready: d.ready,
            segment_starts: segments.iter().map(|r| r.start).collect(),
            run_starts: log
                .run_ranges()
                .iter()
                .map(|r| (r.start, log.time_s.get(r.start).copied().unwrap_or(0.0)))
                .collect(),
            alpha_cache: AlphaCache::default(),
        })
    }

    pub(crate) fn len(&self) -> usize {
        self.time.len()
    }

    /// The samples with full rate history, in order.
    pub(crate) fn ready_samples(&self) -> impl Iterator<Item = usize> + Clone + '_ {
        self.ready.iter().flat_map(|r| r.clone())
    }

    /// How many samples have full rate history.
    pub(crate) fn ready_count(&self) -> usize {
        self.ready.iter().map(|r| r.len()).sum()
    }

    /// The time of the first sample of the run holding sample `i`: the power-on the
    /// self-heating term counts from.
    #[inline]
    fn run_start_s(&self, i: usize) -> f64 {
        match self.run_starts.as_slice() {
            [] => self.time.first().copied().unwrap_or(0.0),
            [(_, t0)] => *t0,
            starts => starts[starts.partition_point(|&(s, _)| s <= i).saturating_sub(1)].1,
        }
    }

    /// The first sample of the segment holding sample `i`.
    #[inline]
    fn segment_start(&self, i: usize) -> usize {
        match self.segment_starts.as_slice() {
            [] | [_] => 0,
            starts => starts[starts.partition_point(|&s| s <= i).saturating_sub(1)],
        }
    }

    /// The log's segments, from their starts.
    fn segments(&self) -> Vec<std::ops::Range<usize>> {
        let n = self.time.len();
        let mut starts = self.segment_starts.clone();
        if starts.is_empty() {
            starts.push(0);
        }
        starts
            .iter()
            .enumerate()
            .map(|(k, &a)| a..starts.get(k + 1).copied().unwrap_or(n))
            .collect()
    }

    /// The same signals with T read through another lag, computed in place: one pass of the
    /// lag and the rates over the log, into the buffers already held (a lag search tries
    /// hundreds of lags on a log of millions of samples). The same bits as
    /// [`Signals::of`] with that lag.
    pub(crate) fn relag(&mut self, log: &Log, spec: &RegressionSpec, lag: (f64, f64)) {
        let (tau, per_c) = lag;
        let steps = steps(spec, self.dt_s);
        let dt_s = self.dt_s;
        let new_lag = || (tau > 0.0).then(|| Lag::new(tau, per_c, dt_s));
        let segments = self.segments();
        // A temperature-dependent weight is an exponential per sample; a log's readings
        // repeat (a sensor's resolution, plateaus, cycles), so weights are kept by reading.
        let cache = &mut self.alpha_cache;
        if let Some(l) = new_lag().filter(Lag::varies) {
            cache.keys.clear();
            cache.keys.resize(ALPHA_CACHE, 0);
            cache.alphas.clear();
            cache.alphas.resize(ALPHA_CACHE, l.alpha_at(0.0));
        }
        self.temp.clear();
        self.tdot.clear();
        self.tddot.clear();
        self.ready.clear();
        // The lag and the rates start afresh in each segment, as in [`Signals::of`].
        for r in &segments {
            let mut rates = signal::Rates::new(steps.within(r.len()), dt_s);
            let mut lag = new_lag();
            for &t in &log.temp_c[r.clone()] {
                let y = match lag.as_mut() {
                    None => t,
                    Some(l) if l.varies() => {
                        let bits = t.to_bits();
                        let k = (bits.wrapping_mul(0x9E37_79B9_7F4A_7C15)
                            >> (64 - ALPHA_CACHE_BITS)) as usize;
                        let alpha = if cache.keys[k] == bits {
                            cache.alphas[k]
                        } else {
                            let a = l.alpha_at(t);
                            cache.keys[k] = bits;
                            cache.alphas[k] = a;
                            a
                        };
                        l.step(t, alpha)
                    }
                    Some(l) => l.push(t),
                };
                let (td, tdd) = rates.push(y);
                self.temp.push(y);
                self.tdot.push(td);
                self.tddot.push(tdd);
            }
            let from = r.start + rates.ready_from().min(r.len());
            if from < r.end {
                self.ready.push(from..r.end);
            }
        }
        self.ready_from = self.ready.first().map_or(log.len(), |r| r.start);
    }

    /// The inputs of sample `i` with the temperature channels read `delay` seconds back
    /// (linear interpolation between samples; before the log's start, its first sample).
    #[inline]
    pub(crate) fn inputs(&self, i: usize, delay: &Delay, channels: &mut [f64]) -> Inputs {
        let f =
            delayed_index(i, delay.at(self.temp[i]), self.dt_s).max(self.segment_start(i) as f64);
        let temp = interp(&self.temp, f);
        for (v, c) in channels.iter_mut().zip(&self.channels) {
            *v = c[i];
        }
        Inputs {
            t_s: self.time[i] - self.run_start_s(i),
            temp,
            tdot: interp(&self.tdot, f),
            tddot: interp(&self.tddot, f),
            dt: self.temp2.map_or(0.0, |t2| temp - interp(t2, f)),
        }
    }
}

/// A first-order lag `dy/dt = (x − y)/τ` stepped once a sample (input held over the step);
/// it starts at its first input.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lag {
    tau_s: f64,
    per_c: f64,
    dt_s: f64,
    /// The step's weight when τ does not change with temperature (computed once).
    alpha: f64,
    y: Option<f64>,
}

impl Lag {
    pub(crate) fn new(tau_s: f64, per_c: f64, dt_s: f64) -> Lag {
        Lag {
            tau_s,
            per_c,
            dt_s,
            alpha: if tau_s > 0.0 {
                1.0 - (-dt_s / tau_s).exp()
            } else {
                1.0
            },
            y: None,
        }
    }

    /// Steps the lag with input `x`; with a temperature-dependent τ, τ is taken at `x`.
    #[inline]
    pub(crate) fn push(&mut self, x: f64) -> f64 {
        let alpha = self.alpha_at(x);
        self.step(x, alpha)
    }

    /// True when the step's weight changes with the input (τ depends on temperature).
    pub(crate) fn varies(&self) -> bool {
        self.per_c != 0.0 && self.tau_s > 0.0
    }

    /// The step's weight for input `x`.
    #[inline]
    pub(crate) fn alpha_at(&self, x: f64) -> f64 {
        if self.varies() {
            1.0 - (-self.dt_s / lag_at(self.tau_s, self.per_c, x)).exp()
        } else {
            self.alpha
        }
    }

    /// Steps the lag with input `x` and its weight `alpha` (from [`Lag::alpha_at`]).
    #[inline]
    pub(crate) fn step(&mut self, x: f64, alpha: f64) -> f64 {
        let y = match self.y {
            Some(y) if y.is_finite() => y + alpha * (x - y),
            _ => x,
        };
        self.y = Some(y);
        y
    }
}

/// The fractional sample index `delay_s` before sample `i` (never before the first sample).
#[inline]
pub(crate) fn delayed_index(i: usize, delay_s: f64, dt_s: f64) -> f64 {
    if delay_s > 0.0 {
        (i as f64 - delay_s / dt_s).max(0.0)
    } else {
        i as f64
    }
}

/// Splits a fractional index into a sample and a weight for the next one.
#[inline]
pub(crate) fn split(f: f64) -> (usize, f64) {
    let j = f.floor();
    (j as usize, f - j)
}

#[inline]
fn interp(x: &[f64], f: f64) -> f64 {
    let (j, w) = split(f);
    if w == 0.0 || j + 1 >= x.len() {
        x[j]
    } else {
        x[j] + (x[j + 1] - x[j]) * w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::regression::Term;

    #[test]
    fn signals_relagged_in_place_are_those_made_afresh() {
        // A ramp with a plateau and a sensor's resolution: readings repeat, as in a log.
        let n = 5000;
        let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let temp: Vec<f64> = (0..n)
            .map(|i| {
                let t = if i < 2000 {
                    20.0 + 0.01 * i as f64
                } else {
                    40.0
                };
                (t * 1000.0 + ((i * 7919) % 5) as f64).round() / 1000.0
            })
            .collect();
        let log = Log::from_columns("ramp", time, vec![0.0; n], temp);
        let spec = RegressionSpec::new("m", vec![Term::One, Term::T, Term::Tdot]);
        let mut held = Signals::of(&log, &spec, None, None).unwrap();
        for lag in [
            (600.0, 0.0125),
            (0.0, 0.0),
            (300.0, 0.0),
            (1800.0, 0.025),
            (600.0, 0.0125),
        ] {
            held.relag(&log, &spec, lag);
            let fresh = Signals::of(&log, &spec, None, Some(lag)).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&held.temp), bits(&fresh.temp), "{lag:?}");
            assert_eq!(bits(&held.tdot), bits(&fresh.tdot), "{lag:?}");
            assert_eq!(bits(&held.tddot), bits(&fresh.tddot), "{lag:?}");
            assert_eq!(held.ready_from, fresh.ready_from);
        }
    }
}
