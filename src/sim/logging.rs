//! What the logger records of a run, and when it says it did: sampling rate, outages, bursts
//! and the time stamps of a host that reads the samples in batches.
//!
//! The gyro and the chamber do not care how they are logged: gaps and bursts only leave samples
//! out, and jittered stamps only change the time column. The data of every sample that is
//! written are those of the regular run, sample for sample.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

use crate::error::Invalid;

use super::noise;

/// A sample lies in a window when it is at most this far before its start, and leaves it this
/// far before its end, s: sample times are rounded to 1 ns, so `[3600, 7200)` holds the sample
/// at 3600 s and not the one at 7200 s whatever the rounding, at any rate up to 1 MHz.
const WINDOW_TOLERANCE_S: f64 = 1e-7;

/// How a run is logged (`driftlab simulate --rate-hz --gap --bursts --jitter`).
///
/// The default logs every sample of the profile at the profile's own rate, stamped with its
/// true time: the run as it has always been.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Logging {
    /// Sampling rate of the log, Hz; `None` is the profile's own (1 Hz for the built-in ones).
    ///
    /// A whole multiple of the profile's rate logs the same run faster. At the profile's
    /// instants the thermal state, the drift and the temperature readings are those of the
    /// slower run, bit for bit. Between two instants the fibre-optic gyro's thermal state (the
    /// housing and every layer of the winding) is the straight line between its states at the
    /// two: the winding is integrated in the profile's explicit 1-s steps, and integrating it
    /// on in finer steps from each instant would relax its outer layer within the second and
    /// print a 1 Hz sawtooth of up to 0.03 °/h into the Shupe term at the ends of ramps. (The
    /// laser gyro's lags are solved exactly over any step, so its state is integrated on from
    /// each instant, the dither relay acting at every faster sample.) The white noise of each
    /// slower sample is split over the faster ones of its interval so that their mean is that
    /// sample's noise: the angle the gyro reports does not depend on the logging rate, and a
    /// fast log averaged over the profile's intervals gives the slow log's noise back.
    ///
    /// Any other rate runs the profile at that rate directly, the physics in steps of at most
    /// 1 s; when it divides the profile's 1 Hz (0.5, 0.2 Hz…) those are the same 1-s steps, so
    /// the thermal state and drift at the common instants are again the same bits, while the
    /// noise is drawn afresh for the longer interval.
    pub rate_hz: Option<f64>,
    /// Logger outages: no sample from their start to their end.
    pub gaps: Vec<Gap>,
    /// Logging in bursts: only the samples inside a burst are written.
    pub bursts: Option<Bursts>,
    /// Time stamps of a host that reads the samples in batches instead of their true times.
    pub jitter: Option<HostJitter>,
}

impl Logging {
    /// Checks every option for a run sampled at `rate_hz`, with a sentence naming the option.
    pub fn check(&self, rate_hz: f64) -> Result<(), Invalid> {
        if let Some(r) = self.rate_hz
            && !(r.is_finite() && r > 0.0)
        {
            return Err(Invalid::new(
                "--rate-hz",
                format!("must be a positive number, got {r}"),
            ));
        }
        for g in &self.gaps {
            g.check()?;
        }
        if let Some(b) = &self.bursts {
            b.check()?;
            b.check_step(1.0 / rate_hz)?;
        }
        if let Some(j) = &self.jitter {
            j.check(rate_hz)?;
        }
        Ok(())
    }

    /// Refuses a gap that starts after `last_sample_s`, the time of the program's last
    /// sample: it would leave nothing out, and the engineer who gave it meant some outage
    /// (a start in minutes or hours typed as seconds, or a program shorter than thought).
    pub(crate) fn check_within(&self, last_sample_s: f64) -> Result<(), Invalid> {
        if let Some(g) = self
            .gaps
            .iter()
            .find(|g| g.start_s - WINDOW_TOLERANCE_S > last_sample_s)
        {
            return Err(Invalid::new(
                format!("--gap {}", g.shown()),
                format!(
                    "starts after the program's last sample ({} s): it would leave no sample \
                     out",
                    crate::number::readable(last_sample_s)
                ),
            ));
        }
        Ok(())
    }

    /// The options that leave samples out (`--gap`, `--bursts`), as flags, for a message.
    pub(crate) fn leaving_out(&self) -> String {
        let pair = |a: f64, b: f64| {
            format!(
                "{}:{}",
                crate::number::readable(a),
                crate::number::readable(b)
            )
        };
        let mut out: Vec<String> = self
            .gaps
            .iter()
            .map(|g| format!("--gap {}", g.shown()))
            .collect();
        if let Some(b) = &self.bursts {
            out.push(format!("--bursts {}", pair(b.on_s, b.every_s)));
        }
        if out.is_empty() {
            return "logging".to_string();
        }
        out.join(" ")
    }

    /// Whether the logger records the sample taken at `time_s`: inside a burst (when logging
    /// in bursts) and outside every gap.
    pub fn records(&self, time_s: f64) -> bool {
        self.bursts.as_ref().is_none_or(|b| b.contains(time_s))
            && !self.gaps.iter().any(|g| g.contains(time_s))
    }

    /// The options as `driftlab simulate` flags, in a fixed order, for the CSV's first line.
    /// A jitter model other than the default is written as `--jitter` too: its constants are
    /// a library choice the command line does not carry.
    pub fn args(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(r) = self.rate_hz {
            out.push(format!("--rate-hz {r}"));
        }
        for g in &self.gaps {
            out.push(format!("--gap {g}"));
        }
        if let Some(b) = &self.bursts {
            out.push(format!("--bursts {b}"));
        }
        if self.jitter.is_some() {
            out.push("--jitter".to_string());
        }
        out
    }
}

/// A logger outage: no sample with `start_s ≤ t < start_s + duration_s` (`--gap START:DUR`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Gap {
    /// Start of the outage, s since the start of the program.
    pub start_s: f64,
    /// Length of the outage, s.
    pub duration_s: f64,
}

impl Gap {
    /// `START:DURATION` with six significant digits at most, for a message (the CSV's first
    /// line writes every digit, through `Display`).
    fn shown(&self) -> String {
        format!(
            "{}:{}",
            crate::number::readable(self.start_s),
            crate::number::readable(self.duration_s)
        )
    }

    /// Whether the sample at `time_s` falls in the outage.
    pub fn contains(&self, time_s: f64) -> bool {
        time_s >= self.start_s - WINDOW_TOLERANCE_S
            && time_s < self.start_s + self.duration_s - WINDOW_TOLERANCE_S
    }

    fn check(&self) -> Result<(), Invalid> {
        if !(self.start_s.is_finite() && self.start_s >= 0.0) {
            return Err(Invalid::new(
                format!("--gap {self}"),
                "the start must be zero or a positive number of seconds",
            ));
        }
        if !(self.duration_s.is_finite() && self.duration_s > 0.0) {
            return Err(Invalid::new(
                format!("--gap {self}"),
                "the duration must be a positive number of seconds",
            ));
        }
        Ok(())
    }
}

/// Logging in bursts: `on_s` seconds logged at the start of every `every_s` seconds, the first
/// burst starting at t = 0 (`--bursts ON:EVERY`, e.g. `10:120`: 10 s every 2 min).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bursts {
    /// Length of a burst, s.
    pub on_s: f64,
    /// Time from the start of one burst to the start of the next, s.
    pub every_s: f64,
}

impl Bursts {
    /// Whether the sample at `time_s` falls inside a burst.
    pub fn contains(&self, time_s: f64) -> bool {
        let k = ((time_s + WINDOW_TOLERANCE_S) / self.every_s).floor();
        let phase = time_s - k * self.every_s;
        phase < self.on_s - WINDOW_TOLERANCE_S
    }

    /// Refuses a burst shorter than the sampling step `step_s` (and so a period shorter
    /// than it, which [`Bursts::check`] holds at least as long): a burst holds at most one
    /// sample, and which samples fall in one is decided by their rounding to the window
    /// tolerance (1e-9:1e-9 lost samples at random-looking places), where the engineer meant
    /// bursts of several.
    fn check_step(&self, step_s: f64) -> Result<(), Invalid> {
        if self.on_s < step_s - WINDOW_TOLERANCE_S {
            let r = crate::number::readable;
            return Err(Invalid::new(
                format!("--bursts {}:{}", r(self.on_s), r(self.every_s)),
                format!(
                    "a burst of {} s is shorter than the sampling step of {} s ({} Hz): it \
                     would hold at most one sample; give ON_S (and EVERY_S ≥ ON_S) of at \
                     least one step",
                    r(self.on_s),
                    r(step_s),
                    r(1.0 / step_s)
                ),
            ));
        }
        Ok(())
    }

    fn check(&self) -> Result<(), Invalid> {
        if !(self.on_s.is_finite() && self.on_s > 0.0) {
            return Err(Invalid::new(
                format!("--bursts {self}"),
                "a burst must last a positive number of seconds",
            ));
        }
        if !(self.every_s.is_finite() && self.every_s >= self.on_s) {
            return Err(Invalid::new(
                format!("--bursts {self}"),
                "bursts must start at least as far apart as they last \
                 (ON_S:EVERY_S with EVERY_S ≥ ON_S)",
            ));
        }
        Ok(())
    }
}

fn parse_pair(flag: &str, what: &str, s: &str) -> Result<(f64, f64), Invalid> {
    let bad = || {
        Invalid::new(
            flag,
            format!("expects {what} in seconds (e.g. 3600:1800), got {s:?}"),
        )
    };
    let (a, b) = s.split_once(':').ok_or_else(bad)?;
    let a: f64 = a.trim().parse().map_err(|_| bad())?;
    let b: f64 = b.trim().parse().map_err(|_| bad())?;
    Ok((a, b))
}

impl FromStr for Gap {
    type Err = Invalid;
    /// `START_S:DURATION_S`.
    fn from_str(s: &str) -> Result<Gap, Invalid> {
        let (start_s, duration_s) = parse_pair("--gap", "START_S:DURATION_S", s)?;
        let g = Gap {
            start_s,
            duration_s,
        };
        g.check()?;
        Ok(g)
    }
}

impl fmt::Display for Gap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.start_s, self.duration_s)
    }
}

impl FromStr for Bursts {
    type Err = Invalid;
    /// `ON_S:EVERY_S`.
    fn from_str(s: &str) -> Result<Bursts, Invalid> {
        let (on_s, every_s) = parse_pair("--bursts", "ON_S:EVERY_S", s)?;
        let b = Bursts { on_s, every_s };
        b.check()?;
        Ok(b)
    }
}

impl fmt::Display for Bursts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.on_s, self.every_s)
    }
}

/// A host that reads the samples in batches and stamps them as it handles them (`--jitter`).
///
/// The gyro samples regularly; the host polls its input buffer. At each read it takes every
/// sample that has arrived since the last read and handles them one after the other, stamping
/// each with its clock: the first with the time of the read, the next `per_sample_s` later, and
/// so on. When the batch is done it waits (uniformly between `wait_min_s` and `wait_max_s`, or
/// with probability `stall_probability` stalls between `stall_min_s` and `stall_max_s`: the
/// host busy with something else) and reads again. Stamps are rounded to `resolution_s`.
///
/// So a stamp is never earlier than its sample, stamps keep the order of the samples, and
/// they stay within a bounded lag of the true times, so over a long log their mean step is the
/// true sampling step. Steps inside a batch are `per_sample_s`; a step from one batch to the
/// next is `per_sample_s` plus the wait (plus the empty reads before it: at most one sampling
/// step more), so no step exceeds `stall_max_s` plus the larger of `per_sample_s` and the
/// sampling step. With the defaults at 100 Hz over 1.5 h (seed 8, `tests/engine/sim_logging.rs`):
/// 53 % of the steps are 2 ms, the median step is 2.0 ms, one in ten is above 22.6 ms, the
/// longest 0.505 s, the mean step 10.000 ms, and no stamp lags its sample by more than
/// 0.52 s: the host stamps of the static MEMS log the real-logs issue describes (about 99 Hz,
/// half the steps 2 ms, the rest up to 0.5 s). The host must handle a sample faster than
/// they come (`per_sample_s` × rate < 1) or it falls ever further behind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HostJitter {
    /// Time the host spends on one sample: the step between stamps within a batch, s.
    pub per_sample_s: f64,
    /// Shortest wait between the end of a batch and the next read, s.
    pub wait_min_s: f64,
    /// Longest ordinary wait, s.
    pub wait_max_s: f64,
    /// Probability that a wait is a stall instead.
    pub stall_probability: f64,
    /// Shortest stall, s.
    pub stall_min_s: f64,
    /// Longest stall, s.
    pub stall_max_s: f64,
    /// Resolution of the host clock: stamps are rounded to it, s.
    pub resolution_s: f64,
}

impl Default for HostJitter {
    /// 2 ms a sample, waits of 1–25 ms, one wait in a hundred a stall of 0.1–0.5 s, a
    /// microsecond clock.
    fn default() -> Self {
        HostJitter {
            per_sample_s: 0.002,
            wait_min_s: 0.001,
            wait_max_s: 0.025,
            stall_probability: 0.01,
            stall_min_s: 0.1,
            stall_max_s: 0.5,
            resolution_s: 1e-6,
        }
    }
}

impl HostJitter {
    /// Checks the constants for a log sampled at `rate_hz`.
    pub fn check(&self, rate_hz: f64) -> Result<(), Invalid> {
        let res = self.resolution_s;
        if !(res.is_finite() && res > 0.0) {
            return Err(Invalid::new(
                "--jitter",
                format!("the host clock resolution must be positive, got {res}"),
            ));
        }
        let positive = [
            ("per_sample_s", self.per_sample_s),
            ("wait_min_s", self.wait_min_s),
            ("stall_min_s", self.stall_min_s),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v >= res) {
                return Err(Invalid::new(
                    "--jitter",
                    format!("{name} must be at least the clock resolution ({res} s), got {v}"),
                ));
            }
        }
        if !(self.wait_max_s.is_finite() && self.wait_max_s >= self.wait_min_s) {
            return Err(Invalid::new(
                "--jitter",
                "wait_max_s must be at least wait_min_s",
            ));
        }
        if !(self.stall_max_s.is_finite() && self.stall_max_s >= self.stall_min_s) {
            return Err(Invalid::new(
                "--jitter",
                "stall_max_s must be at least stall_min_s",
            ));
        }
        if !(0.0..=1.0).contains(&self.stall_probability) {
            return Err(Invalid::new(
                "--jitter",
                format!(
                    "stall_probability must be between 0 and 1, got {}",
                    self.stall_probability
                ),
            ));
        }
        if self.per_sample_s * rate_hz >= 1.0 {
            return Err(Invalid::new(
                "--jitter",
                format!(
                    "a host spending {} s a sample cannot keep up with {rate_hz} Hz \
                     (it would fall ever further behind); log slower",
                    self.per_sample_s
                ),
            ));
        }
        Ok(())
    }
}

/// Stamps samples, in order, as the host of [`HostJitter`] does.
pub(crate) struct Stamper {
    model: HostJitter,
    rng: ChaCha8Rng,
    /// Time of the current read, s; `None` before the first sample.
    read_s: Option<f64>,
    /// Samples stamped in the current batch.
    in_batch: usize,
}

impl Stamper {
    pub(crate) fn new(model: &HostJitter, seed: u64) -> Stamper {
        Stamper {
            model: model.clone(),
            rng: noise::rng(seed, noise::JITTER_STREAM),
            read_s: None,
            in_batch: 0,
        }
    }

    fn wait(&mut self) -> f64 {
        let m = &self.model;
        let stall = self.rng.random::<f64>() < m.stall_probability;
        let (lo, hi) = if stall {
            (m.stall_min_s, m.stall_max_s)
        } else {
            (m.wait_min_s, m.wait_max_s)
        };
        lo + (hi - lo) * self.rng.random::<f64>()
    }

    /// The host's stamp of the sample taken at `time_s` (samples come in time order).
    pub(crate) fn stamp(&mut self, time_s: f64) -> f64 {
        let mut read = match self.read_s {
            Some(r) => r,
            // The host's first read comes a wait after the first sample.
            None => time_s + self.wait(),
        };
        // Reads go on (each after the batch it took is handled and a wait) until one finds
        // this sample in the buffer.
        while time_s > read {
            read += self.in_batch as f64 * self.model.per_sample_s + self.wait();
            self.in_batch = 0;
        }
        self.read_s = Some(read);
        let stamp = read + self.in_batch as f64 * self.model.per_sample_s;
        self.in_batch += 1;
        noise::quantise(stamp, self.model.resolution_s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_hold_their_start_and_not_their_end() {
        let g: Gap = "3600:1800".parse().unwrap();
        assert!(!g.contains(3599.0) && g.contains(3600.0) && g.contains(5399.98));
        assert!(!g.contains(5400.0));
        let b: Bursts = "10:120".parse().unwrap();
        assert!(b.contains(0.0) && b.contains(9.98) && !b.contains(10.0));
        assert!(!b.contains(119.99) && b.contains(120.0) && b.contains(1209.0));
        assert_eq!(g.to_string(), "3600:1800");
        let e = "10".parse::<Bursts>().unwrap_err();
        assert_eq!(e.field, "--bursts");
        assert!(e.reason.contains("ON_S:EVERY_S"));
        let e = "10:5".parse::<Bursts>().unwrap_err();
        assert_eq!(e.field, "--bursts 10:5");
        assert!(e.reason.contains("EVERY_S ≥ ON_S"));
        let e = "5:-1".parse::<Gap>().unwrap_err();
        assert_eq!(e.field, "--gap 5:-1");
        assert!(e.reason.contains("duration"));
    }

    #[test]
    fn a_host_too_slow_for_the_rate_is_refused() {
        let j = HostJitter::default();
        assert!(j.check(100.0).is_ok());
        assert!(
            j.check(500.0)
                .unwrap_err()
                .reason
                .contains("cannot keep up")
        );
    }
}
