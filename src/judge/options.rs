//! Whether the options of the figures of merit make sense on a log, checked before they are
//! computed: a filter longer than the log averages more than every sample, a filter or window
//! beyond any chamber run (1e9 s, inf) is a typing slip. A window longer than the log leaves
//! the windowed figures `n/a`, with the reason, as the figures of merit say.

use crate::error::Invalid;
use crate::judge::metrics::MeritOptions;
use crate::log::Log;
use crate::number::readable;

/// The time a log covers: its first to its last sample, and the last sample's own step.
pub fn log_span_s(log: &Log) -> f64 {
    span_with_step(log, log.nominal_dt_s())
}

/// [`log_span_s`] with the log's nominal step already found (finding it walks the log).
pub fn span_with_step(log: &Log, dt_s: f64) -> f64 {
    if log.is_empty() {
        return 0.0;
    }
    log.duration_s() + dt_s
}

/// Checks `opts` on `log`: a filter and a window that are positive seconds no longer than
/// any chamber run, and a filter that fits in the log. Gives
/// what to tell: a filter shorter than a sample, taken as one ([`one_sample`]); the log's
/// step is found once for both.
///
/// # Errors
/// `filter_s` or `window_s`, with the value and the log's span.
pub fn check_merit(opts: &MeritOptions, log: &Log) -> Result<Option<Invalid>, Invalid> {
    let dt = log.nominal_dt_s();
    let span = span_with_step(log, dt);
    for (field, v, why) in [
        (
            "filter_s",
            opts.filter_s,
            "a moving average longer than the log averages more than every sample",
        ),
        (
            "window_s",
            opts.window_s,
            "not one whole window fits in it, so no windowed figure can be computed",
        ),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Invalid::new(
                field,
                format!("must be a positive number of seconds, got {}", readable(v)),
            ));
        }
        if v > crate::models::recipe::MAX_WINDOW_S {
            return Err(Invalid::new(
                field,
                format!(
                    "{} s is longer than any chamber run: at most {} s (11.6 days)",
                    readable(v),
                    readable(crate::models::recipe::MAX_WINDOW_S)
                ),
            ));
        }
        if v < crate::models::recipe::MIN_WINDOW_S {
            return Err(crate::models::recipe::too_short(field, v));
        }
        // A window shorter than a sample is not refused here either: its figures are `n/a`,
        // with the reason ([`crate::judge::metrics::Unavailable::WindowShorterThanSample`]),
        // so that a slow held-out log judged with the default window keeps its other
        // figures. A window the engineer asked for is refused ([`check_window_asked`]).
        // A window longer than the log is not refused: its figures are `n/a`, with the reason
        // (a short log judged with the default 10-min window is still judged on the rest).
        if field == "filter_s" && v > span {
            return Err(Invalid::new(
                field,
                format!(
                    "{} s is longer than the log {} ({} s): {why}",
                    readable(v),
                    log.source,
                    readable(span)
                ),
            ));
        }
    }
    // A filter that short is none, taken as one sample: said, not refused.
    Ok(one_sample("filter_s", opts.filter_s, dt, &log.source))
}

/// The fewest samples a window of the windowed figures holds: the mean of one sample is that
/// sample, and `max |10-min mean|` over windows of one sample would name a length it does not
/// have.
pub const MIN_WINDOW_SAMPLES: usize = 2;

/// How far a window's whole number of samples times the log's step may be from the length
/// asked for, relative to it, for the figures to carry the length asked for as their label.
///
/// The windows are cut in whole samples (`round(window / step)`), so a length between two
/// whole numbers of samples is computed over one of them and would be labelled with the
/// other. 0.1 % leaves room for what a clock makes of the step, not for a length the step
/// cannot make: the nominal step of a jittered or a burst log is a mean read off its stamps,
/// within a few parts in 10⁵ of the true one (a host's 100 Hz batches: 1e-5), which moves
/// `samples × step` by far less; and it is below what a figure's label says (`600.3-s`
/// for 600 s is 0.05 %). Whereas `--window 2.5` on a 1 Hz log is three samples, 20 % longer,
/// and `--window 100.4` is 100 samples, 0.4 % shorter than its label.
pub const WHOLE_WINDOW_TOLERANCE: f64 = 1e-3;

/// The whole number of samples a window of `window_s` holds on a log sampled every `dt_s`:
/// the rounding the figures cut their windows by.
pub fn window_samples(window_s: f64, dt_s: f64) -> usize {
    crate::signal::seconds_to_samples(window_s, dt_s)
}

/// Whether a window of `window_s` holds fewer than [`MIN_WINDOW_SAMPLES`] on a log sampled
/// every `dt_s` (a step that is no positive number holds no rule).
pub fn window_of_one_sample(window_s: f64, dt_s: f64) -> bool {
    dt_s.is_finite() && dt_s > 0.0 && window_samples(window_s, dt_s) < MIN_WINDOW_SAMPLES
}

/// `window_s` against the whole numbers of samples of `dt_s` nearest it: `None` when the one
/// it is cut to is within [`WHOLE_WINDOW_TOLERANCE`], else the lengths to give instead, each
/// of at least [`MIN_WINDOW_SAMPLES`] (`2 s (2 samples) or 3 s (3 samples)`).
fn not_whole(window_s: f64, dt_s: f64) -> Option<String> {
    if !(dt_s.is_finite() && dt_s > 0.0) {
        return None;
    }
    let n = window_samples(window_s, dt_s);
    if ((n as f64 * dt_s) / window_s - 1.0).abs() <= WHOLE_WINDOW_TOLERANCE {
        return None;
    }
    let x = window_s / dt_s;
    let lo = (x.floor() as usize).max(MIN_WINDOW_SAMPLES);
    let hi = (x.ceil() as usize).max(MIN_WINDOW_SAMPLES);
    let length = |k: usize| format!("{} s ({k} samples)", readable(k as f64 * dt_s));
    Some(if lo == hi {
        length(lo)
    } else {
        format!("{} or {}", length(lo), length(hi))
    })
}

/// Refuses a window the engineer asked for (not a default) that is not a window of whole
/// samples of `log` or does not fit in it: [`check_window_whole`], then
/// [`check_window_fits`] over the whole log (for a caller that judges no one correction; one
/// that does checks the fit over the samples the correction judges).
///
/// # Errors
/// `window_s`, with the value, the log's step and the lengths to give instead.
pub fn check_window_asked(window_s: f64, log: &Log) -> Result<(), Invalid> {
    check_window_whole(window_s, log)?;
    check_window_fits(window_s, log, std::slice::from_ref(&(0..log.len())))
}

/// Refuses a window the engineer asked for (not a default) that is not a window of whole
/// samples of `log`: shorter than its step, or of one sample (the figures would be the samples
/// themselves, labelled with a length they do not have), or a length the step does not make
/// within [`WHOLE_WINDOW_TOLERANCE`] (`--window 2.5` on a 1 Hz log, computed over 3 samples
/// and labelled 2.5 s). The refusal offers the nearest lengths that are.
///
/// # Errors
/// `window_s`, with the value, the log's step and the lengths to give instead.
pub fn check_window_whole(window_s: f64, log: &Log) -> Result<(), Invalid> {
    let dt = log.nominal_dt_s();
    let shortest = || {
        format!(
            "a window holds at least {MIN_WINDOW_SAMPLES} samples ({} s)",
            readable(MIN_WINDOW_SAMPLES as f64 * dt)
        )
    };
    if shorter_than_a_sample(window_s, dt) {
        return Err(Invalid::new(
            "window_s",
            format!(
                "{} s is shorter than the sampling interval of {} ({} s): a window of one \
                 sample would be labelled with a length it does not have; {}",
                readable(window_s),
                log.source,
                readable(dt),
                shortest()
            ),
        ));
    }
    if window_of_one_sample(window_s, dt) {
        return Err(Invalid::new(
            "window_s",
            format!(
                "{} s is one sample of {} (sampled every {} s): a window of one sample is the \
                 sample itself, no mean over a window; {}",
                readable(window_s),
                log.source,
                readable(dt),
                shortest()
            ),
        ));
    }
    if let Some(instead) = not_whole(window_s, dt) {
        return Err(Invalid::new(
            "window_s",
            format!(
                "{} s is {} samples of {} (sampled every {} s): a window is a whole number of \
                 samples, and this one would be {} s labelled {} s; give {instead}",
                readable(window_s),
                readable(window_s / dt),
                log.source,
                readable(dt),
                readable(window_samples(window_s, dt) as f64 * dt),
                readable(window_s),
            ),
        ));
    }
    Ok(())
}

/// Refuses a window the engineer asked for that no stretch of `ready` (the samples of `log`
/// judged, one range per segment: the whole log, or what a correction leaves after its
/// warm-up, [`crate::models::vakhrameev::correct::Correction::ready`]) holds whole: its
/// windowed figures would be n/a, neither honoured nor refused. The length it names is the
/// longest window that gives a figure: the longest stretch judged.
///
/// # Errors
/// `window_s`, with the value and the longest window that fits.
pub fn check_window_fits(
    window_s: f64,
    log: &Log,
    ready: &[std::ops::Range<usize>],
) -> Result<(), Invalid> {
    let dt = log.nominal_dt_s();
    if !(dt.is_finite() && dt > 0.0) {
        return Ok(());
    }
    let longest = ready.iter().map(|r| r.len()).max().unwrap_or(0);
    if window_samples(window_s, dt) <= longest {
        return Ok(());
    }
    let most = readable(longest as f64 * dt);
    let whole = longest == log.len() && ready.len() == 1;
    let judged = if whole {
        format!("the log {} ({most} s)", log.source)
    } else {
        let warm_up = log
            .len()
            .saturating_sub(ready.iter().map(|r| r.len()).sum());
        format!(
            "the longest stretch of {} judged ({most} s, {longest} samples; the {warm_up} \
             warm-up samples the correction needs are left out)",
            log.source
        )
    };
    Err(Invalid::new(
        "window_s",
        format!(
            "{} s is longer than {judged}: not one whole window fits in it, so no windowed \
             figure could be computed; give at most {most} s",
            readable(window_s)
        ),
    ))
}

/// What to tell of a window that was not asked for (the default 10 min) but that `log`'s step
/// does not make in whole samples (a log sampled every 7 s cuts 86 samples, 602 s): the
/// figures are computed over that and keep the default's label. `None` when the step makes it,
/// or holds one sample of it (those figures are n/a, with the reason).
pub fn default_window_not_whole(window_s: f64, log: &Log) -> Option<Invalid> {
    let dt = log.nominal_dt_s();
    if window_of_one_sample(window_s, dt) {
        return None;
    }
    not_whole(window_s, dt).map(|instead| {
        Invalid::new(
            "window_s",
            format!(
                "the default {} s is {} samples of {} (sampled every {} s): the windowed figures \
                 are computed over {} s and labelled {} s; give {instead} to have them labelled \
                 with their length",
                readable(window_s),
                readable(window_s / dt),
                log.source,
                readable(dt),
                readable(window_samples(window_s, dt) as f64 * dt),
                readable(window_s)
            ),
        )
    })
}

/// Whether `v` seconds is shorter than one sampling interval `dt_s` (with 1 % to spare for a
/// jittered clock, whose nominal step is a little off its true one).
fn shorter_than_a_sample(v: f64, dt_s: f64) -> bool {
    dt_s.is_finite() && dt_s > 0.0 && v < 0.99 * dt_s
}

/// A window of `v` seconds, named `field`, that is shorter than the sampling interval `dt_s`
/// of the log `log_name`: it is taken as one sample, longer than asked. `None` when it is not.
pub fn one_sample(field: &str, v: f64, dt_s: f64, log_name: &str) -> Option<Invalid> {
    shorter_than_a_sample(v, dt_s).then(|| {
        Invalid::new(
            field,
            format!(
                "{} s is shorter than the sampling interval of {log_name} ({} s): one sample \
                 ({} s) is used",
                readable(v),
                readable(dt_s),
                readable(dt_s)
            ),
        )
    })
}

/// How a window of `seconds` is named in a table's labels: `10-min`, `90-s`.
pub fn window_label(seconds: f64) -> String {
    if seconds >= 60.0 && (seconds / 60.0).fract() == 0.0 {
        format!("{}-min", readable(seconds / 60.0))
    } else {
        format!("{}-s", readable(seconds))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_and_windows_must_fit_in_the_log() {
        let n = 1000;
        let log = Log::from_columns(
            "run.csv",
            (0..n).map(|i| i as f64).collect(),
            vec![0.0; n],
            vec![20.0; n],
        );
        let ok = MeritOptions {
            filter_s: 100.0,
            window_s: 1000.0,
        };
        assert_eq!(check_merit(&ok, &log), Ok(None));
        // Longer than the log: the windowed figures are n/a, the rest is judged.
        let long = MeritOptions {
            filter_s: 100.0,
            window_s: 1001.0,
        };
        assert_eq!(check_merit(&long, &log), Ok(None));
        for (filter_s, window_s, field) in [
            (f64::INFINITY, 600.0, "filter_s"),
            (1e12, 600.0, "filter_s"),
            (0.0, 600.0, "filter_s"),
            (100.0, f64::INFINITY, "window_s"),
            (100.0, 2e6, "window_s"),
            (100.0, f64::NAN, "window_s"),
        ] {
            let e = check_merit(&MeritOptions { filter_s, window_s }, &log).unwrap_err();
            assert_eq!(e.field, field, "{filter_s} {window_s}: {e}");
        }
        assert_eq!(window_label(600.0), "10-min");
        assert_eq!(window_label(90.0), "90-s");
        assert_eq!(window_label(3600.0), "60-min");
    }
}
