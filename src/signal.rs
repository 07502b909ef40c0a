//! Signal processing on uniformly sampled columns: moving averages and the causal 3-point
//! backward derivative of METHOD.md §1.
//!
//! Two moving averages, for two purposes. The centred one has no lag and is used where the
//! whole log is at hand (filtering Ω for the fit and for display). The causal one uses only past
//! samples, so the same smoothing can run in a gyro's processor; the temperature is smoothed this
//! way before differentiation, so that batch and streaming correction see identical Ṫ and T̈.
//!
//! Both are running sums written with one fixed order of operations, which the streaming
//! corrector repeats, so the two agree to the last bit rather than only approximately.

/// Centred moving average over `window` samples, truncated symmetrically at the ends.
///
/// Sample `i` averages `i − (window−1)/2 ..= i + window/2`; near an end the window shrinks to
/// what is there on that side. A window of 0 or 1 returns the input.
pub fn moving_average_centered(x: &[f64], window: usize) -> Vec<f64> {
    let n = x.len();
    if window <= 1 || n == 0 {
        return x.to_vec();
    }
    let back = (window - 1) / 2;
    let ahead = window / 2;
    // Prefix sums relative to the first value keep the sums small on long logs.
    let origin = x[0];
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    let mut s = 0.0;
    for &v in x {
        s += v - origin;
        prefix.push(s);
    }
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(back);
            let hi = (i + ahead).min(n - 1);
            origin + (prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo) as f64
        })
        .collect()
}

/// Like [`moving_average_centered`] but only where the whole window fits; the first and last
/// half-windows are left out (used by figures of merit, which must not mix window lengths).
pub fn moving_average_valid(x: &[f64], window: usize) -> Vec<f64> {
    let n = x.len();
    if window <= 1 {
        return x.to_vec();
    }
    if n < window {
        return Vec::new();
    }
    // One running sum over the full windows only, relative to the first value so the sum stays
    // small on long logs.
    let origin = x[0];
    let w = window as f64;
    let mut s: f64 = x[..window].iter().map(|v| v - origin).sum();
    let mut out = Vec::with_capacity(n - window + 1);
    out.push(origin + s / w);
    for i in window..n {
        s += (x[i] - origin) - (x[i - window] - origin);
        out.push(origin + s / w);
    }
    out
}

/// Causal moving average: sample `i` averages the last `window` samples up to and including
/// `i` (fewer at the start, while the window fills).
pub fn moving_average_causal(x: &[f64], window: usize) -> Vec<f64> {
    // A window longer than the series never fills: the series' length gives the same means
    // without holding a buffer sized from seconds over a tiny sampling step.
    let mut ma = CausalMean::new(window.min(x.len()));
    x.iter().map(|&v| ma.push(v)).collect()
}

/// Running mean of the last `window` values, one value at a time: the causal filter of both the
/// batch path and the streaming corrector.
#[derive(Debug, Clone)]
pub struct CausalMean {
    buf: Vec<f64>,
    next: usize,
    filled: usize,
    sum: f64,
}

impl CausalMean {
    /// A filter over `window` samples (0 is taken as 1: no smoothing).
    pub fn new(window: usize) -> CausalMean {
        CausalMean {
            buf: vec![0.0; window.max(1)],
            next: 0,
            filled: 0,
            sum: 0.0,
        }
    }

    /// Adds a sample and returns the mean of the window ending at it.
    #[inline]
    pub fn push(&mut self, v: f64) -> f64 {
        let w = self.buf.len();
        if self.filled == w {
            self.sum -= self.buf[self.next];
        } else {
            self.filled += 1;
        }
        self.sum += v;
        self.buf[self.next] = v;
        self.next = if self.next + 1 == w { 0 } else { self.next + 1 };
        self.sum / self.filled as f64
    }
}

/// The 3-point backward difference `(3x_i − 4x_{i−s} + x_{i−2s}) / (2H)` with step `s` samples
/// and `H = s·dt` seconds; exact for quadratics. The first `2s` samples, which lack history,
/// are 0 (no rate known yet, so no rate correction).
pub fn backward_derivative(x: &[f64], step: usize, dt_s: f64) -> Vec<f64> {
    let s = step.max(1);
    let h2 = 2.0 * s as f64 * dt_s;
    (0..x.len())
        .map(|i| {
            if i < s.saturating_mul(2) {
                0.0
            } else {
                backward_step(x[i], x[i - s], x[i - 2 * s], h2)
            }
        })
        .collect()
}

/// One 3-point backward difference, `(3x_i − 4x_{i−s} + x_{i−2s}) / (2H)` with `h2 = 2H`: the
/// one formula of the batch path and of both streaming correctors, so they agree bit for bit.
#[inline]
pub fn backward_step(x: f64, x_s: f64, x_2s: f64, h2: f64) -> f64 {
    (3.0 * x - 4.0 * x_s + x_2s) / h2
}

/// How the temperature is turned into rates, in samples (resolved from seconds for one log).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DerivativeSteps {
    /// Causal moving-average window applied to T before differentiating, samples.
    pub smooth: usize,
    /// Derivative step `s`, samples (H = s·dt).
    pub step: usize,
}

/// The first and second time derivatives of the (smoothed) temperature.
#[derive(Debug, Clone, Default)]
pub struct Derivatives {
    /// Ṫ, °C/s.
    pub tdot: Vec<f64>,
    /// T̈, °C/s².
    pub tddot: Vec<f64>,
    /// First sample from which T̈ has full history (`4·step`), so that both rates are real.
    pub ready_from: usize,
}

/// Ṫ and T̈ of a temperature column by smoothing then differentiating twice with the backward
/// difference (METHOD.md §1, step 2).
///
/// One pass: the smoothed temperature lives only in a ring of its last `2s + 1` values, so a
/// long log costs its two rate columns and nothing more. The arithmetic is that of
/// [`moving_average_causal`] followed twice by [`backward_derivative`], operation for
/// operation, so the rates are the same bits (a test holds them equal).
pub fn derivatives(temp_c: &[f64], steps: DerivativeSteps, dt_s: f64) -> Derivatives {
    let n = temp_c.len();
    let s = steps.step.max(1);
    let h2 = 2.0 * s as f64 * dt_s;
    let mut mean = CausalMean::new(steps.smooth.min(n));
    // The last 2s + 1 (and a few more) smoothed temperatures, indexed by sample number masked
    // to the ring's power-of-two length.
    let mask = (2 * s + 1).next_power_of_two() - 1;
    let mut smoothed = vec![0.0; mask + 1];
    let mut tdot = Vec::with_capacity(n);
    let mut tddot = Vec::with_capacity(n);
    for (i, &t) in temp_c.iter().enumerate() {
        let sm = mean.push(t);
        smoothed[i & mask] = sm;
        let td = if i < 2 * s {
            0.0
        } else {
            backward_step(
                sm,
                smoothed[(i - s) & mask],
                smoothed[(i - 2 * s) & mask],
                h2,
            )
        };
        tdot.push(td);
        let tdd = if i < 2 * s {
            0.0
        } else {
            backward_step(td, tdot[i - s], tdot[i - 2 * s], h2)
        };
        tddot.push(tdd);
    }
    // T̈ at 2s..4s would difference the zeros standing for "no Ṫ yet": not a real rate.
    let ready_from = s.saturating_mul(4).min(n);
    tddot[..ready_from].fill(0.0);
    Derivatives {
        tdot,
        tddot,
        ready_from,
    }
}

/// Resolves a duration in seconds to a whole number of samples (at least 1).
pub fn seconds_to_samples(seconds: f64, dt_s: f64) -> usize {
    if !(seconds.is_finite() && dt_s.is_finite() && dt_s > 0.0) {
        return 1;
    }
    ((seconds / dt_s).round() as usize).max(1)
}
