//! Signal processing on uniformly sampled columns: moving averages and the causal 3-point
//! backward derivative of docs/method.md §1.
//!
//! Two moving averages, for two purposes. The centred one has no lag and is used where the
//! whole log is at hand (filtering Ω for the fit and for display). The causal one uses only past
//! samples, so the same smoothing can run in a gyro's processor; the temperature is smoothed this
//! way before differentiation, so that batch and streaming correction see identical Ṫ and T̈.
//!
//! Both are running sums written with one fixed order of operations, which the streaming
//! corrector repeats, so the two agree to the last bit rather than only approximately.

pub mod interleaved;
pub mod lod;
pub mod plateau;
mod stray;
pub mod summary;
pub mod time_order;
pub mod timing;

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

    /// The window's length, samples.
    pub fn window(&self) -> usize {
        self.buf.len()
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

impl DerivativeSteps {
    /// The first sample whose T̈ has its full history (see [`Rates::ready_from`]), worked out
    /// without building the rings: a window of 10¹³ samples asked of a picosecond log is a
    /// number here, not an allocation.
    pub fn ready_from(self) -> usize {
        self.step
            .max(1)
            .saturating_mul(4)
            .saturating_add(self.smooth.max(1).saturating_sub(1))
    }

    /// The same steps for a series of `n` samples, with no buffer longer than the series: a
    /// window longer than it never fills (its length gives the same means), and a step whose
    /// `2s` reaches past it gives no rate anywhere (any such step gives the same zeros).
    pub fn within(self, n: usize) -> DerivativeSteps {
        DerivativeSteps {
            smooth: self.smooth.min(n),
            step: self.step.min(n.div_ceil(2).max(1)),
        }
    }
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
    /// The samples with full history, one range per segment of the log (a segment restarts
    /// the history, as a streaming corrector restarts after a gap). Fits and figures read
    /// these samples only.
    pub ready: Vec<std::ops::Range<usize>>,
}

impl Derivatives {
    /// The samples with full history, in order.
    pub fn ready_samples(&self) -> impl Iterator<Item = usize> + '_ {
        self.ready.iter().flat_map(|r| r.clone())
    }
}

/// Ṫ and T̈ of a temperature column by smoothing then differentiating twice with the backward
/// difference (docs/method.md §2, step 2).
///
/// One pass of [`Rates`]: the smoothed temperature lives only in its short ring, so a long
/// log costs its two rate columns and nothing more. The arithmetic is that of
/// [`moving_average_causal`] followed twice by [`backward_derivative`], operation for
/// operation, so the rates are the same bits (a test holds them equal).
pub fn derivatives(temp_c: &[f64], steps: DerivativeSteps, dt_s: f64) -> Derivatives {
    let n = temp_c.len();
    let mut rates = Rates::new(steps.within(n), dt_s);
    let (mut tdot, mut tddot) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for &t in temp_c {
        let (td, tdd) = rates.push(t);
        tdot.push(td);
        tddot.push(tdd);
    }
    let ready_from = rates.ready_from().min(n);
    Derivatives {
        tdot,
        tddot,
        ready_from,
        ready: if ready_from < n {
            std::iter::once(ready_from..n).collect()
        } else {
            Vec::new()
        },
    }
}

/// [`derivatives`] of a log made of `segments` (contiguous runs between gaps, covering it in
/// order): each segment is differentiated on its own, its history starting afresh, so no
/// rate is taken across a gap; the samples without history are zero as at the log's start.
/// One segment gives [`derivatives`]'s bits.
pub fn derivatives_in(
    temp_c: &[f64],
    steps: DerivativeSteps,
    dt_s: f64,
    segments: &[std::ops::Range<usize>],
) -> Derivatives {
    if segments.len() <= 1 {
        return derivatives(temp_c, steps, dt_s);
    }
    let n = temp_c.len();
    let mut out = Derivatives {
        tdot: Vec::with_capacity(n),
        tddot: Vec::with_capacity(n),
        ready_from: n,
        ready: Vec::with_capacity(segments.len()),
    };
    for r in segments {
        let d = derivatives(&temp_c[r.clone()], steps, dt_s);
        out.tdot.extend_from_slice(&d.tdot);
        out.tddot.extend_from_slice(&d.tddot);
        out.ready
            .extend(d.ready.iter().map(|q| q.start + r.start..q.end + r.start));
    }
    out.ready_from = out.ready.first().map_or(n, |r| r.start);
    out
}

/// [`moving_average_centered`] within each of `segments`: the window is truncated at a
/// segment's ends as at the log's, so no average reaches across a gap. One segment gives
/// [`moving_average_centered`]'s bits.
pub fn moving_average_centered_in(
    x: &[f64],
    window: usize,
    segments: &[std::ops::Range<usize>],
) -> Vec<f64> {
    if segments.len() <= 1 {
        return moving_average_centered(x, window);
    }
    let mut out = Vec::with_capacity(x.len());
    for r in segments {
        out.extend(moving_average_centered(&x[r.clone()], window));
    }
    out
}

/// The most past samples a streaming corrector keeps of one signal (80 MB of f64): a window,
/// derivative step or delay longer than this, in samples, is refused rather than allocated.
/// Also the limit a calibration file's windows are checked against.
pub const MAX_HISTORY_SAMPLES: usize = 10_000_000;

/// Checks that a streaming corrector at `dt_s` with these steps, looking `back_s` seconds into
/// the past for delays, keeps histories of a sane length.
///
/// # Errors
/// A message naming the step, window or delay that would need more than
/// [`MAX_HISTORY_SAMPLES`] samples, or a step that is not a positive number of seconds.
pub fn check_history(
    steps: DerivativeSteps,
    back_s: f64,
    dt_s: f64,
) -> Result<(), crate::error::Invalid> {
    if !(dt_s.is_finite() && dt_s > 0.0) {
        return Err(crate::error::Invalid::new(
            "sampling step",
            format!("{dt_s} s: a positive number of seconds is needed"),
        ));
    }
    let back = back_s / dt_s;
    for (what, samples) in [
        ("the T smoothing window", steps.smooth as f64),
        (
            "the derivative step's history (2H)",
            2.0 * steps.step as f64 + 1.0,
        ),
        ("the longest delay", back),
    ] {
        if samples > MAX_HISTORY_SAMPLES as f64 {
            return Err(crate::error::Invalid::new(
                what,
                format!(
                    "spans {samples:.3e} samples of {dt_s} s, more than the \
                     {MAX_HISTORY_SAMPLES} a streaming corrector keeps"
                ),
            ));
        }
    }
    Ok(())
}

/// Ṫ and T̈ one sample at a time, from past samples only: the causal mean of T and two
/// backward differences over short rings. The one implementation of docs/method.md §2, step 2,
/// shared by the batch path ([`derivatives`]), the streaming corrector and the lean
/// prediction of `driftlab apply`, so all three give the same bits.
#[derive(Debug, Clone)]
pub struct Rates {
    mean: CausalMean,
    step: usize,
    h2: f64,
    /// Ring index mask: the rings hold a power of two of at least `2·step + 1` values.
    mask: usize,
    smoothed: Vec<f64>,
    tdot: Vec<f64>,
    count: usize,
}

impl Rates {
    /// Rates with these settings for samples `dt_s` seconds apart.
    pub fn new(steps: DerivativeSteps, dt_s: f64) -> Rates {
        let step = steps.step.max(1);
        let len = (2 * step + 1).next_power_of_two();
        Rates {
            mean: CausalMean::new(steps.smooth),
            step,
            h2: 2.0 * step as f64 * dt_s,
            mask: len - 1,
            smoothed: vec![0.0; len],
            tdot: vec![0.0; len],
            count: 0,
        }
    }

    /// Adds a temperature and returns (Ṫ, T̈) at it: 0 while the history is short (Ṫ for the
    /// first `2s` samples, T̈ for the first `4s`: before that it would difference the zeros
    /// standing for "no Ṫ yet").
    #[inline]
    pub fn push(&mut self, temp_c: f64) -> (f64, f64) {
        let (i, s, m) = (self.count, self.step, self.mask);
        let sm = self.mean.push(temp_c);
        self.smoothed[i & m] = sm;
        let tdot = if i < 2 * s {
            0.0
        } else {
            backward_step(
                sm,
                self.smoothed[(i - s) & m],
                self.smoothed[(i - 2 * s) & m],
                self.h2,
            )
        };
        self.tdot[i & m] = tdot;
        let tddot = if i < 4 * s {
            0.0
        } else {
            backward_step(
                tdot,
                self.tdot[(i - s) & m],
                self.tdot[(i - 2 * s) & m],
                self.h2,
            )
        };
        self.count += 1;
        (tdot, tddot)
    }

    /// The first sample whose T̈ has its full history: `4·step` samples after the causal mean
    /// of T first holds its whole window, so that no rate is taken from a mean over fewer
    /// samples than the others (which at the start of a segment in the middle of a ramp would
    /// read as a jump of Ṫ and T̈).
    pub fn ready_from(&self) -> usize {
        DerivativeSteps {
            smooth: self.mean.window(),
            step: self.step,
        }
        .ready_from()
    }
}

/// Resolves a duration in seconds to a whole number of samples (at least 1).
pub fn seconds_to_samples(seconds: f64, dt_s: f64) -> usize {
    if !(seconds.is_finite() && dt_s.is_finite() && dt_s > 0.0) {
        return 1;
    }
    ((seconds / dt_s).round() as usize).max(1)
}
