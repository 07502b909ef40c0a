//! A log averaged into fewer samples before anything else is computed on it: into bins of a
//! fixed length (`--bin S`, the usual first step with 100 Hz–2 kHz IMU logs, whose thermal
//! drift lives at minutes), or one sample per burst for a log written in bursts
//! (docs/method.md §5).
//!
//! A burst of a few seconds cannot carry Ṫ and T̈: a 60-s smoothing and a 30-s derivative step
//! do not fit inside it. What it carries is one good sample: the mean time, rate and temperature
//! over the burst. The bursts' means, a few minutes apart, are then a regular log whose rates
//! of T are taken over real time between bursts.

use super::{Channel, Log, Problem, ProblemKind};
use crate::error::Invalid;
use crate::number::readable;
use crate::signal::timing::Timing;
use rayon::prelude::*;

/// How a log is averaged before it is used.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Resampling {
    /// As recorded.
    None,
    /// Averaged into bins of this many seconds.
    Bins(f64),
    /// One sample per burst.
    BurstMeans,
}

/// The sample ranges averaged into each output sample, in order.
type Groups = Vec<std::ops::Range<usize>>;

/// The log averaged as `how` says (see [`prepare`] for the usual choice), with a sentence
/// saying what was done when anything was.
///
/// # Errors
/// A bin length that is not a positive number of seconds.
pub fn resample(log: Log, how: Resampling) -> Result<(Log, Option<String>), Invalid> {
    match how {
        Resampling::None => Ok((log, None)),
        Resampling::Bins(bin_s) => {
            check_bin(&log, bin_s)?;
            let groups = bins(&log.time_s, bin_s);
            let out = average(&log, &groups);
            let note = format!(
                "averaged into {} bins of {} s ({} samples before)",
                out.len(),
                readable(bin_s),
                log.len()
            );
            Ok((out, Some(note)))
        }
        Resampling::BurstMeans => {
            let timing = log.timing();
            let out = average(&log, &timing.burst_ranges(&log.time_s));
            let note = match timing.bursts {
                Some(b) => format!(
                    "{}: each burst reduced to its mean time, rate and temperature ({} samples \
                     every {:.0} s)",
                    describe_bursts(&b),
                    out.len(),
                    b.every_s
                ),
                None => format!("each of {} segments reduced to its mean", out.len()),
            };
            Ok((out, Some(note)))
        }
    }
}

/// The most bins a log may be cut into: beyond 2⁵³ the bin index `⌊(t − t₀)/bin_s⌋` is no
/// longer an exact integer in f64, and past the largest f64 it is infinite, so that every
/// later sample would fall into one bin of its own making.
const MAX_BINS: f64 = 9_007_199_254_740_992.0;

/// Refuses a bin that is not a positive number of seconds, one shorter than the
/// [`MIN_WINDOW_S`](crate::models::recipe::MIN_WINDOW_S) floor every window keeps (1e-305 s
/// overflows the bin index and drops most of the log into one bin), one shorter than the
/// log's sampling step (every sample a bin of its own: nothing averaged), one that cuts the
/// log into more bins than can be counted exactly, or one at least as long as the log: that
/// would average the whole log into one sample, which nothing after can use (every command
/// refuses the same value, `apply` as `evaluate`, and a session's `bin_s` as the option).
fn check_bin(log: &Log, bin_s: f64) -> Result<(), Invalid> {
    if !(bin_s.is_finite() && bin_s > 0.0) {
        return Err(Invalid::new(
            "bin_s",
            format!("{}: a bin is a positive number of seconds", readable(bin_s)),
        ));
    }
    if bin_s < crate::models::recipe::MIN_WINDOW_S {
        return Err(crate::models::recipe::too_short("bin_s", bin_s));
    }
    if log.len() < 2 {
        return Ok(());
    }
    // The first to the last stamp, read off the ends: no walk over a log of 10⁸ samples
    // that is about to be walked by the binning itself.
    let span = log.duration_s();
    if bin_s >= span {
        return Err(Invalid::new(
            "bin_s",
            format!(
                "{} s is not shorter than the log {} ({} s): it would average the whole log \
                 into one sample",
                readable(bin_s),
                log.source,
                readable(span)
            ),
        ));
    }
    if span / bin_s > MAX_BINS {
        return Err(Invalid::new(
            "bin_s",
            format!(
                "{} s cuts the log {} ({} s) into more bins than can be counted exactly \
                 (2^53)",
                readable(bin_s),
                log.source,
                readable(span)
            ),
        ));
    }
    // The nominal step is at most the mean step over the whole log (gaps only lengthen the
    // latter): a bin at least that long needs no walk to be judged.
    let mean_step = span / (log.len() - 1) as f64;
    if bin_s <= mean_step {
        let step = log.nominal_dt_s();
        // A bin of one step holds one sample (none or two where the clock jitters): nothing
        // is averaged, and the log only loses its own stamps for the bins' centres.
        if bin_s <= step {
            return Err(Invalid::new(
                "bin_s",
                format!(
                    "{} s is {} the step of the log {} ({} s): every sample would be a bin of \
                     its own, and nothing would be averaged; a bin of several steps averages",
                    readable(bin_s),
                    if bin_s < step {
                        "shorter than"
                    } else {
                        "the same as"
                    },
                    log.source,
                    readable(step)
                ),
            ));
        }
    }
    Ok(())
}

/// The resampling a command applies unless told otherwise: `--bin S` when given, else one
/// sample per burst for a log written in bursts, else none.
pub fn choose(log: &Log, bin_s: Option<f64>) -> Resampling {
    match bin_s {
        Some(s) => Resampling::Bins(s),
        None if log.timing().bursts.is_some() => Resampling::BurstMeans,
        None => Resampling::None,
    }
}

/// [`resample`] with [`choose`]'s choice.
///
/// # Errors
/// As [`resample`].
pub fn prepare(log: Log, bin_s: Option<f64>) -> Result<(Log, Option<String>), Invalid> {
    let how = choose(&log, bin_s);
    resample(log, how)
}

/// The log's longest contiguous segment, for analyses that need evenly spaced samples (the
/// Allan deviation), with a sentence saying what was kept when the log has gaps.
pub fn longest_segment(log: Log) -> (Log, Option<String>) {
    let timing = log.timing();
    if timing.segments.len() <= 1 {
        return (log, None);
    }
    let Some(r) = timing.segments.iter().max_by_key(|r| r.len()).cloned() else {
        return (log, None);
    };
    let cut = |x: &[f64]| x[r.clone()].to_vec();
    let note = format!(
        "the log has {} gaps: only its longest stretch is used, {} samples from {} s to {} s",
        timing.gaps.len(),
        r.len(),
        log.time_s[r.start],
        log.time_s[r.end - 1]
    );
    let out = Log {
        source: log.source.clone(),
        time_s: cut(&log.time_s),
        omega_dph: cut(&log.omega_dph),
        temp_c: cut(&log.temp_c),
        extra: log
            .extra
            .iter()
            .map(|c| Channel {
                name: c.name.clone(),
                unit: c.unit.clone(),
                values: cut(&c.values),
            })
            .collect(),
        axis: log.axis.clone(),
        axis_kind: log.axis_kind,
        other_axes: log
            .other_axes
            .iter()
            .map(|a| super::Axis {
                name: a.name.clone(),
                omega_dph: cut(&a.omega_dph),
                kind: a.kind,
            })
            .collect(),
        info: log.info.clone(),
    };
    (out, Some(note))
}

/// "25 bursts of 5.0 s every 305 s".
pub fn describe_bursts(b: &crate::signal::timing::Bursts) -> String {
    format!(
        "{} bursts of {:.1} s every {:.0} s",
        b.count, b.on_s, b.every_s
    )
}

/// The samples of each bin `⌊(t − t₀)/bin_s⌋`, in order; empty bins give no group.
fn bins(time_s: &[f64], bin_s: f64) -> Groups {
    let Some(&t0) = time_s.first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut start = 0;
    let mut current = 0.0f64;
    for (i, &t) in time_s.iter().enumerate() {
        let k = ((t - t0) / bin_s).floor();
        if i == 0 {
            current = k;
        } else if k != current {
            out.push(start..i);
            start = i;
            current = k;
        }
    }
    out.push(start..time_s.len());
    out
}

/// Mean of the finite values of `x` over `r`, NaN when there is none.
fn mean_of(x: &[f64], r: &std::ops::Range<usize>) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for &v in &x[r.clone()] {
        if v.is_finite() {
            sum += v;
            n += 1;
        }
    }
    if n > 0 { sum / n as f64 } else { f64::NAN }
}

/// Every column of `log` averaged over each group of samples.
fn average(log: &Log, groups: &Groups) -> Log {
    let avg = |x: &[f64]| -> Vec<f64> { groups.par_iter().map(|r| mean_of(x, r)).collect() };
    let ((time_s, omega_dph), temp_c) = rayon::join(
        || rayon::join(|| avg(&log.time_s), || avg(&log.omega_dph)),
        || avg(&log.temp_c),
    );
    let extra = log
        .extra
        .par_iter()
        .map(|c| Channel {
            name: c.name.clone(),
            unit: c.unit.clone(),
            values: avg(&c.values),
        })
        .collect();
    let mut info = log.info.clone();
    info.problems.retain(|p| p.kind != ProblemKind::Gap);
    let timing = Timing::of(&time_s);
    if let Some(g) = timing.gaps.first() {
        info.problems.push(Problem {
            line: 0,
            column: None,
            kind: ProblemKind::Gap,
            count: timing.gaps.len(),
            message: format!(
                "{} gap{} between the averaged samples (first after {} s)",
                timing.gaps.len(),
                if timing.gaps.len() == 1 { "" } else { "s" },
                g.from_s
            ),
        });
    }
    let other_axes = log
        .other_axes
        .par_iter()
        .map(|a| super::Axis {
            name: a.name.clone(),
            omega_dph: avg(&a.omega_dph),
            kind: a.kind,
        })
        .collect();
    Log {
        source: log.source.clone(),
        time_s,
        omega_dph,
        temp_c,
        extra,
        axis: log.axis.clone(),
        axis_kind: log.axis_kind,
        other_axes,
        info,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_average_what_they_hold() {
        // 10 Hz for 10 s: bins of 1 s hold 10 samples each; two missing seconds leave a gap.
        let t: Vec<f64> = (0..100)
            .filter(|i| !(30..50).contains(i))
            .map(|i| i as f64 * 0.1)
            .collect();
        let om: Vec<f64> = t.iter().map(|t| 2.0 * t).collect();
        let temp: Vec<f64> = t.iter().map(|t| 20.0 + t).collect();
        let log = Log::from_columns("x", t, om, temp);
        let (b, note) = resample(log.clone(), Resampling::Bins(1.0)).unwrap();
        assert_eq!(b.len(), 8);
        assert!(note.unwrap().contains("8 bins of 1 s"));
        // The first bin holds t = 0.0 … 0.9: mean 0.45.
        assert!((b.time_s[0] - 0.45).abs() < 1e-12);
        assert!((b.omega_dph[0] - 0.9).abs() < 1e-12);
        assert!((b.temp_c[3] - 25.45).abs() < 1e-12);
        assert_eq!(b.timing().gaps.len(), 1);
        assert!(resample(log.clone(), Resampling::Bins(0.0)).is_err());
        assert!(resample(log, Resampling::Bins(f64::INFINITY)).is_err());
    }

    #[test]
    fn a_burst_log_becomes_one_sample_per_burst() {
        let t: Vec<f64> = (0..10)
            .flat_map(|b| (0..250).map(move |i| b as f64 * 300.0 + i as f64 * 0.02))
            .collect();
        let om = vec![1.0; t.len()];
        let temp: Vec<f64> = t.iter().map(|t| 30.0 - t / 900.0).collect();
        let log = Log::from_columns("sat", t, om, temp);
        assert_eq!(choose(&log, None), Resampling::BurstMeans);
        let (b, note) = prepare(log, None).unwrap();
        assert_eq!(b.len(), 10);
        assert!(note.unwrap().starts_with("10 bursts of 5.0 s every 300 s"));
        assert!((b.time_s[1] - (300.0 + 2.49)).abs() < 1e-9);
        assert!((b.temp_c[1] - (30.0 - 302.49 / 900.0)).abs() < 1e-9);
    }
}
