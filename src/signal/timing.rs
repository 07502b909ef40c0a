//! How a log was sampled in real time: the nominal step, the contiguous segments between
//! logger outages, the jitter of host time stamps, and bursts (docs/method.md §5).
//!
//! Every window driftlab applies (the Ω filter, the smoothing of T, the derivative step, plateau
//! durations, warm-up, the 10-minute windows) is a span of real time inside one segment: no
//! average, derivative or window reaches across a gap. A test stand's log is rarely the clean
//! uniform series a simulator writes:
//!
//! - **Gaps.** A logger restarted for an hour leaves one step of an hour. Taking the samples on
//!   either side as neighbours would make Ṫ jump by the whole temperature change of that hour.
//! - **Host time stamps.** A PC that reads a sensor's buffer stamps samples as they arrive:
//!   bunches 2 ms apart, then a pause of up to half a second. The sensor sampled regularly; only
//!   the stamps bunch. The median step (2 ms) is then five times too short, and each pause is
//!   not a gap, since the samples that follow catch up with the clock. A step is a gap only when
//!   the time it loses is not made up by the steps after it.
//! - **Bursts.** A logger that wakes up to save power writes, say, 10 s at 50 Hz (or at 1 Hz)
//!   every two minutes: many short segments of one length at one spacing. Its stamps are runs
//!   at a short step between pauses, as a host's that reads a regular sampler in batches are;
//!   how long the pauses last in real time tells the two apart (`runs_of`).

use std::ops::Range;

pub use super::stray::{End, MAX_STRAY_RUN, STRAY_FACTOR, StrayEnd, StrayStamps, stray_stamps};

/// A step longer than this many nominal steps ends a segment, unless the steps after it make up
/// the time it loses (host stamps catching up).
pub const GAP_FACTOR: f64 = 2.5;

/// Block lengths, in steps, over which the nominal step is estimated: the one whose block
/// means agree best is used. Host stamps bunch over tens of steps and need long blocks to
/// average out; a burst of a few hundred samples needs short ones, so that most blocks lie
/// inside a burst.
const BLOCKS: [usize; 5] = [16, 64, 256, 1024, 4096];

/// The most samples after a long step searched for the time it lost to be made up.
const CATCH_UP_MAX: usize = 1 << 14;

/// The fewest samples after a long step searched: enough for the backlog of a host's stall
/// (half a second at 100 Hz) that follows a shorter wait.
const CATCH_UP_MIN: usize = 256;

/// A segment shorter than this many samples cannot be bursts' worth of data: bursts are
/// recognised only among segments of at least this length.
const MIN_BURST_SAMPLES: usize = 3;

/// A logger outage between two segments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Index of the first sample after the gap.
    pub at: usize,
    /// Time of the last sample before the gap, s.
    pub from_s: f64,
    /// Length of the step across the gap, s.
    pub step_s: f64,
}

/// How irregular the time stamps are within segments, apart from gaps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jitter {
    /// Shortest step, s.
    pub min_step_s: f64,
    /// Longest step that is not a gap, s.
    pub max_step_s: f64,
    /// Share of steps more than 10 % away from the nominal step.
    pub irregular_fraction: f64,
    /// Largest lag of a stamp behind the line of regular sampling through its segment, s.
    pub max_lag_s: f64,
}

/// A log written in bursts: segments of one length at one spacing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bursts {
    /// Number of bursts.
    pub count: usize,
    /// Typical (median) length of a burst, s.
    pub on_s: f64,
    /// Typical (median) time from the start of one burst to the start of the next, s.
    pub every_s: f64,
}

/// The sampling of a log in real time.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    /// The sampling step within segments, s: their mean step (robust to host stamps), or the
    /// median step when the two agree within 1e-6 (a clean clock, whose median is a step
    /// actually in the data and free of the rounding of a long sum).
    pub nominal_dt_s: f64,
    /// Contiguous runs of samples, in order, covering the log.
    pub segments: Vec<Range<usize>>,
    /// The outages between segments, one fewer than the segments (within each run of a
    /// campaign, [`Timing::of_runs`]: two runs are apart by no outage).
    pub gaps: Vec<Gap>,
    /// Stamps that do not keep the nominal step, when more than 1 % of the steps are off it.
    pub jitter: Option<Jitter>,
    /// The log's bursts, when its segments are bursts.
    pub bursts: Option<Bursts>,
}

impl Timing {
    /// The sampling of `time_s` (seconds, strictly increasing as the reader leaves it; steps
    /// that are not positive and finite are treated as regular).
    pub fn of(time_s: &[f64]) -> Timing {
        let n = time_s.len();
        if n < 2 {
            return Timing {
                nominal_dt_s: 1.0,
                segments: std::iter::once(0..n).collect(),
                gaps: Vec::new(),
                jitter: None,
                bursts: None,
            };
        }
        // A clean clock (every step within 10 % of every other: no gap, no jitter) needs one
        // pass; most logs are that.
        // Plain comparisons rather than f64::min/max: a NaN step fails both and the clean
        // test below, and the loop runs at memory speed (a command asks for the timing of a
        // 10M-sample log several times).
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut clean = true;
        for w in time_s.windows(2) {
            let d = w[1] - w[0];
            if d < lo {
                lo = d;
            }
            if d > hi {
                hi = d;
            }
            clean &= !d.is_nan();
        }
        if clean && lo > 0.0 && hi <= 1.1 * lo {
            let segments: Vec<_> = std::iter::once(0..n).collect();
            // Every step the same: that is the step.
            let nominal_dt_s = if lo == hi {
                lo
            } else {
                refine_step(time_s, &segments, 0.5 * (lo + hi))
            };
            return Timing {
                nominal_dt_s,
                segments,
                gaps: Vec::new(),
                jitter: None,
                bursts: None,
            };
        }
        let rough = rough_step(time_s);
        let gaps = find_gaps(time_s, rough);
        let mut segments = Vec::with_capacity(gaps.len() + 1);
        let mut start = 0;
        for g in &gaps {
            segments.push(start..g.at);
            start = g.at;
        }
        segments.push(start..n);
        let nominal_dt_s = refine_step(time_s, &segments, rough);
        let jitter = jitter_of(time_s, &segments, nominal_dt_s);
        let bursts = bursts_of(time_s, &segments);
        Timing {
            nominal_dt_s,
            segments,
            gaps,
            jitter,
            bursts,
        }
    }

    /// The sampling of a campaign's joined log, whose `runs` (ranges of samples, in order,
    /// covering it) were recorded apart: each run is timed on its own ([`Timing::of`]) and its
    /// segments kept, so that a run's end always ends a segment, whatever lies between the
    /// runs on the joined time axis. The gaps are those within runs (the time between two
    /// runs is no logger outage); the step is the first run's (a campaign's runs are sampled
    /// alike, `crate::log::campaign` refuses others); the jitter the worst run's; bursts only
    /// when every run is written in bursts. One run gives [`Timing::of`] bit for bit.
    pub fn of_runs(time_s: &[f64], runs: &[Range<usize>]) -> Timing {
        if runs.len() <= 1 {
            return Timing::of(time_s);
        }
        let mut joined = Timing {
            nominal_dt_s: 1.0,
            segments: Vec::new(),
            gaps: Vec::new(),
            jitter: None,
            bursts: None,
        };
        let mut bursts: Option<Bursts> = None;
        let mut all_bursts = true;
        for (k, r) in runs.iter().enumerate() {
            let t = Timing::of(&time_s[r.clone()]);
            if k == 0 {
                joined.nominal_dt_s = t.nominal_dt_s;
            }
            joined.segments.extend(
                t.segments
                    .iter()
                    .map(|s| s.start + r.start..s.end + r.start),
            );
            joined.gaps.extend(t.gaps.iter().map(|g| Gap {
                at: g.at + r.start,
                ..*g
            }));
            joined.jitter = match (joined.jitter, t.jitter) {
                (Some(a), Some(b)) if b.max_lag_s > a.max_lag_s => Some(b),
                (None, b) => b,
                (a, _) => a,
            };
            match (t.bursts, &mut bursts) {
                (Some(b), None) => bursts = Some(b),
                (Some(b), Some(acc)) => acc.count += b.count,
                (None, _) => all_bursts = false,
            }
        }
        joined.bursts = bursts.filter(|_| all_bursts);
        joined
    }

    /// Whether the log is one contiguous segment.
    pub fn is_contiguous(&self) -> bool {
        self.segments.len() <= 1
    }

    /// The segments shorter than `min_s` seconds of real time (with a nominal step counted
    /// for the last sample), which a window of that length cannot fit in.
    pub fn shorter_than(&self, time_s: &[f64], min_s: f64) -> Vec<Range<usize>> {
        self.segments
            .iter()
            .filter(|r| span_s(time_s, r, self.nominal_dt_s) < min_s)
            .cloned()
            .collect()
    }
}

impl Timing {
    /// What a person should know of the sampling, one sentence a line: segments and gaps,
    /// bursts, jitter. Empty for a clean contiguous log.
    pub fn describe(&self, time_s: &[f64]) -> Vec<String> {
        let mut out = Vec::new();
        let ms = |s: f64| {
            if s < 1.0 {
                format!("{} ms", crate::number::fixed(s * 1e3, 1))
            } else {
                format!("{} s", crate::number::fixed(s, 3))
            }
        };
        if let Some(b) = &self.bursts {
            out.push(format!(
                "written in bursts: {} bursts of {} s every {} s",
                b.count,
                crate::number::fixed(b.on_s, 1),
                crate::number::fixed(b.every_s, 0)
            ));
        } else if !self.gaps.is_empty() {
            let longest = self.gaps.iter().map(|g| g.step_s).fold(0.0, f64::max);
            out.push(format!(
                "{} segments between {} gap{} (the first after {} s, the longest {}): \
                 no window, filter or derivative reaches across a gap",
                self.segments.len(),
                self.gaps.len(),
                if self.gaps.len() == 1 { "" } else { "s" },
                crate::number::fixed(self.gaps[0].from_s, 3),
                ms(longest)
            ));
        }
        if let Some(j) = &self.jitter {
            out.push(format!(
                "time stamps jitter: steps {} … {} around the nominal {} ({:.0} % of them more \
                 than 10 % off), stamps up to {} behind regular sampling; the nominal step is \
                 the mean step within segments",
                ms(j.min_step_s),
                ms(j.max_step_s),
                ms(self.nominal_dt_s),
                100.0 * j.irregular_fraction,
                ms(j.max_lag_s)
            ));
        }
        let short = self.shorter_than(time_s, 60.0);
        if !short.is_empty() && self.bursts.is_none() {
            out.push(format!(
                "{} segment{} shorter than a minute",
                short.len(),
                if short.len() == 1 { " is" } else { "s are" }
            ));
        }
        out
    }
}

/// Real time a segment covers: from its first stamp to one step past its last.
pub fn span_s(time_s: &[f64], r: &Range<usize>, dt_s: f64) -> f64 {
    if r.is_empty() {
        return 0.0;
    }
    time_s[r.end - 1] - time_s[r.start] + dt_s
}

/// The steps of `time_s` that are positive and finite.
fn step(time_s: &[f64], i: usize) -> Option<f64> {
    let s = time_s[i] - time_s[i - 1];
    (s.is_finite() && s > 0.0).then_some(s)
}

/// A first estimate of the sampling step: the step within bursts for a log written in bursts,
/// the mean step over blocks that span several of a host's batches for a host that reads a
/// regular sampler in batches ([`runs_of`] tells the two apart), else [`block_step`] over any
/// block length. Short logs take the median step.
pub(super) fn rough_step(time_s: &[f64]) -> f64 {
    let block = block_step(time_s, 1);
    match (runs_of(time_s), block) {
        // The blocks straddle the pauses: each block mean is a burst and a pause averaged.
        (Some(Runs::Bursts { step }), Some(b)) if b > RUN_AGREE * step => step,
        (Some(Runs::Batches { step, run_steps }), Some(b)) if b <= RUN_AGREE * step => {
            // The blocks lie inside the batches, at the host's pace: average over blocks that
            // hold at least four batches, else over the whole log.
            let min_block = (4.0 * run_steps).ceil() as usize;
            block_step(time_s, min_block).unwrap_or_else(|| mean_step(time_s).unwrap_or(b))
        }
        (_, Some(b)) => b,
        (_, None) => {
            let mut v: Vec<f64> = (1..time_s.len()).filter_map(|i| step(time_s, i)).collect();
            median(&mut v).unwrap_or(1.0)
        }
    }
}

/// Over blocks of consecutive steps, at least `min_block` long, the median of the blocks' mean
/// steps, for the block length whose block means spread least (relative interquartile range).
/// Bunched host stamps average out within long blocks, a gap spoils only its own block, and
/// bursts longer than a block are measured within themselves. `None` when no block length
/// gives eight blocks.
fn block_step(time_s: &[f64], min_block: usize) -> Option<f64> {
    let n = time_s.len();
    let mut best: Option<(f64, f64)> = None; // (spread, median)
    for block in BLOCKS.into_iter().filter(|&b| b >= min_block) {
        let count = (n - 1) / block;
        if count < 8 {
            break;
        }
        let mut means: Vec<f64> = (0..count)
            .map(|b| (time_s[(b + 1) * block] - time_s[b * block]) / block as f64)
            .filter(|d| d.is_finite() && *d > 0.0)
            .collect();
        if means.len() < 8 {
            continue;
        }
        means.sort_unstable_by(f64::total_cmp);
        let q = |f: f64| means[((means.len() - 1) as f64 * f) as usize];
        let m = q(0.5);
        let spread = (q(0.75) - q(0.25)) / m;
        // A shorter block wins ties: it is the finer measure.
        if best.is_none_or(|(s, _)| spread < s - 1e-9) {
            best = Some((spread, m));
        }
    }
    best.map(|(_, m)| m)
}

/// The mean step from the first sample to the last, when it is positive and finite.
fn mean_step(time_s: &[f64]) -> Option<f64> {
    let n = time_s.len();
    let m = (time_s[n - 1] - time_s[0]) / (n - 1) as f64;
    (m.is_finite() && m > 0.0).then_some(m)
}

/// The shortest pause between runs of samples, s, that is read as a logger asleep between
/// bursts rather than a host between two reads of a sensor's buffer ([`runs_of`]).
const MIN_BURST_PAUSE_S: f64 = 2.0;

/// Two estimates of the step within this factor of each other agree: the blocks measure the
/// step within the runs ([`rough_step`]).
const RUN_AGREE: f64 = 1.1;

/// The most steps [`runs_of`] looks at.
const RUNS_SAMPLE: usize = 1 << 14;

/// The length, in steps, of each stretch of consecutive steps [`runs_of`] looks at in a longer
/// log.
const RUNS_CHUNK: usize = 256;

/// Stamps that come in runs at a short step with pauses between them, read ([`runs_of`]).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Runs {
    /// A logger's bursts: the step within the runs is the time base, the pauses are gaps.
    Bursts {
        /// The step within the runs, s.
        step: f64,
    },
    /// A host's reads of a regular sampler: the mean step is the time base, the pauses are
    /// jitter.
    Batches {
        /// The host's step within a batch, s.
        step: f64,
        /// The steps from the start of one batch to the start of the next, on average.
        run_steps: f64,
    },
}

/// How to read stamps that come in runs at a short step separated by pauses, or `None` when
/// they do not, or when neither reading below fits most of them.
///
/// Such stamps are one of two things:
///
/// - **Bursts.** A logger that sleeps to save power wakes, samples for a while at its own step
///   and sleeps again: 10 samples at 1 Hz every 120 s. The step within the runs is the time
///   base and the pauses are gaps. A burst shorter than [`block_step`]'s blocks (16 steps and
///   longer) leaves no block inside a burst: every block mean averages a burst with a pause,
///   and the blocks give the mean step over the log (12 s), at which every pause looks made
///   up by the runs after it and the log reads as a regular one with jitter.
/// - **A host reading a regular sampler in batches.** The host reads the sensor's buffer,
///   stamps the samples a few ms apart as it reads them, and waits for the next read; the
///   samples were taken regularly through the wait. The mean step is the time base and the
///   pauses are jitter: 100 Hz samples stamped in batches of 10 every 0.1 s are a 100 Hz log.
///   When the batches are longer than a block (100 samples read once a second), the blocks
///   lie inside them and give the host's pace (0.1 ms) as the step.
///
/// The stamps alone cannot tell them apart: 10 stamps 1 ms apart every 0.12 s are the bursts
/// above a thousand times faster. What tells them apart is how long the pauses last in real
/// time. A host must read a sensor's buffer before it overflows, so it reads every few ms to
/// about a second (the longest stall of a host driftlab expects, in docs/cli.md and the
/// simulator's `--jitter`, is half a second); a logger that sleeps to save power sleeps for
/// tens of seconds to minutes, long against the burst, or waking costs more than sleeping
/// saves. So, over the log's steps (every step of a log of up to [`RUNS_SAMPLE`] steps, else
/// stretches of [`RUNS_CHUNK`] consecutive steps spread evenly over it, which hold whole runs
/// and pauses in their proportions whatever their period), with `s` the median step and the
/// pauses the steps longer than [`GAP_FACTOR`]·`s`:
///
/// - the steps of runs must be at least twice as many as the pauses (runs of three samples
///   or more, so that `s` is a step within the runs), else `None`;
/// - **bursts** when three pauses in four last [`MIN_BURST_PAUSE_S`] or longer and nine steps
///   of runs in ten keep `s` within 10 % (a sampler's clock), or when the pauses of
///   [`MIN_BURST_PAUSE_S`] or longer hold more than half of the time (a logger asleep between
///   bursts whose samples a host stamps with jitter, in batches, after stalls): the step is
///   `s`;
/// - **a host's batches** when three pauses in four are shorter than [`MIN_BURST_PAUSE_S`]
///   and the pauses hold more than half of the time (the host stamps faster than the sampler
///   samples; a logger that drops samples loses less than that): the step is the mean step.
///
/// [`rough_step`] takes the reading only where [`block_step`] measured the other thing (the
/// mean step for bursts, the step within the runs for batches), so that every log the blocks
/// read right keeps its step to the bit. A log written in bursts then has a gap at every
/// pause, its bursts are its segments, and [`bursts_of`] names them: `inspect` says "written
/// in bursts: 336 bursts of 9.0 s every 120 s" (a burst's length from its first stamp to its
/// last) and reads the step within them (1 s). A host's batches have no gap: `inspect` says
/// "time stamps jitter: steps 2.0 ms … 82.0 ms around the nominal 10.0 ms".
fn runs_of(time_s: &[f64]) -> Option<Runs> {
    let steps = time_s.len().checked_sub(1)?;
    let sample: Vec<f64> = if steps <= RUNS_SAMPLE {
        (1..=steps).filter_map(|i| step(time_s, i)).collect()
    } else {
        let chunks = RUNS_SAMPLE / RUNS_CHUNK;
        (0..chunks)
            .flat_map(|c| {
                let start = 1 + c * (steps - RUNS_CHUNK) / (chunks - 1);
                start..start + RUNS_CHUNK
            })
            .filter_map(|i| step(time_s, i))
            .collect()
    };
    let s = median(&mut sample.clone())?;
    let (mut in_runs, mut regular, mut pauses, mut long_pauses) = (0usize, 0usize, 0usize, 0);
    let (mut paused_s, mut slept_s, mut total_s) = (0.0, 0.0, 0.0);
    for &d in &sample {
        total_s += d;
        if d > GAP_FACTOR * s {
            pauses += 1;
            paused_s += d;
            if d >= MIN_BURST_PAUSE_S {
                long_pauses += 1;
                slept_s += d;
            }
        } else {
            in_runs += 1;
            if (d - s).abs() <= 0.1 * s {
                regular += 1;
            }
        }
    }
    if pauses == 0 || in_runs < 2 * pauses {
        return None;
    }
    // A logger asleep most of the time between runs it logs, whatever stamps its host puts
    // on the samples of a run (jittered, some in batches, some after a stall of half a
    // second): the pauses of 2 s or more are its sleep.
    let asleep = long_pauses > 0 && in_runs >= 2 * long_pauses && slept_s > 0.5 * total_s;
    if (4 * long_pauses >= 3 * pauses && 10 * regular >= 9 * in_runs) || asleep {
        Some(Runs::Bursts { step: s })
    } else if 4 * (pauses - long_pauses) >= 3 * pauses && paused_s > 0.5 * total_s {
        Some(Runs::Batches {
            step: s,
            run_steps: sample.len() as f64 / pauses as f64,
        })
    } else {
        None
    }
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// The steps longer than [`GAP_FACTOR`] nominal steps whose lost time the following steps do
/// not make up. Stamps that keep to the clock stay within a fixed lag of the line
/// `t_{i−1} + (j − i + 1)·dt` drawn from the sample before the step; host stamps that bunch
/// come back to within half the step's lost time of it once the backlog is stamped (even
/// when another pause follows before they do), a gap's never do. The samples searched are a
/// few times the lost time's worth, at least [`CATCH_UP_MIN`], at most [`CATCH_UP_MAX`].
fn find_gaps(time_s: &[f64], dt: f64) -> Vec<Gap> {
    let n = time_s.len();
    let mut gaps = Vec::new();
    for i in 1..n {
        let Some(s) = step(time_s, i) else {
            continue;
        };
        if s <= GAP_FACTOR * dt {
            continue;
        }
        let lost = s - dt;
        // In floats until clamped: a stamp 10²¹ s ahead makes the count past any integer.
        let window =
            (4.0 * lost / dt + 16.0).clamp(CATCH_UP_MIN as f64, CATCH_UP_MAX as f64) as usize;
        let base = time_s[i - 1];
        let end = (i + window).min(n);
        let caught_up =
            (i + 1..end).any(|j| time_s[j] - (base + (j - i + 1) as f64 * dt) <= 0.5 * lost);
        // A pause near the end of the log whose backlog is still being stamped faster than the
        // clock when the log ends is the same jitter, cut short.
        let catching_up_at_end =
            end == n && i + 1 < n && (i + 1..n).all(|j| time_s[j] - time_s[j - 1] < dt);
        if !caught_up && !catching_up_at_end {
            gaps.push(Gap {
                at: i,
                from_s: base,
                step_s: s,
            });
        }
    }
    gaps
}

/// The mean step within segments, or the median step where the two agree within 1e-6.
fn refine_step(time_s: &[f64], segments: &[Range<usize>], rough: f64) -> f64 {
    let (mut span, mut steps) = (0.0, 0usize);
    for r in segments.iter().filter(|r| r.len() >= 2) {
        span += time_s[r.end - 1] - time_s[r.start];
        steps += r.len() - 1;
    }
    if steps == 0 || span.is_nan() || span <= 0.0 {
        return rough;
    }
    let mean = span / steps as f64;
    let stride = (time_s.len() / 10_000).max(1);
    let mut sample: Vec<f64> = segments
        .iter()
        .flat_map(|r| (r.start + 1..r.end).step_by(stride))
        .filter_map(|i| step(time_s, i))
        .collect();
    match median(&mut sample) {
        Some(m) if (m - mean).abs() <= 1e-6 * mean => m,
        _ => mean,
    }
}

fn jitter_of(time_s: &[f64], segments: &[Range<usize>], dt: f64) -> Option<Jitter> {
    let (mut min_step, mut max_step) = (f64::INFINITY, 0.0f64);
    let (mut irregular, mut steps) = (0usize, 0usize);
    let mut max_lag = 0.0f64;
    for r in segments.iter().filter(|r| r.len() >= 2) {
        let t0 = time_s[r.start];
        for i in r.start + 1..r.end {
            let s = time_s[i] - time_s[i - 1];
            min_step = min_step.min(s);
            max_step = max_step.max(s);
            steps += 1;
            if (s - dt).abs() > 0.1 * dt {
                irregular += 1;
            }
            max_lag = max_lag.max(time_s[i] - (t0 + (i - r.start) as f64 * dt));
        }
    }
    let fraction = irregular as f64 / steps.max(1) as f64;
    (steps > 0 && fraction > 0.01).then_some(Jitter {
        min_step_s: min_step,
        max_step_s: max_step,
        irregular_fraction: fraction,
        max_lag_s: max_lag,
    })
}

/// Bursts: at least four segments (besides a possibly cut last one) whose lengths and spacings
/// agree within 20 % of their medians, covering less than half of the time between their
/// starts.
fn bursts_of(time_s: &[f64], segments: &[Range<usize>]) -> Option<Bursts> {
    let groups = asleep_apart(time_s, segments);
    let segments = groups.as_slice();
    // The last burst may be cut short by the end of the run.
    let body = &segments[..segments.len().saturating_sub(1)];
    if body.len() < 4 || body.iter().any(|r| r.len() < MIN_BURST_SAMPLES) {
        return None;
    }
    let mut on: Vec<f64> = body
        .iter()
        .map(|r| time_s[r.end - 1] - time_s[r.start])
        .collect();
    let mut every: Vec<f64> = body
        .windows(2)
        .map(|w| time_s[w[1].start] - time_s[w[0].start])
        .collect();
    let (on_s, every_s) = (median(&mut on.clone())?, median(&mut every.clone())?);
    let steady = |v: &mut [f64], m: f64| v.iter().all(|x| (x - m).abs() <= 0.2 * m);
    let spacing_ok = steady(&mut every, every_s);
    let length_ok = steady(&mut on, on_s);
    (spacing_ok && length_ok && on_s > 0.0 && on_s < 0.5 * every_s).then_some(Bursts {
        count: segments.len(),
        on_s,
        every_s,
    })
}

/// The runs of `segments` between pauses of [`MIN_BURST_PAUSE_S`] or longer: a host's stall
/// of half a second inside a burst splits a segment, not a burst.
fn asleep_apart(time_s: &[f64], segments: &[Range<usize>]) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::with_capacity(segments.len());
    for r in segments {
        match out.last_mut() {
            Some(last)
                if !r.is_empty() && time_s[r.start] - time_s[last.end - 1] < MIN_BURST_PAUSE_S =>
            {
                last.end = r.end;
            }
            _ => out.push(r.clone()),
        }
    }
    out
}

impl Timing {
    /// The samples of each burst when the log is written in bursts ([`Timing::bursts`]): its
    /// segments, those a host's stall split joined again; else the segments.
    pub fn burst_ranges(&self, time_s: &[f64]) -> Vec<Range<usize>> {
        if self.bursts.is_some() {
            asleep_apart(time_s, &self.segments)
        } else {
            self.segments.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn regular(n: usize, dt: f64) -> Vec<f64> {
        (0..n).map(|i| i as f64 * dt).collect()
    }

    #[test]
    fn a_clean_log_is_one_segment_at_its_own_step() {
        let t = regular(5000, 1.0);
        let tm = Timing::of(&t);
        assert_eq!(tm.nominal_dt_s, 1.0);
        assert_eq!(tm.segments, vec![0..5000]);
        assert!(tm.jitter.is_none() && tm.bursts.is_none());
    }

    #[test]
    fn an_outage_splits_the_log() {
        let mut t = regular(7200, 1.0);
        for v in &mut t[3600..] {
            *v += 3600.0;
        }
        let tm = Timing::of(&t);
        assert_eq!(tm.segments, vec![0..3600, 3600..7200]);
        assert_eq!(tm.gaps[0].step_s, 3601.0);
        assert_eq!(tm.nominal_dt_s, 1.0);
    }

    #[test]
    fn host_stamps_that_catch_up_are_not_gaps() {
        // True sampling every 10 ms; stamps in bunches 2 ms apart after pauses of up to
        // 0.5 s, never before the sample was taken.
        let mut t: Vec<f64> = Vec::new();
        for i in 0..20_000 {
            let truth = i as f64 * 0.01;
            let late = if i % 100 == 50 { 0.5 } else { 0.0 };
            let prev = t.last().map_or(f64::NEG_INFINITY, |p| p + 0.002);
            t.push(prev.max(truth + late));
        }
        let tm = Timing::of(&t);
        assert!(
            tm.gaps.is_empty(),
            "{} gaps {:?} dt {}",
            tm.gaps.len(),
            &tm.gaps[..1.min(tm.gaps.len())],
            tm.nominal_dt_s
        );
        assert!(
            (tm.nominal_dt_s - 0.01).abs() < 1e-4,
            "{} {:?}",
            tm.nominal_dt_s,
            &tm.gaps[..tm.gaps.len().min(3)]
        );
        assert!(tm.jitter.is_some());
    }

    #[test]
    fn bursts_are_recognised_with_their_length_and_spacing() {
        // 10 s at 50 Hz every 120 s, 12 bursts.
        let t: Vec<f64> = (0..12)
            .flat_map(|b| (0..500).map(move |i| b as f64 * 120.0 + i as f64 * 0.02))
            .collect();
        let tm = Timing::of(&t);
        assert_eq!(tm.segments.len(), 12);
        let b = tm.bursts.unwrap();
        assert_eq!(b.count, 12);
        assert!((b.on_s - 9.98).abs() < 1e-9 && (b.every_s - 120.0).abs() < 1e-9);
        assert!((tm.nominal_dt_s - 0.02).abs() < 1e-12);
    }

    #[test]
    fn stray_stamps_are_runs_out_of_line_with_both_neighbours() {
        let t = regular(1000, 1.0);
        assert_eq!(stray_stamps(&t), None);
        // One stamp far ahead, one far behind, a pair: each run found, nothing else.
        let mut g = t.clone();
        g[100] = 1e6;
        g[500] = -1e300;
        g[700] = 1e300;
        g[701] = f64::MAX;
        let s = stray_stamps(&g).expect("found");
        assert_eq!(s.runs, vec![100..101, 500..501, 700..702]);
        assert_eq!((s.count(), s.step_s), (4, 1.0));
        // Stamps between their neighbours, however uneven, are not stray; nor is a stamp
        // only a step or two out of order.
        let mut g = t.clone();
        g[100] = 99.9;
        g[300] = 302.0;
        assert_eq!(stray_stamps(&g), None);
        // Three in a row are more than a glitch.
        let mut g = t.clone();
        g[100..103].copy_from_slice(&[1e6, 1e6 + 1.0, 1e6 + 2.0]);
        assert_eq!(stray_stamps(&g), None);
        // A stamp far ahead next to a genuine gap: the samples around it do not keep the step.
        let mut g = t.clone();
        for v in &mut g[101..] {
            *v += 3600.0;
        }
        g[100] = 1e6;
        assert_eq!(stray_stamps(&g), None);
        // NaN is left alone; a first sample far ahead of the steps after it, and a last one
        // far behind the steps before it, are vouched against by their one side.
        let mut g = t.clone();
        g[10] = f64::NAN;
        assert_eq!(stray_stamps(&g), None);
        g[0] = 1e6;
        g[999] = -1e6;
        assert_eq!(stray_stamps(&g).expect("found").runs, vec![0..1, 999..1000]);
        // A first sample far BEHIND the rest is a gap before the log (`stray_end`'s), and a
        // last one far ahead a gap after it: not these.
        let mut g = t.clone();
        g[0] = -1e6;
        g[999] = 1e6;
        assert_eq!(stray_stamps(&g), None);
    }

    #[test]
    fn a_pair_at_an_end_far_from_the_log_is_a_stray_end() {
        let mut t = regular(1000, 1.0);
        t.extend([1e9, 1e9 + 1.0]);
        let e = Timing::of(&t).stray_end(&t).expect("stray");
        assert_eq!((e.end, e.samples, e.body_s), (End::Last, 2, 999.0));
        assert_eq!(e.range(t.len()), 1000..1002);
        // Three are stray too (stamped before a clock was set: 0, 0.5, 0.7 s, then Unix
        // time), up to a hundredth of the log; more are a segment of their own.
        t.push(1e9 + 2.0);
        let e = Timing::of(&t).stray_end(&t).expect("stray");
        assert_eq!((e.end, e.samples), (End::Last, 3));
        t.extend((3..11).map(|k| 1e9 + f64::from(k)));
        assert_eq!(t.len(), 1011);
        assert_eq!(Timing::of(&t).stray_end(&t), None);
    }
}
