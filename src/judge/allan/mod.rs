//! Allan deviation of a gyro rate series, with confidence intervals and the standard gyro
//! read-outs (angle random walk, bias instability, rate random walk).
//!
//! Gyro rate plays the role of fractional frequency `y` and the accumulated angle the role of
//! phase `x = Σ y·τ0`. Every deviation here is computed from the phase form
//!
//! ```text
//! σ²(τ) = Σ_i (x[i+2m] − 2·x[i+m] + x[i])² / (2·τ²·n),   τ = m·τ0
//! ```
//!
//! which costs O(N) per τ whatever `m` is: averaging the rate over `m` samples is a difference
//! of two phase values. The overlapping estimator takes every start `i` (n = N_x − 2m terms,
//! N_x = N + 1 phase points); the non-overlapping one steps `i` by `m` and exists to check
//! against published non-overlapping tables.
//!
//! # Confidence intervals, as Stable32 prints them
//!
//! For each τ: the noise type `α` (S_y(f) ∝ f^α: +2 white PM / angle, 0 white FM / rate, −2
//! random-walk FM / rate random walk) is identified by the lag-1 autocorrelation method of
//! Riley & Greenhall (2004) on the rate averaged over `m` samples; the equivalent degrees of
//! freedom follow Greenhall & Riley (2003), "Uncertainty of stability variances based on finite
//! differences"; the bounds are the chi-squared ones of NIST SP 1065 eq. (45):
//! `σ_min = σ·√(edf/χ²(1−p/2))`, `σ_max = σ·√(edf/χ²(p/2))`, with `p = 1 − confidence`.
//! The lag-1 method needs 30 averaged points; at longer τ the α found at the longest τ that
//! had them is carried forward. A series too short for any identification assumes white rate
//! noise (α = 0). Each point says which of the three happened ([`NoiseIdSource`]).
//!
//! Where this is known to differ from Stable32: with fewer than 30 averages Stable32 identifies
//! the noise with the B1 and R(n) ratios instead of carrying α forward. On PHASE.DAT that makes
//! no difference at octave τ (α = 0 at m = 64 and 128 both ways, and the intervals match the
//! printed ones to 3.3e-4 relative), but in the all-τ tables Stable32 prints α = 1 at 55 of the
//! 106 factors m ≥ 34 where this module carries α = 0 (the lag-1 α agrees at all 33 factors
//! m ≤ 33). Those tables print no intervals, so the effect is unmeasured there; at such τ an
//! interval from here is the white-noise one where Stable32 would use flicker-PM degrees of
//! freedom.
//!
//! # Units
//!
//! Rates are whatever the caller passes (driftlab logs: °/h), τ in seconds; σ(τ) has the
//! rate's unit. The read-outs assume °/h (see [`GyroReadouts`]).

mod chi2;
mod edf;
pub mod kalibr;
mod noise_id;
mod readouts;
pub mod temperature;

pub use chi2::{chi2_quantile, confidence_interval};
pub use edf::edf_greenhall;
pub use noise_id::identify_noise;
use noise_id::identify_noise_from_phase;
pub use readouts::{BIAS_INSTABILITY_FACTOR, GyroReadouts, Readout, SLOPE_TOLERANCE};
pub use temperature::{STEADY_SPAN_C, TemperatureMotion};

use rayon::prelude::*;
use serde::Serialize;

/// Confidence of a one-sigma interval, erf(1/√2): the "Confidence Factor = 0.683" of Stable32.
pub const ONE_SIGMA: f64 = 0.682_689_492_137_085_9;

/// Which averaging factors m (τ = m·τ0) to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TauSpacing {
    /// m = 1, 2, 4, 8, … up to the largest m ≤ N/4. O(N·log N) in all: the default.
    Octave,
    /// Every m = 1, 2, 3, … up to N/4. O(N²): for short series only.
    All,
}

/// How to compute a deviation. Checked by [`allan`], then trusted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AllanOptions {
    /// Sampling interval of the rate series, s.
    pub tau0_s: f64,
    /// Which τ to compute.
    pub spacing: TauSpacing,
    /// Overlapping estimator (every start) rather than the non-overlapping one (starts m
    /// apart). The overlapping one is the default: same expectation, more degrees of freedom.
    pub overlapping: bool,
    /// Confidence of the intervals, in (0, 1); [`ONE_SIGMA`] by default.
    pub confidence: f64,
}

impl Default for AllanOptions {
    fn default() -> Self {
        AllanOptions {
            tau0_s: 1.0,
            spacing: TauSpacing::Octave,
            overlapping: true,
            confidence: ONE_SIGMA,
        }
    }
}

/// Why a deviation could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AllanError {
    /// Fewer than two rate samples: no second difference of phase exists.
    #[error("an Allan deviation needs at least 2 rate samples, the series has {0}")]
    TooShort(usize),
    /// A NaN or infinite sample; the caller decides how to fill or cut, not this module.
    #[error("rate sample {index} is not a finite number ({value})")]
    NotFinite {
        /// 0-based index of the sample.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Every sample the same value: no noise to analyse, and every σ would be 0.
    #[error(
        "every rate sample reads {}: a series that never changes has no noise to analyse (a \
         sensor disconnected or stuck)",
        crate::number::readable(*.0)
    )]
    Constant(f64),
    /// τ0 outside [`MIN_TAU0_S`] ..= [`MAX_TAU0_S`].
    #[error(
        "tau0 must be between 1e-9 s (a gigahertz) and 86400 s (a sample a day), got {}",
        crate::number::readable(*.0)
    )]
    BadTau0(f64),
    /// Confidence outside (0, 1).
    #[error("confidence must lie strictly between 0 and 1, got {0}")]
    BadConfidence(f64),
    /// An averaging factor of 0 or one too long for the series.
    #[error("averaging factor {m} does not fit a series of {n} samples (need 1 <= m <= n/2)")]
    BadFactor {
        /// The factor asked for.
        m: usize,
        /// Rate samples in the series.
        n: usize,
    },
}

/// Where the noise type α of a point came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum NoiseIdSource {
    /// Lag-1 autocorrelation of the rate averaged over m samples (≥ 30 averages).
    Lag1Acf,
    /// Too few averages at this τ: the α identified at the longest shorter τ.
    CarriedForward,
    /// No τ of the series had enough averages: white rate noise (α = 0) assumed.
    Assumed,
}

/// One τ of an Allan deviation curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AllanPoint {
    /// Averaging factor, τ = m·τ0.
    pub m: usize,
    /// Averaging time, s.
    pub tau_s: f64,
    /// σ(τ), in the unit of the rate.
    pub adev: f64,
    /// Number of second differences summed.
    pub n_terms: usize,
    /// Noise type used for the interval (power-law exponent of the rate spectrum).
    pub alpha: i32,
    /// How α was found.
    pub alpha_source: NoiseIdSource,
    /// Equivalent degrees of freedom (Greenhall–Riley), `None` when not defined.
    pub edf: Option<f64>,
    /// Lower bound of the confidence interval.
    pub adev_min: Option<f64>,
    /// Upper bound of the confidence interval.
    pub adev_max: Option<f64>,
}

/// An Allan deviation curve with its read-outs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AllanDeviation {
    /// The options it was computed with.
    pub options: AllanOptions,
    /// Rate samples used.
    pub samples: usize,
    /// The curve, τ increasing.
    pub points: Vec<AllanPoint>,
    /// ARW, bias instability and RRW read off the curve (rates taken as °/h).
    pub readouts: GyroReadouts,
}
/// The averaging factors of a spacing for `n` rate samples: up to N/4 (at least 1 when N ≥ 2),
/// as Stable32 does, so that every σ rests on at least N/2 overlapping terms.
pub fn averaging_factors(n: usize, spacing: TauSpacing) -> Vec<usize> {
    if n < 2 {
        return Vec::new();
    }
    let m_max = (n / 4).max(1);
    match spacing {
        TauSpacing::All => (1..=m_max).collect(),
        TauSpacing::Octave => std::iter::successors(Some(1usize), |&m| m.checked_mul(2))
            .take_while(|&m| m <= m_max)
            .collect(),
    }
}

/// The shortest sampling interval taken as a gyro's, s: a gigahertz. Below it, τ rounds to 0 in
/// every table and the variances divide by τ² that underflows (`--tau0 1e-300` gave NaN).
pub const MIN_TAU0_S: f64 = 1e-9;
/// The longest sampling interval taken as a gyro's, s: one sample a day.
pub const MAX_TAU0_S: f64 = 86_400.0;

/// Checks a sampling interval before anything is computed with it.
///
/// # Errors
/// [`AllanError::BadTau0`] outside [`MIN_TAU0_S`] ..= [`MAX_TAU0_S`] (NaN included).
pub fn check_tau0(tau0_s: f64) -> Result<(), AllanError> {
    if (MIN_TAU0_S..=MAX_TAU0_S).contains(&tau0_s) {
        Ok(())
    } else {
        Err(AllanError::BadTau0(tau0_s))
    }
}

/// What to tell of a τ0 given by hand (`tau0_s`) that differs by more than 1 % from the step
/// the log's own time stamps give (`step_s`), `k = tau0_s / step_s` times it; `None` when they
/// agree.
///
/// σ of the m-sample average does not depend on τ0 (the phase and τ = m·τ0 both carry it, and
/// σ²(τ) = Σ(Δ²x)²/(2τ²n) cancels it), so only the τ axis moves, by k. A read-out is σ read on
/// a line of the log-log curve, so it moves as that line's slope says: the angle random walk
/// (σ·√τ on the −½ line) by √k, the bias instability (the flat minimum) not at all, the rate
/// random walk (σ·√(3/τ) on the +½ line) by 1/√k; Kalibr's noise density and random walk
/// follow them, and its `update_rate` (1/τ0) moves by 1/k.
pub fn tau0_against_step(tau0_s: f64, step_s: f64, log_name: &str) -> Option<String> {
    let agree = step_s.is_finite() && step_s > 0.0 && ((tau0_s / step_s) - 1.0).abs() <= 0.01;
    (!agree && step_s.is_finite() && step_s > 0.0).then(|| {
        let k = tau0_s / step_s;
        let r = crate::number::readable;
        format!(
            "tau0 {} s is not the step of {log_name}'s time stamps ({} s): it scales every τ by \
             {}, the angle random walk (and Kalibr's noise density) by {} (√{}), the rate random \
             walk (and Kalibr's random walk) by {} (1/√{}) and Kalibr's update_rate by {}, and \
             leaves the bias instability as it is; it is used as given",
            r(tau0_s),
            r(step_s),
            r(k),
            r(k.sqrt()),
            r(k),
            r(1.0 / k.sqrt()),
            r(k),
            r(1.0 / k)
        )
    })
}

/// Allan deviation of `rate` at the factors of `opts.spacing`, with intervals and read-outs.
pub fn allan(rate: &[f64], opts: &AllanOptions) -> Result<AllanDeviation, AllanError> {
    allan_at(rate, opts, &averaging_factors(rate.len(), opts.spacing))
}

/// Allan deviation of `rate` at the given averaging factors (sorted here; duplicates removed).
///
/// Errors on NaN, a series shorter than 2, a bad τ0 or confidence, or a factor m with 2m > N.
pub fn allan_at(
    rate: &[f64],
    opts: &AllanOptions,
    factors: &[usize],
) -> Result<AllanDeviation, AllanError> {
    let n = rate.len();
    if n < 2 {
        return Err(AllanError::TooShort(n));
    }
    check_tau0(opts.tau0_s)?;
    if !(opts.confidence > 0.0 && opts.confidence < 1.0) {
        return Err(AllanError::BadConfidence(opts.confidence));
    }
    if let Some((index, &value)) = rate.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(AllanError::NotFinite { index, value });
    }
    if rate.iter().all(|v| v.to_bits() == rate[0].to_bits()) {
        return Err(AllanError::Constant(rate[0]));
    }
    let mut ms = factors.to_vec();
    ms.sort_unstable();
    ms.dedup();
    if let Some(&m) = ms.iter().find(|&&m| m == 0 || m > n / 2) {
        return Err(AllanError::BadFactor { m, n });
    }
    let phase = phase_from_rate(rate, opts.tau0_s);
    let n_phase = phase.len();
    let sums: Vec<(f64, usize)> = if opts.overlapping {
        overlapping_sums(&phase, &ms)
    } else {
        ms.par_iter()
            .map(|&m| non_overlapping_sum(&phase, m))
            .collect()
    };
    let found: Vec<Option<i32>> = ms
        .par_iter()
        .map(|&m| identify_noise_from_phase(&phase, m))
        .collect();

    let mut carried: Option<i32> = None;
    let mut points = Vec::with_capacity(ms.len());
    for ((&m, &(sum, n_terms)), &found) in ms.iter().zip(&sums).zip(&found) {
        let tau_s = m as f64 * opts.tau0_s;
        let adev = (sum / (2.0 * tau_s * tau_s * n_terms as f64)).sqrt();
        let (alpha, alpha_source) = match (found, carried) {
            (Some(a), _) => (a, NoiseIdSource::Lag1Acf),
            (None, Some(a)) => (a, NoiseIdSource::CarriedForward),
            (None, None) => (0, NoiseIdSource::Assumed),
        };
        if found.is_some() {
            carried = found;
        }
        let edf = edf_greenhall(alpha, 2, m, n_phase, opts.overlapping);
        let (adev_min, adev_max) = match edf {
            Some(e) => {
                let (lo, hi) = confidence_interval(adev, e, opts.confidence);
                (Some(lo), Some(hi))
            }
            None => (None, None),
        };
        points.push(AllanPoint {
            m,
            tau_s,
            adev,
            n_terms,
            alpha,
            alpha_source,
            edf,
            adev_min,
            adev_max,
        });
    }
    let readouts = GyroReadouts::of(&points);
    Ok(AllanDeviation {
        options: *opts,
        samples: n,
        points,
        readouts,
    })
}

/// Phase (angle) from rate: `x[0] = 0`, `x[k] = Σ_{j<k} (y[j] − ȳ)·τ0`.
///
/// The mean is taken out first (σ does not depend on it) so that the phase of a long log with
/// a large bias stays small and the second differences do not lose digits.
pub fn phase_from_rate(rate: &[f64], tau0_s: f64) -> Vec<f64> {
    let mean = if rate.is_empty() {
        0.0
    } else {
        rate.iter().sum::<f64>() / rate.len() as f64
    };
    let mut x = Vec::with_capacity(rate.len() + 1);
    let mut acc = 0.0;
    x.push(acc);
    for &y in rate {
        acc += (y - mean) * tau0_s;
        x.push(acc);
    }
    x
}

/// Overlapping sums Σ_i (x\[i+2m\] − 2x\[i+m\] + x\[i\])² for every factor, with their numbers of
/// terms N_x − 2m.
///
/// The sum is memory-bound, so all factors are computed in one pass over the phase, block by
/// block: within a block the rows x[i+m] of factor m are the rows x[i+2·(m/2)] of factor m/2,
/// still in cache, and octave τ read each phase value about twice instead of three times per
/// τ. Blocks run in parallel; their sums are added in block order, so the result does not
/// depend on the number of threads.
fn overlapping_sums(x: &[f64], ms: &[usize]) -> Vec<(f64, usize)> {
    const BLOCK: usize = 4096;
    let nx = x.len();
    let n_blocks = nx.div_ceil(BLOCK);
    let per_block: Vec<Vec<f64>> = (0..n_blocks)
        .into_par_iter()
        .map(|blk| {
            let i0 = blk * BLOCK;
            ms.iter()
                .map(|&m| {
                    let last = nx.saturating_sub(2 * m);
                    if i0 >= last {
                        return 0.0;
                    }
                    let i1 = (i0 + BLOCK).min(last);
                    block_sum(&x[i0..i1], &x[i0 + m..i1 + m], &x[i0 + 2 * m..i1 + 2 * m])
                })
                .collect()
        })
        .collect();
    ms.iter()
        .enumerate()
        .map(|(k, &m)| {
            let s = per_block.iter().map(|b| b[k]).sum();
            (s, nx.saturating_sub(2 * m))
        })
        .collect()
}

/// Σ (c − 2b + a)² over equal-length slices, in four lanes so the loop vectorises.
fn block_sum(a: &[f64], b: &[f64], c: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let chunks = a
        .chunks_exact(4)
        .zip(b.chunks_exact(4))
        .zip(c.chunks_exact(4));
    for ((a4, b4), c4) in chunks {
        for k in 0..4 {
            let d = c4[k] - 2.0 * b4[k] + a4[k];
            acc[k] += d * d;
        }
    }
    let done = a.len() - a.len() % 4;
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for i in done..a.len() {
        let d = c[i] - 2.0 * b[i] + a[i];
        s += d * d;
    }
    s
}

/// The non-overlapping sum: starts i = 0, m, 2m, … while i + 2m < N_x.
fn non_overlapping_sum(x: &[f64], m: usize) -> (f64, usize) {
    if x.len() <= 2 * m {
        return (0.0, 0);
    }
    let last = x.len() - 2 * m;
    let (mut s, mut k) = (0.0, 0);
    for i in (0..last).step_by(m) {
        let d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
        s += d * d;
        k += 1;
    }
    (s, k)
}
