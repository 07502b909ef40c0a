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

use rayon::prelude::*;
use serde::Serialize;

/// Confidence of a one-sigma interval, erf(1/√2): the "Confidence Factor = 0.683" of Stable32.
pub const ONE_SIGMA: f64 = 0.682_689_492_137_085_9;

/// σ_min / B for flicker rate noise (IEEE Std 952, √(2·ln2/π)): the Allan deviation floor of
/// a bias instability B, so B = σ_min / 0.664.
pub const BIAS_INSTABILITY_FACTOR: f64 = 0.664;

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
    /// τ0 not a positive finite number.
    #[error("tau0 must be a positive number of seconds, got {0}")]
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

/// A value read off the Allan curve, with how it was read, so that a reader can redo it by
/// eye on the plot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Readout {
    /// The value, in `unit`.
    pub value: f64,
    /// Its unit.
    pub unit: String,
    /// The τ at which the line (or the curve) was read, s.
    pub read_at_tau_s: f64,
    /// σ at that τ on the line (or the curve), in the rate's unit.
    pub sigma_at_tau: f64,
    /// Slope of the line in log-log (−1/2, 0 for the minimum, +1/2).
    pub slope: f64,
    /// The τ range of the curve points the value rests on, s.
    pub region_tau_s: [f64; 2],
    /// How many curve points lie in that range.
    pub points: usize,
    /// The line was read outside the range it was fitted on.
    pub extrapolated: bool,
    /// One sentence for a human.
    pub method: String,
}

/// The standard gyro read-outs (IEEE Std 952), for a rate in °/h.
///
/// * ARW: white rate noise gives σ(τ) = N/√τ. N in (°/h)·√s is σ at τ = 1 s on the −1/2 line;
///   since √s = √h/60, ARW = N/60 in °/√h.
/// * Bias instability: B = σ_min / 0.664 in °/h, at the bottom of the curve.
/// * RRW: a rate random walk gives σ(τ) = K·√(τ/3). K in (°/h)/√s is σ at τ = 3 s on the +1/2
///   line; since 1/√s = 60/√h, RRW = 60·K in °/h/√h.
///
/// Each is `None` when the curve shows no such region.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct GyroReadouts {
    /// Angle random walk, °/√h.
    pub arw: Option<Readout>,
    /// Bias instability, °/h.
    pub bias_instability: Option<Readout>,
    /// Rate random walk, °/h/√h.
    pub rrw: Option<Readout>,
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
    if !(opts.tau0_s.is_finite() && opts.tau0_s > 0.0) {
        return Err(AllanError::BadTau0(opts.tau0_s));
    }
    if !(opts.confidence > 0.0 && opts.confidence < 1.0) {
        return Err(AllanError::BadConfidence(opts.confidence));
    }
    if let Some((index, &value)) = rate.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(AllanError::NotFinite { index, value });
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

/// Noise type α at averaging factor m by the lag-1 autocorrelation method (Riley & Greenhall
/// 2004, frequency data): average the rate over m samples, remove a linear drift, difference
/// until the lag-1 autocorrelation r1 gives δ = r1/(1+r1) < 0.25 (at most twice, as for the
/// Allan variance), then α = −round(2δ) − 2d, kept within the Allan range −2..=2.
///
/// `None` with fewer than 30 averages, where the estimate is too scattered to trust.
pub fn identify_noise(rate: &[f64], m: usize) -> Option<i32> {
    const MIN_POINTS: usize = 30;
    if m == 0 || rate.len() / m < MIN_POINTS {
        return None;
    }
    let z: Vec<f64> = rate
        .chunks_exact(m)
        .map(|c| c.iter().sum::<f64>() / m as f64)
        .collect();
    lag1_noise_type(z)
}

/// [`identify_noise`] from the phase: the rate averaged over block k is
/// (x\[(k+1)m\] − x\[km\]) / (m·τ0), and the method is blind to scale and offset, so the phase
/// differences serve as they are. O(N/m) instead of O(N).
fn identify_noise_from_phase(x: &[f64], m: usize) -> Option<i32> {
    if m == 0 || x.len() < 2 || (x.len() - 1) / m < 30 {
        return None;
    }
    let blocks = (x.len() - 1) / m;
    let z: Vec<f64> = (0..blocks).map(|k| x[(k + 1) * m] - x[k * m]).collect();
    lag1_noise_type(z)
}

/// The lag-1 autocorrelation steps of [`identify_noise`] on block averages `z`.
fn lag1_noise_type(mut z: Vec<f64>) -> Option<i32> {
    const D_MAX: i32 = 2;
    detrend_linear(&mut z);
    let mut d = 0;
    loop {
        let r1 = lag1_autocorrelation(&z)?;
        let delta = r1 / (1.0 + r1);
        if !delta.is_finite() {
            return None;
        }
        if delta < 0.25 || d >= D_MAX {
            let alpha = -(2.0 * delta).round() as i32 - 2 * d;
            return Some(alpha.clamp(-2, 2));
        }
        for i in 0..z.len() - 1 {
            z[i] = z[i + 1] - z[i];
        }
        z.pop();
        d += 1;
        if z.len() < 2 {
            return None;
        }
    }
}

/// Removes the least-squares line through (i, z\[i\]).
fn detrend_linear(z: &mut [f64]) {
    let n = z.len() as f64;
    if z.len() < 2 {
        return;
    }
    let tm = (n - 1.0) / 2.0;
    let zm = z.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &v) in z.iter().enumerate() {
        let t = i as f64 - tm;
        sxy += t * (v - zm);
        sxx += t * t;
    }
    let slope = sxy / sxx;
    for (i, v) in z.iter_mut().enumerate() {
        *v -= zm + slope * (i as f64 - tm);
    }
}

/// Lag-1 autocorrelation about the mean; `None` for a constant series.
fn lag1_autocorrelation(z: &[f64]) -> Option<f64> {
    let n = z.len();
    if n < 2 {
        return None;
    }
    let mu = z.iter().sum::<f64>() / n as f64;
    let den: f64 = z.iter().map(|v| (v - mu) * (v - mu)).sum();
    if den <= 0.0 || !den.is_finite() {
        return None;
    }
    let num: f64 = z.windows(2).map(|w| (w[0] - mu) * (w[1] - mu)).sum();
    Some(num / den)
}

/// Equivalent degrees of freedom of an unmodified variance (Greenhall & Riley 2003): d = 2
/// Allan, d = 3 Hadamard; `m` the averaging factor, `n_phase` the number of phase points,
/// `overlapping` the stride (m for the overlapping estimator, 1 for the non-overlapping one).
///
/// Follows the paper's cases for unmodified variances: the exact basic sum when it has at
/// most 100 terms, the large-sample approximation of its Tables 2 and 3 when the series is
/// long, and the truncated sum otherwise. `None` when the noise type is outside α + 2d > 1,
/// d is not 2 or 3, or the series is too short for one term.
pub fn edf_greenhall(
    alpha: i32,
    d: u32,
    m: usize,
    n_phase: usize,
    overlapping: bool,
) -> Option<f64> {
    if !(2..=3).contains(&d) || !(-4..=2).contains(&alpha) || alpha + 2 * d as i32 <= 1 || m == 0 {
        return None;
    }
    const J_MAX: f64 = 100.0;
    let df = d as f64;
    let mf = m as f64;
    let s = if overlapping { mf } else { 1.0 };
    let f = Filter::Finite(mf);
    let l = 1.0 + mf * df; // filter length m/F + m·d, with F = m for unmodified variances
    let nf = n_phase as f64;
    if nf < l {
        return None;
    }
    let big_m = 1.0 + (s * (nf - l) / mf).floor();
    let j = big_m.min((df + 1.0) * s);
    let r = big_m / s;
    let inv = match alpha {
        a if a <= 0 => {
            if j <= J_MAX {
                let fp = if mf * (df + 1.0) <= J_MAX {
                    f
                } else {
                    Filter::Infinite
                };
                basic_sum(j, big_m, s, fp, alpha, d) / (sz(0.0, fp, alpha, d).powi(2) * big_m)
            } else if r > df + 1.0 {
                let (a0, a1) = table2(alpha, d)?;
                (a0 - a1 / r) / r
            } else {
                let mp = J_MAX / r;
                basic_sum(J_MAX, J_MAX, mp, Filter::Infinite, alpha, d)
                    / (sz(0.0, Filter::Infinite, alpha, d).powi(2) * J_MAX)
            }
        }
        1 => {
            if j <= J_MAX {
                basic_sum(j, big_m, s, f, 1, d) / (sz(0.0, f, 1, d).powi(2) * big_m)
            } else {
                let (b0, b1) = table3(d);
                let b = b0 + b1 * mf.ln();
                if r > df + 1.0 {
                    let (a0, a1) = table2(1, d)?;
                    (a0 - a1 / r) / (b * b * r)
                } else {
                    let mp = J_MAX / r;
                    basic_sum(J_MAX, J_MAX, mp, Filter::Finite(mp), 1, d) / (b * b * J_MAX)
                }
            }
        }
        _ => {
            // α = 2, white phase (angle) noise.
            let k = r.ceil();
            if k <= df {
                // Few terms: the exact basic sum (the paper's closed form for this case is the
                // same sum written out).
                basic_sum(j, big_m, s, f, 2, d) / (sz(0.0, f, 2, d).powi(2) * big_m)
            } else {
                let a0 = binomial(4 * d, 2 * d) / binomial(2 * d, d).powi(2);
                let a1 = df / 2.0;
                (a0 - a1 / r) / big_m
            }
        }
    };
    let edf = 1.0 / inv;
    (edf.is_finite() && edf > 0.0).then_some(edf)
}

/// The filter factor F of Greenhall's sums; infinite stands for the limit m → ∞.
#[derive(Clone, Copy)]
enum Filter {
    Finite(f64),
    Infinite,
}

/// Eq. (10) of Greenhall & Riley: the basic sum.
fn basic_sum(j: f64, big_m: f64, s: f64, f: Filter, alpha: i32, d: u32) -> f64 {
    let mut sum = sz(0.0, f, alpha, d).powi(2);
    sum += (1.0 - j / big_m) * sz(j / s, f, alpha, d).powi(2);
    let ji = j as usize;
    for jj in 1..ji {
        let jf = jj as f64;
        sum += 2.0 * (1.0 - jf / big_m) * sz(jf / s, f, alpha, d).powi(2);
    }
    sum
}

/// Eq. (9): the d-th difference of sx.
fn sz(t: f64, f: Filter, alpha: i32, d: u32) -> f64 {
    let c: &[f64] = match d {
        2 => &[6.0, -4.0, 1.0],
        _ => &[20.0, -15.0, 6.0, -1.0],
    };
    let mut v = c[0] * sx(t, f, alpha);
    for (k, &ck) in c.iter().enumerate().skip(1) {
        let kf = k as f64;
        v += ck * (sx(t - kf, f, alpha) + sx(t + kf, f, alpha));
    }
    v
}

/// Eq. (8).
fn sx(t: f64, f: Filter, alpha: i32) -> f64 {
    match f {
        Filter::Infinite => sw(t, alpha + 2),
        Filter::Finite(ff) => {
            ff * ff * (2.0 * sw(t, alpha) - sw(t - 1.0 / ff, alpha) - sw(t + 1.0 / ff, alpha))
        }
    }
}

/// Eq. (7): the generalised autocovariance of the noise of type α.
fn sw(t: f64, alpha: i32) -> f64 {
    let at = t.abs();
    let tlog = |p: i32| {
        if t == 0.0 { 0.0 } else { t.powi(p) * at.ln() }
    };
    match alpha {
        2 => -at,
        1 => tlog(2),
        0 => at.powi(3),
        -1 => tlog(4),
        -2 => at.powi(5),
        -3 => tlog(6),
        _ => at.powi(7),
    }
}

/// Table 2 of Greenhall & Riley (unmodified variances): (a0, a1) by α and d.
fn table2(alpha: i32, d: u32) -> Option<(f64, f64)> {
    let v = match (alpha, d) {
        (2, 2) => (35.0 / 18.0, 1.0),
        (2, 3) => (231.0 / 100.0, 1.5),
        (1, 2) => (790.0, 410.0),
        (1, 3) => (9950.0, 6520.0),
        (0, 2) => (2.0 / 3.0, 1.0 / 3.0),
        (0, 3) => (7.0 / 9.0, 0.5),
        (-1, 2) => (0.852, 0.375),
        (-1, 3) => (0.997, 0.617),
        (-2, 2) => (1.079, 0.368),
        (-2, 3) => (1.033, 0.607),
        (-3, 3) => (1.053, 0.553),
        (-4, 3) => (1.302, 0.535),
        _ => return None,
    };
    Some(v)
}

/// Table 3 of Greenhall & Riley (α = 1): (b0, b1) by d.
fn table3(d: u32) -> (f64, f64) {
    if d == 2 { (15.23, 12.0) } else { (47.8, 40.0) }
}

fn binomial(n: u32, k: u32) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// Chi-squared confidence interval of a deviation with `edf` degrees of freedom
/// (NIST SP 1065 eq. 45): (σ·√(edf/χ²_hi), σ·√(edf/χ²_lo)).
pub fn confidence_interval(sigma: f64, edf: f64, confidence: f64) -> (f64, f64) {
    let p = (1.0 - confidence) / 2.0;
    let lo = chi2_quantile(p, edf);
    let hi = chi2_quantile(1.0 - p, edf);
    (sigma * (edf / hi).sqrt(), sigma * (edf / lo).sqrt())
}

/// Quantile of the chi-squared distribution with `k` (not necessarily whole) degrees of
/// freedom: Newton steps on the regularised incomplete gamma function from the
/// Wilson–Hilferty start, kept inside a bisection bracket. NaN for p outside (0, 1) or k ≤ 0.
pub fn chi2_quantile(p: f64, k: f64) -> f64 {
    if !(p > 0.0 && p < 1.0 && k > 0.0 && k.is_finite()) {
        return f64::NAN;
    }
    let z = normal_quantile(p);
    let c = 2.0 / (9.0 * k);
    let wh = k * (1.0 - c + z * c.sqrt()).powi(3);
    if k > 1e5 {
        // Wilson–Hilferty is exact to ~1e-8 here, and the gamma series would need ~√k terms.
        return wh;
    }
    let (mut lo, mut hi) = (0.0f64, k.max(1.0));
    while chi2_cdf(hi, k) < p {
        lo = hi;
        hi *= 2.0;
    }
    let mut x = if wh > lo && wh < hi {
        wh
    } else {
        0.5 * (lo + hi)
    };
    for _ in 0..200 {
        let f = chi2_cdf(x, k) - p;
        if f < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let pdf = chi2_pdf(x, k);
        let mut next = if pdf > 0.0 { x - f / pdf } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - x).abs() <= 1e-14 * x.max(1e-300) {
            return next;
        }
        x = next;
    }
    x
}

fn chi2_cdf(x: f64, k: f64) -> f64 {
    gamma_p(0.5 * k, 0.5 * x)
}

fn chi2_pdf(x: f64, k: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let a = 0.5 * k;
    ((a - 1.0) * (0.5 * x).ln() - 0.5 * x - ln_gamma(a)).exp() * 0.5
}

/// Regularised lower incomplete gamma P(a, x): series below a + 1, continued fraction above.
fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let lead = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (sum.ln() + lead).exp()
    } else {
        // Lentz's method for the continued fraction of Q(a, x).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        1.0 - (lead.exp() * h)
    }
}

/// ln Γ(a) for a > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
fn ln_gamma(a: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if a < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * a).sin()).ln() - ln_gamma(1.0 - a);
    }
    let a = a - 1.0;
    let mut s = C[0];
    for (i, &c) in C.iter().enumerate().skip(1) {
        s += c / (a + i as f64);
    }
    let t = a + G + 0.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (a + 0.5) * t.ln() - t + s.ln()
}

/// Standard normal quantile (Acklam's rational approximation, ~1e-9), a start for Newton.
fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// Largest distance of a segment's log-log slope from the target for it to count as part of
/// a −1/2 or +1/2 region. Octave estimates scatter; ±0.25 still tells −1/2 from 0 and −1.
pub const SLOPE_TOLERANCE: f64 = 0.25;

impl GyroReadouts {
    /// Reads ARW, bias instability and RRW off a curve whose σ is in °/h.
    ///
    /// Slope regions are looked for on the octave points of the curve (m a power of two;
    /// dense all-τ curves are too noisy between neighbours): a region is the longest run of
    /// consecutive segments whose log-log slope is within [`SLOPE_TOLERANCE`] of the target.
    /// The line of that slope is fitted through the region's points in log-log, each point
    /// weighted by its degrees of freedom (the inverse variance of ln σ), or by its number of
    /// terms when no edf is known. The bias instability is the minimum of the curve, and only
    /// when the curve rises past that point's upper bound at some longer τ (otherwise the
    /// curve has not reached its floor).
    pub fn of(points: &[AllanPoint]) -> GyroReadouts {
        let oct: Vec<&AllanPoint> = points
            .iter()
            .filter(|p| p.m.is_power_of_two() && p.adev > 0.0 && p.adev.is_finite())
            .collect();
        let arw = fit_region(&oct, -0.5).map(|(sigma1, lo, hi, k)| {
            // σ at τ = 1 s on the line.
            let n_line = sigma1;
            let extrapolated = !(lo <= 1.0 && 1.0 <= hi);
            Readout {
                value: n_line / 60.0,
                unit: "deg/sqrt(h)".into(),
                read_at_tau_s: 1.0,
                sigma_at_tau: n_line,
                slope: -0.5,
                region_tau_s: [lo, hi],
                points: k,
                extrapolated,
                method: format!(
                    "-1/2 line fitted on tau {lo} .. {hi} s ({k} points), sigma at tau = 1 s / 60"
                ),
            }
        });
        let rrw = fit_region(&oct, 0.5).map(|(sigma1, lo, hi, k)| {
            // The line is σ1·√τ; K = σ(3 s).
            let k_line = sigma1 * 3f64.sqrt();
            Readout {
                value: 60.0 * k_line,
                unit: "deg/h/sqrt(h)".into(),
                read_at_tau_s: 3.0,
                sigma_at_tau: k_line,
                slope: 0.5,
                region_tau_s: [lo, hi],
                points: k,
                extrapolated: !(lo <= 3.0 && 3.0 <= hi),
                method: format!(
                    "+1/2 line fitted on tau {lo} .. {hi} s ({k} points), sigma at tau = 3 s x 60"
                ),
            }
        });
        GyroReadouts {
            arw,
            bias_instability: bias_instability(&oct),
            rrw,
        }
    }
}

/// The weighted fit of a line of fixed `slope` through the longest run of segments near that
/// slope: (σ at τ = 1 s on the line, τ range, points), or `None` without such a run.
fn fit_region(p: &[&AllanPoint], slope: f64) -> Option<(f64, f64, f64, usize)> {
    if p.len() < 2 {
        return None;
    }
    let seg_ok: Vec<bool> = p
        .windows(2)
        .map(|w| {
            let s = (w[1].adev / w[0].adev).ln() / (w[1].tau_s / w[0].tau_s).ln();
            (s - slope).abs() <= SLOPE_TOLERANCE
        })
        .collect();
    // Longest run of good segments; on a tie the first (shorter τ) one.
    let (mut best, mut cur_start, mut best_len) = (None, 0, 0);
    for (i, &ok) in seg_ok.iter().enumerate() {
        if !ok {
            cur_start = i + 1;
            continue;
        }
        let len = i + 1 - cur_start;
        if len > best_len {
            best_len = len;
            best = Some(cur_start);
        }
    }
    let start = best?;
    let region = &p[start..=start + best_len];
    let (mut sw, mut swl) = (0.0, 0.0);
    for q in region {
        let w = q.edf.unwrap_or(q.n_terms as f64).max(1e-12);
        sw += w;
        swl += w * (q.adev.ln() - slope * q.tau_s.ln());
    }
    let sigma1 = (swl / sw).exp();
    Some((
        sigma1,
        region[0].tau_s,
        region[region.len() - 1].tau_s,
        region.len(),
    ))
}

fn bias_instability(p: &[&AllanPoint]) -> Option<Readout> {
    let (imin, pmin) = p
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.adev.total_cmp(&b.1.adev))?;
    if imin == 0 || imin + 1 >= p.len() {
        return None;
    }
    let bar = pmin.adev_max.unwrap_or(pmin.adev);
    if !p[imin + 1..].iter().any(|q| q.adev > bar) {
        return None;
    }
    Some(Readout {
        value: pmin.adev / BIAS_INSTABILITY_FACTOR,
        unit: "deg/h".into(),
        read_at_tau_s: pmin.tau_s,
        sigma_at_tau: pmin.adev,
        slope: 0.0,
        region_tau_s: [p[imin - 1].tau_s, p[imin + 1].tau_s],
        points: 1,
        extrapolated: false,
        method: format!(
            "minimum of the curve at tau = {} s, divided by 0.664",
            pmin.tau_s
        ),
    })
}
